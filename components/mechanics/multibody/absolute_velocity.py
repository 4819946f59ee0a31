"""Sensor of the absolute velocity of a frame origin (MSL ``Sensors.AbsoluteVelocity``)."""

from __future__ import annotations

from flexlib import Output, der, eq

from .frames import resolve2
from .interfaces import PartialAbsoluteSensor

__all__ = ["AbsoluteVelocity"]


class AbsoluteVelocity(PartialAbsoluteSensor):
    """Velocity of the origin of frame_a with respect to the world; the sensor exerts no load.

    ``v_0 = der(r_0,a)`` (world); output ``v = v_0`` (``resolve_in_frame="world"``, default) or
    ``T_a v_0`` (``"frame_a"``); ``f_a = t_a = 0``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.AbsoluteVelocity``.
    """

    v = Output(unit="m/s", shape=3, doc="Absolute velocity of the origin of frame_a")

    def measurement_equations(self) -> list:
        v_0 = der(self.frame_a.r_0)
        return [eq(self.v, v_0 if self.resolve_in_frame == "world" else resolve2(self.frame_a.T, v_0))]
