"""Closed forms of the slider-crank: piston position, velocity and acceleration, dx/dθ, and the crank torque that
balances a piston force by virtual work.

Conventions: SI units (m, kg, s, rad, N, N·m, kg·m²); planar problems with x horizontal, y vertically **up**,
gravity ``(0, -g)``, angles counter-clockwise positive. Independent of flexlib (numpy/scipy only); each function is
checked against a second, independent computation in ``tests/test_references_multibody.py``.
"""

# ``l`` is the textbook symbol (Heywood's rod length).
# ruff: noqa: E741

from __future__ import annotations

import numpy as np

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


