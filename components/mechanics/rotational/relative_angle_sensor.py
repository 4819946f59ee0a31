"""Ideal sensor of the relative angle between two flanges."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialRelativeSensor

__all__ = ["RelativeAngleSensor"]


class RelativeAngleSensor(PartialRelativeSensor):
    """Ideal sensor of the relative angle: ``phi_rel = flange_b.phi - flange_a.phi``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sensors.RelAngleSensor``.
    """

    phi_rel = Output(unit="rad", doc="Relative angle flange_b.phi - flange_a.phi")

    def equations(self) -> list:
        return [*super().equations(), eq(self.flange_a.tau, 0.0),
                eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi)]
