"""Flange fixed in the housing at a given angle."""

from __future__ import annotations

from flexlib import Component, Parameter, eq

from .interfaces import Flange

__all__ = ["Fixed"]


class Fixed(Component):
    """Flange fixed in the housing at a given angle: ``flange.phi = phi0``.

    Connectors
    ----------
    flange : Flange
        Fixed flange; ``flange.tau`` is the reaction torque of the housing.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.Fixed``.
    """

    phi0 = Parameter(0.0, unit="rad", doc="Fixed offset angle of the housing")
    flange = Flange(doc="Flange fixed in the housing")

    def equations(self) -> list:
        return [eq(self.flange.phi, self.phi0)]
