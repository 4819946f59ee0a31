"""Ideal sensor of the torque transmitted between two flanges."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialTwoFlanges

__all__ = ["TorqueSensor"]


class TorqueSensor(PartialTwoFlanges):
    """Ideal torque sensor: rigid (``flange_a.phi = flange_b.phi``), ``tau = flange_a.tau``.

    ``tau`` is the torque transmitted from ``flange_a`` to ``flange_b``.

    Connectors
    ----------
    flange_a, flange_b : Flange
        Rigidly connected flanges, ``flange_b.tau = -flange_a.tau``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sensors.TorqueSensor``.
    """

    tau = Output(unit="N.m", doc="Torque transmitted from flange_a to flange_b")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        return [eq(fa.phi, fb.phi), eq(fa.tau, self.tau), eq(fb.tau, -self.tau)]
