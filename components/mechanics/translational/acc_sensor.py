"""Ideal sensor of the absolute flange acceleration."""

from __future__ import annotations

from flexlib import Output, Variable, der, eq

from .interfaces import PartialAbsoluteSensor

__all__ = ["AccSensor"]


class AccSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute acceleration: ``v = der(flange.s)``, ``a = der(v)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sensors.AccSensor``.
    """

    v = Variable(unit="m/s", doc="Absolute velocity of the flange")
    a = Output(unit="m/s2", doc="Absolute acceleration of the flange")

    def equations(self) -> list:
        return [*super().equations(), eq(self.v, der(self.flange.s)), eq(self.a, der(self.v))]
