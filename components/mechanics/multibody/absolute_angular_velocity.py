"""Sensor of the absolute angular velocity of a frame (MSL ``Sensors.AbsoluteAngularVelocity``)."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Output, eq

from ._resolve import check_resolve_in_frame
from .frames import resolve1
from .interfaces import Frame

__all__ = ["AbsoluteAngularVelocity"]


class AbsoluteAngularVelocity(Component):
    """Angular velocity of frame_a with respect to the world; the sensor exerts no load.

    ``w = T_aᵀ w_a`` (``resolve_in_frame="world"``, default) or ``w_a`` (``"frame_a"``), with ``w_a``
    the connector's angular velocity (resolved in frame_a); ``f_a = t_a = 0``. No orientation branch.

    Parameters
    ----------
    resolve_in_frame : {"world", "frame_a"}
        Frame in which the output is resolved (structural constructor argument).

    Connectors
    ----------
    frame_a : Frame
        Measured frame.
    w : Output (3,) [rad/s]
        Absolute angular velocity of frame_a, resolved in ``resolve_in_frame``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.AbsoluteAngularVelocity``
    (no ``frame_resolve`` connector).
    """

    w = Output(unit="rad/s", shape=3, doc="Absolute angular velocity of frame_a")
    frame_a = Frame(doc="Measured frame")

    def __init__(self, resolve_in_frame: str = "world", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("world", "frame_a"))

    def equations(self) -> list:
        a = self.frame_a
        out = resolve1(a.T, a.w) if self.resolve_in_frame == "world" else a.w
        return [eq(a.f, 0.0), eq(a.t, 0.0), eq(self.w, out)]
