"""Self-checks of ``flexlib.models.reference.closed_form``: each reference against a second computation.

The second computation never reuses the reference's formula: closed forms are checked against
``solve_ivp`` of the minimal-coordinate ODE, minimal-coordinate ODEs against constrained
Newton–Euler in Cartesian coordinates (or a rotation-matrix rigid-body integration), the
Freudenstein/Norton closed form against circle intersection, virtual work against Newton
statics. Tolerances are 1e-8 relative or tighter unless a docstring says otherwise.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flexlib.models.reference import closed_form as ref

ODE = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-13}


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angle difference mapped to (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(angle)))


# ---------------------------------------------------------------------------------------------
# 1. Pendulum periods
# ---------------------------------------------------------------------------------------------


def quarter_period_ode(J: float, mgd: float, theta0: float) -> float:
    """Time from rest at theta0 to the first zero crossing of J θ'' = -mgd sin θ (solve_ivp)."""

    def crossing(t, y):
        return y[0]

    crossing.terminal = True
    crossing.direction = -1
    sol = solve_ivp(lambda t, y: [y[1], -mgd / J * math.sin(y[0])], (0.0, 100.0), [theta0, 0.0],
                    events=crossing, **ODE)
    return float(sol.t_events[0][0])


@pytest.mark.parametrize("theta0", [0.05, 1.0, 2.5, 3.1])
def test_pendulum_period_matches_ode(theta0):
    """T = 4 sqrt(L/g) K(sin²(θ0/2)) vs 4 × quarter period of θ'' = -(g/L) sin θ (rtol 1e-9)."""
    L, g = 0.7, 9.81
    T_ode = 4.0 * quarter_period_ode(L, g, theta0)
    np.testing.assert_allclose(ref.pendulum_period(L, g, theta0), T_ode, rtol=1e-9)


def test_pendulum_period_small_amplitude():
    """Small θ0: T/T0 = 1 + θ0²/16 + 11θ0⁴/3072 + O(θ0⁶) (Landau §11); θ0 = 0 gives T0 exactly."""
    L, g, th = 1.3, 9.81, 1e-2
    T0 = ref.pendulum_period_small(L, g)
    np.testing.assert_allclose(T0, 2.0 * math.pi * math.sqrt(L / g), rtol=1e-15)
    np.testing.assert_allclose(ref.pendulum_period(L, g, 0.0), T0, rtol=1e-15)
    np.testing.assert_allclose(ref.pendulum_period(L, g, th) / T0, 1 + th**2 / 16 + 11 * th**4 / 3072, rtol=1e-13)
    np.testing.assert_allclose(ref.pendulum_period(L, g, -th), ref.pendulum_period(L, g, th), rtol=1e-15)


@pytest.mark.parametrize("theta0", [0.0, 0.3, 2.0])
def test_physical_pendulum_period(theta0):
    """Physical pendulum vs ODE (I_cm + m d²) θ'' = -m g d sin θ (rtol 1e-9); rod → L_eq = 2L/3."""
    m, d, I_cm, g = 2.5, 0.4, 0.09, 9.81
    T = ref.physical_pendulum_period(m, d, I_cm, g, theta0)
    if theta0 > 0.0:
        np.testing.assert_allclose(T, 4.0 * quarter_period_ode(I_cm + m * d * d, m * g * d, theta0), rtol=1e-9)
    else:
        np.testing.assert_allclose(T, 2 * math.pi * math.sqrt((I_cm + m * d * d) / (m * g * d)), rtol=1e-14)
    L = 1.2  # uniform rod pinned at one end
    np.testing.assert_allclose(ref.physical_pendulum_period(m, L / 2, m * L**2 / 12, g, theta0),
                               ref.pendulum_period(2 * L / 3, g, theta0), rtol=1e-14)


def test_pendulum_rejects_rotating_amplitude():
    with pytest.raises(ValueError, match="theta0"):
        ref.pendulum_period(1.0, 9.81, math.pi)


# ---------------------------------------------------------------------------------------------
# 2. Double pendulum
# ---------------------------------------------------------------------------------------------


def e_dir(th: float) -> np.ndarray:
    """Unit vector along a link hanging at absolute angle th from the downward vertical."""
    return np.array([math.sin(th), -math.cos(th)])


def newton_euler_double_pendulum(m1, m2, L1, d1, d2, J1, J2, g, y):
    """Angular accelerations from constrained Newton–Euler in Cartesian body coordinates.

    Coordinates q = (x1, y1, θ1, x2, y2, θ2) (CM positions, body rotations); constraints
    Φ1 = r1 - d1 e(θ1) = 0 (ground pin), Φ2 = r2 - d2 e(θ2) - r1 - (L1 - d1) e(θ1) = 0 (middle
    pin); KKT system [[M, Φqᵀ], [Φq, 0]] [q̈; λ] = [F; γ] with γ = -(Φq q̇)_q q̇ (Haug,
    *Computer-Aided Kinematics and Dynamics of Mechanical Systems*, §6.3).
    """
    th1, th2, w1, w2 = y
    e1, e2 = e_dir(th1), e_dir(th2)
    de1, de2 = np.array([-e1[1], e1[0]]), np.array([-e2[1], e2[0]])  # d e/dθ = (cos θ, sin θ)
    M = np.diag([m1, m1, J1, m2, m2, J2])
    Phi_q = np.zeros((4, 6))
    Phi_q[0:2, 0:2] = np.eye(2)
    Phi_q[0:2, 2] = -d1 * de1
    Phi_q[2:4, 0:2] = -np.eye(2)
    Phi_q[2:4, 2] = -(L1 - d1) * de1
    Phi_q[2:4, 3:5] = np.eye(2)
    Phi_q[2:4, 5] = -d2 * de2
    gamma = np.concatenate([-d1 * e1 * w1**2, -d2 * e2 * w2**2 - (L1 - d1) * e1 * w1**2])
    F = np.array([0.0, -m1 * g, 0.0, 0.0, -m2 * g, 0.0])
    K = np.block([[M, Phi_q.T], [Phi_q, np.zeros((4, 4))]])
    sol = np.linalg.solve(K, np.concatenate([F, gamma]))
    return sol[2], sol[5]


CASES_DP = {
    "point": (1.3, 0.7, 0.9, 0.6, 9.81),
    "rods": (2.0, 1.1, 1.0, 0.8, 9.81),
}


@pytest.mark.parametrize("kind", ["point", "rods"])
def test_double_pendulum_rhs_matches_newton_euler(kind):
    """Lagrangian RHS vs Cartesian constrained Newton–Euler at random states (rtol 1e-11)."""
    m1, m2, L1, L2, g = CASES_DP[kind]
    if kind == "point":
        rhs, _ = ref.double_pendulum_point_masses(m1, m2, L1, L2, g)
        body = (m1, m2, L1, L1, L2, 0.0, 0.0, g)
    else:
        rhs, _ = ref.double_pendulum_rods(m1, m2, L1, L2, g)
        body = (m1, m2, L1, L1 / 2, L2 / 2, m1 * L1**2 / 12, m2 * L2**2 / 12, g)
    rng = np.random.default_rng(1)
    for y in rng.uniform([-np.pi, -np.pi, -6, -6], [np.pi, np.pi, 6, 6], size=(20, 4)):
        dy = rhs(0.0, y)
        np.testing.assert_allclose(dy[:2], y[2:], rtol=0, atol=0)
        np.testing.assert_allclose(dy[2:], newton_euler_double_pendulum(*body, y), rtol=1e-11, atol=1e-11)


@pytest.mark.parametrize("kind", ["point", "rods"])
def test_double_pendulum_energy_conserved(kind):
    """Energy of a chaotic 5 s trajectory (solve_ivp, rtol 1e-12) constant to 1e-9 × m g L."""
    m1, m2, L1, L2, g = CASES_DP[kind]
    make = ref.double_pendulum_point_masses if kind == "point" else ref.double_pendulum_rods
    rhs, energy = make(m1, m2, L1, L2, g)
    sol = solve_ivp(rhs, (0.0, 5.0), [2.0, -1.0, 0.5, 3.0], **ODE)
    E = energy(sol.y)
    assert np.ptp(np.unwrap(sol.y[1])) > 2.0  # genuinely large motion
    np.testing.assert_allclose(E, E[0], rtol=0, atol=1e-9 * (m1 + m2) * g * (L1 + L2))
    np.testing.assert_allclose(energy(sol.y[:, 0]), E[0], rtol=1e-15)


def test_double_pendulum_normal_modes():
    """Equal masses and lengths: ω² = (g/L)(2 ∓ √2) (Thornton & Marion ch. 12) from the RHS Jacobian."""
    m, L, g = 0.8, 0.5, 9.81
    rhs, _ = ref.double_pendulum_point_masses(m, m, L, L, g)
    h = 1e-5
    jac = np.column_stack([(rhs(0, h * e) - rhs(0, -h * e)) / (2 * h) for e in np.eye(4)])
    omega2 = np.sort(-np.linalg.eigvals(jac[2:, :2]).real)
    np.testing.assert_allclose(omega2, g / L * np.array([2 - math.sqrt(2), 2 + math.sqrt(2)]), rtol=1e-8)


def test_double_pendulum_points():
    """Joint and tip positions: link lengths and the hanging configuration."""
    p = ref.double_pendulum_points(0.4, -1.1, 0.9, 0.6)
    np.testing.assert_allclose(np.linalg.norm(p[0]), 0.9, rtol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(p[1] - p[0]), 0.6, rtol=1e-15)
    np.testing.assert_allclose(ref.double_pendulum_points(0.0, 0.0, 1.0, 2.0), [[0, -1], [0, -3]], atol=1e-15)


# ---------------------------------------------------------------------------------------------
# 3. Heavy symmetric top
# ---------------------------------------------------------------------------------------------

TOP = {"m": 0.5, "g": 9.81, "l": 0.04, "I1": 1.2e-3, "I3": 4.0e-4}  # I1 about the tip


def rigid_body_top(y0_R: np.ndarray, w0: np.ndarray, t: np.ndarray, up: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Integrate Euler's equations about the fixed tip plus dR/dt = R [ω]× (no Euler angles).

    I ω̇ = (I ω) × ω + Rᵀ (l R e3 × (0, 0, -m g)), l = tip → CM, I = diag(I1, I1, I3); state (R, ω_body).
    Gravity acts along -e_up (up = 2: z, up = 1: y). Returns R(t) (n, 3, 3) and ω_body(t) (n, 3).
    """
    m, g, lcm, I1, I3 = top_params()
    inertia = np.array([I1, I1, I3])
    weight = np.zeros(3)
    weight[up] = -m * g

    def f(_t, y):
        R, w = y[:9].reshape(3, 3), y[9:]
        torque = R.T @ np.cross(lcm * R[:, 2], weight)
        dw = (np.cross(inertia * w, w) + torque) / inertia
        W = np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
        return np.concatenate([(R @ W).ravel(), dw])

    sol = solve_ivp(f, (0.0, t[-1]), np.concatenate([y0_R.ravel(), w0]), t_eval=t, **ODE)
    return sol.y[:9].T.reshape(-1, 3, 3), sol.y[9:].T


def top_params():
    return TOP["m"], TOP["g"], TOP["l"], TOP["I1"], TOP["I3"]


@pytest.mark.parametrize(("theta", "omega3"), [(math.radians(30), 100.0), (2.0, 20.0), (math.pi / 2, 50.0)])
def test_top_roots_satisfy_quadratic(theta, omega3):
    """Both roots solve I1 cosθ Ω² - I3 ω3 Ω + m g l = 0; ψ̇ form gives the same Ω (rtol 1e-12)."""
    m, g, lcm, I1, I3 = top_params()
    slow, fast = ref.heavy_top_steady_precession(m, g, lcm, I1, I3, theta, omega3)
    assert abs(slow) <= abs(fast)
    for Om in (slow, fast):
        if math.isfinite(Om):
            scale = I3 * abs(omega3 * Om) + m * g * lcm
            assert abs(I1 * math.cos(theta) * Om**2 - I3 * omega3 * Om + m * g * lcm) < 1e-13 * scale
            psi_dot = omega3 - Om * math.cos(theta)
            roots = ref.heavy_top_steady_precession(m, g, lcm, I1, I3, theta, psi_dot, spin_kind="psi_dot")
            assert min(abs(r - Om) for r in roots) < 1e-10 * abs(Om)
    if theta == math.pi / 2:  # cos θ ~ 6e-17: single physical root m g l / (I3 ω3)
        np.testing.assert_allclose(slow, m * g * lcm / (I3 * omega3), rtol=1e-14)
    if theta > math.pi / 2:
        assert slow * fast < 0.0  # hanging top: opposite signs


def test_top_slow_spin_raises():
    m, g, lcm, I1, I3 = top_params()
    with pytest.raises(ValueError, match="discriminant"):
        ref.heavy_top_steady_precession(m, g, lcm, I1, I3, 0.5, 10.0)


def steady_cases():
    m, g, lcm, I1, I3 = top_params()
    out = []
    for theta, w3 in [(math.radians(30), 100.0), (2.0, 20.0)]:
        for Om in ref.heavy_top_steady_precession(m, g, lcm, I1, I3, theta, w3):
            out.append((theta, w3, Om))
    return out


@pytest.mark.parametrize(("theta", "omega3", "Omega"), steady_cases())
def test_top_steady_precession_euler_angle_ode(theta, omega3, Omega):
    """Euler-angle ODE from (θ, θ̇=0, φ̇=Ω, ψ̇=ω3-Ω cosθ): θ stays put (1e-9), φ = Ω t (1e-8)."""
    rhs = ref.symmetric_top_euler_rhs(*top_params())
    ic = ref.heavy_top_initial_conditions(theta, omega3, Omega)
    t = np.linspace(0.0, 0.5, 51)
    sol = solve_ivp(rhs, (0, t[-1]), [0.0, theta, 0.0, Omega, 0.0, ic.psi_dot], t_eval=t, **ODE)
    np.testing.assert_allclose(sol.y[1], theta, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sol.y[0], Omega * t, rtol=1e-8, atol=1e-10)


@pytest.mark.parametrize(("theta", "omega3", "Omega"), steady_cases())
def test_top_steady_precession_rigid_body(theta, omega3, Omega):
    """Rotation-matrix + Euler-equation integration from heavy_top_initial_conditions.

    The symmetry axis must follow e3(t) = (sin(φ0+Ωt) sinθ, -cos(φ0+Ωt) sinθ, cosθ) (atol 1e-8),
    ω_body[2] = ω3 stays constant; ω_world = Ω ẑ + ψ̇ e3 at t = 0 (Goldstein §4.9).
    """
    phi0, psi0 = 0.3, -0.7
    ic = ref.heavy_top_initial_conditions(theta, omega3, Omega, phi=phi0, psi=psi0, l=TOP["l"])
    e3 = ic.R[:, 2]
    np.testing.assert_allclose(ic.omega_world, Omega * np.array([0, 0, 1.0]) + ic.psi_dot * e3, atol=1e-12)
    np.testing.assert_allclose(ic.R.T @ ic.R, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(ic.r_cm, TOP["l"] * e3, rtol=1e-15)
    np.testing.assert_allclose(ic.v_cm, np.cross(ic.omega_world, ic.r_cm), rtol=1e-15)
    t = np.linspace(0.0, 0.5, 26)
    R, w = rigid_body_top(ic.R, ic.omega_body, t)
    phase = phi0 + Omega * t
    axis = np.column_stack([np.sin(phase) * math.sin(theta), -np.cos(phase) * math.sin(theta),
                            np.full_like(t, math.cos(theta))])
    np.testing.assert_allclose(R[:, :, 2], axis, rtol=0, atol=1e-8)
    np.testing.assert_allclose(w[:, 2], omega3, rtol=1e-10)


def test_top_initial_conditions_y_up():
    """world_up="y": same motion in a y-up world (gravity -y): axis precesses about +y at Ω, keeps
    e3·ŷ = cos θ (atol 1e-8); world quantities are the z-up ones rotated by R_x(-π/2)."""
    m, g, lcm, I1, I3 = top_params()
    theta, omega3 = math.radians(30), 100.0
    Omega = ref.heavy_top_steady_precession(m, g, lcm, I1, I3, theta, omega3)[0]
    z = ref.heavy_top_initial_conditions(theta, omega3, Omega, phi=0.3, l=lcm)
    y = ref.heavy_top_initial_conditions(theta, omega3, Omega, phi=0.3, l=lcm, world_up="y")
    Q = ref.WORLD_Z_UP_TO_Y_UP
    np.testing.assert_allclose(Q @ [0, 0, 1.0], [0, 1.0, 0], atol=0)
    np.testing.assert_allclose(np.linalg.det(Q), 1.0, rtol=0)
    for name in ("R", "omega_world", "r_cm", "v_cm"):
        np.testing.assert_allclose(getattr(y, name), Q @ getattr(z, name), rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(y.omega_body, z.omega_body, rtol=0)
    np.testing.assert_allclose(y.omega_world, Omega * np.array([0, 1.0, 0]) + y.psi_dot * y.R[:, 2], atol=1e-12)
    t = np.linspace(0.0, 0.5, 11)
    R, _ = rigid_body_top(y.R, y.omega_body, t, up=1)
    axis0 = y.R[:, 2]
    c, s = np.cos(Omega * t), np.sin(Omega * t)  # rotation about +y: (x, z) -> (c x + s z, -s x + c z)
    expected = np.column_stack([c * axis0[0] + s * axis0[2], np.full_like(t, axis0[1]), -s * axis0[0] + c * axis0[2]])
    np.testing.assert_allclose(R[:, :, 2], expected, rtol=0, atol=1e-8)
    np.testing.assert_allclose(axis0[1], math.cos(theta), rtol=1e-15)


def test_top_euler_angle_ode_matches_rigid_body_with_nutation():
    """General (nutating) motion: Euler-angle ODE → R(φ,θ,ψ) equals the rotation-matrix integration
    (atol 1e-8); energy conserved (rtol 1e-10)."""
    m, g, lcm, I1, I3 = top_params()
    y0 = np.array([0.2, 0.6, -0.4, 3.0, 1.5, 80.0])  # φ, θ, ψ, φ̇, θ̇, ψ̇
    phi, th, psi, phid, thd, psid = y0
    w_body = np.array([phid * math.sin(th) * math.sin(psi) + thd * math.cos(psi),
                       phid * math.sin(th) * math.cos(psi) - thd * math.sin(psi),
                       psid + phid * math.cos(th)])
    t = np.linspace(0.0, 0.4, 21)
    sol = solve_ivp(ref.symmetric_top_euler_rhs(m, g, lcm, I1, I3), (0, t[-1]), y0, t_eval=t, **ODE)
    assert np.ptp(sol.y[1]) > 0.05  # nutation present
    R_rb, _ = rigid_body_top(ref.euler_zxz_matrix(phi, th, psi), w_body, t)
    R_ea = np.array([ref.euler_zxz_matrix(*sol.y[:3, k]) for k in range(t.size)])
    np.testing.assert_allclose(R_ea, R_rb, rtol=0, atol=1e-8)
    E = ref.symmetric_top_energy(sol.y, m, g, lcm, I1, I3)
    np.testing.assert_allclose(E, E[0], rtol=1e-10)


def test_euler_zxz_matrix_axis():
    """R e3 = (sinφ sinθ, -cosφ sinθ, cosθ) and R is a rotation."""
    R = ref.euler_zxz_matrix(0.4, 1.1, -2.0)
    np.testing.assert_allclose(R[:, 2], [math.sin(0.4) * math.sin(1.1), -math.cos(0.4) * math.sin(1.1),
                                         math.cos(1.1)], atol=1e-15)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, rtol=1e-14)


# ---------------------------------------------------------------------------------------------
# 4. Slider-crank
# ---------------------------------------------------------------------------------------------

SC = [(0.05, 0.18, 0.0), (0.05, 0.18, 0.02)]  # r, rod, e [m]


def vector_loop_slider(theta, omega, alpha, r, rod, e):
    """Vector loop r e^{iθ} + rod e^{iφ} = x + i e (φ rod angle), differentiated twice (Norton §6.7, §7.3)."""
    phi = np.arcsin((e - r * np.sin(theta)) / rod)
    phid = -r * omega * np.cos(theta) / (rod * np.cos(phi))
    x = r * np.cos(theta) + rod * np.cos(phi)
    xd = -r * omega * np.sin(theta) - rod * phid * np.sin(phi)
    phidd = (r * omega**2 * np.sin(theta) - r * alpha * np.cos(theta) + rod * phid**2 * np.sin(phi)) / (
        rod * np.cos(phi))
    xdd = (-r * omega**2 * np.cos(theta) - r * alpha * np.sin(theta) - rod * phid**2 * np.cos(phi)
           - rod * phidd * np.sin(phi))
    return x, xd, xdd


@pytest.mark.parametrize(("r", "rod", "e"), SC)
def test_slider_kinematics_vs_vector_loop(r, rod, e):
    """Position (rod length |AP| = rod), velocity and acceleration vs the vector loop (rtol 1e-12)."""
    rng = np.random.default_rng(2)
    theta = rng.uniform(-np.pi, np.pi, 50)
    omega, alpha = rng.uniform(-300, 300, 50), rng.uniform(-1e4, 1e4, 50)
    x = ref.slider_position(theta, r, rod, e)
    np.testing.assert_allclose(np.hypot(x - r * np.cos(theta), e - r * np.sin(theta)), rod, rtol=1e-14)
    x2, xd2, xdd2 = vector_loop_slider(theta, omega, alpha, r, rod, e)
    np.testing.assert_allclose(x, x2, rtol=1e-14)
    scale_v, scale_a = r * np.abs(omega), r * (omega**2 + np.abs(alpha))
    np.testing.assert_allclose(ref.slider_velocity(theta, omega, r, rod, e), xd2, rtol=0, atol=1e-12 * scale_v.max())
    np.testing.assert_allclose(ref.slider_acceleration(theta, omega, alpha, r, rod, e), xdd2, rtol=0,
                               atol=1e-12 * scale_a.max())


@pytest.mark.parametrize(("r", "rod", "e"), SC)
def test_slider_derivatives_integrate_to_position(r, rod, e):
    """solve_ivp of d/dθ [x, x'] = [x', x''] over one revolution reproduces x(θ), x'(θ) (1e-10 r)."""
    theta = np.linspace(0.0, 2 * np.pi, 73)

    def f(th, y):
        dx, ddx = ref.slider_dx_dtheta(th, r, rod, e)
        return [dx, ddx]

    y0 = [ref.slider_position(0.0, r, rod, e), ref.slider_dx_dtheta(0.0, r, rod, e)[0]]
    sol = solve_ivp(f, (0.0, theta[-1]), y0, t_eval=theta, **ODE)
    np.testing.assert_allclose(sol.y[0], ref.slider_position(theta, r, rod, e), rtol=0, atol=1e-10 * r)
    np.testing.assert_allclose(sol.y[1], ref.slider_dx_dtheta(theta, r, rod, e)[0], rtol=0, atol=1e-10 * r)


@pytest.mark.parametrize(("r", "rod", "e"), SC)
def test_crank_torque_vs_newton_statics(r, rod, e):
    """T = F dx/dθ vs two-force-member statics: rod force S along P→A balances F on the slider,
    holding torque T = -(A × f_rod_on_crank)_z (rtol 1e-12)."""
    F = 2.0e4
    theta = np.linspace(-3.0, 3.0, 31)
    x = ref.slider_position(theta, r, rod, e)
    A = np.stack([r * np.cos(theta), r * np.sin(theta)])
    P = np.stack([x, np.full_like(x, e)])
    u = (P - A) / rod  # unit vector crank pin → slider
    S = F / u[0]  # slider x-balance: S u_x - F = 0 (S > 0: rod in compression)
    f_on_crank = -S * u  # the rod pushes the crank pin back
    T_newton = -(A[0] * f_on_crank[1] - A[1] * f_on_crank[0])
    np.testing.assert_allclose(ref.crank_torque_virtual_work(theta, r, rod, F, e), T_newton, rtol=1e-12,
                               atol=1e-12 * F * r)
    if e == 0.0:  # documented sign example: θ = π/2 → dx/dθ = -r, T = -F r
        np.testing.assert_allclose(ref.crank_torque_virtual_work(np.pi / 2, r, rod, F), -F * r, rtol=1e-14)


def test_slider_rejects_short_rod():
    with pytest.raises(ValueError, match="assembled"):
        ref.slider_position(np.pi / 2, 0.2, 0.1)


# ---------------------------------------------------------------------------------------------
# 5. Four-bar
# ---------------------------------------------------------------------------------------------

FOURBARS = {
    "crank-rocker": (2.0, 7.0, 9.0, 6.0),
    "double-crank": (4.0, 5.0, 3.5, 2.0),
    "triple-rocker": (5.0, 4.0, 3.0, 3.5),
}


def circle_intersection_fourbar(a, b, c, d, theta2, branch):
    """θ3, θ4 by intersecting circle(A, b) with circle(O4, c); branch by sign of sin(θ4 - θ3)."""
    A = a * np.exp(1j * theta2)
    O4 = complex(d, 0.0)
    h = abs(O4 - A)
    if h > b + c or h < abs(b - c):
        return math.nan, math.nan
    u = (O4 - A) / h
    along = (b * b - c * c + h * h) / (2 * h)
    perp = math.sqrt(max(b * b - along * along, 0.0))
    for s in (1.0, -1.0):
        B = A + along * u + s * perp * 1j * u
        t3, t4 = np.angle(B - A), np.angle(B - O4)
        if (math.sin(t4 - t3) > 0) == (branch == "open"):
            return t3, t4
    raise AssertionError("no intersection on the requested branch")


@pytest.mark.parametrize("name", list(FOURBARS))
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_fourbar_angles_vs_circle_intersection(name, branch):
    """Norton/Freudenstein closed form vs circle intersection (atol 1e-10 rad), NaN pattern,
    loop closure and Freudenstein's equation."""
    a, b, c, d = FOURBARS[name]
    theta2 = np.linspace(-np.pi, np.pi, 181)
    t3, t4 = ref.fourbar_angles(a, b, c, d, theta2, branch)
    expected = np.array([circle_intersection_fourbar(a, b, c, d, th, branch) for th in theta2])
    np.testing.assert_array_equal(np.isnan(t3), np.isnan(expected[:, 0]))
    ok = ~np.isnan(t3)
    # near toggle positions sqrt(disc) amplifies rounding, so compare where the circuit is clear
    clear = ok & (np.abs(np.sin(expected[:, 1] - expected[:, 0])) > 1e-3)
    np.testing.assert_allclose(wrap(t3[clear] - expected[clear, 0]), 0.0, atol=1e-10)
    np.testing.assert_allclose(wrap(t4[clear] - expected[clear, 1]), 0.0, atol=1e-10)
    closure = a * np.exp(1j * theta2[ok]) + b * np.exp(1j * t3[ok]) - c * np.exp(1j * t4[ok]) - d
    np.testing.assert_allclose(np.abs(closure), 0.0, atol=1e-12 * (a + b + c + d))
    K1, K2, K3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    np.testing.assert_allclose(K1 * np.cos(t4[ok]) - K2 * np.cos(theta2[ok]) + K3, np.cos(theta2[ok] - t4[ok]),
                               atol=1e-12 * (K1 + K2 + abs(K3)))
    if name != "triple-rocker":
        assert ok.all()  # a Grashof crank-rocker/double-crank assembles for every crank angle
    else:
        assert 0 < ok.sum() < ok.size


def test_fourbar_textbook_example():
    """a, b, c, d = 2, 7, 9, 6, θ2 = 30° (cf. Norton Ex. 4-1): open θ3 = 88.84°, θ4 = 117.29°."""
    t3, t4 = ref.fourbar_angles(2, 7, 9, 6, math.radians(30), "open")
    np.testing.assert_allclose(np.degrees([t3, t4]), [88.84, 117.29], atol=5e-3)


def test_fourbar_flat_position_exact():
    """Half-angle degeneracy (A = B = 0 → θ = π) is handled: change-point linkage at θ2 = 0."""
    t3, t4 = ref.fourbar_angles(4.0, 3.0, 5.0, 6.0, 0.0, "open")
    np.testing.assert_allclose(wrap(np.array([t3, t4]) - np.pi), 0.0, atol=1e-12)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_fourbar_velocities(branch):
    """ω3, ω4 satisfy the differentiated loop (1e-12) and integrate (solve_ivp over θ2) to the
    position solution θ3(θ2), θ4(θ2) (atol 1e-9)."""
    a, b, c, d = FOURBARS["crank-rocker"]
    theta2 = np.linspace(0.0, 2 * np.pi, 61)
    t3, t4 = ref.fourbar_angles(a, b, c, d, theta2, branch)
    w3, w4 = ref.fourbar_velocities(a, b, c, theta2, t3, t4, 1.0)
    vel = 1j * (a * np.exp(1j * theta2) + b * w3 * np.exp(1j * t3) - c * w4 * np.exp(1j * t4))
    np.testing.assert_allclose(np.abs(vel), 0.0, atol=1e-12 * (a + b + c))

    def f(th2, y):
        return np.array(ref.fourbar_velocities(a, b, c, th2, y[0], y[1], 1.0))

    sol = solve_ivp(f, (0.0, theta2[-1]), [t3[0], t4[0]], t_eval=theta2, **ODE)
    np.testing.assert_allclose(wrap(sol.y[0] - t3), 0.0, atol=1e-9)
    np.testing.assert_allclose(wrap(sol.y[1] - t4), 0.0, atol=1e-9)


def test_coupler_point():
    """p = b, δ = 0 gives joint B; otherwise |AP| = p and |BP|² = p² + b² - 2pb cos δ."""
    a, b, c, d = FOURBARS["crank-rocker"]
    theta2 = np.linspace(-3, 3, 13)
    t3, t4 = ref.fourbar_angles(a, b, c, d, theta2)
    xB, yB = ref.coupler_point(a, b, theta2, t3, b, 0.0)
    np.testing.assert_allclose(xB + 1j * yB, d + c * np.exp(1j * t4), atol=1e-12)
    p, delta = 3.2, 0.9
    x, y = ref.coupler_point(a, b, theta2, t3, p, delta)
    P, A = x + 1j * y, a * np.exp(1j * theta2)
    np.testing.assert_allclose(np.abs(P - A), p, rtol=1e-14)
    np.testing.assert_allclose(np.abs(P - (xB + 1j * yB)) ** 2, p * p + b * b - 2 * p * b * math.cos(delta),
                               rtol=1e-12)
    assert np.all(np.sin(np.angle(P - A) - t3) > 0)  # δ > 0 is CCW from A→B


def test_grashof():
    assert ref.grashof(2, 7, 9, 6)[:2] == ("grashof", "crank-rocker")
    assert ref.grashof(4, 5, 3.5, 2)[:2] == ("grashof", "double-crank")
    assert ref.grashof(6, 2, 9, 7)[:2] == ("grashof", "double-rocker")
    assert ref.grashof(7, 6, 2, 9)[:2] == ("grashof", "rocker-crank")
    assert ref.grashof(5, 4, 3, 3.5)[:2] == ("non-grashof", "triple-rocker")
    assert ref.grashof(4, 3, 5, 6).condition == "change-point"
    np.testing.assert_allclose(ref.grashof(2, 7, 9, 6).margin, (6 + 7) - (2 + 9))


# ---------------------------------------------------------------------------------------------
# 6. Beam on a pin and a link
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("a_frac", "beta"), [(1.0, 0.0), (0.3, 0.0), (0.7, 0.4), (1.0, -0.25)])
def test_beam_pin_link_reactions(a_frac, beta):
    """Closed form vs a 3×3 linear solve of ΣFx, ΣFy and moments about the beam's centre."""
    m, L, g = 12.0, 2.5, 9.81
    a = a_frac * L
    res = ref.beam_pin_link_reactions(m, L, g, a=a, link_angle=beta)
    u = np.array([math.sin(beta), math.cos(beta)])
    # unknowns (Rx, Ry, T); moment arm about (L/2, 0): pin at -L/2, link at a - L/2
    K = np.array([[1.0, 0.0, u[0]], [0.0, 1.0, u[1]], [0.0, -L / 2, (a - L / 2) * u[1]]])
    expected = np.linalg.solve(K, [0.0, m * g, 0.0])
    np.testing.assert_allclose(res, expected, rtol=1e-13, atol=1e-12 * m * g)
    if a_frac == 1.0 and beta == 0.0:
        np.testing.assert_allclose(res, [0.0, m * g / 2, m * g / 2], atol=1e-12)


def test_beam_default_and_errors():
    np.testing.assert_allclose(ref.beam_pin_link_reactions(2.0, 1.0, 10.0), [0.0, 10.0, 10.0], atol=1e-14)
    with pytest.raises(ValueError, match="a = 0"):
        ref.beam_pin_link_reactions(2.0, 1.0, 10.0, a=0.0)


# ---------------------------------------------------------------------------------------------
# 7. Four-bar holding torque
# ---------------------------------------------------------------------------------------------


def cross2(r: np.ndarray, f: np.ndarray) -> float:
    return float(r[0] * f[1] - r[1] * f[0])


def newton_fourbar_torque(a, b, c, d, theta2, p, delta, m, g, branch):
    """Newton statics of the three moving links (9 unknowns: 4 pin forces + T2).

    Crank: F12 + F32 = 0, T2 + (A - O2) × F32 = 0. Coupler: -F32 + F43 + W = 0,
    (B - A) × F43 + (P - A) × W = 0. Rocker: F14 - F43 = 0, (B - O4) × (-F43) = 0.
    (F_ij: force of link i on link j; W = (0, -m g) at P; B from circle intersection.)
    """
    t3, _ = circle_intersection_fourbar(a, b, c, d, theta2, branch)
    A = a * np.array([math.cos(theta2), math.sin(theta2)])
    B = A + b * np.array([math.cos(t3), math.sin(t3)])
    O4 = np.array([d, 0.0])
    P = A + p * np.array([math.cos(t3 + delta), math.sin(t3 + delta)])
    W = np.array([0.0, -m * g])

    def cross_row(r):  # r × F as a row acting on F = (Fx, Fy)
        return np.array([-r[1], r[0]])

    K, rhs = np.zeros((9, 9)), np.zeros(9)  # x = [F12(2), F32(2), F43(2), F14(2), T2]
    K[0:2, 0:2], K[0:2, 2:4] = np.eye(2), np.eye(2)
    K[2, 2:4], K[2, 8] = cross_row(A), 1.0
    K[3:5, 2:4], K[3:5, 4:6], rhs[3:5] = -np.eye(2), np.eye(2), -W
    K[5, 4:6], rhs[5] = cross_row(B - A), -cross2(P - A, W)
    K[6:8, 6:8], K[6:8, 4:6] = np.eye(2), -np.eye(2)
    K[8, 4:6] = -cross_row(B - O4)
    return np.linalg.solve(K, rhs)[8]


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_static_fourbar_torque(branch):
    """Virtual-work torque vs Newton statics (rtol 1e-10) and vs dV/dθ2 by central differences
    of V = m g y_P (rtol 1e-8)."""
    a, b, c, d = FOURBARS["crank-rocker"]
    p, delta, m, g = 4.0, 0.6, 3.0, 9.81
    theta2 = np.linspace(-3.0, 3.0, 25)
    T = ref.static_fourbar_torque(a, b, c, d, theta2, p, delta, m, g, branch)
    T_newton = [newton_fourbar_torque(a, b, c, d, th, p, delta, m, g, branch) for th in theta2]
    np.testing.assert_allclose(T, T_newton, rtol=1e-10, atol=1e-10 * m * g * (a + p))

    def potential(th2):
        t3, _ = ref.fourbar_angles(a, b, c, d, th2, branch)
        return m * g * ref.coupler_point(a, b, th2, t3, p, delta)[1]

    h = 1e-5
    np.testing.assert_allclose(T, (potential(theta2 + h) - potential(theta2 - h)) / (2 * h), rtol=1e-8,
                               atol=1e-8 * m * g * (a + p))
