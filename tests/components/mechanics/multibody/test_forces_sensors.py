"""Line forces, world forces/torques and sensors of the multibody library against closed-form references.

World x horizontal, y up, gravity −y. Free bodies (attached only through line forces or world forces)
carry quaternion states; their start orientation and angular velocity are initial conditions.
"""

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.mechanics import translational as tr
from flexlib.components.mechanics.multibody import Body, Fixed, FixedTranslation, Revolute, World
from flexlib.components.mechanics.multibody.absolute_angular_velocity import AbsoluteAngularVelocity
from flexlib.components.mechanics.multibody.absolute_position import AbsolutePosition
from flexlib.components.mechanics.multibody.absolute_velocity import AbsoluteVelocity
from flexlib.components.mechanics.multibody.cut_force import CutForce
from flexlib.components.mechanics.multibody.cut_torque import CutTorque
from flexlib.components.mechanics.multibody.distance import Distance
from flexlib.components.mechanics.multibody.line_force import LineForce
from flexlib.components.mechanics.multibody.quaternions import quaternion_from_T
from flexlib.components.mechanics.multibody.relative_position import RelativePosition
from flexlib.components.mechanics.multibody.relative_velocity import RelativeVelocity
from flexlib.components.mechanics.multibody.spring_damper_line import SpringDamperLine
from flexlib.components.mechanics.multibody.world_force import WorldForce
from flexlib.components.mechanics.multibody.world_torque import WorldTorque
from flexlib.models.reference.signal_chain import VectorConstant

G = 9.81
TOL = {"rtol": 1e-10, "atol": 1e-12}


def free_body(r0, v0=(0.0, 0.0, 0.0), m=1.0, inertia=(0.01, 0.02, 0.03), T0=None) -> Body:
    """A body whose position, velocity, orientation and angular velocity (zero) are initial conditions."""
    q0 = [0.0, 0.0, 0.0, 1.0] if T0 is None else quaternion_from_T(T0)
    return Body(m=m, I=np.diag(inertia), Q_start=q0, orientation_fixed=True, w_fixed=True,
                init={"r_0": list(r0), "v_0": list(v0)})


def rot_z(angle: float) -> np.ndarray:
    """T (world → frame) of a frame turned by ``angle`` about z."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


# ---------------------------------------------------------------------------------------------------------------
class HangingSpring(fl.Model):
    """A mass hanging from the world origin by a SpringDamperLine."""

    def __init__(self, m: float, c: float, d: float, s0: float, y0: float) -> None:
        super().__init__()
        self.world = World(g=G)
        self.spring = SpringDamperLine(c=c, d=d, s_unstretched=s0)
        self.body = free_body([0.0, y0, 0.0], m=m)
        self.connect(self.world.frame_b, self.spring.frame_a)
        self.connect(self.spring.frame_b, self.body.frame_a)


def test_spring_damper_line_hanging_mass():
    """Static deflection m g / c: started there the mass stays (1e-10 m); released 0.1 m lower it oscillates
    as y_eq − A cos(√(c/m) t) (1e-7 m over 2 s, undamped), and with damping as the closed-form damped
    oscillator (1e-7 m); it never leaves the vertical (1e-12 m)."""
    m, c, s0, A = 2.0, 100.0, 0.5, 0.1
    y_eq = -(s0 + m * G / c)
    model = HangingSpring(m, c, 0.0, s0, y_eq)
    sim = fl.Simulation(model, use_cache=False)
    res = sim.run(1.0, dt_out=0.1, **TOL)
    np.testing.assert_allclose(res["body.r_0"], [[0.0, y_eq, 0.0]] * len(res.t), atol=1e-10, rtol=0)
    np.testing.assert_allclose(res["spring.f"], m * G, rtol=1e-10)

    model.body.set_start("r_0", [0.0, y_eq - A, 0.0])
    res = sim.run(2.0, dt_out=0.01, **TOL)
    w = np.sqrt(c / m)
    np.testing.assert_allclose(res["body.r_0"][:, 1], y_eq - A * np.cos(w * res.t), atol=1e-7, rtol=0)
    np.testing.assert_allclose(res["body.r_0"][:, [0, 2]], 0.0, atol=1e-12, rtol=0)

    d = 3.0
    res = sim.run(2.0, dt_out=0.01, params={"spring.d": d}, **TOL)
    zeta = d / (2 * np.sqrt(c * m))
    wd = w * np.sqrt(1 - zeta**2)
    y_ref = y_eq - A * np.exp(-zeta * w * res.t) * (np.cos(wd * res.t) + zeta * w / wd * np.sin(wd * res.t))
    np.testing.assert_allclose(res["body.r_0"][:, 1], y_ref, atol=1e-7, rtol=0)


class ThroughAnchor(fl.Model):
    """Zero-length spring (s_unstretched = 0) without gravity: a linear oscillator through the anchor point."""

    def __init__(self) -> None:
        super().__init__()
        self.world = World(g=0.0)
        self.spring = SpringDamperLine(c=4.0, s_unstretched=0.0)
        self.body = free_body([0.3, -0.2, 0.1], m=1.0)
        self.connect(self.world.frame_b, self.spring.frame_a)
        self.connect(self.spring.frame_b, self.body.frame_a)


def test_line_passes_through_zero_length():
    """The regularised length lets the mass pass exactly through the anchor (length 0, no event, no NaN):
    r(t) = r0 cos(2 t) to 1e-7 m over two passes."""
    grid = np.sort(np.r_[np.linspace(0.0, 2.5, 126), np.pi / 4, 3 * np.pi / 4])  # passes at cos(2 t) = 0
    res = fl.Simulation(ThroughAnchor(), use_cache=False).run(2.5, output_times=grid, **TOL)
    r_ref = np.outer(np.cos(2.0 * res.t), [0.3, -0.2, 0.1])
    np.testing.assert_allclose(res["body.r_0"], r_ref, atol=1e-7, rtol=0)
    assert np.sort(res["spring.length"])[1] < 1e-7  # both passes sampled within 0.1 µm of the anchor


# ---------------------------------------------------------------------------------------------------------------
class LineForceVsSpringDamper(fl.Model):
    """Two identical spring pendulums: SpringDamperLine, and LineForce with a 1D SpringDamper on its flanges."""

    def __init__(self, c: float, d: float, s0: float) -> None:
        super().__init__()
        r0, v0 = [0.3, -1.0, 0.2], [0.5, 0.0, -0.3]
        self.world = World(g=G)
        self.anchor = Fixed(r=[0.0, 0.0, 0.0])
        self.spring3d = SpringDamperLine(c=c, d=d, s_unstretched=s0)
        self.body1 = free_body(r0, v0, m=1.5)
        self.line = LineForce()
        self.spring1d = tr.SpringDamper(c=c, d=d, s_rel0=s0)
        self.body2 = free_body(r0, v0, m=1.5)
        self.connect(self.anchor.frame_b, self.spring3d.frame_a, self.line.frame_a)
        self.connect(self.spring3d.frame_b, self.body1.frame_a)
        self.connect(self.line.frame_b, self.body2.frame_a)
        self.connect(self.line.flange_a, self.spring1d.flange_a)
        self.connect(self.spring1d.flange_b, self.line.flange_b)


def test_line_force_with_1d_spring_damper_equals_spring_damper_line():
    """Same 3D swinging-spring trajectory (1e-9 m) and tension (1e-8 N) over 2 s; the 1D spring sees the
    line length (1e-10 m); the anchor carries both tensions."""
    res = fl.Simulation(LineForceVsSpringDamper(40.0, 0.8, 0.6), use_cache=False).run(2.0, dt_out=0.01, **TOL)
    np.testing.assert_allclose(res["body2.r_0"], res["body1.r_0"], atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["line.f_a"], res["spring3d.f"], atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["line.f_b"], res["spring3d.f"], atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["spring1d.s_rel"], np.linalg.norm(res["body2.r_0"], axis=1), atol=1e-10, rtol=0)
    assert np.ptp(res["spring3d.f"]) > 1.0  # the tension really varies
    # the anchor is pulled towards the bodies by both tensions (Fixed's flow is the force acting on it)
    e1 = res["body1.r_0"] / np.linalg.norm(res["body1.r_0"], axis=1)[:, None]
    np.testing.assert_allclose(res["anchor.frame_b.f"], 2 * e1 * res["spring3d.f"][:, None], atol=1e-7, rtol=0)


class Boom(fl.Model):
    """Two identical links on revolutes held by a spring-damper from a wall point: SpringDamperLine vs LineForce
    with a 1D SpringDamper (the set-up of a hydraulic cylinder between two frames of a mechanism)."""

    def __init__(self) -> None:
        super().__init__()
        self.world = World(g=G)
        self.wall = Fixed(r=[0.0, -0.5, 0.0])
        self.rev1, self.rev2 = Revolute(init={"phi": 0.2, "w": 0.0}), Revolute(init={"phi": 0.2, "w": 0.0})
        self.rod1, self.rod2 = FixedTranslation(r=[1.0, 0.0, 0.0]), FixedTranslation(r=[1.0, 0.0, 0.0])
        self.body1, self.body2 = Body(m=3.0, I=np.diag([0.01] * 3)), Body(m=3.0, I=np.diag([0.01] * 3))
        for rev, rod, body in ((self.rev1, self.rod1, self.body1), (self.rev2, self.rod2, self.body2)):
            self.connect(self.world.frame_b, rev.frame_a)
            self.connect(rev.frame_b, rod.frame_a)
            self.connect(rod.frame_b, body.frame_a)
        self.spring3d = SpringDamperLine(c=200.0, d=5.0, s_unstretched=0.9)
        self.line = LineForce()
        self.spring1d = tr.SpringDamper(c=200.0, d=5.0, s_rel0=0.9)
        self.connect(self.wall.frame_b, self.spring3d.frame_a, self.line.frame_a)
        self.connect(self.spring3d.frame_b, self.rod1.frame_b)
        self.connect(self.line.frame_b, self.rod2.frame_b)
        self.connect(self.line.flange_a, self.spring1d.flange_a)
        self.connect(self.line.flange_b, self.spring1d.flange_b)


def test_line_force_in_a_mechanism():
    """Same joint angle (1e-9 rad) and tension (1e-8 N) over 3 s; the joint coordinates are the only states.

    Run at rtol 1e-12: the two halves are different formulations, each with its own global error (≈ 3e-7 N at
    rtol 1e-10 against an rtol-1e-12 run); at rtol 1e-10 they agreed to 4e-11 N only while the builds kept their
    errors identical (before planar geometry was assumed by default; both builds agree to 1.5e-9 N here)."""
    sim = fl.Simulation(Boom(), use_cache=False)
    assert sorted(sim.states) == ["rev1.phi", "rev1.w", "rev2.phi", "rev2.w"]
    res = sim.run(3.0, dt_out=0.01, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(res["rev2.phi"], res["rev1.phi"], atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["line.f_b"], res["spring3d.f"], atol=1e-8, rtol=0)
    assert np.ptp(res["rev1.phi"]) > 1.0


class PushedApart(fl.Model):
    """A 1D force source F on a LineForce: (1) only flange_b connected, the source's support grounded
    (MSL cardinality rule: the tension acts at both frames); (2) the source's support on flange_a."""

    def __init__(self, F: float) -> None:
        super().__init__()
        self.world = World(g=0.0)
        self.F = Constant(k=F)
        self.anchor = Fixed(r=[0.0, 0.0, 0.0])
        self.line1, self.line2 = LineForce(), LineForce()
        self.src1, self.src2 = tr.Force(), tr.Force(use_support=True)
        self.body1 = free_body([1.0, 0.0, 0.0], m=2.0)
        self.body2 = free_body([0.0, 0.0, -1.0], m=2.0)
        self.connect(self.anchor.frame_b, self.line1.frame_a, self.line2.frame_a)
        self.connect(self.line1.frame_b, self.body1.frame_a)
        self.connect(self.line2.frame_b, self.body2.frame_a)
        self.connect(self.F.y, self.src1.f, self.src2.f)
        self.connect(self.src1.flange, self.line1.flange_b)
        self.connect(self.src2.flange, self.line2.flange_b)
        self.connect(self.src2.support, self.line2.flange_a)


def test_line_force_one_flange_connected():
    """A pushing source F moves each body away from the anchor as x = x0 + F t²/(2m) (1e-9 m); both line
    ends carry the same (compressive) tension −F, with flange_a unconnected as with the support on it; the
    anchor takes the reaction."""
    F, m = 3.0, 2.0
    res = fl.Simulation(PushedApart(F), use_cache=False).run(1.0, dt_out=0.05, **TOL)
    s = 1.0 + F * res.t**2 / (2 * m)
    np.testing.assert_allclose(res["body1.r_0"], np.outer(s, [1.0, 0.0, 0.0]), atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["body2.r_0"], np.outer(s, [0.0, 0.0, -1.0]), atol=1e-9, rtol=0)
    for k in (1, 2):
        np.testing.assert_allclose(res[f"line{k}.f_a"], -F, rtol=1e-12)
        np.testing.assert_allclose(res[f"line{k}.f_b"], -F, rtol=1e-12)
        np.testing.assert_allclose(res[f"line{k}.flange_b.s"], s, atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["anchor.frame_b.f"][-1], [-F, 0.0, F], atol=1e-9, rtol=0)  # pushed away


# ---------------------------------------------------------------------------------------------------------------
class Pushed(fl.Model):
    """Free bodies under gravity driven by a world-resolved force, a frame_b-resolved force and a world torque."""

    def __init__(self, F1, F2, tau, T2) -> None:
        super().__init__()
        self.world = World(g=G)
        self.src1, self.src2, self.src3 = VectorConstant(k=F1), VectorConstant(k=F2), VectorConstant(k=tau)
        self.force1 = WorldForce()
        self.force2 = WorldForce(resolve_in_frame="frame_b")
        self.torque3 = WorldTorque()
        self.body1 = free_body([0.0, 0.0, 0.0], [0.1, 0.2, 0.3], m=2.0)
        self.body2 = free_body([1.0, 0.0, 0.0], m=0.5, T0=T2)
        self.body3 = free_body([2.0, 0.0, 0.0], m=1.0, inertia=(0.1, 0.2, 0.3))
        self.connect(self.src1.y, self.force1.force)
        self.connect(self.src2.y, self.force2.force)
        self.connect(self.src3.y, self.torque3.torque)
        self.connect(self.force1.frame_b, self.body1.frame_a)
        self.connect(self.force2.frame_b, self.body2.frame_a)
        self.connect(self.torque3.frame_b, self.body3.frame_a)


def test_world_force_and_torque():
    """a = F/m + g exactly: r = r0 + v0 t + (F/m + g) t²/2 (1e-9 m) for a world-resolved force and for a
    body-resolved force on a body turned 30° about z (world force T0ᵀ F2); a world torque τ about a principal
    axis gives w = τ t / I_zz (1e-9 rad/s) and no translation other than the fall."""
    F1, F2, tau = np.array([1.0, 2.0, -0.5]), np.array([3.0, 0.0, 1.0]), np.array([0.0, 0.0, 0.6])
    T2 = rot_z(np.pi / 6)
    res = fl.Simulation(Pushed(F1, F2, tau, T2), use_cache=False).run(1.0, dt_out=0.05, **TOL)
    t = res.t[:, None]
    g = np.array([0.0, -G, 0.0])
    np.testing.assert_allclose(res["body1.r_0"], np.array([0.1, 0.2, 0.3]) * t + (F1 / 2.0 + g) * t**2 / 2,
                               atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["body2.r_0"], [1.0, 0.0, 0.0] + (T2.T @ F2 / 0.5 + g) * t**2 / 2, atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["body2.frame_a.T"][-1].reshape(3, 3, order="F"), T2, atol=1e-12, rtol=0)
    np.testing.assert_allclose(res["body3.w_a"], t * tau / 0.3, atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["body3.r_0"], [2.0, 0.0, 0.0] + g * t**2 / 2, atol=1e-9, rtol=0)


# ---------------------------------------------------------------------------------------------------------------
class CutSensors(fl.Model):
    """A pendulum hanging at rest with cut sensors at the hinge, and a cantilever with cut sensors at its root."""

    def __init__(self, m: float, m2: float, L2: float) -> None:
        super().__init__()
        self.world = World(g=G)
        self.rev = Revolute(init={"phi": -np.pi / 2, "w": 0.0})
        self.cut_a = CutForce()
        self.cut_w = CutForce(resolve_in_frame="world")
        self.rod = FixedTranslation(r=[1.0, 0.0, 0.0])
        self.body = Body(m=m, I=np.diag([0.01, 0.01, 0.01]))
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.cut_a.frame_a)
        self.connect(self.cut_a.frame_b, self.cut_w.frame_a)
        self.connect(self.cut_w.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.body.frame_a)
        self.wall = Fixed(r=[3.0, 0.0, 0.0])
        self.root_force = CutForce(resolve_in_frame="world")
        self.root_torque = CutTorque()
        self.beam = FixedTranslation(r=[L2, 0.0, 0.0])
        self.tip = Body(m=m2, I=np.diag([0.01, 0.01, 0.01]))
        self.connect(self.wall.frame_b, self.root_torque.frame_a)
        self.connect(self.root_torque.frame_b, self.root_force.frame_a)
        self.connect(self.root_force.frame_b, self.beam.frame_a)
        self.connect(self.beam.frame_b, self.tip.frame_a)


def test_cut_force_and_torque_statics():
    """Hanging pendulum at rest: the hinge side holds the body with +m g upwards, world-resolved (0, m g, 0) and
    in the link frame (x down) (−m g, 0, 0), 1e-9 N; cantilever of length L with a tip mass: root force
    (0, m g, 0) and root torque (0, 0, m g L), 1e-9."""
    m, m2, L2 = 2.5, 1.5, 0.8
    res = fl.Simulation(CutSensors(m, m2, L2), use_cache=False).run(1.0, dt_out=0.5, **TOL)
    np.testing.assert_allclose(res["cut_w.force"], [[0.0, m * G, 0.0]] * len(res.t), atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["cut_a.force"], [[-m * G, 0.0, 0.0]] * len(res.t), atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["root_force.force"], [[0.0, m2 * G, 0.0]] * len(res.t), atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["root_torque.torque"], [[0.0, 0.0, m2 * G * L2]] * len(res.t), atol=1e-9, rtol=0)


# ---------------------------------------------------------------------------------------------------------------
class Rotating(fl.Model):
    """A link turning at constant speed w about z (no gravity), with absolute and relative sensors at its end."""

    def __init__(self, phi0: float, w: float, L: float) -> None:
        super().__init__()
        self.world = World(g=0.0)
        self.rev = Revolute(init={"phi": phi0, "w": w})
        self.rod = FixedTranslation(r=[L, 0.0, 0.0])
        self.body = Body(m=1.0, I=np.diag([0.01, 0.01, 0.01]))
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.body.frame_a)
        self.pos, self.pos_a = AbsolutePosition(), AbsolutePosition(resolve_in_frame="frame_a")
        self.vel, self.vel_a = AbsoluteVelocity(), AbsoluteVelocity(resolve_in_frame="frame_a")
        self.omega, self.omega_a = AbsoluteAngularVelocity(), AbsoluteAngularVelocity(resolve_in_frame="frame_a")
        for s in (self.pos, self.pos_a, self.vel, self.vel_a, self.omega, self.omega_a):
            self.connect(self.rod.frame_b, s.frame_a)
        self.rel_pos = RelativePosition(resolve_in_frame="world")
        self.rel_vel_world = RelativeVelocity(resolve_in_frame="world")  # seen from the (inertial) world
        self.rel_vel_link = RelativeVelocity()  # seen from the turning link: the end is at rest
        self.connect(self.world.frame_b, self.rel_pos.frame_a, self.rel_vel_world.frame_a)
        self.connect(self.body.frame_a, self.rel_pos.frame_b, self.rel_vel_world.frame_b, self.rel_vel_link.frame_b)
        self.connect(self.rev.frame_b, self.rel_vel_link.frame_a)


def test_rotating_link_absolute_and_relative_sensors():
    """End of a link of length L turning at w: position L(cos φ, sin φ, 0), velocity w L (−sin φ, cos φ, 0),
    |v| = w L, in the link frame (L, 0, 0) and (0, w L, 0); angular velocity (0, 0, w); relative sensors
    from the world equal the absolute ones, seen from the link the end is at rest; all 1e-8."""
    phi0, w, L = 0.3, 2.0, 0.8
    res = fl.Simulation(Rotating(phi0, w, L), use_cache=False).run(2.0, dt_out=0.02, **TOL)
    n = len(res.t)
    phi = phi0 + w * res.t
    r_ref = L * np.column_stack([np.cos(phi), np.sin(phi), 0 * phi])
    v_ref = w * L * np.column_stack([-np.sin(phi), np.cos(phi), 0 * phi])
    np.testing.assert_allclose(np.linalg.norm(res["vel.v"], axis=1), w * L, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["vel.v"], v_ref, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["vel_a.v"], [[0.0, w * L, 0.0]] * n, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["pos.r"], r_ref, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["pos_a.r"], [[L, 0.0, 0.0]] * n, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["omega.w"], [[0.0, 0.0, w]] * n, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["omega_a.w"], [[0.0, 0.0, w]] * n, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["rel_pos.r_rel"], r_ref, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["rel_vel_world.v_rel"], v_ref, atol=1e-8, rtol=0)
    np.testing.assert_allclose(res["rel_vel_link.v_rel"], 0.0, atol=1e-8, rtol=0)


# ---------------------------------------------------------------------------------------------------------------
class TwoDrifting(fl.Model):
    """Two force-free bodies drifting at constant velocities, with distance and relative sensors between them."""

    def __init__(self, T2) -> None:
        super().__init__()
        self.world = World(g=0.0)
        self.body1 = free_body([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
        self.body2 = free_body([0.0, 1.0, 0.0], [0.0, 0.0, 0.5], T0=T2)
        self.dist = Distance()
        self.dist_self = Distance()
        self.rel_b = RelativePosition(resolve_in_frame="frame_b")
        self.rel_v = RelativeVelocity()
        for s in (self.dist, self.rel_b, self.rel_v):
            self.connect(self.body1.frame_a, s.frame_a)
            self.connect(self.body2.frame_a, s.frame_b)
        self.connect(self.body1.frame_a, self.dist_self.frame_a, self.dist_self.frame_b)


def test_distance_and_relative_sensors_between_free_bodies():
    """r_rel = (−t, 1, 0.5 t): distance |r_rel| (1e-9 m), r_rel resolved in body2 (turned 40° about z),
    relative velocity (−1, 0, 0.5) (body1 does not rotate), distance of a frame to itself 0; the sensors
    load nothing, so the bodies drift exactly (1e-9 m)."""
    T2 = rot_z(np.deg2rad(40.0))
    res = fl.Simulation(TwoDrifting(T2), use_cache=False).run(2.0, dt_out=0.05, **TOL)
    t = res.t
    r_rel = np.column_stack([-t, np.ones_like(t), 0.5 * t])
    np.testing.assert_allclose(res["body1.r_0"], np.outer(t, [1.0, 0.0, 0.0]), atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["dist.distance"], np.linalg.norm(r_rel, axis=1), atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["rel_b.r_rel"], r_rel @ T2.T, atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["rel_v.v_rel"], [[-1.0, 0.0, 0.5]] * len(t), atol=1e-9, rtol=0)
    np.testing.assert_allclose(res["dist_self.distance"], 0.0, atol=0.0, rtol=0)


def test_bad_resolve_in_frame():
    with pytest.raises(fl.ModelError, match=r"WorldForce: resolve_in_frame = 'frame_a' is not one of"):
        WorldForce(resolve_in_frame="frame_a")
    with pytest.raises(fl.ModelError, match=r"CutForce: resolve_in_frame = 'frame_b'"):
        CutForce(resolve_in_frame="frame_b")
