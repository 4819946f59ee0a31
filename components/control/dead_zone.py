"""Region of zero output."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, ParameterError, eq, if_else

from .interfaces import PartialSISO, check_mirrored_limit, mirror_lower_limit, scalar

__all__ = ["DeadZone"]


class DeadZone(PartialSISO):
    """Dead zone: zero output for ``u_min <= u <= u_max``, slope 1 outside.

    .. math::

        y = \\begin{cases} u - u_{max} & u > u_{max} \\\\ u - u_{min} & u < u_{min}
            \\\\ 0 & \\text{else} \\end{cases}

    Both zone edges are state events.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Nonlinear.DeadZone``.
    """

    u_max = Parameter(unit="1", doc="Upper limit of the dead zone")
    u_min = Parameter(unit="1", doc="Lower limit of the dead zone, <= ``u_max`` (default ``-u_max``, as MSL's)")

    def __init__(self, **kw: Any) -> None:
        self._u_min_follows = mirror_lower_limit(kw, "u_max", "u_min")  # MSL's uMin = -uMax
        super().__init__(**kw)

    def check(self, values: dict) -> None:
        if getattr(self, "_u_min_follows", False):
            check_mirrored_limit(self, values, "u_max", "u_min")
        hi, lo = scalar(values, "u_max"), scalar(values, "u_min")
        if hi is not None and lo is not None and hi < lo:
            raise ParameterError(f"{self.where}: limits must be consistent, but u_max = {hi:g} < u_min = {lo:g}")

    def equations(self) -> list:
        u = self.u
        return [eq(self.y, if_else(u > self.u_max, u - self.u_max, if_else(u < self.u_min, u - self.u_min, 0.0)))]
