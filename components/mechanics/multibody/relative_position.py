"""Sensor of the relative position of two frame origins (MSL ``Sensors.RelativePosition``)."""

from __future__ import annotations

from typing import Any

from flexlib import Output, eq

from .frames import resolve2
from .interfaces import PartialRelativeSensor

__all__ = ["RelativePosition"]


class RelativePosition(PartialRelativeSensor):
    """Vector from the origin of frame_a to the origin of frame_b; the sensor exerts no load.

    ``r_rel_0 = r_0,b − r_0,a`` (world); output ``r_rel = T_a r_rel_0`` (``resolve_in_frame="frame_a"``,
    default), ``T_b r_rel_0`` (``"frame_b"``) or ``r_rel_0`` (``"world"``); ``f_a = f_b = 0``,
    ``t_a = t_b = 0``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.RelativePosition``.
    """

    r_rel = Output(unit="m", shape=3, doc="Position of frame_b's origin relative to frame_a's origin")

    def measurement_equations(self, r_rel_0: Any) -> list:
        a, b = self.frame_a, self.frame_b
        return [eq(self.r_rel, self.resolved(resolve2(a.T, r_rel_0), resolve2(b.T, r_rel_0), r_rel_0))]
