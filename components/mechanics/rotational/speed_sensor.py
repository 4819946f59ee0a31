"""Ideal sensor of the absolute flange angular velocity."""

from __future__ import annotations

from flexlib import Output, der, eq

from .interfaces import PartialAbsoluteSensor

__all__ = ["SpeedSensor"]


class SpeedSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute angular velocity: ``w = der(flange.phi)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sensors.SpeedSensor``.
    """

    w = Output(unit="rad/s", doc="Absolute angular velocity of the flange")

    def equations(self) -> list:
        return [*super().equations(), eq(self.w, der(self.flange.phi))]
