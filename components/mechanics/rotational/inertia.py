"""1D rotational component with inertia."""

from __future__ import annotations

from flexlib import Parameter, Variable, der, eq

from .interfaces import PartialTwoFlanges

__all__ = ["Inertia"]


class Inertia(PartialTwoFlanges):
    """1D rotational component with inertia and two rigidly connected flanges.

    Newton–Euler about the shaft axis: ``J * der(w) = flange_a.tau + flange_b.tau`` with
    ``w = der(phi)`` and ``phi = flange_a.phi = flange_b.phi``.

    Connectors
    ----------
    flange_a, flange_b : Flange
        Rigidly connected flanges; torques positive into the inertia.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.Inertia``.
    """

    J = Parameter(unit="kg.m2", min=0.0, doc="Moment of inertia about the rotation axis")
    phi = Variable(unit="rad", state_select="prefer", doc="Absolute rotation angle (preferred state)")
    w = Variable(unit="rad/s", state_select="prefer", doc="Absolute angular velocity (preferred state)")
    a = Variable(unit="rad/s2", doc="Absolute angular acceleration")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        return [eq(self.phi, fa.phi), eq(self.phi, fb.phi),
                eq(der(self.phi), self.w), eq(der(self.w), self.a),
                eq(self.J * self.a, fa.tau + fb.tau)]
