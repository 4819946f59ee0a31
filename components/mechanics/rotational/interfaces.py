"""Connector and partial models of the 1D rotational library (MSL Rotational.Interfaces).

The partial models hold the topology (which flanges a component has and how their torques
are related); a component derived from one of them adds only its physics.

References
----------
Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Interfaces``.
"""

from __future__ import annotations

from typing import Any

from flexlib import Component, Connector, Flow, Potential, Variable, der, eq
from flexlib.core.options import flag

__all__ = [
    "Flange",
    "PartialAbsoluteSensor",
    "PartialCompliant",
    "PartialCompliantWithRelativeStates",
    "PartialOneFlangeAndSupport",
    "PartialRelativeSensor",
    "PartialTwoFlanges",
    "PartialTwoFlangesAndSupport",
]


class Flange(Connector):
    """1D rotational flange (MSL Rotational.Interfaces.Flange)."""

    phi = Potential(unit="rad", doc="Absolute rotation angle of the flange")
    tau = Flow(unit="N.m", doc="Cut torque in the flange, positive into the component")


def add_support(node: Component, use_support: bool) -> None:
    """The structural option ``use_support`` of ``node``; when on, its ``support`` flange (the housing)."""
    node.use_support = flag(node, "use_support", use_support, structural=True)
    if node.use_support:
        node.support = Flange(doc="Support (housing) flange")


def support_rows(node: Component, reaction: Any) -> list:
    """``phi_support`` of ``node`` from its support flange (0 without one), and the support's torque
    ``reaction``."""
    if not node.use_support:
        return [eq(node.phi_support, 0.0)]
    return [eq(node.phi_support, node.support.phi), eq(node.support.tau, reaction)]


class PartialTwoFlanges(Component):
    """Component with two rotational flanges, ``flange_a`` and ``flange_b``."""

    flange_a = Flange(doc="Flange of the left shaft")
    flange_b = Flange(doc="Flange of the right shaft")


class PartialCompliant(PartialTwoFlanges):
    """Compliant connection of two flanges: ``tau = flange_b.tau = -flange_a.tau``.

    A subclass adds one equation for ``tau`` (MSL Rotational.Interfaces.PartialCompliant).

    Connectors
    ----------
    flange_a, flange_b : Flange
        ``flange_b.tau = tau``, ``flange_a.tau = -tau``.
    """

    phi_rel = Variable(unit="rad", doc="Relative rotation angle, flange_b.phi - flange_a.phi")
    tau = Variable(unit="N.m", doc="Torque between the flanges (= flange_b.tau)")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        return [eq(self.phi_rel, fb.phi - fa.phi), eq(fb.tau, self.tau), eq(fa.tau, -self.tau)]


class PartialCompliantWithRelativeStates(PartialCompliant):
    """Compliant connection with the relative angular velocity ``w_rel = der(phi_rel)``.

    MSL Rotational.Interfaces.PartialCompliantWithRelativeStates, without ``a_rel`` (which
    would force a second differentiation of every damper without being used).
    """

    w_rel = Variable(unit="rad/s", doc="Relative angular velocity, der(phi_rel)")

    def equations(self) -> list:
        return [*super().equations(), eq(self.w_rel, der(self.phi_rel))]


class PartialOneFlangeAndSupport(Component):
    """Component with one flange and an optional support flange.

    With ``use_support=False`` the support is implicitly fixed at angle 0 and its reaction
    torque is not available (MSL PartialElementaryOneFlangeAndSupport2).

    Parameters
    ----------
    use_support : bool
        True if the ``support`` flange is enabled, otherwise implicitly grounded.

    Connectors
    ----------
    support : Flange
        Housing (only if ``use_support``); takes ``-flange.tau``.
    """

    phi_support = Variable(unit="rad", doc="Absolute rotation angle of the support (0 if not used)")
    flange = Flange(doc="Driven flange; ``flange.tau`` is the torque needed to move it")

    def __init__(self, use_support: bool = False, **kw: Any) -> None:
        super().__init__(**kw)
        add_support(self, use_support)

    def support_equations(self) -> list:
        """``phi_support`` from the support (or 0) and the support reaction torque."""
        return support_rows(self, -self.flange.tau)


class PartialTwoFlangesAndSupport(PartialTwoFlanges):
    """Two flanges and an optional support flange (MSL PartialElementaryTwoFlangesAndSupport2).

    Parameters
    ----------
    use_support : bool
        True if the ``support`` flange is enabled, otherwise implicitly grounded.
    """

    phi_support = Variable(unit="rad", doc="Absolute rotation angle of the support (0 if not used)")

    def __init__(self, use_support: bool = False, **kw: Any) -> None:
        super().__init__(**kw)
        add_support(self, use_support)

    def support_equations(self) -> list:
        """``phi_support`` from the support (or 0) and the support reaction torque."""
        return support_rows(self, -self.flange_a.tau - self.flange_b.tau)


class PartialAbsoluteSensor(Component):
    """Sensor measuring an absolute flange quantity; it exerts no torque on the flange."""

    flange = Flange(doc="Measured flange (no torque is exerted on it)")

    def equations(self) -> list:
        return [eq(self.flange.tau, 0.0)]


class PartialRelativeSensor(PartialTwoFlanges):
    """Sensor between two flanges; its torques balance: ``flange_a.tau + flange_b.tau = 0``.

    Connectors
    ----------
    flange_a, flange_b : Flange
        Measured flanges (no torque is exerted on them).
    """

    def equations(self) -> list:
        return [eq(self.flange_a.tau + self.flange_b.tau, 0.0)]
