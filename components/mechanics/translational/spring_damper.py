"""Linear 1D translational spring and damper in parallel."""

from __future__ import annotations

from flexlib import Parameter, Variable, eq

from .interfaces import PartialCompliantWithRelativeStates

__all__ = ["SpringDamper"]


class SpringDamper(PartialCompliantWithRelativeStates):
    """Linear 1D translational spring and damper in parallel.

    ``f = c * (s_rel - s_rel0) + d * v_rel``.

    Variables
    ---------
    f : N
        Total force.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.SpringDamper``.
    """

    c = Parameter(unit="N/m", min=0.0, doc="Spring constant")
    d = Parameter(unit="N.s/m", min=0.0, doc="Damping constant")
    s_rel0 = Parameter(0.0, unit="m", doc="Unstretched spring length")
    f_c = Variable(unit="N", doc="Spring force")
    f_d = Variable(unit="N", doc="Damping force")

    def equations(self) -> list:
        return [*super().equations(),
                eq(self.f_c, self.c * (self.s_rel - self.s_rel0)),
                eq(self.f_d, self.d * self.v_rel),
                eq(self.f, self.f_c + self.f_d)]
