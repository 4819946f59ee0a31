"""Revolute joint (MSL ``MultiBody.Joints.Revolute``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Parameter, Variable, der, eq
from flexlib.components.mechanics.rotational.fixed import Fixed
from flexlib.components.mechanics.rotational.interfaces import Flange
from flexlib.components.mechanics.rotational.position import Position
from flexlib.components.mechanics.rotational.speed import Speed
from flexlib.core.options import flag

from .frames import absolute_rotation, planar_rotation, resolve1
from .interfaces import PartialAxisJoint, add_axis_flange, support_grounded

__all__ = ["Revolute"]


class Revolute(PartialAxisJoint):
    """Rotation of frame_b relative to frame_a by the angle ``phi`` about the fixed axis ``n``.

    ``r_0,b = r_0,a``; ``T_b = T_rel(n, φ) T_a``, ``w_b = T_rel w_a + n·w``; ``f_a = −T_relᵀ f_b``,
    ``t_a = −T_relᵀ t_b``; the net torque about the axis is ``tau = −n·t_b``: the flange's drive torque plus the
    constant ``tau_drive`` minus friction. When the orientation tree is rooted at frame_b the relations are
    written the other way round.

    Parameters
    ----------
    use_axis_flange : bool
        True if the joint has a drive flange ``axis`` and its housing ``support`` (structural).
    use_friction : bool
        True if joint friction acts (structural). Friction law:
        ``τ_f = (τ_C + (stribeck−1)·τ_C·exp(−(w/w_s)²))·tanh(w/w_reg) + d·w`` with
        ``τ_C = tau_c0 + mu·r_bearing·(|F_radial| + F_preload)``; the radial bearing force is the cut force
        of frame_b normal to the axis (smoothed near zero). Regularised (``tanh``, no events): sticking is a
        very slow creep below ``w_reg``.

    Connectors
    ----------
    frame_a, frame_b : Frame
    axis, support : rotational Flange (if ``use_axis_flange``)
        Drive flange (angle ``phi``, torque ``tau``) and its housing. As in MSL the support is grounded inside
        the joint (``support.phi = 0``: "the support flange is fixed to ground"), so a spring, damper or torque
        source between ``support`` and ``axis`` acts between housing and axis (its reaction goes into
        ``frame_a``) and a ``RelativeAngleSensor`` there reads ``phi``; only a support connected to the flange
        of a ``Fixed``, ``Position`` or ``Speed`` is placed by that component and takes ``-(tau + tau_f)``.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.Revolute``.
    """

    #: ``state_select="always"`` (one value, MSL's ``stateSelect``) applies to these
    state_select_variables = ("phi", "w")

    n = Parameter([0.0, 0.0, 1.0], unit="1", shape=3,
                  doc="Axis of rotation resolved in frame_a (= frame_b); normalised, must not be zero")
    mu = Parameter(0.0, unit="1", min=0.0,
                   doc="Bearing friction coefficient (journal bearing: Coulomb torque ``mu·r·|F|``)")
    r_bearing = Parameter(0.0, unit="m", min=0.0, doc="Bearing (journal) radius")
    F_preload = Parameter(0.0, unit="N", min=0.0, doc="Mounting preload added to the radial bearing force")
    tau_c0 = Parameter(0.0, unit="N.m", min=0.0, doc="Load-independent Coulomb friction torque")
    stribeck = Parameter(1.0, unit="1", min=1.0, doc="Ratio of break-away (static) to Coulomb friction")
    w_s = Parameter(0.1, unit="rad/s", min=1e-9, doc="Stribeck velocity")
    d = Parameter(0.0, unit="N.m.s/rad", min=0.0, doc="Viscous friction coefficient")
    w_reg = Parameter(1e-3, unit="rad/s", min=1e-12, doc="Regularisation speed of the Coulomb friction")
    tau_drive = Parameter(0.0, unit="N.m",
                          doc=("Constant drive torque about the axis on frame_b, added to the flange's; a load case, "
                               "and the channel through which :func:`flexlib.analysis.modal_analysis` holds the joint "
                               "when it is locked"))
    phi = Variable(unit="rad", state_select="prefer", doc="Relative rotation angle from frame_a to frame_b")
    w = Variable(unit="rad/s", state_select="prefer", doc="Relative angular velocity")
    a = Variable(unit="rad/s2", doc="Relative angular acceleration")
    tau = Variable(unit="N.m", doc="Net torque about the axis on the frame_b side (drive minus friction)")
    tau_f = Variable(unit="N.m", doc="Friction torque opposing the relative rotation")

    def __init__(self, use_axis_flange: bool = False, use_friction: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        add_axis_flange(self, use_axis_flange, Flange, "Drive flange (phi, tau)",
                        "Housing of the drive, fixed to frame_a")
        self.use_friction = flag(self, "use_friction", use_friction)

    def equations(self):
        a, b = self.frame_a, self.frame_b
        e = self.unit_axis()
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
        eqs.append(eq(self.tau_f, self.friction_torque(e) if self.use_friction else 0.0))
        if self.use_axis_flange:
            eqs += [eq(self.axis.phi - self.support.phi, self.phi),
                    eq(self.axis.tau + self.tau_drive, self.tau + self.tau_f)]
            if support_grounded(self.support, (Fixed, Position, Speed)):
                eqs.append(eq(self.support.phi, 0.0, label="support grounded in the world (MSL)"))
            else:
                eqs.append(eq(self.support.tau, -(self.tau + self.tau_f)))
        else:
            eqs.append(eq(self.tau, self.tau_drive - self.tau_f, label="no drive flange: tau_drive and friction act"))
        return eqs

    def friction_torque(self, e: Any) -> ca.SX:
        """Regularised Coulomb–Stribeck–viscous friction torque with a journal-bearing Coulomb level."""
        f = self.frame_b.f
        f_radial = f - ca.dot(e, f) * e
        F_n = ca.sqrt(ca.dot(f_radial, f_radial) + 1e-12) + self.F_preload
        tau_c = self.tau_c0 + self.mu * self.r_bearing * F_n
        w = self.w
        return (tau_c * (1 + (self.stribeck - 1) * ca.exp(-(w / self.w_s) ** 2)) * ca.tanh(w / self.w_reg)
                + self.d * w)
