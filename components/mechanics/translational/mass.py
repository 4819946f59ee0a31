"""Sliding mass with inertia."""

from __future__ import annotations

from flexlib import Parameter, Variable, der, eq

from .interfaces import PartialRigid

__all__ = ["Mass"]


class Mass(PartialRigid):
    """Sliding mass with inertia: ``m * der(v) = flange_a.f + flange_b.f``, ``v = der(s)``.

    Connectors
    ----------
    flange_a, flange_b : Flange
        Flanges at ``s - L/2`` and ``s + L/2``; forces positive into the mass.

    Variables
    ---------
    s : m
        Absolute position of the centre of the mass (preferred state).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.Mass``.
    """

    m = Parameter(unit="kg", min=0.0, doc="Mass of the sliding mass")
    v = Variable(unit="m/s", state_select="prefer", doc="Absolute velocity (preferred state)")
    a = Variable(unit="m/s2", doc="Absolute acceleration")

    def equations(self) -> list:
        return [*super().equations(), eq(der(self.s), self.v), eq(der(self.v), self.a),
                eq(self.m * self.a, self.flange_a.f + self.flange_b.f)]
