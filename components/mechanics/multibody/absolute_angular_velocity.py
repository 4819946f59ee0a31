"""Sensor of the absolute angular velocity of a frame (MSL ``Sensors.AbsoluteAngularVelocity``)."""

from __future__ import annotations

from flexlib import Output, eq

from .frames import resolve1
from .interfaces import PartialAbsoluteSensor

__all__ = ["AbsoluteAngularVelocity"]


class AbsoluteAngularVelocity(PartialAbsoluteSensor):
    """Angular velocity of frame_a with respect to the world; the sensor exerts no load.

    ``w = T_aᵀ w_a`` (``resolve_in_frame="world"``, default) or ``w_a`` (``"frame_a"``), with ``w_a``
    the connector's angular velocity (resolved in frame_a); ``f_a = t_a = 0``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.AbsoluteAngularVelocity``.
    """

    w = Output(unit="rad/s", shape=3, doc="Absolute angular velocity of frame_a")

    def measurement_equations(self) -> list:
        a = self.frame_a
        return [eq(self.w, resolve1(a.T, a.w) if self.resolve_in_frame == "world" else a.w)]
