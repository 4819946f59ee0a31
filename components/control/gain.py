"""Output the product of a gain and the input signal."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialSISO

__all__ = ["Gain"]


class Gain(PartialSISO):
    """Gain: ``y = k * u``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Math.Gain``.
    """

    k = Parameter(unit="1", doc="Gain value multiplied with the input signal")

    def equations(self) -> list:
        return [eq(self.y, self.k * self.u)]
