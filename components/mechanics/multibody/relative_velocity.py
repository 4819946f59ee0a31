"""Sensor of the relative velocity of two frame origins (MSL ``Sensors.RelativeVelocity``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Component, Output, der, eq

from ._resolve import check_resolve_in_frame
from .frames import resolve1, resolve2
from .interfaces import Frame

__all__ = ["RelativeVelocity"]


class RelativeVelocity(Component):
    """Velocity of the origin of frame_b relative to frame_a, as seen from frame_a; exerts no load.

    As in MSL the relative position is differentiated in frame_a, ``v_rel_a = der(T_a (r_0,b − r_0,a))``
    (written ``T_a der(r_rel_0) − w_a × (T_a r_rel_0)`` with ``der(T_a) = −[w_a×] T_a``), so a point fixed
    in frame_a's body has ``v_rel = 0`` however frame_a moves; this is *not* ``der(r_0,b − r_0,a)`` unless
    frame_a does not rotate. The vector is then resolved: ``v_rel = v_rel_a`` (``resolve_in_frame="frame_a"``,
    default), ``T_b T_aᵀ v_rel_a`` (``"frame_b"``) or ``T_aᵀ v_rel_a`` (``"world"``). ``f = t = 0`` at both
    frames; no orientation branch.

    Parameters
    ----------
    resolve_in_frame : {"frame_a", "frame_b", "world"}
        Frame in which the output is resolved (structural constructor argument).

    Connectors
    ----------
    frame_a, frame_b : Frame
        Reference and measured frame.
    v_rel : Output (3,) [m/s]
        Relative velocity resolved in ``resolve_in_frame``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.RelativeVelocity``
    (no ``frame_resolve`` connector).
    """

    v_rel = Output(unit="m/s", shape=3, doc="Velocity of frame_b's origin relative to frame_a, seen in frame_a")
    frame_a = Frame(doc="Reference frame")
    frame_b = Frame(doc="Measured frame")

    def __init__(self, resolve_in_frame: str = "frame_a", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("frame_a", "frame_b", "world"))

    def equations(self) -> list:
        a, b = self.frame_a, self.frame_b
        r_rel_0 = b.r_0 - a.r_0
        v_rel_a = resolve2(a.T, der(r_rel_0)) - ca.cross(a.w, resolve2(a.T, r_rel_0))
        if self.resolve_in_frame == "frame_a":
            out = v_rel_a
        elif self.resolve_in_frame == "frame_b":
            out = resolve2(b.T, resolve1(a.T, v_rel_a))
        else:
            out = resolve1(a.T, v_rel_a)
        return [eq(a.f, 0.0), eq(a.t, 0.0), eq(b.f, 0.0), eq(b.t, 0.0), eq(self.v_rel, out)]
