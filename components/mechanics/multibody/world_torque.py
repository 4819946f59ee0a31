"""External torque acting on a frame, given by a signal (MSL ``Forces.WorldTorque``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Component, Input, eq

from ._resolve import check_resolve_in_frame
from .interfaces import Frame

__all__ = ["WorldTorque"]


class WorldTorque(Component):
    """The input vector ``torque`` acts on what is attached at frame_b; no force.

    ``resolve_in_frame="world"`` (default): the torque is given in world coordinates,
    ``t_b = −T_b·torque``; ``"frame_b"``: it is given in frame_b and turns with it, ``t_b = −torque``;
    ``f_b = 0``. The attached body receives ``+torque``; no orientation branch, no reaction.

    Parameters
    ----------
    resolve_in_frame : {"world", "frame_b"}
        Frame in which the input is resolved (structural constructor argument).

    Connectors
    ----------
    frame_b : Frame
        Frame the torque acts on.
    torque : Input (3,) [N.m]
        Torque vector resolved in ``resolve_in_frame``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.WorldTorque``
    (``Forces.Internal.BasicWorldTorque``; no ``frame_resolve`` connector).
    """

    torque = Input(unit="N.m", shape=3, doc="Torque vector resolved in resolve_in_frame")
    frame_b = Frame(doc="Frame the torque acts on")

    def __init__(self, resolve_in_frame: str = "world", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("world", "frame_b"))

    def equations(self) -> list:
        fb = self.frame_b
        torque_b = ca.mtimes(fb.T, self.torque) if self.resolve_in_frame == "world" else self.torque
        return [eq(fb.t, -torque_b), eq(fb.f, 0.0)]
