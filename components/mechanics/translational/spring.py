"""Linear 1D translational spring."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialCompliant

__all__ = ["Spring"]


class Spring(PartialCompliant):
    """Linear 1D translational spring: ``f = c * (s_rel - s_rel0)``.

    Variables
    ---------
    f : N
        Spring force (tension positive).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.Spring``.
    """

    c = Parameter(unit="N/m", min=0.0, doc="Spring constant")
    s_rel0 = Parameter(0.0, unit="m", doc="Unstretched spring length")

    def equations(self) -> list:
        return [*super().equations(), eq(self.f, self.c * (self.s_rel - self.s_rel0))]
