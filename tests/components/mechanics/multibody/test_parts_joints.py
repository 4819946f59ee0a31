"""Parts and joints built on the multibody core: FixedRotation, BodyShape/BodyBox/BodyCylinder, Universal,
Cylindrical, FreeMotion — each against an independent reference (textbook formula, quadrature, closed-form
motion or a conservation law) with the tolerance stated in the test's docstring.

World: x horizontal, y up, gravity −y (g = 9.81 m/s²).
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Revolute, World
from flexlib.components.mechanics.multibody.body_box import BodyBox
from flexlib.components.mechanics.multibody.body_cylinder import BodyCylinder
from flexlib.components.mechanics.multibody.body_shape import BodyShape
from flexlib.components.mechanics.multibody.cylindrical import Cylindrical
from flexlib.components.mechanics.multibody.fixed_rotation import FixedRotation
from flexlib.components.mechanics.multibody.free_motion import FreeMotion
from flexlib.components.mechanics.multibody.quaternions import quaternion_from_T
from flexlib.components.mechanics.multibody.universal import Universal
from flexlib.models.reference import closed_form as ref
from flexlib.models.reference.rigid_pendulum import PointOnRod, UniversalPendulum
from tests.components.mechanics.multibody.crossings import upward_crossings

G = 9.81
TIGHT = {"rtol": 1e-10, "atol": 1e-12}


def _frame_T(res: fl.Result, name: str) -> np.ndarray:
    """Transformation matrices world → frame over time, shape (n, 3, 3)."""
    return res[f"{name}.T"].reshape(-1, 3, 3, order="F")


# ---------------------------------------------------------------------------------------------
# Mass properties from geometry
# ---------------------------------------------------------------------------------------------
def _gauss_box_inertia(L: float, rects: list[tuple[float, float, float, float]], rho: float) -> tuple:
    """Mass and CM inertia (box axes: x length, y width, z height) of a prism of length L whose
    cross-section is the union of the rectangles (y0, y1, z0, z1), centred at the origin; by 2-point
    Gauss–Legendre quadrature per rectangle and along x (exact for the quadratic integrands)."""
    g, wq = np.polynomial.legendre.leggauss(2)

    def integrate(f, a0, a1, b0, b1, c0, c1):
        xs, ys, zs = [(lo + hi) / 2 + (hi - lo) / 2 * g for lo, hi in ((a0, a1), (b0, b1), (c0, c1))]
        jac = (a1 - a0) * (b1 - b0) * (c1 - c0) / 8
        return sum(wq[i] * wq[j] * wq[k] * f(xs[i], ys[j], zs[k]) for i in range(2) for j in range(2)
                   for k in range(2)) * jac

    m, Ixx, Iyy, Izz = 0.0, 0.0, 0.0, 0.0
    for y0, y1, z0, z1 in rects:
        box = (-L / 2, L / 2, y0, y1, z0, z1)
        m += rho * integrate(lambda x, y, z: 1.0, *box)
        Ixx += rho * integrate(lambda x, y, z: y**2 + z**2, *box)
        Iyy += rho * integrate(lambda x, y, z: x**2 + z**2, *box)
        Izz += rho * integrate(lambda x, y, z: x**2 + y**2, *box)
    return m, np.diag([Ixx, Iyy, Izz])


def test_body_box_solid_and_hollow_mass_properties():
    """Solid box: m = ρLWH, I = m/12·diag(W²+H², L²+H², L²+W²) (textbook). Hollow box (rectangular tube):
    mass and inertia by Gauss quadrature over the four walls of the cross-section. Orientation: length along
    frame z, width along frame x ⇒ the inertia's frame axes are permuted accordingly. All to 1e-12 relative."""
    L, W, H, rho = 1.2, 0.1, 0.06, 2700.0
    box = BodyBox(r=[L, 0, 0], width=W, height=H, density=rho)
    m = rho * L * W * H
    assert box.mass == pytest.approx(m, rel=1e-12)
    np.testing.assert_allclose(box.center_of_mass, [L / 2, 0, 0], atol=1e-15)
    np.testing.assert_allclose(box.inertia, m / 12 * np.diag([W**2 + H**2, L**2 + H**2, L**2 + W**2]), rtol=1e-12)

    Wi, Hi = 0.08, 0.03
    tube = BodyBox(r=[L, 0, 0], width=W, height=H, inner_width=Wi, inner_height=Hi, density=rho)
    walls = [(-W / 2, W / 2, Hi / 2, H / 2), (-W / 2, W / 2, -H / 2, -Hi / 2),  # top, bottom
             (-W / 2, -Wi / 2, -Hi / 2, Hi / 2), (Wi / 2, W / 2, -Hi / 2, Hi / 2)]  # sides
    m_ref, I_ref = _gauss_box_inertia(L, walls, rho)
    assert tube.mass == pytest.approx(m_ref, rel=1e-12)
    np.testing.assert_allclose(tube.inertia, I_ref, rtol=1e-12, atol=1e-12 * I_ref.max())
    # the run-time parameters of the parts carry the same values
    np.testing.assert_allclose(tube.body.parameter_value("I"), I_ref, rtol=1e-12, atol=1e-12 * I_ref.max())
    np.testing.assert_allclose(tube.frame_translation.parameter_value("r"), [L, 0, 0])

    turned = BodyBox(r=[0, 0, L], r_shape=[0, 0.2, 0], length_direction=[0, 0, 1], width_direction=[1, 0, 0],
                     length=L, width=W, height=H, density=rho)
    I_box = m / 12 * np.array([W**2 + H**2, L**2 + H**2, L**2 + W**2])  # (length, width, height) axes
    np.testing.assert_allclose(np.diag(turned.inertia), [I_box[1], I_box[2], I_box[0]], rtol=1e-12)
    np.testing.assert_allclose(turned.center_of_mass, [0, 0.2, L / 2], atol=1e-15)


def test_body_cylinder_solid_and_tube_mass_properties():
    """Solid: m = ρπr²L, I_axis = m r²/2, I_perp = m(3r² + L²)/12. Tube (r_o, r_i): m = ρπL(r_o² − r_i²),
    I_axis = m(r_o² + r_i²)/2, I_perp = m(3(r_o² + r_i²) + L²)/12 (textbook forms, not the outer − inner
    difference used by the component). Axis along frame y here. 1e-12 relative."""
    L, d, di, rho = 0.8, 0.1, 0.06, 7700.0
    cyl = BodyCylinder(r=[0, L, 0], diameter=d)
    r = d / 2
    m = rho * np.pi * r**2 * L
    assert cyl.mass == pytest.approx(m, rel=1e-12)
    np.testing.assert_allclose(cyl.center_of_mass, [0, L / 2, 0], atol=1e-15)
    I_perp = m * (3 * r**2 + L**2) / 12
    np.testing.assert_allclose(cyl.inertia, np.diag([I_perp, m * r**2 / 2, I_perp]), rtol=1e-12, atol=1e-15)

    tube = BodyCylinder(r=[0, L, 0], diameter=d, inner_diameter=di)
    ro, ri = d / 2, di / 2
    m = rho * np.pi * L * (ro**2 - ri**2)
    assert tube.mass == pytest.approx(m, rel=1e-12)
    I_perp = m * (3 * (ro**2 + ri**2) + L**2) / 12
    np.testing.assert_allclose(tube.inertia, np.diag([I_perp, m * (ro**2 + ri**2) / 2, I_perp]), rtol=1e-12,
                               atol=1e-15)
    # default diameter = length/20, default density 7700 (MSL)
    slim = BodyCylinder(r=[2.0, 0, 0])
    assert slim.mass == pytest.approx(7700.0 * np.pi * 0.05**2 * 2.0, rel=1e-12)


def test_geometry_input_errors_name_the_component():
    with pytest.raises(fl.ParameterError, match=r"BodyBox: inner_width = 0.2 must be smaller than width = 0.1"):
        BodyBox(r=[1, 0, 0], width=0.1, inner_width=0.2)
    with pytest.raises(fl.ParameterError, match=r"BodyBox: inner_height = 0.05 must be smaller than height = 0.05"):
        BodyBox(r=[1, 0, 0], width=0.1, height=0.05, inner_width=0.01, inner_height=0.05)
    with pytest.raises(fl.ParameterError, match=r"BodyBox: height = -0.1 must be > 0"):
        BodyBox(r=[1, 0, 0], height=-0.1)
    with pytest.raises(fl.ParameterError, match=r"BodyBox: length_direction .* has zero length"):
        BodyBox(r=[0, 0, 0])
    with pytest.raises(fl.ParameterError, match=r"BodyCylinder: inner_diameter = 0.1 must be smaller than"):
        BodyCylinder(r=[1, 0, 0], diameter=0.1, inner_diameter=0.1)
    with pytest.raises(fl.ParameterError, match=r"BodyCylinder: density = 0.0 must be > 0"):
        BodyCylinder(r=[1, 0, 0], density=0.0)
    with pytest.raises(fl.ParameterError, match=r"BodyShape: .*m = -2"):
        BodyShape(r=[1, 0, 0], r_CM=[0.5, 0, 0], m=-2.0)
    with pytest.raises(fl.ParameterError, match=r"FixedRotation: rotation axis n = \[0.0, 0.0, 0.0\] has zero"):
        FixedRotation(n=[0, 0, 0])
    with pytest.raises(fl.ParameterError, match=r"Universal: axes n_a = .* are parallel"):
        Universal(n_a=[0, 0, 1], n_b=[0, 0, -2])
    with pytest.raises(fl.ParameterError, match=r"Cylindrical: n = \[0.0, 0.0, 0.0\] has zero length"):
        Cylindrical(n=[0, 0, 0])
    with pytest.raises(fl.ParameterError, match=r"FreeMotion: Q_start = \[0.0, 0.0, 0.0, 0.0\] has zero length"):
        FreeMotion(Q_start=[0, 0, 0, 0])


# ---------------------------------------------------------------------------------------------
# FixedRotation
# ---------------------------------------------------------------------------------------------
class RotatedMass(fl.Model):
    """World → FixedRotation → body (``reverse``: the World holds frame_b and the body hangs at frame_a)."""

    def __init__(self, reverse: bool, r: list[float], angle: float, m: float, r_CM: list[float]) -> None:
        super().__init__()
        self.world = World(g=G)
        self.rot = FixedRotation(r=r, n=[0, 0, 1], angle=angle)
        self.body = Body(m=m, r_CM=r_CM, I=np.zeros((3, 3)))
        held, free = (self.rot.frame_b, self.rot.frame_a) if reverse else (self.rot.frame_a, self.rot.frame_b)
        self.connect(self.world.frame_b, held)
        self.connect(free, self.body.frame_a)


@pytest.mark.parametrize("reverse", [False, True], ids=["rooted_at_a", "rooted_at_b"])
def test_fixed_rotation_geometry_and_statics(reverse):
    """A frame rotated 90° about z: its x axis is the world y axis (frame_b from frame_a; in the reverse
    set-up frame_a's x axis is world −y), its origin at r (reverse: −T_aᵀ r). The weight of a point mass
    behind the part reaches the world as force (0, −m g, 0) and torque p_CM × (0, −m g, 0). 1e-12."""
    r, m, r_CM = [1.0, 2.0, 3.0], 2.0, [0.5, 0.0, 0.0]
    res = fl.Simulation(RotatedMass(reverse, r, np.pi / 2, m, r_CM), use_cache=False).run(0.1, dt_out=0.1)
    T_free = _frame_T(res, "body.frame_a")[-1]
    R_ref = Rotation.from_rotvec([0, 0, np.pi / 2]).as_matrix()  # active rotation: frame_b axes in frame_a
    if not reverse:
        np.testing.assert_allclose(T_free.T @ [1, 0, 0], [0, 1, 0], atol=1e-12)
        np.testing.assert_allclose(T_free, R_ref.T, atol=1e-12)
        origin = np.array(r)
    else:
        np.testing.assert_allclose(T_free.T @ [1, 0, 0], [0, -1, 0], atol=1e-12)
        np.testing.assert_allclose(T_free, R_ref, atol=1e-12)
        origin = -T_free.T @ r
    np.testing.assert_allclose(res["body.frame_a.r_0"][-1], origin, atol=1e-12)
    p_cm = origin + T_free.T @ r_CM
    weight = np.array([0.0, -m * G, 0.0])
    np.testing.assert_allclose(res["world.frame_b.f"][-1], weight, atol=1e-12)
    np.testing.assert_allclose(res["world.frame_b.t"][-1], np.cross(p_cm, weight), atol=1e-11)


# ---------------------------------------------------------------------------------------------
# BodyShape / BodyBox pendulum
# ---------------------------------------------------------------------------------------------
class ShapePendulum(fl.Model):
    """Revolute (axis z) at the world origin carrying a BodyShape or BodyBox along the link's x axis."""

    def __init__(self, link: BodyShape, theta0: float) -> None:
        super().__init__()
        self.world = World(g=G)
        self.rev = Revolute(n=[0, 0, 1], init={"phi": theta0 - np.pi / 2, "w": 0.0})
        self.link = link
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.link.frame_a)


@pytest.mark.parametrize("kind", ["shape", "box"])
def test_body_shape_pendulum_period(kind):
    """Physical pendulum (θ0 = 1.0 rad): period vs the exact elliptic-integral period of
    ``ref.physical_pendulum_period`` to 1e-5 relative; BodyShape with explicit m, r_CM, I, and a BodyBox
    whose I_cm about z is the textbook m(L² + W²)/12. frame_b stays at distance L from the pivot (1e-10)."""
    theta0, L = 1.0, 0.9
    if kind == "shape":
        m, d, I_cm = 1.5, 0.6, 0.07
        link = BodyShape(r=[L, 0, 0], r_CM=[d, 0, 0], m=m, I=np.diag([0.01, I_cm, I_cm]))
    else:
        W = 0.12
        link = BodyBox(r=[L, 0, 0], width=W, height=0.05, density=1000.0)
        m, d = link.mass, L / 2
        I_cm = m * (L**2 + W**2) / 12
    sim = fl.Simulation(ShapePendulum(link, theta0), use_cache=False)
    assert sorted(sim.states) == ["rev.phi", "rev.w"]
    res = sim.run(5.0, dt_out=2e-3, **TIGHT)
    theta = res["rev.phi"] + np.pi / 2
    periods = np.diff(upward_crossings(res.t, theta, res["rev.w"]))
    assert len(periods) >= 2
    np.testing.assert_allclose(periods, ref.physical_pendulum_period(m, d, I_cm, G, theta0), rtol=1e-5)
    tip = res["link.frame_b.r_0"]
    np.testing.assert_allclose(np.linalg.norm(tip, axis=1), L, rtol=1e-10)
    np.testing.assert_allclose(tip[:, 2], 0.0, atol=1e-12)


# ---------------------------------------------------------------------------------------------
# Universal joint
# ---------------------------------------------------------------------------------------------
def _tip(phi_a: float, phi_b: float, L: float) -> np.ndarray:
    """Tip of the rod in world: T_b = T(z, φ_b) T(x, φ_a) is passive, so the active rotation is its
    transpose R_x(φ_a) R_z(φ_b) (SciPy, independent of the library's planar_rotation)."""
    Ra = Rotation.from_rotvec([phi_a, 0, 0]).as_matrix()
    Rb = Rotation.from_rotvec([0, 0, phi_b]).as_matrix()
    return Ra @ Rb @ np.array([0.0, -L, 0.0])


@pytest.mark.parametrize("solver", ["ida", "casadi-idas"])
def test_universal_conical_pendulum(solver):
    """A point mass on a universal joint is a spherical pendulum; started on the conical orbit of tilt θ
    (closed form Ω = sqrt(g/(L cos θ))) it keeps its tilt (1e-7 rad) and precesses at Ω (1e-7 relative);
    energy is conserved to 1e-8 relative. Run on both backends: on the default one, the point mass's
    acceleration (a derivative-level unknown) is kept out of IDA's error test, without which the step size
    collapsed (27 600 steps for 0.01 s)."""
    L, m, theta = 0.8, 1.2, 0.5
    omega = np.sqrt(G / (L * np.cos(theta)))
    phi_a, phi_b = theta, 0.0  # tilt the rod in the y–z plane
    p0 = _tip(phi_a, phi_b, L)
    v0 = np.cross([0, omega, 0], p0)  # rotation about the vertical
    h = 1e-6
    J = np.column_stack([(_tip(phi_a + h, phi_b, L) - _tip(phi_a - h, phi_b, L)) / (2 * h),
                         (_tip(phi_a, phi_b + h, L) - _tip(phi_a, phi_b - h, L)) / (2 * h)])
    rates, *_ = np.linalg.lstsq(J, v0, rcond=None)
    assert np.linalg.norm(J @ rates - v0) < 1e-8
    init = {"phi_a": phi_a, "phi_b": phi_b, "w_a": rates[0], "w_b": rates[1]}
    sim = fl.Simulation(UniversalPendulum(PointOnRod(L, m), init), use_cache=False)
    assert sorted(sim.states) == ["joint.phi_a", "joint.phi_b", "joint.w_a", "joint.w_b"]
    res = sim.run(2.0, dt_out=0.01, solver=solver, **TIGHT)
    p = res["link.mass.r_0"]
    np.testing.assert_allclose(np.arccos(-p[:, 1] / L), theta, atol=1e-7)
    azimuth = np.unwrap(np.arctan2(-p[:, 2], p[:, 0]))  # positive about +y
    np.testing.assert_allclose(azimuth - azimuth[0], omega * res.t, rtol=1e-7, atol=1e-7)
    energy = 0.5 * m * np.sum(res["link.mass.v_0"] ** 2, axis=1) + m * G * p[:, 1]
    np.testing.assert_allclose(energy, energy[0], rtol=1e-8)


def test_universal_carrying_cylinder_energy():
    """A BodyCylinder (with rotational inertia) swinging and twisting on a universal joint: total energy
    ½ m v_CM² + ½ ωᵀ I ω + m g y_CM conserved to 1e-6 relative over 3 s."""
    link = BodyCylinder(r=[0, -0.6, 0], diameter=0.08, density=2000.0)
    init = {"phi_a": 0.7, "phi_b": -0.4, "w_a": 1.0, "w_b": 2.5}
    res = fl.Simulation(UniversalPendulum(link, init), use_cache=False).run(3.0, dt_out=0.01, **TIGHT)
    m, inertia, r_cm = link.mass, link.inertia, link.center_of_mass
    T = _frame_T(res, "link.frame_a")
    w = res["link.body.w_a"]
    v_cm = res["link.body.v_0"] + np.einsum("nji,nj->ni", T, np.cross(w, r_cm))
    y_cm = res["link.body.r_0"][:, 1] + np.einsum("nj,j->n", T[:, :, 1], r_cm)
    energy = 0.5 * m * np.sum(v_cm**2, axis=1) + 0.5 * np.einsum("ni,ij,nj->n", w, inertia, w) + m * G * y_cm
    assert np.ptp(res["joint.phi_b"]) > 0.5 and np.ptp(res["joint.phi_a"]) > 0.5  # both axes move
    np.testing.assert_allclose(energy, energy[0], rtol=1e-6)


# ---------------------------------------------------------------------------------------------
# Cylindrical joint
# ---------------------------------------------------------------------------------------------
class VerticalCylindrical(fl.Model):
    """Cylindrical joint with a vertical axis at the world origin, an off-axis box spinning on it."""

    def __init__(self, w0: float) -> None:
        super().__init__()
        self.world = World(g=G)
        self.joint = Cylindrical(n=[0, 1, 0], init={"s": 0.0, "v": 0.0, "phi": 0.0, "w": w0})
        self.arm = BodyBox(r=[0.3, 0.0, 0.0], width=0.05, density=1000.0)
        self.connect(self.world.frame_b, self.joint.frame_a)
        self.connect(self.joint.frame_b, self.arm.frame_a)


def test_cylindrical_slide_and_spin():
    """Free fall along the vertical axis, s(t) = −½ g t², v = −g t (1e-8), while the off-axis arm spins at
    constant rate (no torque about the axis): φ(t) = ω0 t (1e-8 rad); the arm's CM stays at radius 0.15 m."""
    w0 = 3.0
    sim = fl.Simulation(VerticalCylindrical(w0), use_cache=False)
    assert sorted(sim.states) == ["joint.phi", "joint.s", "joint.v", "joint.w"]
    res = sim.run(1.0, dt_out=0.01, **TIGHT)
    t = res.t
    np.testing.assert_allclose(res["joint.s"], -0.5 * G * t**2, atol=1e-8)
    np.testing.assert_allclose(res["joint.v"], -G * t, atol=1e-8)
    np.testing.assert_allclose(res["joint.w"], w0, atol=1e-8)
    np.testing.assert_allclose(res["joint.phi"], w0 * t, atol=1e-8)
    T = _frame_T(res, "arm.frame_a")
    cm = res["arm.body.r_0"] + np.einsum("nji,j->ni", T, [0.15, 0, 0])
    np.testing.assert_allclose(np.hypot(cm[:, 0], cm[:, 2]), 0.15, atol=1e-10)


# ---------------------------------------------------------------------------------------------
# FreeMotion: a floating body
# ---------------------------------------------------------------------------------------------
M_FREE, R_CM_FREE, I_FREE = 2.0, np.array([0.1, -0.05, 0.2]), np.diag([0.05, 0.08, 0.11])


class FreeFlight(fl.Model):
    """World –FreeMotion– body; ``reverse`` connects the world to the joint's frame_b and the body to its frame_a
    (the joint then writes the orientation of frame_a from frame_b)."""

    def __init__(self, reverse: bool, p0: np.ndarray, v0: np.ndarray, w0: np.ndarray) -> None:
        super().__init__()
        self.world = World(g=G)
        if not reverse:  # relative = absolute coordinates of the body frame
            self.joint = FreeMotion(orientation_fixed=True, w_fixed=True, w_start=w0,
                                    init={"r_rel_a": p0, "v_rel_a": v0})
        else:  # at t0 the body frame is aligned with the world: r_rel_a = −p0, w_rel_b = −w0,
            # v_rel_a = d/dt(T_a (0 − r_a)) = w0 × p0 − v0
            self.joint = FreeMotion(orientation_fixed=True, w_fixed=True, w_start=-w0,
                                    init={"r_rel_a": -p0, "v_rel_a": np.cross(w0, p0) - v0})
        self.body = Body(m=M_FREE, r_CM=R_CM_FREE, I=I_FREE)
        world_side, body_side = (self.joint.frame_b, self.joint.frame_a) if reverse else \
            (self.joint.frame_a, self.joint.frame_b)
        self.connect(self.world.frame_b, world_side)
        self.connect(body_side, self.body.frame_a)


P0, V0, W0 = np.array([0.5, 1.0, -0.3]), np.array([2.0, 5.0, 1.0]), np.array([3.0, 0.4, -1.5])


@pytest.mark.parametrize(("reverse", "t_end"), [(False, 1.0), (True, 1.0)], ids=["rooted_at_a", "rooted_at_b"])
def test_free_motion_flight_and_torque_free_spin(reverse, t_end):
    """Projectile + torque-free spin: the CM follows p(t) = p_CM0 + v_CM0 t + ½ g t² (1e-9 m); the angular
    momentum about the CM in world coordinates, H = T_bᵀ I ω, is conserved to 1e-8 relative; the relative
    quaternion keeps unit norm (1e-10).

    With the reversed joint (body at frame_a) the body's velocity is an algebraic variable computed from the
    quaternion's derivatives; the engine keeps such derivative-level unknowns out of IDA's error test
    (``flexlib.compile.structure.derivative_level``), without which the run failed after 0.15 s."""
    p0, v0, w0 = P0, V0, W0
    sim = fl.Simulation(FreeFlight(reverse, p0, v0, w0), use_cache=False)
    res = sim.run(t_end, dt_out=0.01, rtol=1e-11, atol=1e-12)
    T = _frame_T(res, "body.frame_a")
    np.testing.assert_allclose(T[0], np.eye(3), atol=1e-12)
    cm = res["body.r_0"] + np.einsum("nji,j->ni", T, R_CM_FREE)
    cm0, vcm0 = p0 + R_CM_FREE, v0 + np.cross(w0, R_CM_FREE)
    t = res.t[:, None]
    np.testing.assert_allclose(cm, cm0 + vcm0 * t + 0.5 * np.array([0, -G, 0]) * t**2, atol=1e-9)
    w = res["body.w_a"]
    np.testing.assert_allclose(w[0], w0, atol=1e-12)
    H = np.einsum("nji,nj->ni", T, w @ I_FREE)
    np.testing.assert_allclose(H - H[0], 0.0, atol=1e-8 * np.linalg.norm(H[0]))
    assert np.ptp(w, axis=0).max() > 0.1  # the body really tumbles (ω changes in the body frame)
    np.testing.assert_allclose(np.sum(res["joint.Q"] ** 2, axis=1), 1.0, atol=1e-10)


def test_free_motion_start_orientation():
    """Q_start sets the relative orientation at t0 (3 residues): a start rotation of 0.7 rad about the
    axis (1, 2, 2)/3 reproduces SciPy's rotation matrix to 1e-12."""
    e = np.array([1.0, 2.0, 2.0]) / 3
    R = Rotation.from_rotvec(0.7 * e).as_matrix()  # active: body axes in world
    model = FreeFlight(False, np.zeros(3), np.zeros(3), np.zeros(3))
    model.joint.Q_start = quaternion_from_T(R.T)
    res = fl.Simulation(model, use_cache=False).run(0.1, dt_out=0.1, **TIGHT)
    np.testing.assert_allclose(_frame_T(res, "body.frame_a")[0], R.T, atol=1e-12)


class Whirl(fl.Model):
    """A hub spinning freely about the vertical axis carries a slider on a frictionless radial prismatic joint."""

    def __init__(self) -> None:
        super().__init__()
        from flexlib.components.mechanics.multibody.prismatic import Prismatic

        self.world = World(g=G)
        self.hub = Revolute(n=[0, 1, 0], init={"phi": 0.0, "w": 3.0})
        self.arm = Body(m=1.0, I=np.diag([0.25, 0.5, 0.25]))
        self.slide = Prismatic(n=[1, 0, 0], init={"s": 0.1, "v": 0.0})
        self.slider = Body(m=2.0, I=np.diag([0.01, 0.01, 0.01]))
        self.connect(self.world.frame_b, self.hub.frame_a)
        self.connect(self.hub.frame_b, self.arm.frame_a)
        self.connect(self.hub.frame_b, self.slide.frame_a)
        self.connect(self.slide.frame_b, self.slider.frame_a)


def test_slider_on_a_spinning_hub_keeps_momentum_and_energy():
    """The slider is flung outward (0.1 → 0.7 m in 1 s) while the hub slows down: angular momentum about the axis
    ``(J_hub + J_slider + m s²) ω`` and kinetic energy ``½ (J_hub + J_slider + m s²) ω² + ½ m ṡ²`` are conserved to
    1e-7 (measured 1e-9 at rtol 1e-10). The Coriolis force ``2 m ω ṡ`` is what slows the hub: a prismatic joint
    that dropped its term from the frame acceleration it carries would break the momentum balance."""
    res = fl.Simulation(Whirl(), use_cache=False).run(1.0, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False)
    s, v, w = res["slide.s"], res["slide.v"], res["hub.w"]
    assert s[-1] > 0.6 and w[-1] < 0.5 * w[0]
    J = 0.5 + 0.01 + 2.0 * s**2
    momentum, energy = J * w, 0.5 * J * w**2 + 0.5 * 2.0 * v**2
    np.testing.assert_allclose(momentum, momentum[0], rtol=1e-7)
    np.testing.assert_allclose(energy, energy[0], rtol=1e-7)
