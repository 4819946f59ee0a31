"""Ideal sensor of the absolute flange angular acceleration."""

from __future__ import annotations

from flexlib import Output, Variable, der, eq

from .interfaces import PartialAbsoluteSensor

__all__ = ["AccSensor"]


class AccSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute angular acceleration: ``w = der(flange.phi)``, ``a = der(w)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sensors.AccSensor``.
    """

    w = Variable(unit="rad/s", doc="Absolute angular velocity of the flange")
    a = Output(unit="rad/s2", doc="Absolute angular acceleration of the flange")

    def equations(self) -> list:
        return [*super().equations(), eq(self.w, der(self.flange.phi)), eq(self.a, der(self.w))]
