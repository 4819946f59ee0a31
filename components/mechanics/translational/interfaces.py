"""Connector and partial models of the 1D translational library (MSL Translational.Interfaces).

The partial models hold the topology (which flanges a component has and how their forces
are related); a component derived from one of them adds only its physics.

References
----------
Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Interfaces``.
"""

from __future__ import annotations

from typing import Any

from flexlib import Component, Connector, Flow, Parameter, Potential, Variable, der, eq
from flexlib.core.options import flag

__all__ = [
    "Flange",
    "PartialAbsoluteSensor",
    "PartialCompliant",
    "PartialCompliantWithRelativeStates",
    "PartialOneFlangeAndSupport",
    "PartialRelativeSensor",
    "PartialRigid",
    "PartialTwoFlanges",
    "PartialTwoFlangesAndSupport",
]


class Flange(Connector):
    """1D translational flange (MSL Translational.Interfaces.Flange)."""

    s = Potential(unit="m", doc="Absolute position of the flange")
    f = Flow(unit="N", doc="Cut force in the flange, positive into the component")


def add_support(node: Component, use_support: bool) -> None:
    """The structural option ``use_support`` of ``node``; when on, its ``support`` flange (the housing)."""
    node.use_support = flag(node, "use_support", use_support, structural=True)
    if node.use_support:
        node.support = Flange(doc="Support (housing) flange")


def support_rows(node: Component, reaction: Any) -> list:
    """``s_support`` of ``node`` from its support flange (0 without one), and the support's force ``reaction``."""
    if not node.use_support:
        return [eq(node.s_support, 0.0)]
    return [eq(node.s_support, node.support.s), eq(node.support.f, reaction)]


class PartialTwoFlanges(Component):
    """Component with two translational flanges, ``flange_a`` and ``flange_b``."""

    flange_a = Flange(doc="Left flange")
    flange_b = Flange(doc="Right flange")


class PartialRigid(PartialTwoFlanges):
    """Rigid component of length ``L`` whose centre is at ``s``.

    ``flange_a.s = s - L/2`` and ``flange_b.s = s + L/2`` (MSL PartialRigid).
    """

    L = Parameter(0.0, unit="m", min=0.0, doc="Length of the component, from flange_a to flange_b")
    s = Variable(unit="m", state_select="prefer", doc="Absolute position of the centre of the component")

    def equations(self) -> list:
        return [eq(self.flange_a.s, self.s - self.L / 2), eq(self.flange_b.s, self.s + self.L / 2)]


class PartialCompliant(PartialTwoFlanges):
    """Compliant connection of two flanges: ``f = flange_b.f = -flange_a.f``.

    A subclass adds one equation for ``f`` (MSL Translational.Interfaces.PartialCompliant).

    Connectors
    ----------
    flange_a, flange_b : Flange
        ``flange_b.f = f``, ``flange_a.f = -f``.
    """

    s_rel = Variable(unit="m", doc="Relative distance, flange_b.s - flange_a.s")
    f = Variable(unit="N", doc="Force between the flanges (= flange_b.f)")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        return [eq(self.s_rel, fb.s - fa.s), eq(fb.f, self.f), eq(fa.f, -self.f)]


class PartialCompliantWithRelativeStates(PartialCompliant):
    """Compliant connection with the relative velocity ``v_rel = der(s_rel)``.

    MSL Translational.Interfaces.PartialCompliantWithRelativeStates, without ``a_rel``.
    """

    v_rel = Variable(unit="m/s", doc="Relative velocity, der(s_rel)")

    def equations(self) -> list:
        return [*super().equations(), eq(self.v_rel, der(self.s_rel))]


class PartialOneFlangeAndSupport(Component):
    """Component with one flange and an optional support flange.

    With ``use_support=False`` the support is implicitly fixed at position 0 and its
    reaction force is not available (MSL PartialElementaryOneFlangeAndSupport2).

    Parameters
    ----------
    use_support : bool
        True if the ``support`` flange is enabled, otherwise implicitly grounded.

    Connectors
    ----------
    support : Flange
        Housing (only if ``use_support``); takes ``-flange.f``.
    """

    s_support = Variable(unit="m", doc="Absolute position of the support (0 if not used)")
    flange = Flange(doc="Driven flange; ``flange.f`` is the force needed to move it")

    def __init__(self, use_support: bool = False, **kw: Any) -> None:
        super().__init__(**kw)
        add_support(self, use_support)

    def support_equations(self) -> list:
        """``s_support`` from the support (or 0) and the support reaction force."""
        return support_rows(self, -self.flange.f)


class PartialTwoFlangesAndSupport(PartialTwoFlanges):
    """Two flanges and an optional support flange (MSL PartialElementaryTwoFlangesAndSupport2).

    Parameters
    ----------
    use_support : bool
        True if the ``support`` flange is enabled, otherwise implicitly grounded.
    """

    s_support = Variable(unit="m", doc="Absolute position of the support (0 if not used)")

    def __init__(self, use_support: bool = False, **kw: Any) -> None:
        super().__init__(**kw)
        add_support(self, use_support)

    def support_equations(self) -> list:
        """``s_support`` from the support (or 0) and the support reaction force."""
        return support_rows(self, -self.flange_a.f - self.flange_b.f)


class PartialAbsoluteSensor(Component):
    """Sensor measuring an absolute flange quantity; it exerts no force on the flange."""

    flange = Flange(doc="Measured flange (no force is exerted on it)")

    def equations(self) -> list:
        return [eq(self.flange.f, 0.0)]


class PartialRelativeSensor(PartialTwoFlanges):
    """Sensor between two flanges; its forces balance: ``flange_a.f + flange_b.f = 0``.

    Connectors
    ----------
    flange_a, flange_b : Flange
        Measured flanges (no force is exerted on them).
    """

    def equations(self) -> list:
        return [eq(self.flange_a.f + self.flange_b.f, 0.0)]
