"""Closed forms of the heavy symmetric top with a fixed tip: steady precession, consistent start values, Euler's
equations in Z-X-Z angles and their energy (world z **up**, gravity ``(0, 0, -g)``; ``world_up="y"`` re-expresses
the start values for a y-up world).

Conventions: SI units (m, kg, s, rad, N, N·m, kg·m²); planar problems with x horizontal, y vertically **up**,
gravity ``(0, -g)``, angles counter-clockwise positive. Independent of flexlib (numpy/scipy only); each function is
checked against a second, independent computation in ``tests/test_references_multibody.py``.
"""

# ``l`` is the textbook symbol (Goldstein's tip-to-CM distance).
# ruff: noqa: E741

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

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


