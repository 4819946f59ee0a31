"""Independent reference solutions for the multibody tests (numpy/scipy only, no flexlib).

Every function states its formula, its source (textbook section or the derivation) and its SI
units. Each one is checked against a second, independent computation in
``tests/test_references_multibody.py`` (closed form vs. ``solve_ivp`` of the minimal-coordinate
ODE, vector-loop vs. Freudenstein, virtual work vs. Newton statics, ...).

Import from any test below ``tests/``: pytest (``importmode=prepend``, the default) puts the
directory of ``tests/conftest.py`` on ``sys.path``, so ``import references_multibody as ref``
works without an ``__init__.py``.

Common conventions
------------------
* SI units throughout: m, kg, s, rad, N, N·m, kg·m².
* Planar problems: x horizontal, y vertically **up**, gravity ``(0, -g)``; angles in rad,
  counter-clockwise (CCW) positive; torques CCW positive.
* Pendulum angles are measured from the **downward** vertical (``theta = 0`` hangs at rest).
* The heavy top uses a world frame with z **up**, gravity ``(0, 0, -g)``, fixed tip at the origin;
  ``heavy_top_initial_conditions(..., world_up="y")`` re-expresses its output for a y-up world
  (gravity ``(0, -g, 0)``, the Modelica MultiBody default adopted in docs/multibody_design.md).

Contents
--------
1. ``pendulum_period``, ``pendulum_period_small``, ``physical_pendulum_period``
2. ``double_pendulum_bodies`` (general), ``double_pendulum_point_masses``,
   ``double_pendulum_rods``, ``double_pendulum_points``
3. ``heavy_top_steady_precession``, ``heavy_top_initial_conditions``,
   ``symmetric_top_euler_rhs``, ``symmetric_top_energy``, ``euler_zxz_matrix``
4. ``slider_position``, ``slider_velocity``, ``slider_acceleration``, ``slider_dx_dtheta``,
   ``crank_torque_virtual_work``
5. ``fourbar_angles``, ``fourbar_velocities``, ``coupler_point``, ``grashof``
6. ``beam_pin_link_reactions``
7. ``static_fourbar_torque``
"""

# ``l`` is the textbook symbol (Goldstein's tip-to-CM distance, Heywood's rod length) and part of
# the requested signatures, so E741 (ambiguous name ``l``) is waived for this module only.
# ruff: noqa: E741

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from scipy.special import ellipk

__all__ = [
    "WORLD_Z_UP_TO_Y_UP",
    "BeamReactions",
    "GrashofResult",
    "TopInitialConditions",
    "beam_pin_link_reactions",
    "coupler_point",
    "crank_torque_virtual_work",
    "double_pendulum_bodies",
    "double_pendulum_point_masses",
    "double_pendulum_points",
    "double_pendulum_rods",
    "euler_zxz_matrix",
    "fourbar_angles",
    "fourbar_velocities",
    "grashof",
    "heavy_top_initial_conditions",
    "heavy_top_steady_precession",
    "pendulum_period",
    "pendulum_period_small",
    "physical_pendulum_period",
    "slider_acceleration",
    "slider_dx_dtheta",
    "slider_position",
    "slider_velocity",
    "static_fourbar_torque",
    "symmetric_top_energy",
    "symmetric_top_euler_rhs",
]


# ---------------------------------------------------------------------------------------------
# 1. Pendulum periods
# ---------------------------------------------------------------------------------------------


def _check_amplitude(theta0: float) -> float:
    theta0 = float(theta0)
    if not 0.0 <= abs(theta0) < math.pi:
        raise ValueError(f"amplitude theta0 = {theta0} rad must satisfy |theta0| < pi (no libration otherwise)")
    return abs(theta0)


def pendulum_period(L: float, g: float, theta0: float) -> float:
    r"""Exact period of a simple (point-mass, massless-rod) pendulum of amplitude ``theta0``.

    .. math::

        T = 4 \sqrt{L/g}\; K(m), \qquad m = k^2 = \sin^2(\theta_0/2),

    with :math:`K(m) = \int_0^{\pi/2} d\phi / \sqrt{1 - m \sin^2\phi}` the complete elliptic
    integral of the first kind in *parameter* convention (``scipy.special.ellipk(m)``, **not**
    the modulus k).

    Parameters
    ----------
    L : float
        Pendulum length, pivot to mass [m], > 0.
    g : float
        Gravitational acceleration [m/s²], > 0.
    theta0 : float
        Amplitude, i.e. the turning-point angle from the downward vertical [rad],
        ``|theta0| < pi``. ``theta0 = 0`` gives the small-amplitude period.

    Returns
    -------
    float
        Period [s].

    Notes
    -----
    Derivation: energy conservation :math:`\dot\theta^2 = (2g/L)(\cos\theta - \cos\theta_0)`;
    the substitution :math:`\sin(\theta/2) = k \sin\phi` turns
    :math:`T = 4\int_0^{\theta_0} d\theta/\dot\theta` into :math:`4\sqrt{L/g}\,K(k^2)`.
    Series: :math:`T = T_0 (1 + \theta_0^2/16 + 11\theta_0^4/3072 + \dots)`.

    References
    ----------
    Landau & Lifshitz, *Mechanics*, 3rd ed., §11, problem 1; Thornton & Marion, *Classical
    Dynamics of Particles and Systems*, 5th ed., §4.4 (the plane pendulum).
    """
    k = math.sin(_check_amplitude(theta0) / 2.0)
    return 4.0 * math.sqrt(L / g) * float(ellipk(k * k))


def pendulum_period_small(L: float, g: float) -> float:
    r"""Small-amplitude (linearised) period of a simple pendulum, :math:`T_0 = 2\pi\sqrt{L/g}`.

    Parameters
    ----------
    L : float
        Pendulum length [m], > 0.
    g : float
        Gravitational acceleration [m/s²], > 0.

    Returns
    -------
    float
        Period [s].

    References
    ----------
    Thornton & Marion, *Classical Dynamics*, 5th ed., §4.4; limit ``theta0 -> 0`` of
    :func:`pendulum_period` (``K(0) = pi/2``).
    """
    return 2.0 * math.pi * math.sqrt(L / g)


def physical_pendulum_period(m: float, d: float, I_cm: float, g: float, theta0: float = 0.0) -> float:
    r"""Exact period of a physical (compound) pendulum: rigid body on a frictionless pin.

    Equation of motion :math:`I_O \ddot\theta = -m g d \sin\theta` with
    :math:`I_O = I_{cm} + m d^2` (parallel-axis theorem), i.e. a simple pendulum of equivalent
    length :math:`L_{eq} = I_O / (m d)`:

    .. math::

        T = 4 \sqrt{\frac{I_{cm} + m d^2}{m g d}}\; K\!\left(\sin^2\frac{\theta_0}{2}\right).

    Parameters
    ----------
    m : float
        Body mass [kg], > 0.
    d : float
        Distance from the pin to the centre of mass [m], > 0.
    I_cm : float
        Moment of inertia about the axis through the centre of mass parallel to the pin
        [kg·m²], >= 0 (``I_cm = 0`` is the simple pendulum of length ``d``).
    g : float
        Gravitational acceleration [m/s²], > 0.
    theta0 : float, optional
        Amplitude measured from the downward vertical through the pin [rad], ``|theta0| < pi``;
        default 0 (small-amplitude period ``2 pi sqrt(I_O/(m g d))``).

    Returns
    -------
    float
        Period [s].

    Notes
    -----
    Uniform slender rod pinned at one end: ``d = L/2``, ``I_cm = m L**2/12`` → ``L_eq = 2L/3``.

    References
    ----------
    Thornton & Marion, *Classical Dynamics*, 5th ed., §4.4 and ch. 11 (rigid bodies);
    Landau & Lifshitz, *Mechanics*, §11 problem 1 with ``L -> L_eq``.
    """
    if d <= 0.0 or m <= 0.0:
        raise ValueError("physical pendulum needs m > 0 and d > 0")
    L_eq = (I_cm + m * d * d) / (m * d)
    return pendulum_period(L_eq, g, theta0)


# ---------------------------------------------------------------------------------------------
# 2. Planar double pendulum
# ---------------------------------------------------------------------------------------------

DoublePendulum = tuple[Callable[[float, np.ndarray], np.ndarray], Callable[[np.ndarray], np.ndarray]]


def double_pendulum_bodies(
    m1: float, m2: float, L1: float, d1: float, d2: float, J1: float, J2: float, g: float
) -> DoublePendulum:
    r"""Planar double pendulum of two rigid bodies: RHS for ``solve_ivp`` and energy function.

    Body 1 swings about a ground pin at the origin; its centre of mass (CM) lies at distance
    ``d1`` along the body line, the pin to body 2 at distance ``L1``. Body 2's CM lies at
    distance ``d2`` from that pin. Absolute angles from the downward vertical, CCW positive:
    ``r_cm1 = d1 (sin θ1, -cos θ1)``, ``r_cm2 = L1 (sin θ1, -cos θ1) + d2 (sin θ2, -cos θ2)``.

    State ``y = [θ1, θ2, ω1, ω2]`` [rad, rad, rad/s, rad/s]. With ``Δ = θ1 - θ2`` and

    .. math::

        A = J_1 + m_1 d_1^2 + m_2 L_1^2,\quad B = J_2 + m_2 d_2^2,\quad C = m_2 L_1 d_2,\quad
        G_1 = (m_1 d_1 + m_2 L_1) g,\quad G_2 = m_2 d_2 g,

    the Lagrangian :math:`\mathcal L = \tfrac12 A\omega_1^2 + \tfrac12 B\omega_2^2
    + C\cos\Delta\,\omega_1\omega_2 + G_1\cos\theta_1 + G_2\cos\theta_2` gives

    .. math::

        \begin{bmatrix} A & C\cos\Delta \\ C\cos\Delta & B \end{bmatrix}
        \begin{bmatrix} \dot\omega_1 \\ \dot\omega_2 \end{bmatrix} =
        \begin{bmatrix} -C\sin\Delta\,\omega_2^2 - G_1\sin\theta_1 \\
                         \phantom{-}C\sin\Delta\,\omega_1^2 - G_2\sin\theta_2 \end{bmatrix},

    and the conserved energy :math:`E = \tfrac12 A\omega_1^2 + \tfrac12 B\omega_2^2
    + C\cos\Delta\,\omega_1\omega_2 - G_1\cos\theta_1 - G_2\cos\theta_2` (zero potential at the
    pin height).

    Parameters
    ----------
    m1, m2 : float
        Masses of body 1 and body 2 [kg].
    L1 : float
        Distance ground pin → pin between the bodies [m].
    d1, d2 : float
        Distance of each body's CM from its own (upper) pin, along the body line [m].
    J1, J2 : float
        Moments of inertia about the CM, perpendicular to the plane [kg·m²].
    g : float
        Gravitational acceleration [m/s²], acting along -y.

    Returns
    -------
    rhs : callable
        ``rhs(t, y) -> dy/dt``, shape (4,), for ``scipy.integrate.solve_ivp``.
    energy : callable
        ``energy(y) -> E`` [J]; ``y`` of shape (4,) or (4, n) (``sol.y``).

    References
    ----------
    Lagrange's equations, e.g. Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §1.4
    and §1.6; derivation above (``d/dt ∂L/∂ω_i - ∂L/∂θ_i = 0``).
    """
    A = J1 + m1 * d1 * d1 + m2 * L1 * L1
    B = J2 + m2 * d2 * d2
    C = m2 * L1 * d2
    G1 = (m1 * d1 + m2 * L1) * g
    G2 = m2 * d2 * g

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        th1, th2, w1, w2 = y
        delta = th1 - th2
        c, s = math.cos(delta), math.sin(delta)
        f1 = -C * s * w2 * w2 - G1 * math.sin(th1)
        f2 = C * s * w1 * w1 - G2 * math.sin(th2)
        det = A * B - (C * c) ** 2
        a1 = (B * f1 - C * c * f2) / det
        a2 = (A * f2 - C * c * f1) / det
        return np.array([w1, w2, a1, a2])

    def energy(y: np.ndarray) -> np.ndarray:
        th1, th2, w1, w2 = np.asarray(y, dtype=float)
        kinetic = 0.5 * A * w1**2 + 0.5 * B * w2**2 + C * np.cos(th1 - th2) * w1 * w2
        return kinetic - G1 * np.cos(th1) - G2 * np.cos(th2)

    return rhs, energy


def double_pendulum_point_masses(m1: float, m2: float, L1: float, L2: float, g: float) -> DoublePendulum:
    r"""Double pendulum of two point masses on massless rigid rods (absolute angles).

    Special case of :func:`double_pendulum_bodies` with ``d1 = L1``, ``d2 = L2``,
    ``J1 = J2 = 0``: ``A = (m1+m2) L1²``, ``B = m2 L2²``, ``C = m2 L1 L2``,
    ``G1 = (m1+m2) g L1``, ``G2 = m2 g L2``.

    Parameters
    ----------
    m1, m2 : float
        Point masses [kg].
    L1, L2 : float
        Rod lengths [m] (pin → m1, m1 → m2).
    g : float
        Gravitational acceleration [m/s²].

    Returns
    -------
    rhs, energy : callable
        See :func:`double_pendulum_bodies`; state ``[θ1, θ2, ω1, ω2]``, angles from the
        downward vertical, CCW positive.

    References
    ----------
    Standard result, e.g. Goldstein et al., *Classical Mechanics*, 3rd ed., §1.6 (derivation
    in :func:`double_pendulum_bodies`).
    """
    return double_pendulum_bodies(m1, m2, L1, L1, L2, 0.0, 0.0, g)


def double_pendulum_rods(m1: float, m2: float, L1: float, L2: float, g: float) -> DoublePendulum:
    r"""Double pendulum of two uniform slender rods, pinned end to end (absolute angles).

    Special case of :func:`double_pendulum_bodies` with ``d = L/2``, ``J = m L²/12``:
    ``A = (m1/3 + m2) L1²``, ``B = m2 L2²/3``, ``C = m2 L1 L2 / 2``,
    ``G1 = (m1/2 + m2) g L1``, ``G2 = m2 g L2 / 2``.

    Parameters
    ----------
    m1, m2 : float
        Rod masses [kg].
    L1, L2 : float
        Rod lengths [m].
    g : float
        Gravitational acceleration [m/s²].

    Returns
    -------
    rhs, energy : callable
        See :func:`double_pendulum_bodies`.

    References
    ----------
    Derivation in :func:`double_pendulum_bodies`; slender-rod inertia ``m L²/12`` (Thornton &
    Marion, *Classical Dynamics*, ch. 11).
    """
    return double_pendulum_bodies(m1, m2, L1, L1 / 2.0, L2 / 2.0, m1 * L1**2 / 12.0, m2 * L2**2 / 12.0, g)


def double_pendulum_points(theta1: np.ndarray, theta2: np.ndarray, L1: float, L2: float) -> np.ndarray:
    r"""Positions of the middle joint and the tip of a double pendulum (ground pin at origin).

    ``p1 = L1 (sin θ1, -cos θ1)``, ``p2 = p1 + L2 (sin θ2, -cos θ2)`` (y up, angles from the
    downward vertical, CCW positive). For a CM at distance ``d`` pass ``L = d``.

    Parameters
    ----------
    theta1, theta2 : array_like
        Absolute angles [rad].
    L1, L2 : float
        Link lengths [m].

    Returns
    -------
    numpy.ndarray
        Shape ``(2, 2) + shape(theta)``: ``[[x1, y1], [x2, y2]]`` [m].

    References
    ----------
    Geometry of the vector chain; same convention as :func:`double_pendulum_bodies`.
    """
    theta1, theta2 = np.asarray(theta1, dtype=float), np.asarray(theta2, dtype=float)
    x1, y1 = L1 * np.sin(theta1), -L1 * np.cos(theta1)
    return np.array([[x1, y1], [x1 + L2 * np.sin(theta2), y1 - L2 * np.cos(theta2)]])


# ---------------------------------------------------------------------------------------------
# 3. Heavy symmetric top with a fixed tip
# ---------------------------------------------------------------------------------------------


def euler_zxz_matrix(phi: float, theta: float, psi: float) -> np.ndarray:
    r"""Rotation matrix body → world for z-x-z Euler angles (Goldstein's convention).

    :math:`R = R_z(\phi) R_x(\theta) R_z(\psi)`; ``R @ v_body = v_world``. Goldstein's matrix
    **A** (world → body) is ``R.T``. The body symmetry axis in world coordinates is
    ``R[:, 2] = (sin φ sin θ, -cos φ sin θ, cos θ)``.

    Parameters
    ----------
    phi, theta, psi : float
        Precession, nutation (tilt of body axis 3 from world z), spin angles [rad].

    Returns
    -------
    numpy.ndarray
        (3, 3) proper orthogonal matrix [-].

    References
    ----------
    Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §4.4 (Euler angles, x-convention).
    """
    cf, sf, ct, st, cp, sp = (math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta),
                              math.cos(psi), math.sin(psi))
    Rz_phi = np.array([[cf, -sf, 0.0], [sf, cf, 0.0], [0.0, 0.0, 1.0]])
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, ct, -st], [0.0, st, ct]])
    Rz_psi = np.array([[cp, -sp, 0.0], [sp, cp, 0.0], [0.0, 0.0, 1.0]])
    return Rz_phi @ Rx @ Rz_psi


def _stable_quadratic_roots(a: float, b: float, c: float) -> tuple[float, float]:
    """Roots of a x² + b x + c = 0 as (small, large) magnitude, cancellation-free.

    ``a == 0`` gives the single root ``-c/b`` and ``±inf`` for the missing one.
    """
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        raise ValueError(f"no real root: discriminant {disc:.6g} < 0")
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b if b != 0.0 else 1.0))
    if q == 0.0:  # b = 0 and c = 0
        return 0.0, (0.0 if a == 0.0 else -b / a)
    small = c / q
    large = q / a if a != 0.0 else math.copysign(math.inf, q)
    if abs(small) > abs(large):
        small, large = large, small
    return small, large


def heavy_top_steady_precession(
    m: float, g: float, l: float, I1: float, I3: float, theta: float, spin: float, spin_kind: str = "omega3"
) -> tuple[float, float]:
    r"""Steady (uniform, nutation-free) precession rates of a heavy symmetric top, both roots.

    Setting :math:`\ddot\theta = \dot\theta = 0` in the θ Lagrange equation of the top,
    :math:`I_1\ddot\theta = \sin\theta\,(I_1\dot\phi^2\cos\theta - I_3\omega_3\dot\phi + m g l)`,
    gives for :math:`\Omega = \dot\phi`:

    .. math::

        I_1 \cos\theta\;\Omega^2 - I_3\,\omega_3\,\Omega + m g l = 0,
        \qquad \omega_3 = \dot\psi + \dot\phi\cos\theta .

    **Spin variable.** With ``spin_kind="omega3"`` (default, Goldstein's choice) ``spin`` is
    :math:`\omega_3`, the component of the *total* angular velocity along the body symmetry
    axis (a constant of motion, = ``omega_body[2]``). With ``spin_kind="psi_dot"`` ``spin`` is
    the *relative* spin rate :math:`\dot\psi` (body about its axis relative to the precessing
    line-of-nodes frame, e.g. a revolute-joint speed); then
    :math:`\omega_3 = \dot\psi + \Omega\cos\theta` and the quadratic becomes
    :math:`(I_1 - I_3)\cos\theta\,\Omega^2 - I_3\dot\psi\,\Omega + m g l = 0`.

    Parameters
    ----------
    m : float
        Mass of the top [kg].
    g : float
        Gravitational acceleration [m/s²] (world -z).
    l : float
        Distance fixed tip → centre of mass along the symmetry axis [m].
    I1 : float
        Transverse principal moment of inertia **about the fixed tip** [kg·m²]
        (``I1 = I1_cm + m l²``).
    I3 : float
        Axial moment of inertia about the symmetry axis [kg·m²].
    theta : float
        Constant tilt of the symmetry axis from the **upward** vertical [rad], 0 < θ < π.
    spin : float
        Spin rate [rad/s], meaning set by ``spin_kind``. Positive = CCW about the body
        symmetry axis (pointing from the tip to the CM).
    spin_kind : {"omega3", "psi_dot"}
        Which spin variable ``spin`` is (see above).

    Returns
    -------
    (Omega_slow, Omega_fast) : tuple of float
        Precession rates :math:`\dot\phi` about world +z [rad/s]: the root of smaller and of
        larger magnitude. ``Omega_fast = ±inf`` when the Ω² coefficient vanishes (θ = π/2 for
        ``omega3``); for θ > π/2 (hanging top) the two roots have opposite signs.

    Raises
    ------
    ValueError
        If no steady precession exists: for ``omega3`` when
        :math:`I_3^2\omega_3^2 < 4 I_1 m g l\cos\theta` (the "fast top" condition fails).

    References
    ----------
    Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §5.7 (heavy symmetrical top with
    one point fixed, uniform precession); roots in cancellation-free form
    (Press et al., *Numerical Recipes*, 3rd ed., §5.6).
    """
    ct = math.cos(theta)
    mgl = m * g * l
    if spin_kind == "omega3":
        a = I1 * ct
    elif spin_kind == "psi_dot":
        a = (I1 - I3) * ct
    else:
        raise ValueError(f"spin_kind must be 'omega3' or 'psi_dot', not {spin_kind!r}")
    if abs(a) < 1e-15 * max(abs(I1), abs(I3)):
        a = 0.0
    return _stable_quadratic_roots(a, -I3 * spin, mgl)


WORLD_Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
"""Rotation R_x(-π/2) taking a z-up world (Goldstein) to a y-up world (Modelica MultiBody): z → y."""


class TopInitialConditions(NamedTuple):
    """State of a symmetric top in steady precession at the Euler angles ``(phi, theta, psi)``.

    Attributes
    ----------
    R : numpy.ndarray
        (3, 3) rotation body → world [-] (:func:`euler_zxz_matrix`, pre-multiplied by
        ``WORLD_Z_UP_TO_Y_UP`` when ``world_up="y"``). Modelica's ``Frames.Orientation.T``
        (world → frame) is ``R.T``.
    omega_body : numpy.ndarray
        Angular velocity in body principal axes (1, 2 transverse, 3 symmetry) [rad/s].
    omega_world : numpy.ndarray
        Angular velocity in world axes, ``R @ omega_body`` [rad/s].
    phi_dot, theta_dot, psi_dot : float
        Euler-angle rates [rad/s] (``theta_dot = 0``).
    omega3 : float
        ``psi_dot + phi_dot cos(theta)`` = ``omega_body[2]`` [rad/s].
    r_cm, v_cm : numpy.ndarray or None
        World position and velocity of the CM, ``l R e3`` and ``omega_world × r_cm`` [m, m/s]
        (None when ``l`` is not given).
    """

    R: np.ndarray
    omega_body: np.ndarray
    omega_world: np.ndarray
    phi_dot: float
    theta_dot: float
    psi_dot: float
    omega3: float
    r_cm: np.ndarray | None
    v_cm: np.ndarray | None


def heavy_top_initial_conditions(
    theta: float,
    spin: float,
    Omega: float,
    spin_kind: str = "omega3",
    phi: float = 0.0,
    psi: float = 0.0,
    l: float | None = None,
    world_up: str = "z",
) -> TopInitialConditions:
    r"""Initial orientation and body angular velocity giving steady precession at (θ, spin, Ω).

    Body components of ω in z-x-z Euler angles (Goldstein §4.9) with
    :math:`\dot\theta = 0`, :math:`\dot\phi = \Omega`:

    .. math::

        \omega_{body} = \big(\Omega\sin\theta\sin\psi,\; \Omega\sin\theta\cos\psi,\;
        \omega_3\big), \qquad \omega_3 = \dot\psi + \Omega\cos\theta .

    ``Omega`` must be a root from :func:`heavy_top_steady_precession` (same ``spin`` and
    ``spin_kind``) for the motion to be steady; this function does not check it. Then the body
    axis 3 stays at tilt θ and precesses about world +z:
    ``e3(t) = (sin(φ+Ωt) sin θ, -cos(φ+Ωt) sin θ, cos θ)``.

    Parameters
    ----------
    theta : float
        Tilt of the symmetry axis from the upward world z axis [rad].
    spin : float
        ``omega3`` or ``psi_dot`` [rad/s] per ``spin_kind``.
    Omega : float
        Precession rate about world +z [rad/s].
    spin_kind : {"omega3", "psi_dot"}
        Meaning of ``spin``, as in :func:`heavy_top_steady_precession`.
    phi, psi : float, optional
        Initial precession and spin angles [rad]; default 0 (then the symmetry axis lies in
        the world y-z plane at ``(0, -sin θ, cos θ)`` and ``omega_body = (0, Ω sin θ, ω3)``).
    l : float, optional
        Tip → CM distance [m]; if given, ``r_cm`` and ``v_cm`` are filled in.
    world_up : {"z", "y"}
        Vertical axis of the world frame in which ``R``, ``omega_world``, ``r_cm``, ``v_cm`` are
        expressed. ``"z"``: gravity (0, 0, -g), precession about +z (Goldstein). ``"y"``: gravity
        (0, -g, 0), precession about +y; every world quantity is pre-multiplied by
        ``WORLD_Z_UP_TO_Y_UP`` = R_x(-π/2) (maps z → y, y → -z). ``omega_body`` is unchanged.

    Returns
    -------
    TopInitialConditions
        See the class docstring.

    References
    ----------
    Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §4.9 (ω in terms of Euler angles)
    and §5.7 (uniform precession).
    """
    if spin_kind == "omega3":
        omega3 = float(spin)
        psi_dot = omega3 - Omega * math.cos(theta)
    elif spin_kind == "psi_dot":
        psi_dot = float(spin)
        omega3 = psi_dot + Omega * math.cos(theta)
    else:
        raise ValueError(f"spin_kind must be 'omega3' or 'psi_dot', not {spin_kind!r}")
    R = euler_zxz_matrix(phi, theta, psi)
    st = math.sin(theta)
    omega_body = np.array([Omega * st * math.sin(psi), Omega * st * math.cos(psi), omega3])
    omega_world = R @ omega_body
    if world_up == "y":
        R, omega_world = WORLD_Z_UP_TO_Y_UP @ R, WORLD_Z_UP_TO_Y_UP @ omega_world
    elif world_up != "z":
        raise ValueError(f"world_up must be 'z' or 'y', not {world_up!r}")
    r_cm = v_cm = None
    if l is not None:
        r_cm = l * R[:, 2]
        v_cm = np.cross(omega_world, r_cm)
    return TopInitialConditions(R, omega_body, omega_world, float(Omega), 0.0, psi_dot, omega3, r_cm, v_cm)


def symmetric_top_euler_rhs(m: float, g: float, l: float, I1: float, I3: float) -> Callable:
    r"""Euler-angle equations of motion of a heavy symmetric top with a fixed tip.

    State ``y = [φ, θ, ψ, φ̇, θ̇, ψ̇]``. From
    :math:`\mathcal L = \tfrac12 I_1(\dot\theta^2 + \dot\phi^2\sin^2\theta)
    + \tfrac12 I_3(\dot\psi + \dot\phi\cos\theta)^2 - m g l\cos\theta`, with
    :math:`\omega_3 = \dot\psi + \dot\phi\cos\theta` (conserved):

    .. math::

        \ddot\theta &= \sin\theta\,(I_1\dot\phi^2\cos\theta - I_3\omega_3\dot\phi + m g l)/I_1,\\
        \ddot\phi &= \dot\theta\,(I_3\omega_3 - 2 I_1\dot\phi\cos\theta)/(I_1\sin\theta),\\
        \ddot\psi &= \dot\phi\dot\theta\sin\theta - \ddot\phi\cos\theta .

    (φ̈ from :math:`p_\phi = I_1\sin^2\theta\,\dot\phi + I_3\omega_3\cos\theta` = const.,
    ψ̈ from :math:`\dot\omega_3 = 0`.) Singular at sin θ = 0 (gimbal lock).

    Parameters
    ----------
    m, g, l, I1, I3 : float
        As in :func:`heavy_top_steady_precession` [kg, m/s², m, kg·m², kg·m²]; ``I1`` about
        the tip.

    Returns
    -------
    callable
        ``rhs(t, y) -> dy/dt`` for ``solve_ivp`` [rad/s, rad/s²].

    References
    ----------
    Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §5.7.
    """
    mgl = m * g * l

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        _, th, _, phid, thd, psid = y
        st, ct = math.sin(th), math.cos(th)
        w3 = psid + phid * ct
        thdd = st * (I1 * phid * phid * ct - I3 * w3 * phid + mgl) / I1
        phidd = thd * (I3 * w3 - 2.0 * I1 * phid * ct) / (I1 * st)
        psidd = phid * thd * st - phidd * ct
        return np.array([phid, thd, psid, phidd, thdd, psidd])

    return rhs


def symmetric_top_energy(y: np.ndarray, m: float, g: float, l: float, I1: float, I3: float) -> np.ndarray:
    r"""Total energy of the heavy symmetric top, state as in :func:`symmetric_top_euler_rhs`.

    :math:`E = \tfrac12 I_1(\dot\theta^2 + \dot\phi^2\sin^2\theta)
    + \tfrac12 I_3(\dot\psi + \dot\phi\cos\theta)^2 + m g l\cos\theta` [J]
    (zero potential at the tip height).

    Parameters
    ----------
    y : array_like
        State ``[φ, θ, ψ, φ̇, θ̇, ψ̇]``, shape (6,) or (6, n) [rad, rad/s].
    m, g, l, I1, I3 : float
        As in :func:`heavy_top_steady_precession`.

    Returns
    -------
    numpy.ndarray
        Energy [J].

    References
    ----------
    Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §5.7.
    """
    _, th, _, phid, thd, psid = np.asarray(y, dtype=float)
    w3 = psid + phid * np.cos(th)
    return 0.5 * I1 * (thd**2 + (phid * np.sin(th)) ** 2) + 0.5 * I3 * w3**2 + m * g * l * np.cos(th)


# ---------------------------------------------------------------------------------------------
# 4. Slider-crank
# ---------------------------------------------------------------------------------------------


def _slider_terms(theta: np.ndarray, r: float, l: float, e: float) -> tuple[np.ndarray, ...]:
    theta = np.asarray(theta, dtype=float)
    u = e - r * np.sin(theta)  # vertical offset slider pin − crank pin
    s2 = l * l - u * u
    if np.any(s2 <= 0.0):
        raise ValueError("slider-crank cannot be assembled: need |e - r sin(theta)| < l")
    return theta, u, np.sqrt(s2)


def slider_position(theta: np.ndarray, r: float, l: float, e: float = 0.0) -> np.ndarray:
    r"""Slider (piston pin) position of an in-line or offset slider-crank.

    Crank pivot at the origin, crank pin ``A = r (cos θ, sin θ)``; the slider pin moves on the
    line ``y = e`` at ``P = (x, e)``, on the +x side of the crank (|AP| = l):

    .. math::

        x(\theta) = r\cos\theta + \sqrt{l^2 - (e - r\sin\theta)^2}
        \quad\big(e = 0:\; x = r\cos\theta + \sqrt{l^2 - r^2\sin^2\theta}\big).

    Parameters
    ----------
    theta : array_like
        Crank angle [rad], CCW from the +x axis (the line of stroke, pointing from the crank
        axis toward the slider); θ = 0 is top dead centre (x = r + l for e = 0).
    r : float
        Crank radius [m].
    l : float
        Connecting-rod length, crank pin → slider pin [m], l > r + |e|.
    e : float, optional
        Offset of the slider line from the crank axis, along +y [m]; default 0.

    Returns
    -------
    numpy.ndarray
        Slider position x [m].

    References
    ----------
    Heywood, *Internal Combustion Engine Fundamentals*, §2.2 (e = 0); Norton, *Design of
    Machinery*, 5th ed., §4.6 (offset slider-crank, vector loop ``R2 + R3 = R4 + R1``).
    """
    theta, _, s = _slider_terms(theta, r, l, e)
    return r * np.cos(theta) + s


def slider_dx_dtheta(theta: np.ndarray, r: float, l: float, e: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    r"""First and second geometric derivatives ``dx/dθ`` [m/rad] and ``d²x/dθ²`` [m/rad²].

    With :math:`u = e - r\sin\theta`, :math:`s = \sqrt{l^2 - u^2}`:

    .. math::

        x' = -r\sin\theta + \frac{r\cos\theta\,u}{s},\qquad
        x'' = -r\cos\theta - \frac{r\sin\theta\,u + r^2\cos^2\theta}{s}
              - \frac{r^2\cos^2\theta\,u^2}{s^3}.

    Parameters
    ----------
    theta : array_like
        Crank angle [rad] (convention of :func:`slider_position`).
    r, l, e : float
        Crank radius, rod length, offset [m].

    Returns
    -------
    (dx, ddx) : tuple of numpy.ndarray
        ``dx/dθ`` [m/rad] and ``d²x/dθ²`` [m/rad²].

    References
    ----------
    Differentiation of :func:`slider_position` (chain rule); for e = 0 this is the classical
    ``x'' = -r [cos θ + r cos 2θ / s + r³ sin²θ cos²θ / s³]`` (Heywood §2.2; Norton §7.3).
    """
    theta, u, s = _slider_terms(theta, r, l, e)
    st, ct = np.sin(theta), np.cos(theta)
    dx = -r * st + r * ct * u / s
    ddx = -r * ct - (r * st * u + r * r * ct * ct) / s - (r * ct * u) ** 2 / s**3
    return dx, ddx


def slider_velocity(theta: np.ndarray, omega: np.ndarray, r: float, l: float, e: float = 0.0) -> np.ndarray:
    r"""Slider velocity :math:`\dot x = x'(\theta)\,\omega` [m/s].

    Parameters
    ----------
    theta : array_like
        Crank angle [rad] (convention of :func:`slider_position`).
    omega : array_like
        Crank angular velocity dθ/dt [rad/s], CCW positive.
    r, l, e : float
        Crank radius, rod length, offset [m].

    Returns
    -------
    numpy.ndarray
        dx/dt [m/s], positive = slider moving away from the crank axis.

    References
    ----------
    See :func:`slider_dx_dtheta`.
    """
    dx, _ = slider_dx_dtheta(theta, r, l, e)
    return dx * np.asarray(omega, dtype=float)


def slider_acceleration(
    theta: np.ndarray, omega: np.ndarray, alpha: np.ndarray, r: float, l: float, e: float = 0.0
) -> np.ndarray:
    r"""Slider acceleration :math:`\ddot x = x''(\theta)\,\omega^2 + x'(\theta)\,\alpha` [m/s²].

    Parameters
    ----------
    theta : array_like
        Crank angle [rad] (convention of :func:`slider_position`).
    omega : array_like
        Crank angular velocity [rad/s].
    alpha : array_like
        Crank angular acceleration [rad/s²] (0 for constant crank speed).
    r, l, e : float
        Crank radius, rod length, offset [m].

    Returns
    -------
    numpy.ndarray
        d²x/dt² [m/s²].

    References
    ----------
    See :func:`slider_dx_dtheta`.
    """
    dx, ddx = slider_dx_dtheta(theta, r, l, e)
    omega = np.asarray(omega, dtype=float)
    return ddx * omega**2 + dx * np.asarray(alpha, dtype=float)


def crank_torque_virtual_work(theta: np.ndarray, r: float, l: float, F: float, e: float = 0.0) -> np.ndarray:
    r"""Static crank torque that balances a piston force, by virtual work: ``T = F · dx/dθ``.

    Sign convention: ``F > 0`` is a force on the slider in the **−x** direction, i.e. pushing
    the piston toward the crank axis (gas pressure in an engine). ``T`` is the CCW torque that
    must be *applied to the crank* (from ground, e.g. by the load or a motor) to hold the
    mechanism at rest. Virtual work of all applied loads vanishes:
    :math:`T\,\delta\theta + (-F)\,\delta x = 0 \Rightarrow T = F\,dx/d\theta`.
    The torque the gas force itself exerts on the crank is ``-T``. Friction-free, massless
    links (inertia forces are not included).

    Parameters
    ----------
    theta : array_like
        Crank angle [rad] (convention of :func:`slider_position`).
    r, l : float
        Crank radius and rod length [m].
    F : float
        Piston force toward the crank axis [N].
    e : float, optional
        Slider-line offset [m]; default 0.

    Returns
    -------
    numpy.ndarray
        Holding torque on the crank [N·m], CCW positive. E.g. e = 0, 0 < θ < π: dx/dθ < 0, so
        ``T < 0``: the gas force drives the crank CCW and a clockwise load torque holds it.

    References
    ----------
    Principle of virtual work (Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §1.4);
    Norton, *Design of Machinery*, 5th ed., ch. 11 (energy method / virtual work); Heywood §2.2
    for the kinematics.
    """
    dx, _ = slider_dx_dtheta(theta, r, l, e)
    return F * dx


# ---------------------------------------------------------------------------------------------
# 5. Planar four-bar linkage
# ---------------------------------------------------------------------------------------------

_BRANCH_SIGN = {"open": -1.0, "crossed": 1.0}


def _branch_sign(branch: str) -> float:
    try:
        return _BRANCH_SIGN[branch]
    except KeyError:
        raise ValueError(f"branch must be 'open' or 'crossed', not {branch!r}") from None


def _half_angle_root(P: np.ndarray, Q: np.ndarray, S: np.ndarray, sign: float) -> np.ndarray:
    """Angle ``2 atan2(-Q + sign sqrt(Q² - 4PS), 2P)`` of the root of ``P t² + Q t + S = 0``.

    ``t = tan(angle/2)``. The same root is also ``2 atan2(2S, -Q - sign sqrt(...))`` (product of
    the roots = S/P); per element the form with the larger arguments is used, so ``P = Q = 0``
    (root t = ∞, angle = π) and cancellation are handled. NaN where the discriminant is < 0.
    """
    disc = Q * Q - 4.0 * P * S
    tol = 1e-12 * (Q * Q + np.abs(4.0 * P * S))
    ok = disc >= -tol
    root = np.sqrt(np.where(ok, np.maximum(disc, 0.0), 0.0))
    y1, x1 = -Q + sign * root, 2.0 * P
    y2, x2 = 2.0 * S, -Q - sign * root
    first = np.abs(y1) + np.abs(x1) >= np.abs(y2) + np.abs(x2)
    angle = 2.0 * np.arctan2(np.where(first, y1, y2), np.where(first, x1, x2))
    angle = np.angle(np.exp(1j * angle))  # wrap to (-pi, pi]
    return np.where(ok, angle, np.nan)


def fourbar_angles(
    a: float, b: float, c: float, d: float, theta2: np.ndarray, branch: str = "open"
) -> tuple[np.ndarray, np.ndarray]:
    r"""Closed-form position analysis of a planar four-bar: coupler and rocker angles.

    Ground pivots ``O2 = (0, 0)`` (crank) and ``O4 = (d, 0)`` (rocker); the x axis runs from O2
    to O4. All angles are absolute, CCW from +x. Vector loop (Norton §4.5):
    :math:`a e^{i\theta_2} + b e^{i\theta_3} - c e^{i\theta_4} - d = 0`, i.e. crank pin
    ``A = a e^{iθ2}``, coupler ``A → B`` at θ3, rocker ``O4 → B`` at θ4.

    With :math:`K_1 = d/a`, :math:`K_2 = d/c`, :math:`K_3 = (a^2 - b^2 + c^2 + d^2)/(2ac)`,
    :math:`K_4 = d/b`, :math:`K_5 = (c^2 - d^2 - a^2 - b^2)/(2ab)`:

    .. math::

        A &= \cos\theta_2 - K_1 - K_2\cos\theta_2 + K_3,\;
        B = -2\sin\theta_2,\;
        C = K_1 - (K_2 + 1)\cos\theta_2 + K_3,\\
        \theta_4 &= 2\,\mathrm{atan2}\!\left(-B \mp \sqrt{B^2 - 4AC},\; 2A\right),\\
        D &= \cos\theta_2 - K_1 + K_4\cos\theta_2 + K_5,\;
        E = -2\sin\theta_2,\;
        F = K_1 + (K_4 - 1)\cos\theta_2 + K_5,\\
        \theta_3 &= 2\,\mathrm{atan2}\!\left(-E \mp \sqrt{E^2 - 4DF},\; 2D\right),

    the upper sign (−) for ``branch="open"``, the lower (+) for ``"crossed"``. θ4 satisfies
    Freudenstein's equation :math:`K_1\cos\theta_4 - K_2\cos\theta_2 + K_3 = \cos(\theta_2 -
    \theta_4)`.

    Branch = assembly circuit, a geometric invariant: ``"open"`` has
    :math:`\sin(\theta_4 - \theta_3) > 0` (the rocker direction O4→B is CCW from the coupler
    direction A→B, transmission angle :math:`\theta_4 - \theta_3 \in (0, \pi)` mod 2π),
    ``"crossed"`` has :math:`\sin(\theta_4 - \theta_3) < 0`. The sign changes only at toggle
    positions (A, B, O4 collinear), so a branch label follows one circuit continuously, except
    for change-point linkages (S + L = P + Q), whose circuits cross at the flattened position.
    Check: ``a, b, c, d = 2, 7, 9, 6``, θ2 = 30° gives θ3 = 88.84°, θ4 = 117.29° (open),
    cf. Norton Example 4-1.

    Parameters
    ----------
    a : float
        Crank length O2–A [m].
    b : float
        Coupler length A–B [m].
    c : float
        Rocker (output) length O4–B [m].
    d : float
        Ground link length O2–O4 [m].
    theta2 : array_like
        Crank angle [rad], CCW from the line O2→O4.
    branch : {"open", "crossed"}
        Assembly circuit.

    Returns
    -------
    (theta3, theta4) : tuple of numpy.ndarray
        Coupler and rocker angles in (−π, π] [rad]; NaN where the linkage cannot be
        assembled at that θ2 (``B² - 4AC < 0``).

    Notes
    -----
    The half-angle root is evaluated in whichever of the equivalent forms
    ``2 atan2(-B ∓ √Δ, 2A)`` / ``2 atan2(2C, -B ± √Δ)`` is better conditioned, so θ = π
    (A = 0) is exact. Near a change-point bifurcation the square root of a vanishing
    discriminant limits the accuracy to ~sqrt(machine eps) relative.

    References
    ----------
    Norton, *Design of Machinery*, 5th ed., §4.5 (algebraic position analysis, half-angle
    form); Freudenstein, F. (1955), "Approximate synthesis of four-bar linkages", Trans. ASME 77.
    """
    sign = _branch_sign(branch)
    t2 = np.asarray(theta2, dtype=float)
    c2, s2 = np.cos(t2), np.sin(t2)
    K1, K2, K3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2.0 * a * c)
    K4, K5 = d / b, (c * c - d * d - a * a - b * b) / (2.0 * a * b)
    A = c2 - K1 - K2 * c2 + K3
    B = -2.0 * s2
    C = K1 - (K2 + 1.0) * c2 + K3
    D = c2 - K1 + K4 * c2 + K5
    E = -2.0 * s2
    F = K1 + (K4 - 1.0) * c2 + K5
    theta4 = _half_angle_root(A, B, C, sign)
    theta3 = _half_angle_root(D, E, F, sign)
    return theta3, theta4


def fourbar_velocities(
    a: float, b: float, c: float, theta2: np.ndarray, theta3: np.ndarray, theta4: np.ndarray, omega2: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    r"""Coupler and rocker angular velocities of a four-bar from its position solution.

    Differentiating the vector loop :math:`a e^{i\theta_2} + b e^{i\theta_3} - c e^{i\theta_4}
    - d = 0` and taking imaginary parts after multiplying by :math:`e^{-i\theta_4}` and
    :math:`e^{-i\theta_3}`:

    .. math::

        \omega_3 = \frac{a\,\omega_2}{b}\,\frac{\sin(\theta_4 - \theta_2)}{\sin(\theta_3 - \theta_4)},
        \qquad
        \omega_4 = \frac{a\,\omega_2}{c}\,\frac{\sin(\theta_2 - \theta_3)}{\sin(\theta_4 - \theta_3)}.

    Parameters
    ----------
    a, b, c : float
        Crank, coupler, rocker lengths [m].
    theta2, theta3, theta4 : array_like
        Link angles [rad] (from :func:`fourbar_angles`).
    omega2 : array_like
        Crank angular velocity [rad/s], CCW positive.

    Returns
    -------
    (omega3, omega4) : tuple of numpy.ndarray
        [rad/s]; infinite/NaN at toggle (sin(θ4 − θ3) = 0).

    References
    ----------
    Norton, *Design of Machinery*, 5th ed., §6.7 (analytical velocity analysis of the four-bar).
    """
    t2, t3, t4 = (np.asarray(v, dtype=float) for v in (theta2, theta3, theta4))
    w2 = np.asarray(omega2, dtype=float)
    w3 = a * w2 * np.sin(t4 - t2) / (b * np.sin(t3 - t4))
    w4 = a * w2 * np.sin(t2 - t3) / (c * np.sin(t4 - t3))
    return w3, w4


def coupler_point(
    a: float, b: float, theta2: np.ndarray, theta3: np.ndarray, p: float, delta: float
) -> tuple[np.ndarray, np.ndarray]:
    r"""Position of a point P fixed on the coupler of a four-bar.

    .. math::

        \mathbf R_P = a e^{i\theta_2} + p\,e^{i(\theta_3 + \delta)},

    P lies at distance ``p`` from the crank–coupler joint A, at angle ``delta`` measured CCW
    from the line A→B.

    Parameters
    ----------
    a : float
        Crank length [m].
    b : float
        Coupler length [m]. Not needed by the formula; accepted for a uniform four-bar
        signature (``delta = 0, p = b`` gives joint B).
    theta2, theta3 : array_like
        Crank and coupler angles [rad] (:func:`fourbar_angles`).
    p : float
        Distance A → P [m].
    delta : float
        Angle of AP relative to AB, CCW positive [rad].

    Returns
    -------
    (x, y) : tuple of numpy.ndarray
        Coordinates of P in the ground frame (origin O2, x toward O4) [m].

    References
    ----------
    Norton, *Design of Machinery*, 5th ed., §4.9 (position of any point on a linkage).
    """
    t2, t3 = np.asarray(theta2, dtype=float), np.asarray(theta3, dtype=float)
    return a * np.cos(t2) + p * np.cos(t3 + delta), a * np.sin(t2) + p * np.sin(t3 + delta)


class GrashofResult(NamedTuple):
    """Grashof classification of a four-bar (see :func:`grashof`).

    Attributes
    ----------
    condition : str
        ``"grashof"`` (S + L < P + Q), ``"change-point"`` (=, within 1e-12 relative) or
        ``"non-grashof"`` (>).
    kind : str
        Grashof: ``"crank-rocker"`` (shortest = crank a), ``"double-crank"`` (shortest =
        ground d), ``"double-rocker"`` (shortest = coupler b), ``"rocker-crank"`` (shortest =
        rocker c). Non-Grashof: ``"triple-rocker"``. Change point: ``"change-point"``.
    margin : float
        ``(P + Q) - (S + L)`` [m]; > 0 for Grashof.
    """

    condition: str
    kind: str
    margin: float


def grashof(a: float, b: float, c: float, d: float) -> GrashofResult:
    r"""Grashof condition of a four-bar: at least one link fully rotates iff S + L ≤ P + Q.

    S, L are the shortest and longest of (a, b, c, d), P, Q the other two. For S + L < P + Q
    the inversion is set by which link is shortest (crank → crank-rocker, ground →
    double-crank, coupler → Grashof double-rocker, rocker → rocker-crank); for S + L > P + Q
    all inversions are triple rockers (Barker class non-Grashof).

    Parameters
    ----------
    a, b, c, d : float
        Crank, coupler, rocker, ground lengths [m] (as in :func:`fourbar_angles`).

    Returns
    -------
    GrashofResult
        ``(condition, kind, margin)``. Ties for the shortest link are resolved in the order
        a, d, b, c.

    References
    ----------
    Norton, *Design of Machinery*, 5th ed., §2.12 (the Grashof condition); Grashof (1883).
    """
    lengths = {"a": a, "d": d, "b": b, "c": c}
    values = sorted(lengths.values())
    S, P, Q, L = values
    margin = (P + Q) - (S + L)
    if abs(margin) <= 1e-12 * (P + Q):
        return GrashofResult("change-point", "change-point", margin)
    if margin < 0.0:
        return GrashofResult("non-grashof", "triple-rocker", margin)
    shortest = min(lengths, key=lengths.__getitem__)
    kind = {"a": "crank-rocker", "d": "double-crank", "b": "double-rocker", "c": "rocker-crank"}[shortest]
    return GrashofResult("grashof", kind, margin)


# ---------------------------------------------------------------------------------------------
# 6. Static reactions of a pinned beam held by a link
# ---------------------------------------------------------------------------------------------


class BeamReactions(NamedTuple):
    """Reactions of :func:`beam_pin_link_reactions` (ground frame, y up).

    Attributes
    ----------
    Rx, Ry : float
        Force exerted **by the ground pin on the beam** at x = 0 [N].
    T : float
        Link force [N], positive = tension (the link pulls the beam toward its ground pin).
    """

    Rx: float
    Ry: float
    T: float


def beam_pin_link_reactions(
    m: float, L: float, g: float, a: float | None = None, link_angle: float = 0.0
) -> BeamReactions:
    r"""Static reactions of a horizontal uniform beam, pinned at x = 0 and hung from a link.

    The beam (mass m, length L, weight at x = L/2) is pinned to ground at x = 0 and held at
    x = a by a massless two-force link whose other end is pinned to ground above the beam.
    Unit vector beam → ground pin along the link: :math:`u = (\sin\beta, \cos\beta)`,
    β = ``link_angle`` (0 = vertical). Moments about the beam pin and force balance:

    .. math::

        T = \frac{m g L}{2 a \cos\beta},\qquad R_x = -T\sin\beta,\qquad R_y = m g - T\cos\beta .

    Vertical link (β = 0) at the tip (a = L): ``T = Ry = m g / 2``, ``Rx = 0``.

    Parameters
    ----------
    m : float
        Beam mass [kg].
    L : float
        Beam length [m].
    g : float
        Gravitational acceleration [m/s²], along −y.
    a : float, optional
        Link attachment coordinate along the beam [m], default ``L``. a ≠ 0; a > 0 on the beam
        side of the pin (tension), a < 0 gives a compressive link (T < 0).
    link_angle : float, optional
        Inclination β of the link from the vertical [rad], |β| < π/2, positive when the upper
        ground pin lies at larger x than the attachment point; default 0.

    Returns
    -------
    BeamReactions
        ``(Rx, Ry, T)`` [N, N, N]; see the class docstring for signs.

    References
    ----------
    Hibbeler, *Engineering Mechanics: Statics*, 14th ed., ch. 5 (equilibrium of a rigid body,
    two-force members §5.4).
    """
    a = L if a is None else float(a)
    if a == 0.0:
        raise ValueError("link attached at the pin (a = 0): statically indeterminate/singular")
    if not abs(link_angle) < math.pi / 2:
        raise ValueError("|link_angle| must be < pi/2 (link must reach above the beam)")
    T = m * g * L / (2.0 * a * math.cos(link_angle))
    return BeamReactions(-T * math.sin(link_angle), m * g - T * math.cos(link_angle), T)


# ---------------------------------------------------------------------------------------------
# 7. Static holding torque of a four-bar carrying a weight on the coupler
# ---------------------------------------------------------------------------------------------


def static_fourbar_torque(
    a: float,
    b: float,
    c: float,
    d: float,
    theta2: np.ndarray,
    p: float,
    delta: float,
    m: float,
    g: float,
    branch: str = "open",
) -> np.ndarray:
    r"""Crank torque holding a four-bar at rest with a point mass on the coupler (virtual work).

    Ground link horizontal (O2 → O4 along +x, y up, gravity −y); a point mass ``m`` sits at
    the coupler point P (:func:`coupler_point`); links are otherwise massless and frictionless.
    Virtual work :math:`T_2\,\delta\theta_2 - m g\,\delta y_P = 0` with
    :math:`dy_P/d\theta_2 = a\cos\theta_2 + p\cos(\theta_3 + \delta)\,\omega_3/\omega_2`:

    .. math::

        T_2 = m g \left[a\cos\theta_2 + p\cos(\theta_3 + \delta)\,
              \frac{a \sin(\theta_4 - \theta_2)}{b \sin(\theta_3 - \theta_4)}\right].

    Parameters
    ----------
    a, b, c, d : float
        Crank, coupler, rocker, ground lengths [m] (:func:`fourbar_angles`).
    theta2 : array_like
        Crank angle [rad], CCW from O2→O4.
    p, delta : float
        Coupler point: distance from A [m] and angle from line A→B [rad].
    m : float
        Point mass at P [kg].
    g : float
        Gravitational acceleration [m/s²].
    branch : {"open", "crossed"}
        Assembly circuit.

    Returns
    -------
    numpy.ndarray
        Torque applied to the crank by a motor on the ground [N·m], CCW positive, equal to
        ``dV/dθ2`` with ``V = m g y_P``. NaN where not assemblable.

    References
    ----------
    Norton, *Design of Machinery*, 5th ed., §6.7 (velocity ratio) and ch. 11 (kinetostatic
    force analysis); principle of virtual work (Goldstein et al. §1.4).
    """
    theta3, theta4 = fourbar_angles(a, b, c, d, theta2, branch)
    t2 = np.asarray(theta2, dtype=float)
    w3, _ = fourbar_velocities(a, b, c, t2, theta3, theta4, 1.0)
    return m * g * (a * np.cos(t2) + p * np.cos(theta3 + delta) * w3)
