"""Sensor of the absolute position of a frame origin (MSL ``Sensors.AbsolutePosition``)."""

from __future__ import annotations

from flexlib import Output, eq

from .frames import resolve2
from .interfaces import PartialAbsoluteSensor

__all__ = ["AbsolutePosition"]


class AbsolutePosition(PartialAbsoluteSensor):
    """Position vector from the world origin to the origin of frame_a; the sensor exerts no load.

    ``r = r_0,a`` (``resolve_in_frame="world"``, default) or ``T_a r_0,a`` (``"frame_a"``); ``f_a = t_a = 0``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.AbsolutePosition``.
    """

    r = Output(unit="m", shape=3, doc="Position of the origin of frame_a")

    def measurement_equations(self) -> list:
        r_0 = self.frame_a.r_0
        return [eq(self.r, r_0 if self.resolve_in_frame == "world" else resolve2(self.frame_a.T, r_0))]
