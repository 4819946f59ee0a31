"""Forced movement of a flange according to a reference angle signal."""

from __future__ import annotations

from flexlib import Input, Variable, der, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["Position"]


class Position(PartialOneFlangeAndSupport):
    """Position source: the flange angle follows ``phi_ref`` exactly.

    ``flange.phi - phi_support = phi_ref``. The speed and acceleration of the flange are
    the first and second derivatives of the reference, so the compiler differentiates the
    equations that produce ``phi_ref`` (the reference must be twice differentiable).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sources.Position``
    (``exact = true``).
    """

    phi_ref = Input(unit="rad", doc="Reference angle of the flange relative to the support")
    phi = Variable(unit="rad", doc="Flange angle relative to the support")
    w = Variable(unit="rad/s", doc="Relative angular velocity")
    a = Variable(unit="rad/s2", doc="Relative angular acceleration")

    def equations(self) -> list:
        return [*self.support_equations(),
                eq(self.phi, self.flange.phi - self.phi_support), eq(self.phi, self.phi_ref),
                eq(self.w, der(self.phi)), eq(self.a, der(self.w))]
