"""Ideal sensor of the absolute flange velocity."""

from __future__ import annotations

from flexlib import Output, der, eq

from .interfaces import PartialAbsoluteSensor

__all__ = ["SpeedSensor"]


class SpeedSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute velocity: ``v = der(flange.s)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sensors.SpeedSensor``.
    """

    v = Output(unit="m/s", doc="Absolute velocity of the flange")

    def equations(self) -> list:
        return [*super().equations(), eq(self.v, der(self.flange.s))]
