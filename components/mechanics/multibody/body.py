"""Rigid body with mass and inertia tensor (MSL ``MultiBody.Parts.Body``)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Component, Parameter, Variable, der, eq
from flexlib.core.options import flag
from flexlib.errors import ParameterError

from .frames import equality_constraint, resolve1
from .interfaces import Frame
from .quaternions import floating_frame_equations, quaternion_to_T
from .world import gravity_of

__all__ = ["Body"]


class Body(Component):
    """Rigid body: Newton–Euler equations resolved in ``frame_a``.

    ``f_a = m·(α_a + z × r_CM + w × (w × r_CM))``,
    ``t_a = I z + w × (I w) + r_CM × f_a``, with ``α_a = T_a (a_0 − g_0)`` the acceleration of frame_a's origin less
    the World's gravity ``g_0``, ``w`` and ``z = der(w)`` the angular velocity and acceleration, all resolved in
    frame_a and read from the frame (recursive kinematics, :class:`~.interfaces.Frame`), and ``I`` the inertia
    tensor at the centre of mass resolved in frame_a. ``v_0 = T_aᵀ v_a`` and ``a_0 = T_aᵀ α_a + g_0`` report the
    motion in the world. If no definite root (World/Fixed) reaches the body, it is the root of its orientation tree:
    its orientation comes from a unit quaternion ``Q`` (states; ``|Q| = 1`` is kept by index reduction — no drift,
    no singularity), its position from ``der(r_0) = v_0``, ``der(v_0) = a_0``, and it gives frame_a its ``v``,
    ``a``, ``z``.

    Parameters
    ----------
    orientation_fixed, w_fixed : bool
        True if the start orientation / angular velocity are initial conditions (structural).

    Connectors
    ----------
    frame_a : Frame
        Body-fixed frame.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.Body``; Shabana, *Dynamics of Multibody
    Systems*, 4th ed., §3.
    """

    m = Parameter(1.0, unit="kg", min=0.0, doc="Mass")
    r_CM = Parameter([0.0, 0.0, 0.0], unit="m", shape=3, doc="Centre of mass from frame_a resolved in frame_a")
    I = Parameter(np.diag([1e-3, 1e-3, 1e-3]), unit="kg.m2", shape=(3, 3),
                  doc=("Inertia tensor at the centre of mass, resolved in frame_a; symmetric positive semi-definite "
                       "(checked)"))
    Q_start = Parameter([0.0, 0.0, 0.0, 1.0], unit="1", shape=4,
                        doc=("Start orientation as a quaternion ``(e·sin(φ/2), cos(φ/2))``, used if "
                             "``orientation_fixed`` (and as the initial guess of a free body's quaternion)"))
    w_start = Parameter([0.0, 0.0, 0.0], unit="rad/s", shape=3,
                        doc="Start angular velocity resolved in frame_a, used if ``w_fixed``")
    r_0 = Variable(unit="m", shape=3, state_select="avoid", doc="Origin of frame_a resolved in world")
    v_0 = Variable(unit="m/s", shape=3, state_select="avoid", doc="Velocity of frame_a origin in world")
    a_0 = Variable(unit="m/s2", shape=3, doc="Acceleration of frame_a origin in world")
    w_a = Variable(unit="rad/s", shape=3, state_select="avoid", doc="Angular velocity resolved in frame_a")
    z_a = Variable(unit="rad/s2", shape=3, doc="Angular acceleration resolved in frame_a")
    Q = Variable(unit="1", shape=4, start=[0.0, 0.0, 0.0, 1.0], state_select="prefer",
                 doc="Orientation quaternion (e·sin(φ/2), cos(φ/2)); used only by a free body")
    frame_a = Frame(doc="Body frame")

    def __init__(self, orientation_fixed: bool = False, w_fixed: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.orientation_fixed = flag(self, "orientation_fixed", orientation_fixed)
        self.w_fixed = flag(self, "w_fixed", w_fixed)
        self.potential_root(self.frame_a)
        q0 = self.parameter_value("Q_start")
        if np.linalg.norm(q0) > 1e-12:  # else check() names the zero quaternion
            self.set_start("Q", q0 / np.linalg.norm(q0), fixed=False)

    def initial_equations(self):
        """``orientation_fixed``: T(t0) = T(Q_start) (3 equations); ``w_fixed``: w_a(t0) = w_start."""
        out = []
        if self.orientation_fixed:
            q0 = self.Q_start / ca.norm_2(self.Q_start)
            out.append(eq(equality_constraint(quaternion_to_T(q0), self.frame_a.T), 0.0, label="start orientation"))
        if self.w_fixed:
            out.append(eq(self.w_a, self.w_start, label="start angular velocity"))
        return out

    def check(self, values: dict[str, Any]) -> None:
        """The inertia tensor is symmetric, positive semi-definite and obeys the triangle inequality
        (principal moments ``I1 + I2 >= I3``); ``Q_start`` is not zero."""
        super().check(values)
        label = self.where
        q = values.get("Q_start")
        if q is not None and not np.linalg.norm(q) > 1e-12:
            raise ParameterError(f"{self.param_label('Q_start')} = {q.tolist()} has zero length")
        I = values.get("I")
        if I is None:
            return
        if not np.allclose(I, I.T, atol=1e-12 * max(1.0, np.abs(I).max())):
            raise ParameterError(f"{label}: inertia tensor I is not symmetric: {I.tolist()}")
        eig = np.linalg.eigvalsh(I)
        if eig.min() < -1e-12 * max(1.0, eig.max()):
            raise ParameterError(f"{label}: inertia tensor I is not positive semi-definite (eigenvalues {eig})")
        if not (eig[0] + eig[1] >= eig[2] * (1 - 1e-9)):
            raise ParameterError(f"{label}: inertia tensor I violates the triangle inequality (eigenvalues {eig})")

    def equations(self):
        fa = self.frame_a
        g_0 = gravity_of(self)
        w, z, r_cm = self.w_a, self.z_a, self.r_CM
        if self.is_root(fa):
            kin = [eq(der(self.r_0), self.v_0), eq(der(self.v_0), self.a_0), eq(der(self.w_a), self.z_a)]
        else:
            kin = [eq(self.v_0, resolve1(fa.T, fa.v)), eq(self.a_0, resolve1(fa.T, fa.a) + g_0), eq(self.z_a, fa.z)]
        eqs = [
            eq(self.r_0, fa.r_0), *kin,
            eq(fa.f, self.m * (fa.a + ca.cross(z, r_cm) + ca.cross(w, ca.cross(w, r_cm)))),
            eq(fa.t, ca.mtimes(self.I, z) + ca.cross(w, ca.mtimes(self.I, w)) + ca.cross(r_cm, fa.f)),
        ]
        if self.is_root(fa):
            eqs += [*floating_frame_equations(fa, self.Q), eq(self.w_a, fa.w)]
        else:  # orientation comes through the tree; Q is unused (eliminated as a constant)
            eqs += [eq(self.w_a, fa.w), eq(self.Q, [0.0, 0.0, 0.0, 1.0])]
        return eqs
