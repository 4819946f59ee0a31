"""Input signal acting as external torque on a flange."""

from __future__ import annotations

from flexlib import Input, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["Torque"]


class Torque(PartialOneFlangeAndSupport):
    """Torque source: the input signal ``tau`` drives the flange, ``flange.tau = -tau``.

    A positive ``tau`` accelerates the flange in the positive direction; the reaction acts
    on the support.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sources.Torque``.
    """

    tau = Input(unit="N.m", doc="Accelerating torque acting at the flange")

    def equations(self) -> list:
        return [*self.support_equations(), eq(self.flange.tau, -self.tau)]
