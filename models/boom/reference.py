"""Smooth references for boom joints: position and speed with continuous speed.

A motion planner or an operator's joystick moves a joint with a trapezoidal speed profile: constant acceleration
``a_max`` up to ``v_max``, cruise, constant deceleration to rest at the target (a triangle when the move is too short
to reach ``v_max``). The position is C1 (piecewise quadratic), the speed continuous (piecewise linear) and zero at
every stop, the acceleration bounded; so the feed-forward flow ``A·dL/dt`` ramps instead of jumping (a
piecewise-linear reference with a piecewise-constant feed-forward would change the flow stepwise at every knot).

Representation: knots ``(t_k, y_k, dy_k)`` and the cubic Hermite polynomial through each pair of knots, which
reproduces a quadratic phase exactly. The position block evaluates those cubics and the speed block their exact
derivatives (quadratics), so ``dy`` is the derivative of ``y`` to rounding everywhere, not a second interpolation.
Both are :class:`~flexlib.components.control.TimeTable` blocks (every knot a time event, ends held) with their
segment polynomials given: the library's ``TimeTable`` offers C1 splines (Akima, Fritsch–Butland) whose knot
slopes it chooses itself, but no cubic Hermite with *given* knot slopes, which exact planner profiles need
(:class:`HermiteTable` adds that by overriding :meth:`~flexlib.components.control.TimeTable.coefficients`).

A joint profile becomes a cylinder-length profile through the kinematics ``L(q)`` (:func:`joint_to_length`): the
joint profile sampled densely, ``L(q(t))`` and ``dL/dt = dL/dq·dq/dt`` at each sample as the new knots; the speed
stays continuous (C1 Hermite), the length within ``O(h⁴)`` of ``L(q(t))`` between the samples.

References
----------
L. Biagiotti, C. Melchiorri, *Trajectory Planning for Automatic Machines and Robots*, Springer 2008, §3.2
(trapezoidal velocity profile) and §4.4 (cubic Hermite interpolation with assigned velocities). Modelica Standard
Library 4.0, ``Blocks.Sources.CombiTimeTable`` and ``Mechanics.Rotational.Sources.KinematicPTP``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import flexlib as fl
from flexlib import Output
from flexlib.components.control import TimeTable
from flexlib.errors import ParameterError

from ._checks import positive

__all__ = ["HermiteTable", "SmoothReference", "joint_to_length", "trapezoid_profile", "waypoint_moves"]

Knots = tuple[np.ndarray, np.ndarray, np.ndarray]


def hermite_coefficients(t: np.ndarray, y: np.ndarray, dy: np.ndarray) -> np.ndarray:
    """Coefficients ``c[k] = (c0, c1, c2, c3)`` in ``s = t − t[k]`` of the cubic through ``(y, dy)`` at both ends."""
    h, m = np.diff(t), np.diff(y) / np.diff(t)
    return np.column_stack([y[:-1], dy[:-1], (3 * m - 2 * dy[:-1] - dy[1:]) / h, (dy[:-1] + dy[1:] - 2 * m) / h**2])


class HermiteTable(TimeTable):
    """A :class:`~flexlib.components.control.TimeTable` whose segments are given cubic polynomials.

    Parameters
    ----------
    t : array_like
        Knot times [s], strictly increasing.
    c : array_like
        ``len(t) − 1`` rows ``(c0, c1, c2, c3)``: the output on segment k is ``c0 + c1 s + c2 s² + c3 s³`` with
        ``s = t − t[k]``; before ``t[0]`` the value at ``t[0]`` is held, after ``t[-1]`` the last segment's end value.
    hold : float
        The output of a table of one knot (no segments).
    """

    def __init__(self, t: Any, c: Any, hold: float = 0.0, **kw: Any) -> None:
        t_arr, c_arr = np.asarray(t, dtype=float), np.asarray(c, dtype=float).reshape(-1, 4)
        if t_arr.ndim != 1 or len(c_arr) != max(len(t_arr) - 1, 0):
            raise ParameterError(f"HermiteTable: c needs {max(t_arr.size - 1, 0)} rows of 4 coefficients for "
                                 f"{t_arr.size} knots, got shape {np.shape(c)}")
        h = np.diff(t_arr)
        y = np.append(c_arr[:, 0], c_arr[-1] @ h[-1] ** np.arange(4)) if len(c_arr) else np.full(t_arr.size, hold)
        super().__init__(t=t_arr, y=y, **kw)
        self.table_c = c_arr

    def coefficients(self) -> np.ndarray:
        return self.table_c


def trapezoid_profile(q_start: float, moves: Sequence[Sequence[float]]) -> Knots:
    """Knots ``(t, q, dq)`` of a sequence of point-to-point moves with trapezoidal speed.

    Parameters
    ----------
    q_start : float
        Position before the first move.
    moves : sequence of (t_start, target, v_max, a_max)
        Each move starts at rest at ``t_start`` [s] (not before the previous move has ended), accelerates at
        ``a_max`` to ``v_max`` (or less, for a short move), cruises and decelerates to rest at ``target``.

    Returns
    -------
    t, q, dq : ndarray
        Knot times, positions and speeds (zero at the start and end of every move).
    """
    part = "SmoothReference"
    q = float(q_start)
    if not math.isfinite(q):
        raise ParameterError(f"{part}: q_start must be a finite number, got {q_start!r}")
    t_k, q_k, dq_k = [], [], []
    t_free = -math.inf
    for i, move in enumerate(moves):
        if len(move) != 4:
            raise ParameterError(f"{part}: moves[{i}] must be (t_start, target, v_max, a_max), got {move!r}")
        t0, target = float(move[0]), float(move[1])
        v, a = positive(part, f"moves[{i}] v_max", move[2], "1/s"), positive(part, f"moves[{i}] a_max", move[3], "1/s2")
        if not (math.isfinite(t0) and math.isfinite(target)):
            raise ParameterError(f"{part}: moves[{i}] t_start and target must be finite, got {move!r}")
        if t0 < t_free - 1e-12:
            raise ParameterError(f"{part}: moves[{i}] starts at t = {t0:g} s, before the previous move ends "
                                 f"({t_free:g} s)")
        d = target - q
        if d == 0.0:
            continue
        sgn, dist = math.copysign(1.0, d), abs(d)
        v = min(v, math.sqrt(dist * a))  # a triangle if v_max is not reached
        t_acc, t_cru = v / a, dist / v - v / a
        ts = [t0, t0 + t_acc, t0 + t_acc + t_cru, t0 + 2 * t_acc + t_cru]
        qs = [q, q + sgn * v * t_acc / 2, target - sgn * v * t_acc / 2, target]
        vs = [0.0, sgn * v, sgn * v, 0.0]
        keep = [0, 1, 3] if t_cru <= 1e-12 * ts[-1] + 1e-15 else [0, 1, 2, 3]
        if t_k and t_k[-1] >= ts[0]:  # moves back to back: the end knot of one is the start of the next
            keep = keep[1:]
        t_k += [ts[j] for j in keep]
        q_k += [qs[j] for j in keep]
        dq_k += [vs[j] for j in keep]
        q, t_free = target, ts[-1]
    if not t_k:
        return np.zeros(1), np.array([q]), np.zeros(1)
    return np.array(t_k), np.array(q_k), np.array(dq_k)


def waypoint_moves(t: Sequence[float], q: Sequence[float], a_max: float) -> list[tuple[float, float, float, float]]:
    """Moves through waypoints ``(t_k, q_k)``: from each to the next, at rest at both, arriving exactly at ``t_k+1``.

    The cruise speed of a trapezoid covering ``d = |q_k+1 − q_k|`` in ``T = t_k+1 − t_k`` at acceleration ``a_max``
    is ``v = (a T − sqrt(a² T² − 4 a d))/2`` (it exists if ``a T² >= 4 d``).
    """
    part = "SmoothReference"
    t_arr, q_arr = np.asarray(t, dtype=float), np.asarray(q, dtype=float)
    a = positive(part, "a_max", a_max, "1/s2")
    if t_arr.ndim != 1 or t_arr.shape != q_arr.shape or t_arr.size < 1 or not np.all(np.isfinite([*t_arr, *q_arr])):
        raise ParameterError(f"{part}: waypoints t and q must be finite vectors of the same length, got shapes "
                             f"{t_arr.shape}, {q_arr.shape}")
    if np.any(np.diff(t_arr) <= 0):
        raise ParameterError(f"{part}: waypoint times must be strictly increasing, got {t_arr.tolist()}")
    moves = []
    for k in range(t_arr.size - 1):
        T, d = t_arr[k + 1] - t_arr[k], abs(q_arr[k + 1] - q_arr[k])
        if d == 0.0:
            continue
        disc = a * a * T * T - 4 * a * d
        if disc < 0:
            raise ParameterError(f"{part}: waypoint {k + 1} cannot be reached from waypoint {k} in {T:g} s at a_max = "
                                 f"{a:g} (needs a_max >= 4|dq|/T² = {4 * d / T**2:g})")
        v = (a * T - math.sqrt(disc)) / 2
        moves.append((float(t_arr[k]), float(q_arr[k + 1]), v, a))
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


def joint_to_length(knots: Knots, L: Callable[[float], float], dt: float = 1.0, n: int = 4, dq: float = 1e-6,
                    dL: Callable[[float], float] | None = None) -> Knots:
    """Cylinder-length knots ``(t, L, dL/dt)`` of a joint profile through the kinematics ``L(q)``.

    Each moving segment of the joint profile is split into equal steps of at most ``dt``, at least ``n``; at every
    sample ``L(q(t))`` and
    ``dL/dt = L'(q)·dq/dt`` (``L'`` given as ``dL``, or a central difference of step ``dq``) are the new knots.
    Segments where the joint rests stay one segment.

    Parameters
    ----------
    knots : (t, q, dq) arrays
        Joint profile (e.g. from :func:`trapezoid_profile`).
    L : callable
        Pin-to-pin length [m] of the joint's cylinder at the joint angle ``q`` [rad] (e.g.
        ``lambda q: record.drive(k).state(q).length``).
    dt : float
        Largest sample step [s] (default 1 s: a length error ``O(dt⁴)``, about 1e-8 m on a 42 m boom's joint).
    n : int
        Least number of steps per moving segment (>= 1).
    dq : float
        Step of the central difference of ``L`` [rad] (without ``dL``).
    dL : callable, optional
        ``dL/dq`` [m/rad] at ``q`` (e.g. ``lambda q: record.drive(k).state(q).lever_arm``).
    """
    if not isinstance(n, int) or isinstance(n, bool) or n < 1:
        raise ParameterError(f"SmoothReference: n must be an integer >= 1, got {n!r}")
    dq, dt = positive("SmoothReference", "dq", dq, "rad"), positive("SmoothReference", "dt", dt, "s")
    t, q, v = (np.asarray(a, dtype=float) for a in knots)
    samples = [t[:1]]
    for k in range(t.size - 1):
        moving = not (q[k] == q[k + 1] and v[k] == 0.0 and v[k + 1] == 0.0)
        steps = max(n, math.ceil((t[k + 1] - t[k]) / dt - 1e-9))
        samples.append(np.linspace(t[k], t[k + 1], steps + 1)[1:] if moving else t[k + 1:k + 2])
    ts = np.concatenate(samples)
    qs, vs = _evaluate((t, q, v), ts)
    at_knot = np.isin(ts, t)  # the knots themselves exactly (a stop stays a stop, not a rounding of it)
    qs[at_knot], vs[at_knot] = q[np.searchsorted(t, ts[at_knot])], v[np.searchsorted(t, ts[at_knot])]
    lengths = np.array([float(L(x)) for x in qs])
    slopes = np.array([float(dL(x)) if dL is not None else (float(L(x + dq)) - float(L(x - dq))) / (2 * dq)
                       for x in qs])
    return ts, lengths, slopes * vs


class SmoothReference(fl.Model):
    """Reference with continuous speed: position ``y`` and speed ``dy`` of a C1 cubic Hermite profile.

    Contains ``position`` and ``speed`` (:class:`HermiteTable`): the Hermite cubics through the knots
    ``(t_k, y_k, dy_k)`` and their exact derivatives (module docstring). With ``ff_gain = (k_pos, k_neg)`` a third
    table ``feed_forward`` gives ``k_pos·dy`` where the speed is positive and ``k_neg·dy`` where it is negative (a
    cylinder's feed-forward valve command: ``A_p/Q_nom`` extending, ``A_r/Q_nom`` retracting); continuous because
    the speed changes sign only at knots where it is zero (a stop).

    Build the knots with :func:`trapezoid_profile` (moves), :func:`waypoint_moves` (waypoints) and
    :func:`joint_to_length` (joint angle → cylinder length), or use :meth:`from_moves`.

    Parameters
    ----------
    t, y, dy : array_like
        Knot times [s] (strictly increasing), positions and speeds (the signal's unit and per second).
    ff_gain : (float, float), optional
        Gains of the feed-forward output for positive and negative speed.

    Connectors
    ----------
    y : Output
        Position.
    dy : Output
        Speed ``dy/dt``.
    ff : Output [1]
        Feed-forward (only with ``ff_gain``).
    """

    def __init__(self, t: Any, y: Any, dy: Any, ff_gain: Sequence[float] | None = None, **kw: Any) -> None:
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
        self.knots = (t_arr, y_arr, dy_arr)
        c = hermite_coefficients(t_arr, y_arr, dy_arr) if t_arr.size > 1 else np.zeros((0, 4))
        dc = np.column_stack([c[:, 1], 2 * c[:, 2], 3 * c[:, 3], np.zeros(len(c))])
        self.y, self.dy = Output(unit="1", doc="Position"), Output(unit="1", doc="Speed dy/dt")
        self.position, self.speed = HermiteTable(t_arr, c, hold=float(y_arr[0])), HermiteTable(t_arr, dc)
        self.connect(self.position.y, self.y)
        self.connect(self.speed.y, self.dy)
        if ff_gain is not None:
            if len(ff_gain) != 2:
                raise ParameterError(f"{part}: ff_gain must be (gain for dy > 0, gain for dy < 0), got {ff_gain!r}")
            k_pos, k_neg = (positive(part, f"ff_gain[{i}]", g, "1") for i, g in enumerate(ff_gain))
            mid = dc[:, 0] + dc[:, 1] * np.diff(t_arr) / 2 + dc[:, 2] * (np.diff(t_arr) / 2) ** 2
            self.ff = Output(unit="1", doc="Feed-forward: ff_gain[0]·dy (dy > 0), ff_gain[1]·dy (dy < 0)")
            self.feed_forward = HermiteTable(t_arr, dc * np.where(mid >= 0, k_pos, k_neg)[:, None])
            self.connect(self.feed_forward.y, self.ff)

    @classmethod
    def from_moves(cls, q_start: float, moves: Sequence[Sequence[float]], **kw: Any) -> SmoothReference:
        """The reference of :func:`trapezoid_profile` ``(q_start, moves)``."""
        return cls(*trapezoid_profile(q_start, moves), **kw)

    def evaluate(self, ts: Any) -> tuple[np.ndarray, np.ndarray]:
        """Position and speed at times ``ts`` [s] (the same profile, in numpy)."""
        return _evaluate(self.knots, np.asarray(ts, dtype=float))
