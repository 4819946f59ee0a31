"""A new integrator is one adapter: a fixed-step backward-Euler adapter, defined here, runs a mass–spring–damper with a
time event and a state event through ``Simulation.run`` and the one run loop, and matches the closed form at
backward-Euler accuracy (first order: the error halves with the step). The three real backends give the same output
grid, the same events and the same statistics keys."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
from scipy.optimize import brentq

import flexlib as fl
from flexlib import Parameter, Variable, der, eq, if_else, time
from flexlib.solve.backends.base import Limits, Stop
from flexlib.solve.events import watched_relations
from flexlib.solve.loop import STATS_KEYS
from flexlib.solve.native import native_available
from flexlib.solve.solvers import Solver

M, K, D, F0, T_ON = 1.0, 4.0, 0.4, 1.0, 0.5


class PushedOscillator(fl.Model):
    """m·x'' + d·x' + k·x = f with f stepping from 0 to F0 at t = t_on (a time event); ``below`` says whether the
    mass is below its rest position (the relation ``x < 0``: a state event where x first crosses zero)."""

    m = Parameter(M, unit="kg")
    k = Parameter(K, unit="N/m")
    d = Parameter(D, unit="N.s/m")
    t_on = Parameter(T_ON, unit="s")
    x = Variable(unit="m")
    v = Variable(unit="m/s")
    f = Variable(unit="N")
    below = Variable()

    def equations(self):
        return [eq(der(self.x), self.v), eq(self.m * der(self.v), self.f - self.k * self.x - self.d * self.v),
                eq(self.f, if_else(time >= self.t_on, F0, 0.0)), eq(self.below, if_else(self.x < 0.0, 1.0, 0.0))]


def exact_x(t: np.ndarray) -> np.ndarray:
    """x(t) from x(0) = 1, v(0) = 0, with the step force from t_on (superposition of the free and the step response)."""
    t = np.asarray(t, dtype=float)
    delta = D / (2 * M)
    wd = np.sqrt(K / M - delta**2)

    def free(s: np.ndarray) -> np.ndarray:
        return np.exp(-delta * s) * (np.cos(wd * s) + delta / wd * np.sin(wd * s))

    s = np.maximum(t - T_ON, 0.0)
    return free(t) + np.where(t >= T_ON, F0 / K * (1.0 - free(s)), 0.0)


class BackwardEuler:
    """Fixed-step backward Euler behind the Integrator protocol: one step per call, Newton on
    ``F(t1, y1, (y1 − y0)/h) = 0``, a state event located by bisection on the length of the last step."""

    name = "backward-euler"
    watch_steps = 0
    settles_roots = False
    monitors = False
    progress_every = 1

    def __init__(self, h: float, rtol: float = 1e-6, atol: float = 1e-8) -> None:
        self.h, self.rtol, self.atol = h, rtol, atol
        self.nfev = self.njev = 0

    def start(self, model, t, y, yp, p, grid, t_end) -> None:
        self.model, self.p, self.n_par = model, p, model.n_params
        self.res, self.jac, self.ind = model.function("res"), model.function("jac"), model.function("ind")
        self.diff = np.asarray(model.differential, dtype=bool)
        self.state_rel = watched_relations(model)
        self.grid = [] if grid is None else [float(g) for g in grid]
        self.every_step = grid is None
        self.t, self.y, self.yp = t, np.array(y, dtype=float), np.array(yp, dtype=float)

    def step_to(self, t1: float) -> tuple[np.ndarray, np.ndarray]:
        h, y = t1 - self.t, self.y + (t1 - self.t) * self.yp
        for _ in range(50):
            yp = np.where(self.diff, (y - self.y) / h, 0.0)
            r = np.asarray(self.res(t1, y, yp, self.p)).ravel()
            J = np.asarray(self.jac(t1, y, yp, self.p, 1.0 / h).full())
            self.nfev, self.njev = self.nfev + 1, self.njev + 1
            dy = np.linalg.solve(J, r)
            y = y - dy
            if np.max(np.abs(dy)) <= 1e-13 * (1.0 + np.max(np.abs(y))):
                break
        return y, np.where(self.diff, (y - self.y) / h, 0.0)

    def switched(self, t: float, y: np.ndarray, yp: np.ndarray) -> list[tuple[int, bool]]:
        z = np.asarray(self.ind(t, y, yp, self.p)).ravel()
        values = [(int(k), bool(self.model.relations[k].value(z[k]))) for k in self.state_rel]
        return [(k, v) for k, v in values if float(v) != self.p[self.n_par + k]]

    def advance(self, t_stop: float, limits: Limits) -> Stop:
        t1 = t_stop if t_stop - self.t <= 1.000001 * self.h else self.t + self.h
        y1, yp1 = self.step_to(t1)
        roots = self.switched(t1, y1, yp1)
        if roots:  # the first instant of the step where a relation has switched
            lo, hi = self.t, t1
            while hi - lo > 1e-12 * max(1.0, abs(hi)):
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if self.switched(mid, *self.step_to(mid)) else (mid, hi)
            t1 = hi
            y1, yp1 = self.step_to(t1)
            roots = self.switched(t1, y1, yp1)
        rows: tuple[list, list, list] = ([], [], [])
        while self.grid and self.grid[0] <= t1:  # the step's linear interpolant
            tg = self.grid.pop(0)
            w = (tg - self.t) / (t1 - self.t)
            rows[0].append(tg)
            rows[1].append((1 - w) * self.y + w * y1)
            rows[2].append(yp1.copy())
        if self.every_step:
            rows = ([t1], [y1], [yp1])
        self.t, self.y, self.yp = t1, y1, yp1
        kind = "root" if roots else "tstop" if t1 >= t_stop else "step"
        return Stop(kind, t1, 1, rows, roots=roots)

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        self.t, self.y, self.yp = t, np.array(y, dtype=float), np.array(yp, dtype=float)

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.y, self.yp

    def accepted(self) -> tuple[float, Any, Any]:
        return self.t, self.y, self.yp

    def unsaved_rows(self) -> tuple[list, list, list]:
        return [], [], []

    def last_step(self) -> None:
        return None

    def stats(self, wall: float) -> dict[str, Any]:
        return {"solver": self.name, "max_order": 1, "nfev": self.nfev, "njev": self.njev}


@dataclass(frozen=True)
class BackwardEulerSolver(Solver):
    """The solver object that makes the adapter (``sim.run(solver=BackwardEulerSolver(h))``)."""

    h: float = 1e-3
    label = "backward-euler"

    def adapter(self, rtol, atol, max_step, max_order, max_steps):
        return BackwardEuler(self.h, rtol, atol)


@pytest.fixture(scope="module")
def sim() -> fl.Simulation:
    return fl.Simulation(PushedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


def crossings(t_end: float = 3.0) -> list[float]:
    """The zeros of the closed-form x(t) in (0, t_end) (the state events of ``x < 0``)."""
    t = np.linspace(0.0, t_end, 3001)
    x = exact_x(t)
    return [brentq(exact_x, t[i], t[i + 1], xtol=1e-14) for i in np.flatnonzero(np.sign(x[:-1]) != np.sign(x[1:]))]


def test_backward_euler_adapter_matches_closed_form_at_first_order(sim):
    errors = []
    for h in (2e-3, 1e-3):
        res = sim.run(3.0, dt_out=0.05, solver=BackwardEulerSolver(h), progress=False)
        assert res.success and res.t[-1] == 3.0
        zeros = crossings()
        assert [text.split(":")[0] for _, text in res.events] == ["time event"] + ["state event"] * len(zeros)
        assert res.events[0][0] == T_ON  # the loop stops the integrator exactly at the time event
        # located on the backward-Euler solution, within its error of the closed form's zeros
        np.testing.assert_allclose([t for t, _ in res.events[1:]], zeros, atol=50 * h)
        assert res.stats["time_events"] == 1 and res.stats["state_events"] == len(zeros) == 2
        assert res.stats["solver"] == "backward-euler" and res.stats["steps"] >= 3.0 / h
        assert set(STATS_KEYS) <= set(res.stats)
        grid = ~np.isin(res.t, [t for t, _ in res.events])  # the output grid's rows (not the event rows)
        err = np.max(np.abs(res["x"][grid] - exact_x(res.t[grid])))
        assert err < 10 * h  # O(h)
        down, up = (t for t, _ in res.events[1:])
        np.testing.assert_array_equal(res["below"][grid], (res.t[grid] > down) & (res.t[grid] < up))
        errors.append(err)
    assert 1.6 < errors[0] / errors[1] < 2.4  # first order: half the step, half the error


BACKENDS = ["ida-sksundae", "casadi-idas"] + (["ida-native"] if native_available() else [])


def test_real_backends_give_the_same_grid_events_and_stats_keys(sim):
    runs = {b: sim.run(3.0, dt_out=0.05, rtol=1e-9, atol=1e-11, solver=b, progress=False) for b in BACKENDS}
    ref = runs["ida-sksundae"]
    zeros = crossings()
    for b, res in runs.items():
        assert res.success, b
        grid = ~np.isin(res.t, [t for t, _ in res.events])  # the output grid (t_end its last point), exactly
        np.testing.assert_array_equal(res.t[grid], ref.t[~np.isin(ref.t, [t for t, _ in ref.events])], err_msg=b)
        assert res.t[-1] == 3.0 and len(res.t) == len(ref.t), b  # and the same event rows
        assert [text for _, text in res.events] == [text for _, text in ref.events], b
        assert res.events[0][0] == T_ON, b
        np.testing.assert_allclose([t for t, _ in res.events[1:]], zeros, atol=1e-6, err_msg=b)
        assert set(STATS_KEYS) <= set(res.stats), b
        assert res.stats["solver"] == b and res.stats["time_events"] == 1, b
        assert res.stats["state_events"] == len(zeros), b
        np.testing.assert_allclose(res["x"], exact_x(res.t), atol=1e-6, err_msg=b)
