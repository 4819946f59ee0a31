"""Massless rigid rod."""

from __future__ import annotations

from flexlib import eq

from .interfaces import PartialRigid

__all__ = ["Rod"]


class Rod(PartialRigid):
    """Massless rod of length ``L``: ``flange_b.s = flange_a.s + L``, ``flange_a.f + flange_b.f = 0``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.Rod``.
    """

    def equations(self) -> list:
        return [*super().equations(), eq(self.flange_a.f + self.flange_b.f, 0.0)]
