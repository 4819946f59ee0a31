"""Spherical joint (MSL ``MultiBody.Joints.Spherical``, default variant without states)."""

from __future__ import annotations

import casadi as ca

from flexlib import Component, eq

from .frames import resolve1
from .interfaces import Frame

__all__ = ["Spherical"]


class Spherical(Component):
    """Ball joint: the origins coincide, no torque is transmitted, orientations are independent.

    ``r_0,b = r_0,a``; ``t_a = t_b = 0``; ``f_a + T_a T_bᵀ f_b = 0``. It declares no orientation branch,
    so it cuts the orientation graph: a body behind it that no other path roots gets quaternion states
    (a free rotation), and a kinematic loop through it needs no loop-closure orientation equations.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.Spherical``.
    """

    frame_a = Frame(doc="First frame")
    frame_b = Frame(doc="Second frame")

    def equations(self):
        a, b = self.frame_a, self.frame_b
        return [eq(b.r_0, a.r_0), eq(a.t, 0.0), eq(b.t, 0.0),
                eq(a.f + ca.mtimes(a.T, resolve1(b.T, b.f)), 0.0)]
