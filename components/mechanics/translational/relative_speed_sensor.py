"""Ideal sensor of the relative velocity of two flanges."""

from __future__ import annotations

from flexlib import Output, Variable, der, eq

from .interfaces import PartialRelativeSensor

__all__ = ["RelativeSpeedSensor"]


class RelativeSpeedSensor(PartialRelativeSensor):
    """Ideal sensor of the relative velocity: ``v_rel = der(flange_b.s - flange_a.s)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sensors.RelSpeedSensor``.
    """

    s_rel = Variable(unit="m", doc="Relative position flange_b.s - flange_a.s")
    v_rel = Output(unit="m/s", doc="Relative velocity der(flange_b.s) - der(flange_a.s)")

    def equations(self) -> list:
        return [*super().equations(), eq(self.flange_a.f, 0.0),
                eq(self.s_rel, self.flange_b.s - self.flange_a.s), eq(self.v_rel, der(self.s_rel))]
