"""Parameter checks shared by the hydraulic components (private helper).

:class:`Parameter` bounds (``min=0.0``) reject negative values whenever a value is set, at
build time and at run time. Quantities that must be strictly positive (a volume, a
displacement, a time constant) are listed in ``_positive`` and checked by the components'
parameter hook (:meth:`flexlib.Component.check`), which runs at construction, at flatten and
for ``run(params=...)`` overrides, with a message naming the component and the parameter.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from flexlib.core.options import remember_option
from flexlib.errors import ParameterError

from .fluid import Fluid

__all__ = ["PositiveParameters", "pressure_start", "store_fluid"]


class PositiveParameters:
    """Mixin: parameters named in ``_positive`` must be > 0."""

    _positive: tuple[str, ...] = ()

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)  # type: ignore[misc]
        for name in self._positive:
            v = values.get(name)
            if v is not None and not np.all(v > 0.0):
                unit = self._decls[name].unit  # type: ignore[attr-defined]
                raise ParameterError(f"{self.param_label(name)} must be > 0 [{unit}] "  # type: ignore[attr-defined]
                                     f"(got {float(np.min(v))!r})")


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
    remember_option(node, "fluid", lambda v: (store_fluid(node, v), v)[1])  # node.fluid = ... later: checked, recorded


def pressure_start(node: Any, value: Any) -> Any:
    """``p_start`` of a chamber: None, or an absolute pressure [Pa] >= 0 (a gauge value such as ``-1e5`` is refused
    naming the component class and the value; NaN is named later, at initialisation, with the instance path)."""
    if value is None:
        return None
    from flexlib.core.values import not_a_scalar

    why = not_a_scalar(value)
    if why is not None:
        raise ParameterError(f"{type(node).__name__}: p_start {'is None' if value is None else f'= {value!r} is {why}'}"
                             "; give an absolute pressure [Pa]")
    if float(value) < 0.0:
        raise ParameterError(f"{type(node).__name__}: p_start = {value!r} Pa is negative; pressures are absolute "
                             "[Pa], >= 0 (atmospheric: 1.01325e5 Pa)")
    return value
