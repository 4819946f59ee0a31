"""Ideal sensor of the force transmitted between two flanges."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialTwoFlanges

__all__ = ["ForceSensor"]


class ForceSensor(PartialTwoFlanges):
    """Ideal force sensor: rigid (``flange_a.s = flange_b.s``), ``f = flange_a.f``.

    ``f`` is the force transmitted from ``flange_a`` to ``flange_b``.

    Connectors
    ----------
    flange_a, flange_b : Flange
        Rigidly connected flanges, ``flange_b.f = -flange_a.f``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sensors.ForceSensor``.
    """

    f = Output(unit="N", doc="Force transmitted from flange_a to flange_b")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        return [eq(fa.s, fb.s), eq(fa.f, self.f), eq(fb.f, -self.f)]
