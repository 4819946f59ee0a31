"""Ideal sensor of the absolute flange position."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialAbsoluteSensor

__all__ = ["PositionSensor"]


class PositionSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute flange position: ``s = flange.s``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sensors.PositionSensor``.
    """

    s = Output(unit="m", doc="Absolute position of the flange")

    def equations(self) -> list:
        return [*super().equations(), eq(self.s, self.flange.s)]
