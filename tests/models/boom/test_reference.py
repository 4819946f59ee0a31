"""Bench tests of :class:`flexlib.models.boom.SmoothReference` and its profile helpers.

References and tolerances:

* trapezoidal speed profile (closed form, Biagiotti & Melchiorri 2008 §3.2): per move of length ``d`` at ``v``,
  ``a``: ``q = a τ²/2`` while accelerating (``τ < v/a``), then ``v`` constant, then the mirror image; the part's
  equations, solved at each time (the compiled residual, no integration), equal it to 1e-12 (the Hermite cubics
  reproduce the quadratic phases exactly); the simulated outputs to the integrator's tolerance, 1e-8 (the outputs
  are algebraic unknowns that IDA interpolates between its steps, which cross the knots: the profile has no time
  events, its speed being continuous; measured 9e-10 at rtol 1e-9);
* ``dy`` is the derivative of ``y``: central differences of the simulated ``y`` (step ``h`` = 5 ms) within
  ``a_max·h`` of ``dy`` (the bound of a difference straddling an acceleration step; 1e-12 elsewhere);
* continuity: at every knot the speed jumps by less than 1e-9 of its maximum (left and right limits evaluated
  1e-9 s apart); the issue's check on the flows: per move at most two runs of ``|d(dy)/dt|`` above 20 % of its
  maximum (acceleration and deceleration);
* jerk-limited (S-curve) move: against the hand-integrated seven phases of constant jerk (see the test);
* waypoints hit to 1e-12, speed within ``v_max`` and acceleration within ``a_max`` (1e-9 relative, on the part's
  equations);
* joint → cylinder length through a pump-truck drive's kinematics ``L(q)`` (``record.drive(2)``): ``L(q(t))`` within
  1e-6 m of the length profile and ``L'(q)·dq/dt`` within 1e-6 m/s of its speed on a 10 ms grid (the knots refined
  to ``tol`` = 1e-6 where the Hermite errors peak; measured 7.1e-7 m, 9.3e-7 m/s with 58 knots), the speed
  continuous at every knot as above and at most two runs of ``|d²L/dt²|`` above 20 % of its maximum per move.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.errors import ParameterError
from flexlib.models.boom import SmoothReference, joint_to_length, motion_profile, waypoint_moves
from flexlib.models.pump_truck.parameters import PumpTruckParameters

MOVES = [(1.0, 1.0, 0.2, 0.1), (12.0, 0.5, 0.3, 0.2), (16.0, 0.52, 0.3, 0.2)]  # the last one a triangle
DT = 0.005


def trapezoid_exact(t: np.ndarray, q0: float, moves) -> tuple[np.ndarray, np.ndarray]:
    """Position and speed of the moves, phase by phase."""
    q, v_out, q_prev = np.full(t.shape, q0), np.zeros(t.shape), q0
    for t0, target, v, a in moves:
        d = abs(target - q_prev)
        sgn = np.sign(target - q_prev)
        v = min(v, np.sqrt(d * a))
        T = d / v + v / a
        tau = np.clip(t - t0, 0.0, T)
        pos = np.where(tau < v / a, a * tau**2 / 2,
                       np.where(tau < T - v / a, v**2 / (2 * a) + v * (tau - v / a), d - a * (T - tau) ** 2 / 2))
        speed = np.where(tau < v / a, a * tau, np.where(tau < T - v / a, v, a * (T - tau)))
        active = (t >= t0)
        q = np.where(active, q_prev + sgn * pos, q)
        v_out = np.where(active & (t <= t0 + T), sgn * speed, v_out)
        q_prev = target
    return q, v_out


def runs_above(x: np.ndarray, fraction: float = 0.2) -> int:
    """Number of runs of |x| above ``fraction`` of its maximum."""
    above = np.abs(x) > fraction * np.max(np.abs(x))
    return int(np.count_nonzero(above[1:] & ~above[:-1]) + above[0])


def samples(res: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``time, y, dy`` of a result, each time once (an event point is stored twice)."""
    t, keep = np.unique(res["time"], return_index=True)
    return t, res["y"][keep], res["dy"][keep]


def simulate(ref: SmoothReference, t_end: float, **run) -> dict[str, np.ndarray]:
    """The reference's outputs ``y``, ``dy`` (and ``ff``) over ``0 … t_end``, simulated."""
    res = fl.Simulation(ref, use_cache=False).run(t_end, **run)
    return {name: res[name] for name in ("time", "y", "dy", "ff") if name == "time" or name in res.names}


def equations_at(ref: SmoothReference, ts: np.ndarray) -> dict[str, np.ndarray]:
    """The part's outputs solved from its compiled residual at each time (Newton's method, no integration)."""
    import casadi as ca

    sim = fl.Simulation(ref, use_cache=False, codegen=False)
    c = sim.compiled
    res = c.sx_function("res")
    jac = res.factory("res_y", res.name_in(), [f"jac:{res.name_out(0)}:{res.name_in(1)}"])
    p = np.concatenate([sim.parameter_vector(), np.zeros(c.n_relations)])
    zero = np.zeros(c.n)

    def solve(t: float) -> np.ndarray:
        y = np.zeros(c.n)
        for _ in range(3):  # piecewise linear in the outputs (ff switches on the sign of dy): Newton, exact in 2
            y = y - np.linalg.solve(np.asarray(ca.DM(jac(t, y, zero, p))), np.asarray(res(t, y, zero, p)))[:, 0]
        return y

    out = np.array([solve(t) for t in ts])
    return {"time": ts, **{name: out[:, k] for k, name in enumerate(c.y_names)}}


def knot_jumps(ref: SmoothReference) -> np.ndarray:
    t = ref.knots[0]
    _, left = ref.evaluate(t - 5e-10)
    _, right = ref.evaluate(t + 5e-10)
    return np.abs(right - left)


@pytest.fixture(scope="module")
def run():
    ref = SmoothReference.from_moves(0.0, MOVES, ff_gain=(2.0, 0.5))
    return ref, equations_at(ref, np.arange(0.0, 22.0 + DT / 2, DT))


def test_trapezoid_closed_form(run):
    ref, res = run
    t = res["time"]
    q, v = trapezoid_exact(t, 0.0, MOVES)
    assert np.max(np.abs(res["y"] - q)) < 1e-12
    assert np.max(np.abs(res["dy"] - v)) < 1e-12
    sim = simulate(ref, 22.0, dt_out=DT, rtol=1e-9, atol=1e-12)  # integrated: the interpolation of IDA
    q, v = trapezoid_exact(sim["time"], 0.0, MOVES)
    assert np.max(np.abs(sim["y"] - q)) < 1e-8
    assert np.max(np.abs(sim["dy"] - v)) < 1e-8


def test_speed_is_derivative_and_continuous(run):
    ref, res = run
    t, y, dy = samples(res)
    fd = (y[2:] - y[:-2]) / (t[2:] - t[:-2])
    a_max = max(m[3] for m in MOVES)
    assert np.max(np.diff(t)) <= DT * (1 + 1e-9)
    assert np.max(np.abs(fd - dy[1:-1])) < a_max * DT
    assert np.max(knot_jumps(ref)) < 1e-9 * np.max(np.abs(dy))
    acc = np.gradient(dy, t)
    bounds = [m[0] for m in MOVES] + [t[-1]]
    for lo, hi in itertools.pairwise(bounds):
        seg = (t >= lo) & (t < hi)
        assert runs_above(acc[seg]) <= 2, (lo, hi)


def test_limits_and_feed_forward(run):
    _, res = run
    t, _, dy = samples(res)
    assert np.max(np.abs(dy[t < 12.0])) <= 0.2 * (1 + 1e-9)
    assert np.max(np.abs(dy)) <= 0.3 * (1 + 1e-9)
    assert np.max(np.abs(np.diff(dy) / np.diff(t))) <= 0.2 * (1 + 1e-9)
    assert np.max(np.abs(res["ff"] - np.where(res["dy"] > 0, 2.0, 0.5) * res["dy"])) < 1e-12



def test_feed_forward_lead():
    """``ff_lead``: the feed-forward is the closed-form trapezoid's speed ``lead`` ahead (``k·v(t + lead)``, the gain of
    the sign of that speed), while ``y`` and ``dy`` stay the reference's own; 1e-12 as above."""
    lead = 0.171
    ref = SmoothReference.from_moves(0.0, MOVES, ff_gain=(2.0, 0.5), ff_lead=lead)
    res = equations_at(ref, np.arange(0.0, 22.0 + DT / 2, DT))
    q, v = trapezoid_exact(res["time"], 0.0, MOVES)
    _, v_ahead = trapezoid_exact(res["time"] + lead, 0.0, MOVES)
    assert np.max(np.abs(res["y"] - q)) < 1e-12
    assert np.max(np.abs(res["dy"] - v)) < 1e-12
    assert np.max(np.abs(res["ff"] - np.where(v_ahead > 0, 2.0, 0.5) * v_ahead)) < 1e-12
    assert np.max(np.abs(res["ff"] - np.where(v > 0, 2.0, 0.5) * v)) > 1e-3  # it does lead
    with pytest.raises(ParameterError, match="SmoothReference: ff_lead must"):
        SmoothReference.from_moves(0.0, MOVES, ff_gain=(2.0, 0.5), ff_lead=-0.1)

# S-curve d = 1, v = 0.2, a = 0.1, j = 0.1 from t = 1 s, by hand: seven phases of constant jerk
# (duration, acceleration at the start, jerk); q and v at the phase boundaries follow by integration
S_PHASES = [(1.0, 0.0, 0.1), (1.0, 0.1, 0.0), (1.0, 0.1, -0.1), (2.0, 0.0, 0.0), (1.0, 0.0, -0.1),
            (1.0, -0.1, 0.0), (1.0, -0.1, 0.1)]


def s_curve_exact(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    q, v, a = np.zeros(t.shape), np.zeros(t.shape), np.zeros(t.shape)
    t0, q0, v0 = 1.0, 0.0, 0.0
    for tau, a0, jerk in S_PHASES:
        s = t - t0
        inside = (s >= 0) & (s <= tau)
        q = np.where(inside, q0 + v0 * s + a0 * s**2 / 2 + jerk * s**3 / 6, q)
        v = np.where(inside, v0 + a0 * s + jerk * s**2 / 2, v)
        a = np.where(inside, a0 + jerk * s, a)
        q0, v0, t0 = q0 + v0 * tau + a0 * tau**2 / 2 + jerk * tau**3 / 6, v0 + a0 * tau + jerk * tau**2 / 2, t0 + tau
    return np.where(t > t0, q0, q), v, a


def test_jerk_limited_s_curve():
    """Duration ``d/v + v/a + a/j`` = 8 s (both limits reached); position and speed against the hand-integrated
    phases (the profile 1e-14, the part's equations 1e-12; the simulated outputs 1e-8, the integrator's); the
    acceleration continuous (jumps of its central differences below ``j_max·h``), within
    ``a_max``, the jerk within ``j_max`` (second differences of the speed, 1e-9 relative)."""
    ref = SmoothReference.from_moves(0.0, [(1.0, 1.0, 0.2, 0.1, 0.1)])
    assert ref.knots[0][-1] == pytest.approx(1.0 + 1 / 0.2 + 0.2 / 0.1 + 0.1 / 0.1, abs=1e-12)
    sim = simulate(ref, 10.0, dt_out=DT, rtol=1e-9, atol=1e-12)
    q, v, _ = s_curve_exact(sim["time"])
    assert np.max(np.abs(sim["y"] - q)) < 1e-8
    assert np.max(np.abs(sim["dy"] - v)) < 1e-8
    t, y, dy = samples(equations_at(ref, np.arange(0.0, 10.0 + DT / 2, DT)))
    q, v, a = s_curve_exact(t)
    y_ref, dy_ref = ref.evaluate(t)
    assert np.max(np.abs(y_ref - q)) < 1e-14
    assert np.max(np.abs(dy_ref - v)) < 1e-14
    assert np.max(np.abs(y - q)) < 1e-12
    assert np.max(np.abs(dy - v)) < 1e-12
    acc = np.diff(dy) / np.diff(t)
    assert np.max(np.abs(acc)) <= 0.1 * (1 + 1e-9)
    assert np.max(np.abs(np.diff(acc))) <= 0.1 * DT * (1 + 1e-9)  # no acceleration step
    assert np.max(np.abs(np.diff(acc) / np.diff(t)[1:])) <= 0.1 * (1 + 1e-6)
    assert np.max(np.abs(acc - a[:-1])) < 0.1 * DT
    assert runs_above(acc) == 2


def test_waypoints_hit():
    t_w, q_w, a = [0.0, 10.0, 14.0, 30.0], [0.0, 1.0, 1.0, -0.5], 0.1
    ref = SmoothReference(*motion_profile(0.0, waypoint_moves(t_w, q_w, a)))
    q, v = ref.evaluate(np.array(t_w))
    assert np.max(np.abs(q - q_w)) < 1e-12
    assert np.max(np.abs(v)) < 1e-12
    assert np.max(knot_jumps(ref)) < 1e-9
    with pytest.raises(ParameterError, match="SmoothReference: waypoint 1 cannot be reached"):
        waypoint_moves([0.0, 1.0], [0.0, 1.0], 1.0)
    moves = waypoint_moves(t_w, q_w, a, j_max=0.2)  # jerk-limited: the cruise speed in closed form
    t, q, v = motion_profile(0.0, moves)
    for tk, qk in zip(t_w, q_w, strict=True):
        k = np.argmin(np.abs(t - tk))
        assert abs(t[k] - tk) < 1e-9 and abs(q[k] - qk) < 1e-12 and v[k] == 0.0


def test_cruise_speed_closed_form_against_root_finding():
    """The jerk-limited move's cruise speed in closed form (quadratic with the acceleration limit reached, cubic
    without) equals Brent's root of the move's duration ``T(v) = T`` (scipy.optimize, an independent route) to
    1e-9 relative, and the move it gives takes ``T`` to 1e-13, over distances, limits and durations spanning both
    regimes, down to the move without cruise."""
    from scipy.optimize import brentq

    from flexlib.models.boom.reference import _cruise_speed, _move_duration, _peak_speed

    rng = np.random.default_rng(7)
    regimes = set()
    for k in range(2000):
        d, a, j = 10 ** rng.uniform(-4, 2), 10 ** rng.uniform(-3, 1), 10 ** rng.uniform(-3, 3)
        v_free = _peak_speed(d, math.inf, a, j)[0]
        T_min = _move_duration(d, v_free, a, j)
        T = T_min * (1 + (10 ** rng.uniform(-12, 2) if k % 10 else 0.0))
        v = _cruise_speed(d, T, a, j)
        assert abs(_move_duration(d, min(v, v_free), a, j) - T) < 1e-13 * T
        if k % 10:
            ref = brentq(lambda w, d=d, a=a, j=j, T=T: _move_duration(d, w, a, j) - T, d / T, v_free, rtol=1e-14,
                         xtol=1e-300)
            assert abs(v - ref) < 1e-9 * ref, (d, a, j, T)
        regimes.add(v >= a * a / j)
    assert regimes == {True, False}


def test_joint_to_length_through_kinematics():
    drive = PumpTruckParameters().drive(2)
    joint = motion_profile(2.9, [(0.0, 0.5, 0.05, 0.02), (60.0, 1.5, 0.05, 0.02)])
    knots = joint_to_length(joint, lambda q: drive.state(q).length, dL=lambda q: drive.state(q).lever_arm)
    ref = SmoothReference(*knots)
    t = np.linspace(0.0, 90.0, 9001)
    q, w = trapezoid_exact(t, 2.9, [(0.0, 0.5, 0.05, 0.02), (60.0, 1.5, 0.05, 0.02)])
    L, dL = ref.evaluate(t)
    L_exact = np.array([drive.state(x).length for x in q])
    dL_exact = np.array([drive.state(x).lever_arm for x in q]) * w
    assert np.max(np.abs(L - L_exact)) < 1e-6
    assert np.max(np.abs(dL - dL_exact)) < 1e-6
    assert np.max(knot_jumps(ref)) < 1e-9 * np.max(np.abs(dL))
    numeric = joint_to_length(joint, lambda q: drive.state(q).length)  # central differences
    assert np.max(np.abs(numeric[2] - knots[2])) < 1e-7
    for seg in (t < 60.0, t >= 60.0):  # the check on each move of the cylinder's speed
        assert runs_above(np.gradient(dL[seg], t[seg])) <= 2


def test_no_moves_holds_the_start():
    ref = SmoothReference.from_moves(0.3, [(5.0, 0.3, 1.0, 1.0)])  # a move to where it is: nothing moves
    res = simulate(ref, 1.0, dt_out=0.5)
    assert np.all(res["y"] == 0.3)
    assert np.all(res["dy"] == 0.0)


@pytest.mark.parametrize(("call", "message"), [
    (lambda: motion_profile(0.0, [(0.0, 1.0, 0.0, 1.0)]), "moves\\[0\\] v_max must"),
    (lambda: motion_profile(0.0, [(0.0, 1.0, 1.0, -1.0)]), "moves\\[0\\] a_max must"),
    (lambda: motion_profile(0.0, [(0.0, 1.0, 1.0, 1.0), (1.0, 2.0, 1.0, 1.0)]), "moves\\[1\\] starts"),
    (lambda: motion_profile(0.0, [(0.0, 1.0)]), "moves\\[0\\] must be"),
    (lambda: SmoothReference([0.0, 1.0], [0.0, 1.0], [1.0, 0.0]), "the speed must be 0"),
    (lambda: SmoothReference([1.0, 0.0], [0.0, 1.0], [0.0, 0.0]), "t must be strictly increasing"),
    (lambda: SmoothReference([0.0, 1.0], [0.0, 1.0], [0.0, 0.0], ff_gain=(1.0, 0.0)), "ff_gain\\[1\\] must"),
    (lambda: joint_to_length((np.zeros(1), np.zeros(1), np.zeros(1)), abs, tol=0.0), "tol must"),
])
def test_bad_arguments(call, message):
    with pytest.raises(ParameterError, match=f"SmoothReference: {message}"):
        call()
