"""Ideal sensor of the absolute flange angle."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialAbsoluteSensor

__all__ = ["AngleSensor"]


class AngleSensor(PartialAbsoluteSensor):
    """Ideal sensor of the absolute flange angle: ``phi = flange.phi``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sensors.AngleSensor``.
    """

    phi = Output(unit="rad", doc="Absolute angle of the flange")

    def equations(self) -> list:
        return [*super().equations(), eq(self.phi, self.flange.phi)]
