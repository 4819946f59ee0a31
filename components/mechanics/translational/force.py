"""Input signal acting as external force on a flange."""

from __future__ import annotations

from flexlib import Input, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["Force"]


class Force(PartialOneFlangeAndSupport):
    """Force source: the input signal ``f`` drives the flange, ``flange.f = -f``.

    A positive ``f`` accelerates the flange in the positive direction; the reaction acts on
    the support.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sources.Force``.
    """

    f = Input(unit="N", doc="Driving force acting at the flange")

    def equations(self) -> list:
        return [*self.support_equations(), eq(self.flange.f, -self.f)]
