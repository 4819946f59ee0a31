"""Constant torque acting on a flange, independent of its speed."""

from __future__ import annotations

from flexlib import Parameter, Variable, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["ConstantTorque"]


class ConstantTorque(PartialOneFlangeAndSupport):
    """Constant torque source: ``tau = tau_constant`` drives the flange, ``flange.tau = −tau``, at any speed.

    A positive ``tau_constant`` accelerates the flange in the positive direction; a negative one acts as a load
    in the positive direction of rotation. The reaction acts on the support.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sources.ConstantTorque`` (its relative speed
    ``w`` is not a variable here: read the flange's, e.g. an inertia's ``w``).
    """

    tau_constant = Parameter(unit="N.m", doc="Constant torque (negative: a load in the positive direction)")
    tau = Variable(unit="N.m", doc="Accelerating torque acting at the flange (= -flange.tau)")

    def equations(self) -> list:
        return [*self.support_equations(), eq(self.tau, self.tau_constant), eq(self.flange.tau, -self.tau)]
