"""Parameter checks shared by the hydraulic components (private helper).

:class:`Parameter` bounds (``min=0.0``) reject negative values whenever a value is set, at
build time and at run time. Quantities that must be strictly positive (a volume, a
displacement, a time constant) are listed in ``_positive`` and checked here as soon as they
are set, with a message naming the component and the parameter.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from flexlib.errors import ParameterError

from .fluid import Fluid

__all__ = ["PositiveParameters", "store_fluid"]


class PositiveParameters:
    """Mixin: parameters named in ``_positive`` must be > 0."""

    _positive: tuple[str, ...] = ()

    def _assign(self, name: str, value: Any) -> None:
        super()._assign(name, value)  # type: ignore[misc]  # bounds, shape, finiteness
        if name in self._positive:
            v = self._values[name]  # type: ignore[attr-defined]
            if not np.all(v > 0.0):
                label = self._label(name) if self._parent is not None else f"{type(self).__name__}: {name}"  # type: ignore[attr-defined]
                unit = self._decls[name].unit  # type: ignore[attr-defined]
                raise ParameterError(f"{label} must be > 0 [{unit}] (got {float(np.min(v))!r})")


def store_fluid(node: Any, fluid: Fluid) -> None:
    """Attach the (structural) fluid record to a component, as :class:`PartialTwoPort` does.

    The record's numbers enter the equations as constants, so they must be part of the
    model's cache key; the key hashes plain-data attributes only (a dataclass is skipped),
    hence the tuple copy ``fluid_record``.
    """
    if not isinstance(fluid, Fluid):
        raise ParameterError(f"{type(node).__name__}: fluid must be a Fluid record, got {fluid!r}")
    node.__dict__["fluid"] = fluid
    node.__dict__["fluid_record"] = dataclasses.astuple(fluid)
