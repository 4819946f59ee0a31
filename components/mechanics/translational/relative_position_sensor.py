"""Ideal sensor of the relative position of two flanges."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialRelativeSensor

__all__ = ["RelativePositionSensor"]


class RelativePositionSensor(PartialRelativeSensor):
    """Ideal sensor of the relative position: ``s_rel = flange_b.s - flange_a.s``.

    References
    ----------
    Modelica Standard Library 4.0,
    ``Modelica.Mechanics.Translational.Sensors.RelPositionSensor``.
    """

    s_rel = Output(unit="m", doc="Relative position flange_b.s - flange_a.s")

    def equations(self) -> list:
        return [*super().equations(), eq(self.flange_a.f, 0.0),
                eq(self.s_rel, self.flange_b.s - self.flange_a.s)]
