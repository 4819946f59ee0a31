"""FMI: a flexlib model exported as a standard co-simulation unit (:func:`export_fmu`), and a co-simulation unit as
a block of a flexlib model (:func:`FMU`)."""

from flexlib.fmi.block import FMU, FMUBlock
from flexlib.fmi.export import export_fmu

__all__ = ["FMU", "FMUBlock", "export_fmu"]
