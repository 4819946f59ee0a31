"""Joint with all six degrees of freedom (MSL ``MultiBody.Joints.FreeMotion``)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Parameter, Variable, der, eq
from flexlib.core.options import flag
from flexlib.errors import ParameterError

from .frames import absolute_rotation, equality_constraint, resolve1
from .interfaces import PartialTwoFrames
from .quaternions import quaternion_to_T, quaternion_w

__all__ = ["FreeMotion"]


class FreeMotion(PartialTwoFrames):
    """Free relative motion of frame_b with respect to frame_a: relative position and quaternion states.

    ``r_0,b = r_0,a + T_aᵀ r_rel_a``, ``v_rel_a = der(r_rel_a)``, ``a_rel_a = der(v_rel_a)``; the relative
    rotation ``T_rel = T(Q)`` (frame_a-resolved → frame_b-resolved) with ``w_rel_b = 2 G(Q) der(Q)`` and
    ``Q·Q = 1`` (index reduction keeps the norm constraint and selects 3 of the 4 quaternion entries as
    states, switching during the run if needed: no singular orientation). If the orientation tree reaches
    the joint at frame_a, ``T_b = T_rel T_a``, ``w_b = T_rel w_a + w_rel_b``; otherwise ``T_a = T_relᵀ T_b``,
    ``w_a = T_relᵀ (w_b − w_rel_b)``. No force or torque is transmitted: ``f_a = t_a = f_b = t_b = 0``.

    Use it (MSL ``enforceStates = true``, the default there) to give a floating body relative coordinates
    with respect to a frame, e.g. the world: ``connect(world.frame_b, joint.frame_a)``,
    ``connect(joint.frame_b, body.frame_a)``. Without it, a lone :class:`Body` is already free (it becomes the
    root of its orientation tree with absolute quaternion states).

    Initial conditions: ``init={"r_rel_a": ..., "v_rel_a": ...}`` for the translation; the relative
    orientation with ``Q_start`` and ``orientation_fixed=True`` (three residues, never four quaternion
    entries); the relative angular velocity with ``w_start`` and ``w_fixed=True`` (or
    ``init={"w_rel_b": ...}``).

    Parameters
    ----------
    orientation_fixed, w_fixed : bool
        True if the start orientation / relative angular velocity are initial conditions (structural).

    Connectors
    ----------
    frame_a, frame_b : Frame

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.FreeMotion`` (``useQuaternions = true``,
    ``enforceStates = true``).
    """

    Q_start = Parameter([0.0, 0.0, 0.0, 1.0], unit="1", shape=4,
                        doc=("Start orientation of frame_b relative to frame_a as a quaternion ``(e·sin(φ/2), "
                             "cos(φ/2))``, normalised; used if ``orientation_fixed`` and as the start guess of ``Q``"))
    w_start = Parameter([0.0, 0.0, 0.0], unit="rad/s", shape=3,
                        doc=("Start relative angular velocity of frame_b with respect to frame_a, resolved in frame_b; "
                             "used if ``w_fixed``"))
    r_rel_a = Variable(unit="m", shape=3, state_select="prefer", doc="Position of frame_b from frame_a in frame_a")
    v_rel_a = Variable(unit="m/s", shape=3, state_select="prefer", doc="der(r_rel_a)")
    a_rel_a = Variable(unit="m/s2", shape=3, doc="der(v_rel_a)")
    Q = Variable(unit="1", shape=4, start=[0.0, 0.0, 0.0, 1.0], state_select="prefer",
                 doc="Relative orientation quaternion (e·sin(φ/2), cos(φ/2)) of frame_b relative to frame_a")
    w_rel_b = Variable(unit="rad/s", shape=3, state_select="prefer",
                       doc="Angular velocity of frame_b relative to frame_a, resolved in frame_b")
    z_rel_b = Variable(unit="rad/s2", shape=3,
                       doc="der(w_rel_b): relative angular acceleration, resolved in frame_b")

    def __init__(self, orientation_fixed: bool = False, w_fixed: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.orientation_fixed = flag(self, "orientation_fixed", orientation_fixed)
        self.w_fixed = flag(self, "w_fixed", w_fixed)
        q0 = self.parameter_value("Q_start")
        if np.linalg.norm(q0) > 1e-12:  # else check() names the zero quaternion
            self.set_start("Q", q0 / np.linalg.norm(q0), fixed=False)

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        q = values.get("Q_start")
        if q is not None and not np.linalg.norm(q) > 1e-12:
            raise ParameterError(f"{self.where}: Q_start = {q.tolist()} has zero length")

    def initial_equations(self):
        """``orientation_fixed``: T_rel(t0) = T(Q_start) (3 equations); ``w_fixed``: w_rel_b(t0) = w_start."""
        out = []
        if self.orientation_fixed:
            q0 = self.Q_start / ca.norm_2(self.Q_start)
            out.append(eq(equality_constraint(quaternion_to_T(q0), quaternion_to_T(self.Q)), 0.0,
                          label="start relative orientation"))
        if self.w_fixed:
            out.append(eq(self.w_rel_b, self.w_start, label="start relative angular velocity"))
        return out

    def equations(self):
        a, b = self.frame_a, self.frame_b
        Q = self.Q
        T_rel = quaternion_to_T(Q)
        eqs = [eq(b.r_0, a.r_0 + resolve1(a.T, self.r_rel_a)), eq(der(self.r_rel_a), self.v_rel_a),
               eq(der(self.v_rel_a), self.a_rel_a), eq(self.w_rel_b, quaternion_w(Q, der(Q))),
               eq(ca.dot(Q, Q), 1.0, label="quaternion norm"),
               eq(a.f, 0.0), eq(a.t, 0.0), eq(b.f, 0.0), eq(b.t, 0.0)]
        w_r = self.w_rel_b
        eqs.append(eq(der(w_r), self.z_rel_b))
        if self.rooted(a):
            eqs += [eq(b.T, absolute_rotation(a.T, T_rel)), eq(b.w, ca.mtimes(T_rel, a.w) + w_r)]
        else:
            eqs += [eq(a.T, absolute_rotation(b.T, T_rel.T)), eq(a.w, resolve1(T_rel, b.w - w_r))]
        return eqs
