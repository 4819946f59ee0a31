"""A fixed-step implicit integrator for the index-reduced DAE (``solver=fl.FixedStep(h=1e-3)``): real-time use.

Every step has the same size ``h`` (a step that would pass a time event or the end is shortened to land on it; one that
ends there up to round-off keeps its size and the formula's history) and a
bounded cost: at most ``newton_iters`` Newton corrections, stopping early when the weighted correction is below 1 (the
measure IDA's Newton iteration uses). A step whose corrections do not converge is taken as two implicit-Euler halves
instead, each halved again where needed, up to ``max_halvings`` times (default 2: a step costs at most seven step
solutions; counted in ``halved_steps``): a valve opening across its corner within one step (a counterbalance check
valve cracking, the pump truck at 1.281 s of expand-fold with h = 1 ms) is what defeats Newton's method with the step's
full size and passes with a smaller one, as IDA cuts its step there. BDF2 goes on from the step's two ends after halves
(their spacing is ``h``). At the smallest size, a step whose corrections still contract is taken and counted in
``unconverged_steps`` (a real-time step ends when its budget does); one whose corrections grow or turn non-finite fails
the run. A correction that turns back on the one before (their weighted scalar product below −½ of the product of
their norms: Newton cycling round a corner of a piecewise law, a poppet reaching its full opening) is taken by half.
The iteration matrix ``J = ∂F/∂y + c ∂F/∂y'`` of an earlier step is reused; it is evaluated and factorised again at the
predictor when ``c`` changed (a restart, a shortened step), when the last step needed more than two corrections, or —
once per step — when the corrections do not converge with the old matrix: as soon as its rate of contraction ``ρ`` (a
correction's norm over the one before) cannot meet the test within the corrections left (``norm·ρ^left ≥ 1``), not after
all of them, so that a step with a matrix evaluation spends few corrections on the old one. The choice depends on the
numbers only, never on timing: two runs take the same steps. The formulas are BDF2 with constant steps,
``y' = (3/2 y_{n+1} − 2 y_n + 1/2 y_{n−1}) / h`` (``method="bdf2"``, second order, A-stable), or implicit Euler,
``y' = (y_{n+1} − y_n) / h`` (``method="euler"``, first order, L-stable); the first step after a start or an event and a
shortened step are implicit Euler. There is no error control: accuracy is the step's (the benchmarks report it against
IDA).

Two implementations take the same steps: :class:`FixedStepNative` steps in C (the ``ida-native`` driver's fixed-step
mode, ``ida_driver.c``: the model's compiled residual and matrix, dense LU or KLU, no Python per step; the default
where the driver builds) and :class:`FixedStepIntegrator` in Python (scipy's LU; ``FixedStep(native=False)``).

Real-time pacing (``realtime=True``): after each step the run waits until the wall clock, counted from the run's first
step, reaches the step's simulated time; a step that ends later than that is an overrun (``stats["overruns"]``, the
worst lateness ``stats["worst_late"]`` [s]). ``stats`` also give the mean and worst cost of a step
(``mean_step_wall``, ``worst_step_wall`` [s]), when the costliest step started (``worst_step_t`` [s]) and what it did
(``worst_step_work``: its Newton corrections, matrix evaluations and full LU factorisations): a costly step that did
little work was the machine's (another process, an interrupt), not the method's. ``step_work`` counts the steps by
their work, and the costliest step by its work at the run's mean cost of each (``worst_step_by_work`` [s],
``worst_work``) is the method's own worst step, what a real-time loop is sized for.

Events are handled at step boundaries, with the run loop's event logic: after each step every state relation is
evaluated there, and a relation whose value has changed is reported as a root at the step's end (it is not located
inside the step: its instant is late by less than ``h``). Time events are hit exactly (the step is shortened).
Outputs on a requested grid are interpolated linearly between the steps around each grid time.

References
----------
E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer 1996, §V.1 (BDF) and §VI.1
(index-1 DAEs); K. E. Brenan, S. L. Campbell, L. R. Petzold, *Numerical Solution of Initial-Value Problems in
Differential-Algebraic Equations*, SIAM 1996, §3.1.
"""

from __future__ import annotations

import time as _time
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from flexlib.compile.codegen import CompiledModel
from flexlib.solve.backends.base import DENSE_MAX, Limits, Stop, absolute_tolerances
from flexlib.solve.backends.ida_c import IdaC
from flexlib.solve.events import relation_value, watched_relations
from flexlib.solve.native import FD_DIVERGED
from flexlib.solve.solvers import METHODS
from flexlib.solve.sundae_callbacks import Callbacks

__all__ = ["METHODS", "FixedStepIntegrator", "FixedStepNative"]


Rows = tuple[list[float], list[np.ndarray], list[np.ndarray]]


class FixedStepIntegrator:
    """The fixed-step adapter behind :class:`~flexlib.solve.backends.base.Integrator` (see the module docstring).

    Parameters
    ----------
    h : float
        Step size [s].
    method : {"bdf2", "euler"}
        The formula.
    newton_iters : int
        Most Newton corrections per step (its cost bound).
    rtol, atol : float
        Weights of the Newton convergence test (``rtol·|y| + atol·nominal``) [1], [SI units of each unknown].
    realtime : bool
        Pace the steps to the wall clock (module docstring).
    max_halvings : int
        Times a step that does not converge may be halved.
    """

    name = "fixed-step"
    watch_steps = 0
    settles_roots = False
    monitors = False
    progress_every = 50
    error_test_all: bool | None = None

    def __init__(self, h: float, method: str = "bdf2", newton_iters: int = 4, rtol: float = 1e-6,
                 atol: float = 1e-8, realtime: bool = False, max_halvings: int = 2) -> None:
        self.h, self.method, self.newton_iters = float(h), method, int(newton_iters)
        self.rtol, self.atol, self.realtime, self.max_halvings = rtol, atol, bool(realtime), int(max_halvings)
        self.counts: dict[str, Any] = {"steps": 0, "nfev": 0, "njev": 0, "newton_iters": 0, "unconverged_steps": 0,
                                       "halved_steps": 0, "first_unconverged_t": float("nan"),
                                       "worst_step_t": float("nan"), "worst_step_work": (0, 0, 0),
                                       "step_work": {},
                                       "worst_step_wall": 0.0, "step_wall": 0.0, "overruns": 0, "worst_late": 0.0}
        self.wall0: tuple[float, float] | None = None  # (wall clock, simulated time) of the first step (pacing)
        # seconds in the residual, the matrix evaluations, the LU factorisations and the solves (worst_by_work)
        self.seconds = {"wall_res": 0.0, "wall_jac": 0.0, "wall_lsetup": 0.0, "wall_lsolve": 0.0}

    def start(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
              grid: np.ndarray | None, t_end: float) -> None:
        self.model, self.p = model, p
        self.state_rel = watched_relations(model)
        self.ind = model.function("ind")
        self.cb = Callbacks(model, p, np.zeros(0, dtype=int), dense=False)
        self.nz, self.r = np.zeros(len(model.jac_row)), np.zeros(model.n)
        self.pattern = self.cb.pattern.copy()
        self.rows = np.asarray(model.jac_row, dtype=np.intp)
        self.cols = np.repeat(np.arange(model.n), np.diff(model.jac_colind))
        self.dense = np.zeros((model.n, model.n)) if model.n <= DENSE_MAX else None
        self.atol_vec = absolute_tolerances(model, self.atol, self.error_test_all)
        self.grid = None if grid is None else np.asarray(grid, dtype=float)
        self.ig = 0
        self.reinit(t, y, yp)

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        self.t, self.y, self.yp = float(t), np.array(y, dtype=float), np.array(yp, dtype=float)
        self.y_prev: np.ndarray | None = None  # one step of history (BDF2), none after a restart
        self.lu: Any = None  # a restart (an event changed the equations) evaluates the matrix again
        self.contracting = False
        self.c_lu, self.slow = 0.0, False

    def advance(self, t_stop: float, limits: Limits) -> Stop:
        rows: Rows = ([], [], [])
        steps = 0
        while steps < max(1, limits.steps):
            if self.t >= t_stop:
                return Stop("tstop", self.t, steps, rows)
            h = self.h
            landing = self.t + h >= t_stop - 1e-9 * h
            short = landing and t_stop - self.t < h * (1.0 - 1e-9)  # landing on a whole step keeps its size
            if short:
                h = t_stop - self.t
            bdf2 = self.method == "bdf2" and self.y_prev is not None and not short
            t_old, y_old, yp_old = self.t, self.y, self.yp
            ok = self.step(h, bdf2)
            if ok and landing:
                self.t = t_stop  # a whole step ends on t_stop up to round-off
            steps += 1
            self.y_prev = None if short else y_old
            self.output(rows, t_old, y_old, yp_old)
            if not ok:
                return Stop("failed", self.t, steps, rows, message=diverged(self.t, self.newton_iters, self.h))
            self.pace()
            roots = self.switched()
            if roots:
                return Stop("root", self.t, steps, rows, roots=roots)
            if landing:
                return Stop("tstop", self.t, steps, rows)
        return Stop("step", self.t, steps, rows)

    def step(self, h: float, bdf2: bool) -> bool:
        """One step of size ``h`` [s] from ``(t, y)``; False if it cannot be taken (the point is kept)."""
        newton0, njev0 = self.counts["newton_iters"], self.counts["njev"]
        w0 = _time.perf_counter()
        t_end = self.t + h
        ok = self.attempt(h, bdf2, 0)
        if ok:
            self.t = t_end  # exactly, also after halves
        self.counts["steps"] += 1
        wall = _time.perf_counter() - w0
        self.counts["step_wall"] += wall
        # scipy's LU factorises afresh at every matrix evaluation: as many full factorisations
        njev = self.counts["njev"] - njev0
        work = (self.counts["newton_iters"] - newton0, njev, njev)
        if wall > self.counts["worst_step_wall"]:
            self.counts["worst_step_wall"], self.counts["worst_step_t"] = wall, t_end - h
            self.counts["worst_step_work"] = work
        self.counts["step_work"][work] = self.counts["step_work"].get(work, 0) + 1
        return ok

    def attempt(self, h: float, bdf2: bool, depth: int) -> bool:
        """Solve the step of size ``h`` from ``(t, y)``; where its corrections do not converge and ``depth`` is below
        ``max_halvings``, take it as two implicit-Euler halves instead. True if taken (the point moved)."""
        t1 = self.t + h
        if bdf2:
            assert self.y_prev is not None
            c, base = 1.5 / h, (-2.0 * self.y + 0.5 * self.y_prev) / h
            y0 = 2.0 * self.y - self.y_prev  # linear extrapolation of the last two points
        else:
            c, base = 1.0 / h, -self.y / h
            y0 = self.y + h * self.yp
        fresh = self.lu is None or c != self.c_lu or self.slow
        y, converged, iters = self.corrections(t1, y0, c, base, fresh)
        if not converged and not fresh:  # the old matrix does not do: once more with a fresh one
            y, converged, more = self.corrections(t1, y0, c, base, True)
            iters += more
        self.slow = iters > 2
        if not converged and depth < self.max_halvings:
            self.counts["halved_steps"] += 1
            start = (self.t, self.y, self.yp)
            if self.attempt(0.5 * h, False, depth + 1) and self.attempt(0.5 * h, False, depth + 1):
                return True
            self.t, self.y, self.yp = start
            return False
        if not converged:
            self.counts["unconverged_steps"] += 1
            if np.isnan(self.counts["first_unconverged_t"]):
                self.counts["first_unconverged_t"] = t1
        # a real-time step ends after its corrections: taken while they contract, the run fails where they do not
        ok = (converged or self.contracting) and bool(np.all(np.isfinite(y)))
        if ok:
            self.t, self.y, self.yp = t1, y, c * y + base
        return ok

    def pace(self) -> None:
        """Wait until the wall clock reaches the simulated time (``realtime``); count a step that ends after it."""
        if not self.realtime:
            return
        now = _time.monotonic()
        if self.wall0 is None:
            self.wall0 = (now, self.t - self.h)
        due = self.wall0[0] + (self.t - self.wall0[1])
        if now > due:
            self.counts["overruns"] += 1
            self.counts["worst_late"] = max(self.counts["worst_late"], now - due)
        else:
            _time.sleep(due - now)

    def corrections(self, t1: float, y: np.ndarray, c: float, base: np.ndarray, fresh: bool
                    ) -> tuple[np.ndarray, bool, int]:
        """At most ``newton_iters`` Newton corrections of ``F(t1, y, c·y + base) = 0`` from ``y`` (the matrix evaluated
        there first if ``fresh``; an old one given up as soon as its rate of contraction, the last correction's norm
        over the one before, cannot bring the norm below 1 within the corrections left): the point, whether the last
        correction met the test, the corrections taken."""
        clock, seconds = _time.perf_counter, self.seconds
        if fresh:
            w0 = clock()
            self.cb.jacobian_into(t1, y, c * y + base, c, self.nz)
            w1 = clock()
            self.counts["njev"] += 1
            self.factorise()
            seconds["wall_jac"] += w1 - w0
            seconds["wall_lsetup"] += clock() - w1
            self.c_lu = c
        first, w_last, norm_last = np.inf, None, 0.0
        for k in range(1, self.newton_iters + 1):
            w0 = clock()
            self.cb.resfn(t1, y, c * y + base, self.r)
            w1 = clock()
            self.counts["nfev"] += 1
            self.counts["newton_iters"] += 1
            dy = self.solve(-self.r)
            seconds["wall_res"] += w1 - w0
            seconds["wall_lsolve"] += clock() - w1
            y = y + dy
            w = dy / (self.rtol * np.abs(y) + self.atol_vec)
            norm = float(np.sqrt(np.mean(w**2)))
            if norm < 1.0:
                return y, True, k
            if not fresh and 1 < k < self.newton_iters and norm * (norm / norm_last) ** (self.newton_iters - k) >= 1:
                # an old matrix whose rate of contraction cannot meet the test within the corrections left: given up
                # at once for a fresh one (not after all of them)
                self.contracting = norm < first
                return y, False, k
            if w_last is not None and float(np.dot(w, w_last)) < -0.5 * norm * norm_last * len(w):
                y = y - 0.5 * dy  # the correction turns back on the last one (Newton cycling round a corner of a
                #                   valve law): half of it
            if k == 1:
                first = norm
            w_last, norm_last = w, norm
        self.contracting = self.newton_iters == 1 or norm < first
        return y, False, self.newton_iters

    def factorise(self) -> None:
        """LU of the iteration matrix held in ``nz``: dense up to :data:`DENSE_MAX` unknowns, sparse above."""
        if self.dense is not None:
            self.dense[self.rows, self.cols] = self.nz
            self.lu = sla.lu_factor(self.dense, check_finite=False)
        else:
            self.pattern.data = self.nz.copy()
            self.lu = spla.splu(self.pattern.tocsc())

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.dense is not None:
            return sla.lu_solve(self.lu, b, check_finite=False)
        return self.lu.solve(b)

    def switched(self) -> list[tuple[int, bool]]:
        """The state relations whose value at the step's end differs from their frozen value."""
        if not len(self.state_rel):
            return []
        z = np.asarray(self.ind(self.t, self.y, self.yp, self.p), dtype=float).ravel()
        n_par = self.model.n_params
        out = []
        for k in self.state_rel:
            v = relation_value(self.model.relations[k], z[k], self.p[n_par + k])
            if v != self.p[n_par + k]:
                out.append((int(k), bool(v)))
        return out

    def output(self, rows: Rows, t0: float, y0: np.ndarray, yp0: np.ndarray) -> None:
        """Rows for the step just taken from ``(t0, y0, yp0)``: every step without a grid, else the grid times it
        passes (linear interpolation)."""
        if self.grid is None:
            rows[0].append(self.t)
            rows[1].append(self.y.copy())
            rows[2].append(self.yp.copy())
            return
        while self.ig < len(self.grid) and self.grid[self.ig] <= self.t:
            tg = float(self.grid[self.ig])
            if tg > t0:
                s = (tg - t0) / (self.t - t0)
                rows[0].append(tg)
                rows[1].append((1 - s) * y0 + s * self.y)
                rows[2].append((1 - s) * yp0 + s * self.yp)
            self.ig += 1

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.y, self.yp

    def accepted(self) -> tuple[float, Any, Any] | None:
        return self.t, self.y, self.yp

    def unsaved_rows(self) -> Rows:
        return [], [], []

    def last_step(self) -> float | None:
        return self.h

    def stats(self, wall: float) -> dict[str, Any]:
        n = max(1, self.counts["steps"])
        work = [[*k, v] for k, v in sorted(self.counts["step_work"].items())]
        # every matrix is factorised afresh (scipy's LU): each setup a full factorisation
        costs = {**self.seconds, "nfev": self.counts["nfev"], "n_lsolve": self.counts["newton_iters"],
                 "njev": self.counts["njev"], "n_lsetup": self.counts["njev"], "n_factor_full": self.counts["njev"]}
        return {"solver": self.name, "method": self.method, "h": self.h, "max_order": METHODS[self.method],
                "realtime": self.realtime, **self.counts, "mean_step_wall": self.counts["step_wall"] / n,
                "worst_step_work": list(self.counts["worst_step_work"]), "step_work": work,
                **worst_by_work(work, costs, self.seconds["wall_lsetup"])}


class FixedStepNative(IdaC):
    """The same fixed-step method stepped in C (the ``ida-native`` driver's fixed-step mode; arguments as
    :class:`FixedStepIntegrator`'s). The driver's IDA is set up but never stepped."""

    name = "fixed-step"
    watch_steps = 0
    settles_roots = False
    monitors = False

    def __init__(self, h: float, method: str = "bdf2", newton_iters: int = 4, rtol: float = 1e-6,
                 atol: float = 1e-8, realtime: bool = False, max_halvings: int = 2) -> None:
        super().__init__(rtol, atol, 0.0, METHODS[method])
        self.h, self.method, self.newton_iters, self.realtime = float(h), method, int(newton_iters), bool(realtime)
        self.max_halvings = int(max_halvings)

    def start(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
              grid: np.ndarray | None, t_end: float) -> None:
        super().start(model, t, y, yp, p, grid, t_end)
        self.drv.set_fixed_step(self.h, self.method == "bdf2", self.newton_iters, self.max_halvings, self.rtol,
                                model.n_params + np.asarray(self.state_rel, dtype=int), self.realtime)

    def stop(self, code: int, t: float, nsteps: int, rows: Any) -> Stop:
        if code == FD_DIVERGED:
            return Stop("failed", t, nsteps, rows, message=diverged(t, self.newton_iters, self.h))
        return super().stop(code, t, nsteps, rows)

    def last_step(self) -> float:
        return self.h

    def stats(self, wall: float) -> dict[str, Any]:
        out = super().stats(wall)
        for key in ("n_newton", "n_newton_fail", "n_err_fail"):  # IDA's, never stepped
            out.pop(key, None)
        fixed = self.drv.fixed_stats()
        fixed.pop("steps")
        t_full = fixed.pop("t_full")
        return {**out, "method": self.method, "h": self.h, "realtime": self.realtime, **fixed,
                **worst_by_work(fixed["step_work"], out, t_full),
                "mean_step_wall": fixed["step_wall"] / max(1, self.drv.stats()["steps"])}


def worst_by_work(work: list[list[int]], out: dict[str, Any], t_full: float) -> dict[str, Any]:
    """The costliest step by its work (``work``: rows ``[corrections, matrix evaluations, full factorisations,
    steps]``) at the run's mean costs of a correction (a residual and a solve), a matrix (an evaluation and a
    refactorisation) and a full factorisation (``t_full`` [s] of them all): ``worst_step_by_work`` [s] and its work
    ``worst_work``. A step's measured cost also holds what the machine did meanwhile (another process, an interrupt);
    this is the method's own, the bound a real-time loop is sized for."""
    def mean(total: str, count: str) -> float:
        return float(out.get(total, 0.0)) / out[count] if out.get(count) else 0.0

    correction = mean("wall_res", "nfev") + mean("wall_lsolve", "n_lsolve")
    n_full = int(out.get("n_factor_full", 0))
    full = t_full / n_full if n_full else 0.0
    refactor = (float(out.get("wall_lsetup", 0.0)) - t_full) / max(1, int(out.get("n_lsetup", 0)))
    matrix = mean("wall_jac", "njev") + refactor
    cost = {(c, m, f): c * correction + m * matrix + f * full for c, m, f, _ in work}
    if not cost:
        return {"worst_step_by_work": 0.0, "worst_work": [0, 0, 0]}
    key = max(cost, key=cost.__getitem__)
    return {"worst_step_by_work": cost[key], "worst_work": list(key)}


def diverged(t: float, newton_iters: int, h: float) -> str:
    """The message of a step whose Newton corrections grew."""
    return (f"fixed-step Newton iteration diverged at t = {t:.10g} s in {newton_iters} iterations (h = {h:g} s: "
            "try a smaller step)")
