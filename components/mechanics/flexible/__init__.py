"""Flexible bodies: the :class:`FlexibleBody` component, a modal body in the floating frame of reference (SI
units). Its modal data — the beam mesher, FE importers, Craig–Bampton reduction, the HDF5 modal file, mode
selection, output and drawing — come from :mod:`flexlib.fe`."""

from .arguments import frame_names
from .body import FlexibleBody
from .results import cayley_rotation

__all__ = ["FlexibleBody", "cayley_rotation", "frame_names"]
