"""Closed forms of pendulums: periods of the simple and the physical pendulum, the double pendulum's
linearised modes and its point positions (pendulum angles from the **downward** vertical).

Conventions: SI units (m, kg, s, rad, N, N·m, kg·m²); planar problems with x horizontal, y vertically **up**,
gravity ``(0, -g)``, angles counter-clockwise positive. Independent of flexlib (numpy/scipy only); each function is
checked against a second, independent computation in ``tests/test_references_multibody.py``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.special import ellipj, ellipk

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


def pendulum_angle(t: np.ndarray, L: float, g: float, theta0: float) -> np.ndarray:
    r"""Exact angle of a simple pendulum released at rest from ``theta0``, at times ``t``.

    With :math:`k = \sin(\theta_0/2)` and :math:`\omega_0 = \sqrt{g/L}` the libration is
    :math:`\sin(\theta/2) = k\,\mathrm{sn}(K(k^2) - \omega_0 t;\,k^2)` (Jacobi elliptic sine, parameter
    :math:`m = k^2`), which starts at :math:`\theta_0` with zero rate.

    Parameters
    ----------
    t : array_like
        Times [s] after the release.
    L : float
        Length [m] (for a physical pendulum its equivalent length :math:`I_O/(m d)`).
    g : float
        Gravitational acceleration [m/s^2].
    theta0 : float
        Release angle [rad] from the downward vertical, ``|theta0| < pi``.

    Returns
    -------
    numpy.ndarray
        Angle [rad] from the downward vertical.

    References
    ----------
    Lawden, *Elliptic Functions and Applications*, §5.2 (the simple pendulum).
    """
    a = _check_amplitude(theta0)
    k2 = math.sin(a / 2.0) ** 2
    sn, _, _, _ = ellipj(ellipk(k2) - math.sqrt(g / L) * np.asarray(t, dtype=float), k2)
    return math.copysign(1.0, theta0) * 2.0 * np.arcsin(math.sqrt(k2) * sn)


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


