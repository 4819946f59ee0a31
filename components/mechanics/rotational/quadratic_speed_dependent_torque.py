"""Torque growing with the square of the speed (a fan, a pump, air drag)."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, Variable, der, eq, no_event
from flexlib.core.options import flag

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["QuadraticSpeedDependentTorque"]


class QuadraticSpeedDependentTorque(PartialOneFlangeAndSupport):
    """Torque ``tau = tau_nominal (w / w_nominal)²`` on the flange (``flange.tau = −tau``), ``w`` the flange's speed
    relative to the support; with ``torque_direction=False`` it changes sign with ``w`` (``… |w| w / w_nominal²``,
    once continuously differentiable: no event).

    Parameters
    ----------
    torque_direction : bool
        True (MSL's default): the same direction of torque in both directions of rotation (structural).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sources.QuadraticSpeedDependentTorque``.
    """

    tau_nominal = Parameter(unit="N.m", doc="Nominal torque (negative: a load in the positive direction)")
    w_nominal = Parameter(unit="rad/s", gt=0.0, doc="Nominal speed")
    phi = Variable(unit="rad", doc="Angle of the flange relative to the support")
    w = Variable(unit="rad/s", doc="Angular velocity of the flange relative to the support")
    tau = Variable(unit="N.m", doc="Accelerating torque acting at the flange (= -flange.tau)")

    def __init__(self, torque_direction: bool = True, **kw: Any) -> None:
        super().__init__(**kw)
        self.torque_direction = flag(self, "torque_direction", torque_direction, structural=True)

    def equations(self) -> list:
        x = self.w / self.w_nominal
        law = x**2 if self.torque_direction else no_event(self.w >= 0, x**2, -(x**2))
        return [*self.support_equations(), eq(self.phi, self.flange.phi - self.phi_support),
                eq(self.w, der(self.phi)), eq(self.flange.tau, -self.tau), eq(self.tau, self.tau_nominal * law)]
