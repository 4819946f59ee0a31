"""External force acting at a frame, given by a signal (MSL ``Forces.WorldForce``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Component, Input, eq

from ._resolve import check_resolve_in_frame
from .interfaces import Frame

__all__ = ["WorldForce"]


class WorldForce(Component):
    """The input vector ``force`` acts on what is attached at frame_b, at its origin; no torque.

    ``resolve_in_frame="world"`` (default): the force is given in world coordinates,
    ``f_b = −T_b·force``; ``"frame_b"``: it is given in frame_b and turns with it, ``f_b = −force``;
    ``t_b = 0``. (The minus sign: ``f_b`` is the cut force acting on this component, so the attached
    body receives ``+force``.) No orientation branch: frame_b's orientation comes from what it is
    connected to, and the reaction goes to nobody (an external force).

    Parameters
    ----------
    resolve_in_frame : {"world", "frame_b"}
        Frame in which the input is resolved (structural constructor argument).

    Connectors
    ----------
    frame_b : Frame
        Point of application.
    force : Input (3,) [N]
        Force vector resolved in ``resolve_in_frame``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.WorldForce``
    (``Forces.Internal.BasicWorldForce``; no ``frame_resolve`` connector).
    """

    force = Input(unit="N", shape=3, doc="Force vector resolved in resolve_in_frame")
    frame_b = Frame(doc="Point of application")

    def __init__(self, resolve_in_frame: str = "world", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("world", "frame_b"))

    def equations(self) -> list:
        fb = self.frame_b
        force_b = ca.mtimes(fb.T, self.force) if self.resolve_in_frame == "world" else self.force
        return [eq(fb.f, -force_b), eq(fb.t, 0.0)]
