"""Rigid translation between two frames (MSL ``MultiBody.Parts.FixedTranslation``)."""

from __future__ import annotations

import casadi as ca

from flexlib import Parameter, eq

from .frames import resolve1
from .interfaces import PartialTwoFrames

__all__ = ["FixedTranslation"]


class FixedTranslation(PartialTwoFrames):
    """Massless rod: frame_b is frame_a shifted by ``r`` (resolved in frame_a), same orientation.

    ``r_0,b = r_0,a + T_aᵀ r``; ``T_b = T_a``, ``w_b = w_a``;
    ``f_a + f_b = 0``; ``t_a + t_b + r × f_b = 0``.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.FixedTranslation``.
    """

    r = Parameter([0.0, 0.0, 0.0], unit="m", shape=3, doc="Vector from frame_a to frame_b resolved in frame_a")

    def equations(self):
        a, b = self.frame_a, self.frame_b
        orient = [eq(b.T, a.T), eq(b.w, a.w)] if self.rooted(a) else [eq(a.T, b.T), eq(a.w, b.w)]
        return [
            eq(b.r_0, a.r_0 + resolve1(a.T, self.r)),
            *orient,
            eq(a.f + b.f, 0.0),
            eq(a.t + b.t + ca.cross(self.r, b.f), 0.0),
        ]
