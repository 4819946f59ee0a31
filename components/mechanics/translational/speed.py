"""Forced movement of a flange according to a reference velocity signal."""

from __future__ import annotations

from flexlib import Input, Variable, der, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["Speed"]


class Speed(PartialOneFlangeAndSupport):
    """Speed source: the flange velocity follows ``v_ref`` exactly.

    ``v = der(flange.s - s_support) = v_ref``; the position is the integral of the
    reference and needs an initial condition (e.g. ``init={"s": 0.0}``).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sources.Speed``
    (``exact = true``).
    """

    v_ref = Input(unit="m/s", doc="Reference velocity of the flange relative to the support")
    s = Variable(unit="m", doc="Flange position relative to the support")
    v = Variable(unit="m/s", doc="Relative velocity")
    a = Variable(unit="m/s2", doc="Relative acceleration")

    def equations(self) -> list:
        return [*self.support_equations(),
                eq(self.s, self.flange.s - self.s_support), eq(self.v, der(self.s)),
                eq(self.v, self.v_ref), eq(self.a, der(self.v))]
