"""Sensor of the relative position of two frame origins (MSL ``Sensors.RelativePosition``)."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Output, eq

from ._resolve import check_resolve_in_frame
from .frames import resolve2
from .interfaces import Frame

__all__ = ["RelativePosition"]


class RelativePosition(Component):
    """Vector from the origin of frame_a to the origin of frame_b; the sensor exerts no load.

    ``r_rel_0 = r_0,b − r_0,a`` (world); output ``r_rel = T_a r_rel_0`` (``resolve_in_frame="frame_a"``,
    default), ``T_b r_rel_0`` (``"frame_b"``) or ``r_rel_0`` (``"world"``); ``f_a = f_b = 0``,
    ``t_a = t_b = 0``. No orientation branch: the frames are independent.

    Parameters
    ----------
    resolve_in_frame : {"frame_a", "frame_b", "world"}
        Frame in which the output is resolved (structural constructor argument).

    Connectors
    ----------
    frame_a, frame_b : Frame
        Measured frames.
    r_rel : Output (3,) [m]
        Relative position resolved in ``resolve_in_frame``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.RelativePosition``
    (no ``frame_resolve`` connector).
    """

    r_rel = Output(unit="m", shape=3, doc="Position of frame_b's origin relative to frame_a's origin")
    frame_a = Frame(doc="Reference frame")
    frame_b = Frame(doc="Measured frame")

    def __init__(self, resolve_in_frame: str = "frame_a", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("frame_a", "frame_b", "world"))

    def equations(self) -> list:
        a, b = self.frame_a, self.frame_b
        r_rel_0 = b.r_0 - a.r_0
        if self.resolve_in_frame == "frame_a":
            out = resolve2(a.T, r_rel_0)
        elif self.resolve_in_frame == "frame_b":
            out = resolve2(b.T, r_rel_0)
        else:
            out = r_rel_0
        return [eq(a.f, 0.0), eq(a.t, 0.0), eq(b.f, 0.0), eq(b.t, 0.0), eq(self.r_rel, out)]
