"""Weighted sum of two input signals."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialSI2SO

__all__ = ["Add"]


class Add(PartialSI2SO):
    """Weighted sum of two inputs: ``y = k1 * u1 + k2 * u2``.

    Connectors
    ----------
    u1, u2 : Input [1]
        Input signals.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Math.Add``.
    """

    k1 = Parameter(1.0, unit="1", doc="Gain of input signal 1")
    k2 = Parameter(1.0, unit="1", doc="Gain of input signal 2")

    def equations(self) -> list:
        return [eq(self.y, self.k1 * self.u1 + self.k2 * self.u2)]
