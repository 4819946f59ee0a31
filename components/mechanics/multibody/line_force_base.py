"""Geometry of a force acting along the line between two frame origins (MSL ``Interfaces.LineForceBase``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Component, Parameter, Variable, eq, no_event

from .interfaces import Frame

__all__ = ["LineForceBase", "smooth_length"]


def smooth_length(r: Any, s_small: Any) -> ca.SX:
    """``|r|``, made differentiable at ``r = 0`` (MSL ``Sensors.Distance``).

    For ``|r| ≥ s_small`` the result is exactly ``sqrt(r·r)``. Below, ``sqrt`` (whose derivative is
    infinite at 0) is replaced by the quadratic in ``L2 = r·r`` through 0 that matches value and slope at
    ``s_small``: ``L2/(2 s_small)·(3 − L2/s_small²)``. The switch is evaluated continuously (no event); the
    result is once continuously differentiable in ``r``, ``≤ |r|·3/2`` below ``s_small`` and its
    derivatives are finite everywhere.
    """
    L2 = ca.dot(r, r)
    s2 = s_small * s_small
    return no_event(L2 > s2, ca.sqrt(L2), L2 / (2 * s_small) * (3 - L2 / s2))


class LineForceBase(Component):
    """Base of force elements acting along the straight line between the origins of frame_a and frame_b.

    ``r_rel_0 = r_0,b − r_0,a`` (world); ``length = smooth_length(r_rel_0, s_small)``; unit vector
    ``e_rel_0 = r_rel_0 / max(length, s_small)`` (continuous ``fmax``, no event: it shrinks linearly to 0
    when the frames nearly coincide instead of dividing by zero, so a line force vanishes smoothly
    through coincident frames where its direction is undefined). No torques act at the frames:
    ``t_a = t_b = 0``. The element declares no orientation branch: each frame gets its orientation from
    what it is connected to (a body attached only through line forces rotates freely). A subclass adds
    the six equations of the frame forces and its own law.

    Connectors
    ----------
    frame_a, frame_b : Frame
        The two attachment points (only their origins matter).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Interfaces.LineForceBase``; the small-length
    approximation of ``Modelica.Mechanics.MultiBody.Sensors.Distance``.
    """

    s_small = Parameter(1e-6, unit="m", min=1e-12,
                        doc=("Regularisation length for coinciding frames: below it ``length`` is ``smooth_length`` "
                             "and ``e_rel_0`` shrinks to zero"))
    length = Variable(unit="m", start=1.0, doc="Distance between the frame origins (regularised below ``s_small``)")
    frame_a = Frame(doc="First attachment point")
    frame_b = Frame(doc="Second attachment point")

    @property
    def r_rel_0(self) -> ca.SX:
        """Vector from the origin of frame_a to the origin of frame_b, resolved in world [m]."""
        return self.frame_b.r_0 - self.frame_a.r_0

    @property
    def e_rel_0(self) -> ca.SX:
        """Unit vector from frame_a to frame_b, resolved in world [1] (shorter below ``s_small``)."""
        return self.r_rel_0 / ca.fmax(self.length, self.s_small)

    def line_force_equations(self, f_a: Any, f_b: Any) -> list:
        """Frame forces of tensions ``f_a`` at frame_a and ``f_b`` at frame_b (positive: frames pulled together).

        The force on whatever is attached at frame_a is ``+e_rel_0·f_a`` (towards frame_b), at frame_b
        ``−e_rel_0·f_b``; the cut forces acting on this component are their negatives, resolved in each frame.
        """
        a, b = self.frame_a, self.frame_b
        e = self.e_rel_0
        return [eq(a.f, -ca.mtimes(a.T, e) * f_a), eq(b.f, ca.mtimes(b.T, e) * f_b)]

    def equations(self) -> list:
        return [eq(self.length, smooth_length(self.r_rel_0, self.s_small), label="length of the line"),
                eq(self.frame_a.t, 0.0), eq(self.frame_b.t, 0.0)]
