"""Constant output signal."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialSO

__all__ = ["Constant"]


class Constant(PartialSO):
    """Constant output signal: ``y = k``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.Constant``.
    """

    k = Parameter(unit="1", doc="Constant output value")

    def equations(self) -> list:
        return [eq(self.y, self.k)]
