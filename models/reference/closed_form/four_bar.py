"""Closed forms of the planar four-bar: position (Freudenstein, half-angle roots) and velocity analysis, coupler
point, Grashof classification, the static crank torque, and the reactions of a beam on a pin held by a link.

Conventions: SI units (m, kg, s, rad, N, N·m, kg·m²); planar problems with x horizontal, y vertically **up**,
gravity ``(0, -g)``, angles counter-clockwise positive. Independent of flexlib (numpy/scipy only); each function is
checked against a second, independent computation in ``tests/test_references_multibody.py``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

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
    a, b, c, d : float
        Crank O2–A, coupler A–B, rocker (output) O4–B and ground O2–O4 lengths [m].
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
