"""Ideal sensor of the relative angular velocity of two flanges."""

from __future__ import annotations

from flexlib import Output, Variable, der, eq

from .interfaces import PartialRelativeSensor

__all__ = ["RelativeSpeedSensor"]


class RelativeSpeedSensor(PartialRelativeSensor):
    """Ideal sensor of the relative angular velocity: ``w_rel = der(flange_b.phi - flange_a.phi)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sensors.RelSpeedSensor``.
    """

    phi_rel = Variable(unit="rad", doc="Relative angle flange_b.phi - flange_a.phi")
    w_rel = Output(unit="rad/s", doc="Relative angular velocity der(flange_b.phi) - der(flange_a.phi)")

    def equations(self) -> list:
        return [*super().equations(), eq(self.flange_a.tau, 0.0),
                eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi), eq(self.w_rel, der(self.phi_rel))]
