"""Ideal planetary gear."""

from __future__ import annotations

from flexlib import Component, Parameter, eq

from .interfaces import Flange

__all__ = ["IdealPlanetary"]


class IdealPlanetary(Component):
    """Planetary gear without inertia, elasticity or losses; ``ratio`` is the ring's teeth over the sun's::

        (1 + ratio) carrier.phi = sun.phi + ratio ring.phi
        ring.tau = ratio sun.tau,   carrier.tau = −(1 + ratio) sun.tau

    Connectors
    ----------
    sun, carrier, ring : Flange
        The sun shaft, the planet carrier, the ring gear.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.IdealPlanetary``.
    """

    ratio = Parameter(unit="1", gt=0.0, doc="Number of ring teeth over sun teeth (e.g. 100/50)")
    sun = Flange(doc="Flange of the sun shaft")
    carrier = Flange(doc="Flange of the carrier shaft")
    ring = Flange(doc="Flange of the ring shaft")

    def equations(self) -> list:
        r = self.ratio
        return [eq((1 + r) * self.carrier.phi, self.sun.phi + r * self.ring.phi),
                eq(self.ring.tau, r * self.sun.tau), eq(self.carrier.tau, -(1 + r) * self.sun.tau)]
