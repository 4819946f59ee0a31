"""Smooth references for boom joints: position and speed with continuous speed.

A motion planner or an operator's joystick moves a joint with a trapezoidal speed profile: constant acceleration
``a_max`` up to ``v_max``, cruise, constant deceleration to rest at the target (a triangle when the move is too short
to reach ``v_max``). The position is C1 (piecewise quadratic), the speed continuous (piecewise linear) and zero at
every stop, the acceleration bounded; so the feed-forward flow ``A·dL/dt`` ramps instead of jumping (a
piecewise-linear reference with a piecewise-constant feed-forward would change the flow stepwise at every knot).
With a jerk limit ``j_max`` the corners of the trapezoid are rounded (S-curve: seven phases of constant jerk), so
the acceleration, and the rate of change of the flow, is continuous too.

Representation: knots ``(t_k, y_k, dy_k)`` at the phase boundaries and the cubic Hermite polynomial through each
pair of knots, which reproduces a phase of constant acceleration (quadratic) or constant jerk (cubic) exactly. The
part selects the segment that holds the time (its start ``t_k`` and four coefficients, by a binary search over
the knots, :func:`flexlib.segment_row`; no time events: the profile's value and speed are continuous at every knot,
so the integrator may step across one) and evaluates the cubic for ``y`` and its exact derivative for ``dy``, so
``dy`` is the derivative of ``y`` to rounding everywhere, not a second interpolation. (A ``TimeTable`` per output
would evaluate every segment's polynomial at every residual call, and stop the integrator at every knot.)

A joint profile becomes a cylinder-length profile through the kinematics ``L(q)`` (:func:`joint_to_length`): the
joint profile sampled densely, ``L(q(t))`` and ``dL/dt = dL/dq·dq/dt`` at each sample as the new knots; the speed
stays continuous (C1 Hermite); the samples are refined until the length is within a tolerance of ``L(q(t))``.

References
----------
L. Biagiotti, C. Melchiorri, *Trajectory Planning for Automatic Machines and Robots*, Springer 2008, §3.2
(trapezoidal velocity profile), §3.4 (double-S, jerk-limited profile) and §4.4 (cubic Hermite interpolation with
assigned velocities). Modelica Standard Library 4.0, ``Blocks.Sources.CombiTimeTable`` and
``Blocks.Sources.KinematicPTP``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import flexlib as fl
from flexlib import Output
from flexlib.errors import ParameterError

from ._checks import positive

__all__ = ["SmoothReference", "joint_to_length", "motion_profile", "waypoint_moves"]

Knots = tuple[np.ndarray, np.ndarray, np.ndarray]


def hermite_coefficients(t: np.ndarray, y: np.ndarray, dy: np.ndarray) -> np.ndarray:
    """Coefficients ``c[k] = (c0, c1, c2, c3)`` in ``s = t − t[k]`` of the cubic through ``(y, dy)`` at both ends."""
    h, m = np.diff(t), np.diff(y) / np.diff(t)
    return np.column_stack([y[:-1], dy[:-1], (3 * m - 2 * dy[:-1] - dy[1:]) / h, (dy[:-1] + dy[1:] - 2 * m) / h**2])


def _accel_phase(v: float, a: float, j: float) -> tuple[float, float, float]:
    """``(a_peak, T_j, T_ca)`` of a jerk-limited acceleration from rest to ``v``: jerk ``j`` for ``T_j``, constant
    acceleration for ``T_ca``, jerk ``−j`` for ``T_j`` (``j = inf``: a step to ``a``, ``T_j = 0``)."""
    if math.isinf(j):
        return a, 0.0, v / a
    if v >= a * a / j:
        return a, a / j, v / a - a / j
    t_j = math.sqrt(v / j)
    return j * t_j, t_j, 0.0


def _peak_speed(dist: float, v: float, a: float, j: float) -> tuple[float, float]:
    """Peak speed and cruise time of a rest-to-rest move over ``dist`` with the limits ``v``, ``a``, ``j``.

    The acceleration phase to ``v_p`` is point-symmetric in speed: it covers ``v_p·T_a/2``, ``T_a = 2 T_j + T_ca``.
    Without cruise ``v_p·T_a = dist``: ``v_p = sqrt(a·dist)`` (no jerk limit), ``v_p (v_p/a + a/j) = dist`` (``a``
    reached), ``2 v_p^(3/2)/sqrt(j) = dist`` (``a`` not reached)."""
    _, t_j, t_ca = _accel_phase(v, a, j)
    d_acc = v * (2 * t_j + t_ca)  # both ramps
    if d_acc <= dist:
        return v, (dist - d_acc) / v
    if math.isinf(j):
        return math.sqrt(a * dist), 0.0
    vp = a / 2 * (-a / j + math.sqrt((a / j) ** 2 + 4 * dist / a))
    return (vp, 0.0) if vp >= a * a / j else ((dist * math.sqrt(j) / 2) ** (2 / 3), 0.0)


def _cruise_speed(dist: float, T: float, a: float, j: float) -> float:
    """Cruise speed ``v`` of the jerk-limited move over ``dist`` that takes ``T`` (the root of ``T(v) = T`` on the
    branch with a cruise, ``v <= v_p`` of :func:`_peak_speed`), in closed form.

    With the acceleration ``a`` reached (``v >= a²/j``) the move takes ``T = dist/v + v/a + a/j``: the smaller root
    of ``v²/a − (T − a/j) v + dist = 0``. Without (``v < a²/j``, ramps of ``T_j = sqrt(v/j)``) it takes ``T =
    dist/v + 2 sqrt(v/j)``: with ``s = sqrt(v)`` the smallest positive root of ``(2/sqrt(j)) s³ − T s² + dist = 0``
    (the cubic's roots, polished by Newton steps on it)."""
    b = T - a / j
    disc = b * b - 4 * dist / a
    if disc >= -1e-12 * b * b:  # (a move without cruise: 0 up to round-off)
        disc = max(disc, 0.0)
        v = 2 * dist / (b + math.sqrt(disc)) if b > 0 else 0.0  # = a (b − sqrt(disc))/2 without cancellation
        if v >= a * a / j:
            return v
    c3 = 2 / math.sqrt(j)
    roots = np.roots([c3, -T, 0.0, dist])
    s = min(float(r.real) for r in roots if abs(r.imag) <= 1e-9 * abs(r) and r.real > 0)
    for _ in range(3):
        f, df = (c3 * s - T) * s * s + dist, (3 * c3 * s - 2 * T) * s
        if df == 0.0:
            break
        s -= f / df
    return s * s


def _move_duration(dist: float, v: float, a: float, j: float) -> float:
    vp, t_c = _peak_speed(dist, v, a, j)
    _, t_j, t_ca = _accel_phase(vp, a, j)
    return 2 * (2 * t_j + t_ca) + t_c


def _move_knots(q: float, dist: float, sgn: float, v: float, a: float, j: float) -> list[tuple[float, float, float]]:
    """``(duration, q_end, v_end)`` of each phase (of nonzero duration) of one move, phases of constant jerk."""
    vp, t_c = _peak_speed(dist, v, a, j)
    ap, t_j, t_ca = _accel_phase(vp, a, j)
    jerk = 0.0 if math.isinf(j) else ap / t_j if t_j > 0 else 0.0
    # (duration, acceleration at its start, jerk): up, constant, down, cruise, and the mirror image
    phases = [(t_j, 0.0, jerk), (t_ca, ap, 0.0), (t_j, ap, -jerk), (t_c, 0.0, 0.0),
              (t_j, 0.0, -jerk), (t_ca, -ap, 0.0), (t_j, -ap, jerk)]
    if math.isinf(j):  # steps of acceleration: the ramps carry it as their start value
        phases = [(0.0, 0.0, 0.0), (t_ca, ap, 0.0), (0.0, 0.0, 0.0), (t_c, 0.0, 0.0),
                  (0.0, 0.0, 0.0), (t_ca, -ap, 0.0), (0.0, 0.0, 0.0)]
    out, x, w = [], 0.0, 0.0
    for tau, acc, jk in phases:
        if tau <= 1e-12 * (t_c + 4 * t_j + 2 * t_ca):
            continue
        x, w = x + w * tau + acc * tau**2 / 2 + jk * tau**3 / 6, w + acc * tau + jk * tau**2 / 2
        out.append((tau, q + sgn * x, sgn * w))
    out[-1] = (out[-1][0], q + sgn * dist, 0.0)  # at rest on the target, exactly
    return out


def motion_profile(q_start: float, moves: Sequence[Sequence[float]]) -> Knots:
    """Knots ``(t, q, dq)`` of a sequence of rest-to-rest moves with trapezoidal speed, optionally jerk-limited.

    Parameters
    ----------
    q_start : float
        Position before the first move.
    moves : sequence of (t_start, target, v_max, a_max) or (t_start, target, v_max, a_max, j_max)
        Each move starts at rest at ``t_start`` [s] (not before the previous move has ended), accelerates to
        ``v_max`` (or less, for a short move), cruises and decelerates to rest at ``target``: with a constant
        acceleration ``a_max`` (trapezoidal speed, C1 position), or with the acceleration ramped at the jerk
        ``j_max`` (S-curve: 7 phases of constant jerk, C2 position, the acceleration continuous).

    Returns
    -------
    t, q, dq : ndarray
        Knot times (one per phase boundary), positions and speeds (zero at the start and end of every move).
    """
    part = "SmoothReference"
    q = float(q_start)
    if not math.isfinite(q):
        raise ParameterError(f"{part}: q_start must be a finite number, got {q_start!r}")
    t_k, q_k, dq_k = [], [], []
    t_free = -math.inf
    for i, move in enumerate(moves):
        if len(move) not in (4, 5):
            raise ParameterError(f"{part}: moves[{i}] must be (t_start, target, v_max, a_max[, j_max]), got {move!r}")
        t0, target = float(move[0]), float(move[1])
        v, a = positive(part, f"moves[{i}] v_max", move[2], "1/s"), positive(part, f"moves[{i}] a_max", move[3], "1/s2")
        j = positive(part, f"moves[{i}] j_max", move[4], "1/s3") if len(move) == 5 else math.inf
        if not (math.isfinite(t0) and math.isfinite(target)):
            raise ParameterError(f"{part}: moves[{i}] t_start and target must be finite, got {move!r}")
        if t0 < t_free - 1e-9 * max(1.0, abs(t0)):
            raise ParameterError(f"{part}: moves[{i}] starts at t = {t0:g} s, before the previous move ends "
                                 f"({t_free:g} s)")
        if target == q:
            continue
        if not (t_k and t_k[-1] >= t0 - 1e-9 * max(1.0, abs(t0))):  # else back to back: one knot between them
            t_k, q_k, dq_k = [*t_k, t0], [*q_k, q], [*dq_k, 0.0]
        for tau, q_end, v_end in _move_knots(q, abs(target - q), math.copysign(1.0, target - q), v, a, j):
            t_k, q_k, dq_k = [*t_k, t_k[-1] + tau], [*q_k, q_end], [*dq_k, v_end]
        q, t_free = target, t_k[-1]
    if not t_k:
        return np.zeros(1), np.array([q]), np.zeros(1)
    return np.array(t_k), np.array(q_k), np.array(dq_k)


def waypoint_moves(t: Sequence[float], q: Sequence[float], a_max: float,
                   j_max: float | None = None) -> list[tuple[float, ...]]:
    """Moves through waypoints ``(t_k, q_k)``: from each to the next, at rest at both, arriving at ``t_k+1``.

    A waypoint inside a stretch of constant speed (the same slope before and after it, as in a piecewise-linear
    time table where another joint's knot falls) is passed, not stopped at: each stretch of constant speed of the
    piecewise-linear path through the waypoints becomes one rest-to-rest move over the same time.

    The cruise speed of a move covering ``d = |q_k+1 − q_k|`` in ``T = t_k+1 − t_k``: without a jerk limit the
    trapezoid's ``v = (a T − sqrt(a² T² − 4 a d))/2`` (it exists if ``a T² >= 4 d``); with ``j_max`` the root of
    the S-curve's duration ``T(v) = T`` (:func:`_cruise_speed`, in closed form).
    """
    part = "SmoothReference"
    t_arr, q_arr = np.asarray(t, dtype=float), np.asarray(q, dtype=float)
    a = positive(part, "a_max", a_max, "1/s2")
    j = math.inf if j_max is None else positive(part, "j_max", j_max, "1/s3")
    if t_arr.ndim != 1 or t_arr.shape != q_arr.shape or t_arr.size < 1 or not np.all(np.isfinite([*t_arr, *q_arr])):
        raise ParameterError(f"{part}: waypoints t and q must be finite vectors of the same length, got shapes "
                             f"{t_arr.shape}, {q_arr.shape}")
    if np.any(np.diff(t_arr) <= 0):
        raise ParameterError(f"{part}: waypoint times must be strictly increasing, got {t_arr.tolist()}")
    slope = np.diff(q_arr) / np.diff(t_arr)
    keep = np.ones(t_arr.size, dtype=bool)  # corners of the piecewise-linear path (and its ends)
    keep[1:-1] = ~np.isclose(slope[1:], slope[:-1], rtol=1e-9, atol=1e-12 * max(1.0, float(np.max(np.abs(slope)))))
    t_arr, q_arr = t_arr[keep], q_arr[keep]
    moves: list[tuple[float, ...]] = []
    for k in range(t_arr.size - 1):
        T, d = float(t_arr[k + 1] - t_arr[k]), float(abs(q_arr[k + 1] - q_arr[k]))
        if d == 0.0:
            continue
        v_free = _peak_speed(d, math.inf, a, j)[0]  # no cruise
        if _move_duration(d, v_free, a, j) > T:
            raise ParameterError(f"{part}: waypoint {k + 1} cannot be reached from waypoint {k} in {T:g} s at a_max "
                                 f"= {a:g}" + ("" if math.isinf(j) else f", j_max = {j:g}") +
                                 f" (it takes {_move_duration(d, v_free, a, j):g} s at least)")
        if math.isinf(j):
            v = (a * T - math.sqrt(max(a * a * T * T - 4 * a * d, 0.0))) / 2
            moves.append((float(t_arr[k]), float(q_arr[k + 1]), v, a))
        else:
            v = min(_cruise_speed(d, T, a, j), v_free)  # (at T = T(v_free) the root is v_free up to round-off)
            moves.append((float(t_arr[k]), float(q_arr[k + 1]), v, a, j))
    return moves


def _evaluate(knots: Knots, ts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position and speed of the Hermite profile through ``knots`` at times ``ts`` (ends held)."""
    t, y, dy = knots
    if t.size < 2:
        return np.full(ts.shape, y[0]), np.zeros(ts.shape)
    c = hermite_coefficients(t, y, dy)
    k = np.clip(np.searchsorted(t, ts, side="right") - 1, 0, t.size - 2)
    s = np.clip(ts, t[0], t[-1]) - t[k]
    ck = c[k]
    return (ck[:, 0] + s * (ck[:, 1] + s * (ck[:, 2] + s * ck[:, 3])),
            np.where((ts < t[0]) | (ts > t[-1]), 0.0, ck[:, 1] + s * (2 * ck[:, 2] + 3 * s * ck[:, 3])))


def joint_to_length(knots: Knots, L: Callable[[float], float], tol: float = 1e-6, dq: float = 1e-6,
                    dL: Callable[[float], float] | None = None, max_knots: int = 100_000) -> Knots:
    """Cylinder-length knots ``(t, L, dL/dt)`` of a joint profile through the kinematics ``L(q)``, to ``tol``.

    At each knot ``L(q(t))`` and ``dL/dt = L'(q)·dq/dt`` (``L'`` given as ``dL``, or a central difference of step
    ``dq``); between knots the cubic Hermite polynomial through them (C1: the speed continuous). Starting from the
    joint profile's own knots, every moving segment is halved until the polynomial's position at the segment's
    midpoint is within ``tol`` of ``L(q(t))`` and its speed at ``h(1/2 − 1/(2√3))`` within ``tol`` per second of
    ``dL/dt`` (where the leading error terms of cubic Hermite interpolation, ``O(h⁴)`` in position and ``O(h³)`` in
    speed, peak); so knots gather where the kinematics bends and a long cruise needs few. Segments where the joint
    rests stay one.

    Parameters
    ----------
    knots : (t, q, dq) arrays
        Joint profile (e.g. from :func:`motion_profile`).
    L : callable
        Pin-to-pin length [m] of the joint's cylinder at the joint angle ``q`` [rad] (e.g.
        ``record.drive(k).length``).
    tol : float
        Largest position error at the midpoints [m] (and speed error [m/s]); default 1 µm.
    dq : float
        Step of the central difference of ``L`` [rad] (without ``dL``).
    dL : callable, optional
        ``dL/dq`` [m/rad] at ``q`` (e.g. ``lambda q: record.drive(k).state(q).lever_arm``).
    max_knots : int
        Refuse to go beyond this many knots (``L`` not smooth enough for ``tol``).
    """
    part = "SmoothReference"
    tol, dq = positive(part, "tol", tol, "m"), positive(part, "dq", dq, "rad")
    t, q, v = (np.asarray(a, dtype=float) for a in knots)

    def sample(ts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        qs, vs = _evaluate((t, q, v), ts)
        at_knot = np.isin(ts, t)  # the joint profile's knots exactly (a stop stays a stop, not a rounding of it)
        qs[at_knot], vs[at_knot] = q[np.searchsorted(t, ts[at_knot])], v[np.searchsorted(t, ts[at_knot])]
        lengths = np.array([float(L(x)) for x in qs])
        slopes = np.array([float(dL(x)) if dL is not None else (float(L(x + dq)) - float(L(x - dq))) / (2 * dq)
                           for x in qs])
        return lengths, slopes * vs

    ts = t.copy()
    ys, dys = sample(ts)
    moving = ~((q[:-1] == q[1:]) & (v[:-1] == 0.0) & (v[1:] == 0.0))
    split = np.flatnonzero(moving)  # segments (between ts[i] and ts[i + 1]) to check
    while split.size:
        h, y0, y1, d0, d1 = ts[split + 1] - ts[split], ys[split], ys[split + 1], dys[split], dys[split + 1]
        m = (y1 - y0) / h
        c2, c3 = (3 * m - 2 * d0 - d1) / h, (d0 + d1 - 2 * m) / h**2
        # the leading error terms peak at the midpoint (position, ∝ s²(h − s)²) and at s = h(1/2 − 1/(2√3)) (speed)
        s_y, s_v = h / 2, h * (0.5 - 0.5 / math.sqrt(3.0))
        mid = ts[split] + s_y
        y_mid, dy_mid = sample(mid)
        _, dy_v = sample(ts[split] + s_v)
        bad = ((np.abs(y0 + s_y * (d0 + s_y * (c2 + s_y * c3)) - y_mid) > tol)
               | (np.abs(d0 + s_v * (2 * c2 + 3 * s_v * c3) - dy_v) > tol))
        if not np.any(bad):
            break
        if ts.size + np.count_nonzero(bad) > max_knots:
            raise ParameterError(f"{part}: the length profile needs more than {max_knots} knots for tol = {tol:g} m "
                                 "(is L(q) smooth over the joint's range?)")
        order = np.argsort(np.concatenate([ts, mid[bad]]), kind="stable")
        new = np.concatenate([np.zeros(ts.size, bool), np.ones(np.count_nonzero(bad), bool)])[order]
        ts = np.concatenate([ts, mid[bad]])[order]
        ys, dys = np.concatenate([ys, y_mid[bad]])[order], np.concatenate([dys, dy_mid[bad]])[order]
        # the two halves of each split segment are checked next
        idx = np.flatnonzero(new)
        split = np.unique(np.concatenate([idx - 1, idx]))
    return ts, ys, dys


class SmoothReference(fl.Model):
    """Reference with continuous speed: position ``y`` and speed ``dy`` of a C1 cubic Hermite profile.

    The cubic Hermite polynomials through the knots ``(t_k, y_k, dy_k)`` give ``y``, their exact derivatives ``dy``
    (module docstring); before the first knot and after the last the end positions are held at zero speed. With
    ``ff_gain = (k_pos, k_neg)`` the output ``ff`` is ``k_pos·dy`` where the speed is positive and ``k_neg·dy`` where
    it is negative (a cylinder's feed-forward valve command: ``A_p/Q_nom`` extending, ``A_r/Q_nom`` retracting);
    continuous, as the speed changes sign only through zero. With ``ff_lead > 0`` the feed-forward is the speed
    ``ff_lead`` ahead, ``k·dy(t + ff_lead)``: it makes up for the lags between the command and the flow (the valve
    amplifier's command filter and the spool), so the cylinder follows the reference instead of trailing it by the
    lag and the loop does not brake it past the end of a move (the same segment selection, at the shifted time).

    Build the knots with :func:`motion_profile` (moves), :func:`waypoint_moves` (waypoints) and
    :func:`joint_to_length` (joint angle → cylinder length), or use :meth:`from_moves`.

    Parameters
    ----------
    t, y, dy : array_like
        Knot times [s] (strictly increasing), positions and speeds (the signal's unit and per second).
    ff_gain : (float, float), optional
        Gains of the feed-forward output for positive and negative speed.
    ff_lead : float
        Time by which the feed-forward leads the reference [s] (default 0; structural).

    Connectors
    ----------
    y : Output
        Position.
    dy : Output
        Speed ``dy/dt``.
    ff : Output [1]
        Feed-forward (only with ``ff_gain``).
    """

    def __init__(self, t: Any, y: Any, dy: Any, ff_gain: Sequence[float] | None = None, ff_lead: float = 0.0,
                 **kw: Any) -> None:
        super().__init__(**kw)
        part = "SmoothReference"
        t_arr, y_arr, dy_arr = (np.asarray(a, dtype=float) for a in (t, y, dy))
        if not (t_arr.ndim == 1 and t_arr.size >= 1 and t_arr.shape == y_arr.shape == dy_arr.shape):
            raise ParameterError(f"{part}: t, y and dy must be vectors of one length, got shapes {t_arr.shape}, "
                                 f"{y_arr.shape}, {dy_arr.shape}")
        if not np.all(np.isfinite([*t_arr, *y_arr, *dy_arr])):
            raise ParameterError(f"{part}: t, y and dy must be finite")
        if np.any(np.diff(t_arr) <= 0):
            raise ParameterError(f"{part}: t must be strictly increasing")
        if dy_arr[0] != 0.0 or dy_arr[-1] != 0.0:
            raise ParameterError(f"{part}: the speed must be 0 at the first and last knot (the ends are held), got "
                                 f"dy[0] = {dy_arr[0]:g}, dy[-1] = {dy_arr[-1]:g}")
        # structure: the knots relative to the first (public: in the build's key); the start value is a parameter
        self.profile = (t_arr, y_arr - y_arr[0], dy_arr)
        self.ff_gain = None
        self.ff_lead = positive(part, "ff_lead", ff_lead, "s", allow_zero=True)  # structure: a second selection
        if ff_gain is not None:
            if isinstance(ff_gain, str | bytes) or not hasattr(ff_gain, "__len__") or len(ff_gain) != 2:
                raise ParameterError(f"{part}: ff_gain must be (gain for dy > 0, gain for dy < 0), got {ff_gain!r}")
            self.ff_gain = tuple(positive(part, f"ff_gain[{i}]", g, "1") for i, g in enumerate(ff_gain))
            self.ff = Output(unit="1", doc="Feed-forward: ff_gain[0]·dy (dy > 0), ff_gain[1]·dy (dy < 0)")
        self.y, self.dy = Output(unit="1", doc="Position"), Output(unit="1", doc="Speed dy/dt")
        # the start value is a parameter, the profile relative to it structure: a joint held in another pose is the
        # same build (a machine's static starts in many poses share one)
        self.y_start = fl.Parameter(float(y_arr[0]), unit="1", doc="Position at the first knot")

    @property
    def knots(self) -> Knots:
        """The knots ``(t, y, dy)`` as given."""
        t, y, dy = self.profile
        return t, y + float(self.parameter_value("y_start")), dy

    def _segment(self, time: Any) -> tuple[Any, list[Any]]:
        """``(s, [c0, c1, c2, c3])`` of the segment holding ``time``, ``s = time − t_k`` (relative to the first knot;
        the held ends: ``c = (y_end − y_start, 0, 0, 0)``): a binary search over the knots
        (:func:`flexlib.segment_row`), whose cost does not grow with the number of knots."""
        t, y, dy = self.profile  # relative to y_start
        c = hermite_coefficients(t, y, dy) if t.size > 1 else np.zeros((0, 4))
        # segments: the held start, the cubics, the held end; each (t_k, c0, c1, c2, c3)
        rows = [(t[0], y[0], 0.0, 0.0, 0.0), *((t[k], *c[k]) for k in range(len(c))), (t[-1], y[-1], 0.0, 0.0, 0.0)]
        seg = fl.segment_row(time, t, rows)  # segment i holds the times before t[i]
        return time - seg[0], seg[1:]

    def equations(self) -> list:
        """``y = y_start + c0 + s(c1 + s(c2 + s c3))``, ``dy = c1 + s(2 c2 + 3 s c3)``, ``s = t − t_k``, with ``t_k``
        and ``c`` those of the segment holding ``t``; ``ff = k·dy(t + ff_lead)`` (the speed ``ff_lead`` ahead)."""
        s, (c0, c1, c2, c3) = self._segment(fl.time)
        out = [fl.eq(self.y, self.y_start + c0 + s * (c1 + s * (c2 + s * c3))),
               fl.eq(self.dy, c1 + s * (2 * c2 + 3 * s * c3))]
        if self.ff_gain is not None:
            k_pos, k_neg = self.ff_gain
            speed: Any = self.dy  # without a lead, the speed itself
            if self.ff_lead > 0:
                s, (_, c1, c2, c3) = self._segment(fl.time + self.ff_lead)
                speed = c1 + s * (2 * c2 + 3 * s * c3)
            out.append(fl.eq(self.ff, fl.no_event(speed > 0, k_pos, k_neg) * speed))
        return out

    @classmethod
    def from_moves(cls, q_start: float, moves: Sequence[Sequence[float]], **kw: Any) -> SmoothReference:
        """The reference of :func:`motion_profile` ``(q_start, moves)``."""
        return cls(*motion_profile(q_start, moves), **kw)

    def evaluate(self, ts: Any) -> tuple[np.ndarray, np.ndarray]:
        """Position and speed at times ``ts`` [s] (the same profile, in numpy)."""
        return _evaluate(self.knots, np.asarray(ts, dtype=float))
