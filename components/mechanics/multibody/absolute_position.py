"""Sensor of the absolute position of a frame origin (MSL ``Sensors.AbsolutePosition``)."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Output, eq

from ._resolve import check_resolve_in_frame
from .frames import resolve2
from .interfaces import Frame

__all__ = ["AbsolutePosition"]


class AbsolutePosition(Component):
    """Position vector from the world origin to the origin of frame_a; the sensor exerts no load.

    ``r = r_0,a`` (``resolve_in_frame="world"``, default) or ``T_a r_0,a`` (``"frame_a"``); ``f_a = t_a = 0``.
    No orientation branch.

    Parameters
    ----------
    resolve_in_frame : {"world", "frame_a"}
        Frame in which the output is resolved (structural constructor argument).

    Connectors
    ----------
    frame_a : Frame
        Measured frame.
    r : Output (3,) [m]
        Position of the origin of frame_a, resolved in ``resolve_in_frame``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.AbsolutePosition``
    (no ``frame_resolve`` connector).
    """

    r = Output(unit="m", shape=3, doc="Position of the origin of frame_a")
    frame_a = Frame(doc="Measured frame")

    def __init__(self, resolve_in_frame: str = "world", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("world", "frame_a"))

    def equations(self) -> list:
        a = self.frame_a
        out = a.r_0 if self.resolve_in_frame == "world" else resolve2(a.T, a.r_0)
        return [eq(a.f, 0.0), eq(a.t, 0.0), eq(self.r, out)]
