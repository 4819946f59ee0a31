"""Product of two input signals."""

from __future__ import annotations

from flexlib import eq

from .interfaces import PartialSI2SO

__all__ = ["Product"]


class Product(PartialSI2SO):
    """Product of two inputs: ``y = u1 * u2``.

    Connectors
    ----------
    u1, u2 : Input [1]
        Input signals.
    y : Output [1]
        Product of the inputs.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Math.Product``.
    """

    def equations(self) -> list:
        return [eq(self.y, self.u1 * self.u2)]
