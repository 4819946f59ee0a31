"""Compliant six-component connection between two frames (ADAMS ``BUSHING``, Simscape Bushing Joint)."""

from __future__ import annotations

import casadi as ca

from flexlib import Component, Parameter, Variable, der, eq

from .interfaces import Frame

__all__ = ["Bushing", "cardan_angles"]


def cardan_angles(T_rel: ca.SX) -> ca.SX:
    """Cardan (Bryant) x-y-z angles ``φ`` of ``T_rel = A_z(φ3) A_y(φ2) A_x(φ1)`` (passive ``A`` as ``planar_rotation``).

    ``φ1 = atan2(−T21, T22)``, ``φ2 = atan2(T20, cos φ1 T22 − sin φ1 T21)``, ``φ3 = atan2(−T10, T00)``
    (0-based indices; the second argument of φ2 is ``cos φ2`` written without a square root). φ1, φ3 ∈ (−π, π],
    φ2 ∈ [−π/2, π/2]; singular (gimbal lock) at φ2 = ±π/2.
    """
    phi1 = ca.atan2(-T_rel[2, 1], T_rel[2, 2])
    phi2 = ca.atan2(T_rel[2, 0], ca.cos(phi1) * T_rel[2, 2] - ca.sin(phi1) * T_rel[2, 1])
    return ca.vertcat(phi1, phi2, ca.atan2(-T_rel[1, 0], T_rel[0, 0]))


class Bushing(Component):
    """Massless linear bushing: stiffness, damping and preload in three translational and three rotational directions.

    Kinematics of frame_b relative to frame_a (a Cartesian joint followed by a gimbal, as the Simscape
    Bushing Joint): ``r_rel = T_a (r_0,b − r_0,a)`` and ``v_rel = der(r_rel)`` along frame_a's axes;
    ``T_rel = T_b T_aᵀ = A_z(φ3) A_y(φ2) A_x(φ1)`` defines the Cardan angles ``phi_rel`` (rotation about
    frame_a's x, then the new y, then the new z = frame_b's z). The gimbal axes resolved in frame_a are
    ``e1 = (1, 0, 0)``, ``e2 = (0, cos φ1, sin φ1)``, ``e3 = T_relᵀ (0, 0, 1)``, ``E = [e1 e2 e3]``, and the
    relative angular velocity is ``T_relᵀ w_b − w_a = E phi_d``. Constitutive law (per direction, no coupling):

    ``f = −c_trans∘r_rel − d_trans∘v_rel + f_preload``, ``tau = −c_rot∘phi_rel − d_rot∘phi_d + t_preload``.

    ``f`` is the force and ``t`` the torque (about frame_b's origin) that the bushing applies to the part at
    frame_b, both resolved in frame_a; ``t`` is the torque whose component along each gimbal axis is that
    axis' torque, ``Eᵀ t = tau`` (so ``tau`` is the generalised force of ``phi_rel`` and the springs derive
    from the potential ``½ Σ c_rot,i φ_i²``: conservative at any angle). The part at frame_a receives the
    reaction ``−f`` and ``−t − r_rel × f`` (lever arm of the deflection). Cut forces acting on the element:
    ``f_a = f``, ``t_a = t + r_rel × f``, ``f_b = −T_rel f``, ``t_b = −T_rel t``.

    Connectors
    ----------
    frame_a, frame_b : Frame
        Reference (ADAMS J marker) and moving (I marker) frame. No orientation branch: each frame must
        get its orientation elsewhere (a World/Fixed, a joint, or a Body that then becomes a free root).

    Notes
    -----
    Rotation measure: for small angles ``phi_rel`` equals the small-angle rotation vector (ADAMS' projected
    angles a, b, c) and ``phi_d`` the relative angular velocity in frame_a, so the law is ADAMS' BUSHING. At
    finite angles Cardan angles stay well defined while ``|φ2| < π/2``: φ1 and φ3 may be large (put a free or
    soft hinge about frame_a's z or x axis; ADAMS likewise allows only c to be large). ``E`` is singular at
    ``|φ2| = π/2`` (``det E = cos φ2``) and φ1, φ3 jump by 2π at ±π (harmless when that direction has no
    stiffness). Stiff directions add fast modes ``√(c/m)``: give them damping and mind the step size.
    Known engine limit: closing a loop with stiffness around 1e8 N/m keeps the element's force in IDA's
    error test and the run crawls (``docs/engine.md``, "Error-test policy"); 1e6 N/m runs well (tested).

    Unlike a joint, a bushing closes a kinematic loop without constraints, so nothing is dropped as
    redundant and the reactions of statically indeterminate supports follow from the stiffnesses.

    References
    ----------
    MSC Adams/Solver, ``BUSHING`` statement (constitutive equations, I/J markers, caution on large rotations);
    MathWorks Simscape Multibody, *Bushing Joint* (Cartesian + gimbal primitives with internal spring-dampers);
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.Spring`` /
    ``Forces.Internal.BasicForce`` (force element between two frames without an orientation branch).
    """

    c_trans = Parameter([0.0, 0.0, 0.0], unit="N/m", shape=3, min=0.0,
                        doc="Translational stiffness along frame_a's x, y, z")
    d_trans = Parameter([0.0, 0.0, 0.0], unit="N.s/m", shape=3, min=0.0,
                        doc="Translational damping along frame_a's x, y, z")
    c_rot = Parameter([0.0, 0.0, 0.0], unit="N.m/rad", shape=3, min=0.0,
                      doc="Rotational stiffness about the gimbal axes x, y', z''")
    d_rot = Parameter([0.0, 0.0, 0.0], unit="N.m.s/rad", shape=3, min=0.0, doc="Rotational damping (gimbal axes)")
    f_preload = Parameter([0.0, 0.0, 0.0], unit="N", shape=3,
                          doc="Preload force on frame_b at zero deflection and rate, resolved in frame_a")
    t_preload = Parameter([0.0, 0.0, 0.0], unit="N.m", shape=3,
                          doc="Preload torques about the gimbal axes on frame_b at zero deflection and rate")
    r_rel = Variable(unit="m", shape=3, doc="Origin of frame_b from frame_a's, resolved in frame_a")
    v_rel = Variable(unit="m/s", shape=3, doc="der(r_rel)")
    phi_rel = Variable(unit="rad", shape=3, doc="Cardan x-y-z angles of frame_b relative to frame_a")
    phi_d = Variable(unit="rad/s", shape=3, doc="Rates of phi_rel (from the relative angular velocity)")
    f = Variable(unit="N", shape=3, doc="Force on the frame_b side, resolved in frame_a")
    t = Variable(unit="N.m", shape=3, doc="Torque on the frame_b side about its origin, resolved in frame_a")
    tau = Variable(unit="N.m", shape=3, doc="Torques about the gimbal axes on the frame_b side")
    frame_a = Frame(doc="Reference frame (ADAMS J marker)")
    frame_b = Frame(doc="Moving frame (ADAMS I marker)")

    def equations(self) -> list:
        a, b = self.frame_a, self.frame_b
        T_rel = ca.mtimes(b.T, a.T.T)
        phi1 = self.phi_rel[0]
        E = ca.horzcat(ca.vertcat(1.0, 0.0, 0.0), ca.vertcat(0.0, ca.cos(phi1), ca.sin(phi1)), T_rel[2, :].T)
        return [
            eq(self.r_rel, ca.mtimes(a.T, b.r_0 - a.r_0), label="relative position in frame_a"),
            eq(der(self.r_rel), self.v_rel),
            eq(self.phi_rel, cardan_angles(T_rel), label="Cardan angles of frame_b relative to frame_a"),
            eq(ca.mtimes(E, self.phi_d), ca.mtimes(T_rel.T, b.w) - a.w, label="relative angular velocity"),
            eq(self.f, -self.c_trans * self.r_rel - self.d_trans * self.v_rel + self.f_preload),
            eq(self.tau, -self.c_rot * self.phi_rel - self.d_rot * self.phi_d + self.t_preload),
            eq(ca.mtimes(E.T, self.t), self.tau, label="gimbal torques are the axial components of t"),
            eq(a.f, self.f), eq(a.t, self.t + ca.cross(self.r_rel, self.f)),
            eq(b.f, -ca.mtimes(T_rel, self.f)), eq(b.t, -ca.mtimes(T_rel, self.t)),
        ]
