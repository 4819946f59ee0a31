"""A frame fixed in the world at a given position (MSL ``MultiBody.Parts.Fixed``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Component, Parameter, eq

from .interfaces import Frame

__all__ = ["Fixed"]


class Fixed(Component):
    """Frame fixed in the world: ``r_0 = r``, ``T = I``, ``w = 0``.

    Connectors
    ----------
    frame_b : Frame
        The fixed frame (a definite orientation root).

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.Fixed``.
    """

    r = Parameter([0.0, 0.0, 0.0], unit="m", shape=3, doc="Position of the frame origin resolved in world")
    frame_b = Frame(doc="Fixed frame")

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.definite_root(self.frame_b)

    def equations(self):
        fb = self.frame_b
        return [eq(fb.r_0, self.r), eq(fb.T, ca.SX.eye(3)), eq(fb.w, 0.0)]
