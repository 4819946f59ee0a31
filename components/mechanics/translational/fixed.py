"""Flange fixed in the housing at a given position."""

from __future__ import annotations

from flexlib import Component, Parameter, eq

from .interfaces import Flange

__all__ = ["Fixed"]


class Fixed(Component):
    """Flange fixed in the housing at a given position: ``flange.s = s0``.

    Connectors
    ----------
    flange : Flange
        Fixed flange; ``flange.f`` is the reaction force of the housing.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.Fixed``.
    """

    s0 = Parameter(0.0, unit="m", doc="Fixed offset position of the housing")
    flange = Flange(doc="Flange fixed in the housing")

    def equations(self) -> list:
        return [eq(self.flange.s, self.s0)]
