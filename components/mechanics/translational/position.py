"""Forced movement of a flange according to a reference position signal."""

from __future__ import annotations

from flexlib import Input, Variable, der, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["Position"]


class Position(PartialOneFlangeAndSupport):
    """Position source: the flange position follows ``s_ref`` exactly.

    ``flange.s - s_support = s_ref``. The velocity and acceleration of the flange are the
    first and second derivatives of the reference, so the compiler differentiates the
    equations that produce ``s_ref`` (the reference must be twice differentiable).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sources.Position``
    (``exact = true``).
    """

    s_ref = Input(unit="m", doc="Reference position of the flange relative to the support")
    s = Variable(unit="m", doc="Flange position relative to the support")
    v = Variable(unit="m/s", doc="Relative velocity")
    a = Variable(unit="m/s2", doc="Relative acceleration")

    def equations(self) -> list:
        return [*self.support_equations(),
                eq(self.s, self.flange.s - self.s_support), eq(self.s, self.s_ref),
                eq(self.v, der(self.s)), eq(self.a, der(self.v))]
