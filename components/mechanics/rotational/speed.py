"""Forced movement of a flange according to a reference angular velocity signal."""

from __future__ import annotations

from flexlib import Input, Variable, der, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["Speed"]


class Speed(PartialOneFlangeAndSupport):
    """Speed source: the flange angular velocity follows ``w_ref`` exactly.

    ``w = der(flange.phi - phi_support) = w_ref``; the angle is the integral of the
    reference and needs an initial condition (e.g. ``init={"phi": 0.0}``).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sources.Speed``
    (``exact = true``).
    """

    w_ref = Input(unit="rad/s", doc="Reference angular velocity of the flange relative to the support")
    phi = Variable(unit="rad", doc="Flange angle relative to the support")
    w = Variable(unit="rad/s", doc="Relative angular velocity")
    a = Variable(unit="rad/s2", doc="Relative angular acceleration")

    def equations(self) -> list:
        return [*self.support_equations(),
                eq(self.phi, self.flange.phi - self.phi_support), eq(self.w, der(self.phi)),
                eq(self.w, self.w_ref), eq(self.a, der(self.w))]
