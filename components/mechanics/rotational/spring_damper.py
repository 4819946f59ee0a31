"""Linear 1D rotational spring and damper in parallel."""

from __future__ import annotations

from flexlib import Parameter, Variable, eq

from .interfaces import PartialCompliantWithRelativeStates

__all__ = ["SpringDamper"]


class SpringDamper(PartialCompliantWithRelativeStates):
    """Linear 1D rotational spring and damper in parallel.

    ``tau = c * (phi_rel - phi_rel0) + d * w_rel``.

    Variables
    ---------
    tau : N.m
        Total torque.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.SpringDamper``.
    """

    c = Parameter(unit="N.m/rad", min=0.0, doc="Spring constant")
    d = Parameter(unit="N.m.s/rad", min=0.0, doc="Damping constant")
    phi_rel0 = Parameter(0.0, unit="rad", doc="Unstretched spring angle")
    tau_c = Variable(unit="N.m", doc="Spring torque")
    tau_d = Variable(unit="N.m", doc="Damping torque")

    def equations(self) -> list:
        return [*super().equations(),
                eq(self.tau_c, self.c * (self.phi_rel - self.phi_rel0)),
                eq(self.tau_d, self.d * self.w_rel),
                eq(self.tau, self.tau_c + self.tau_d)]
