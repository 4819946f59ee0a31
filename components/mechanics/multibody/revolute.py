"""Revolute joint (MSL ``MultiBody.Joints.Revolute``)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Parameter, Variable, der, eq
from flexlib.components.mechanics.rotational.interfaces import Flange
from flexlib.errors import ParameterError

from .frames import absolute_rotation, planar_rotation, resolve1
from .interfaces import PartialTwoFrames

__all__ = ["Revolute"]


class Revolute(PartialTwoFrames):
    """Rotation of frame_b relative to frame_a by the angle ``phi`` about the fixed axis ``n``.

    ``r_0,b = r_0,a``; ``T_b = T_rel(n, φ) T_a``, ``w_b = T_rel w_a + n·w``; ``f_a = −T_relᵀ f_b``,
    ``t_a = −T_relᵀ t_b``; the driving torque about the axis is ``tau = −n·t_b`` (zero without an
    axis flange). When the orientation tree is rooted at frame_b the relations are written the other
    way round.

    Parameters
    ----------
    n : array_like (3,)
        Axis of rotation resolved in frame_a (= frame_b) [1]; normalised, must not be zero.

    Connectors
    ----------
    frame_a, frame_b : Frame
    axis, support : rotational Flange (if ``use_axis_flange``)
        Drive flange (angle ``phi``, torque ``tau``) and its housing (fixed to frame_a).

    Variables
    ---------
    phi [rad], w [rad/s], a [rad/s2]: relative angle, speed and acceleration; tau [N.m]: driving torque.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.Revolute``.
    """

    n = Parameter([0.0, 0.0, 1.0], unit="1", shape=3, doc="Axis of rotation resolved in frame_a")
    phi = Variable(unit="rad", state_select="prefer", doc="Relative rotation angle from frame_a to frame_b")
    w = Variable(unit="rad/s", state_select="prefer", doc="Relative angular velocity")
    a = Variable(unit="rad/s2", doc="Relative angular acceleration")
    tau = Variable(unit="N.m", doc="Driving torque in direction of the axis")

    def __init__(self, use_axis_flange: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.use_axis_flange = use_axis_flange
        if use_axis_flange:
            self.axis = Flange(doc="Drive flange (phi, tau)")
            self.support = Flange(doc="Housing of the drive, fixed to frame_a")
        n = self.parameter_value("n")
        if n is not None and not np.linalg.norm(n) > 1e-12:
            raise ParameterError(f"{self.path or type(self).__name__}: joint axis n = {n.tolist()} has zero length")

    def _assign(self, name: str, value: Any) -> None:
        super()._assign(name, value)
        if name == "n" and not np.linalg.norm(self._values["n"]) > 1e-12:
            raise ParameterError(f"{self.path or type(self).__name__}: joint axis n = {self._values['n'].tolist()} "
                                 "has zero length")

    def equations(self):
        a, b = self.frame_a, self.frame_b
        e = self.n / ca.norm_2(self.n)
        eqs = [eq(b.r_0, a.r_0), eq(der(self.phi), self.w), eq(der(self.w), self.a)]
        if self.rooted(a):
            T_rel = planar_rotation(e, self.phi)
            eqs += [eq(b.T, absolute_rotation(a.T, T_rel)), eq(b.w, ca.mtimes(T_rel, a.w) + e * self.w),
                    eq(a.f, -resolve1(T_rel, b.f)), eq(a.t, -resolve1(T_rel, b.t))]
        else:
            T_rel = planar_rotation(-e, self.phi)
            eqs += [eq(a.T, absolute_rotation(b.T, T_rel)), eq(a.w, ca.mtimes(T_rel, b.w) - e * self.w),
                    eq(b.f, -resolve1(T_rel, a.f)), eq(b.t, -resolve1(T_rel, a.t))]
        eqs.append(eq(self.tau, -ca.dot(e, b.t)))
        if self.use_axis_flange:
            eqs += [eq(self.axis.phi - self.support.phi, self.phi), eq(self.axis.tau, self.tau),
                    eq(self.support.tau, -self.tau)]
        else:
            eqs.append(eq(self.tau, 0.0, label="free joint axis (no drive)"))
        return eqs
