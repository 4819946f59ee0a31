"""Sensor of the absolute velocity of a frame origin (MSL ``Sensors.AbsoluteVelocity``)."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Output, der, eq

from ._resolve import check_resolve_in_frame
from .frames import resolve2
from .interfaces import Frame

__all__ = ["AbsoluteVelocity"]


class AbsoluteVelocity(Component):
    """Velocity of the origin of frame_a with respect to the world; the sensor exerts no load.

    ``v_0 = der(r_0,a)`` (world); output ``v = v_0`` (``resolve_in_frame="world"``, default) or
    ``T_a v_0`` (``"frame_a"``); ``f_a = t_a = 0``. No orientation branch.

    Parameters
    ----------
    resolve_in_frame : {"world", "frame_a"}
        Frame in which the output is resolved (structural constructor argument).

    Connectors
    ----------
    frame_a : Frame
        Measured frame.
    v : Output (3,) [m/s]
        Absolute velocity of the origin of frame_a, resolved in ``resolve_in_frame``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.AbsoluteVelocity``
    (no ``frame_resolve`` connector).
    """

    v = Output(unit="m/s", shape=3, doc="Absolute velocity of the origin of frame_a")
    frame_a = Frame(doc="Measured frame")

    def __init__(self, resolve_in_frame: str = "world", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("world", "frame_a"))

    def equations(self) -> list:
        a = self.frame_a
        v_0 = der(a.r_0)
        out = v_0 if self.resolve_in_frame == "world" else resolve2(a.T, v_0)
        return [eq(a.f, 0.0), eq(a.t, 0.0), eq(self.v, out)]
