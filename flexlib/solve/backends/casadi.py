"""CasADi's own (C) IDAS through ``casadi.integrator`` (``solver="casadi-idas"``).

Each :meth:`CasadiIdas.advance` is one or more integrator calls over an output grid (IDAS's own interpolation),
all inside CasADi's C interface to SUNDIALS: no Python per residual, Jacobian or step. State events are found on
the grid and located by re-running from the bracket's left end (:mod:`flexlib.solve.casadi_runner` has the
integrators, the bracketing and the design with its measurements). Every relation switch is an event, also in a
sliding mode, so this backend does without the run loop's sign check after restarts.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import SolverError
from flexlib.solve.backends.base import Limits, Stop
from flexlib.solve.casadi_runner import (
    DENSE_POINTS,
    DETECT_POINTS,
    FIRST_CHUNK,
    RETRY_STEPS,
    Runner,
    backend,
    call_grid,
)
from flexlib.solve.events import watched_relations

__all__ = ["CasadiIdas"]

Rows = tuple[list[float], list[np.ndarray], list[np.ndarray]]


class CasadiIdas:
    """CasADi's IDAS behind :class:`~flexlib.solve.backends.base.Integrator` (no state-selection monitor).

    ``max_step`` is implemented by refining the grid to ``max_step`` and limiting each step to one grid interval;
    ``max_steps`` bounds one call (at most ``min(max_steps, 100000)`` steps per output interval). Without an output
    grid the rows are a uniform grid of :data:`~flexlib.solve.casadi_runner.DENSE_POINTS` intervals.
    """

    name = "casadi-idas"
    watch_steps = 0
    settles_roots = False
    monitors = False
    progress_every = 1
    error_test_all: bool | None = None

    def __init__(self, rtol: float = 1e-6, atol: float = 1e-8, max_step: float = 0.0, max_order: int = 5,
                 max_steps: int = 5_000_000) -> None:
        self.rtol, self.atol, self.max_step, self.max_order = rtol, atol, max_step, int(max_order)
        self.max_steps = int(max_steps)
        self.counts: dict[str, Any] = {"steps": 0, "nfev": 0, "njev": 0, "integrator_calls": 0}

    def start(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
              grid: np.ndarray | None, t_end: float) -> None:
        self.model, self.p = model, p
        self.state_rel = watched_relations(model)
        self.runner = Runner(model, backend(model), p, self.counts, self.rtol, self.atol, self.max_step > 0.0,
                             self.max_steps, self.state_rel, self.max_order, self.error_test_all)
        if grid is None:
            req = t + (t_end - t) * np.arange(1, DENSE_POINTS + 1) / DENSE_POINTS
            req[-1] = t_end
        else:
            req = np.asarray(grid, dtype=float)
            req = req[(req > t) & (req <= t_end)]
        self.req, self.ir = req, 0  # the requested outputs, and the next one
        self.spacing = (t_end - t) / DETECT_POINTS if len(self.state_rel) else np.inf
        if self.max_step > 0.0:
            self.spacing = min(self.spacing, self.max_step)
        # with state relations, a call runs on with frozen (wrong) relation values after an event it contains,
        # until its end: short calls right after events, doubling while none occurs
        cap = self.runner.chunk_cap
        self.chunk = cap if not len(self.state_rel) else min(cap, FIRST_CHUNK)
        self.suspect = False  # a call failed since the last event: retries use a small step budget
        self.t, self.y, self.yp = float(t), np.array(y, dtype=float), np.array(yp, dtype=float)

    def advance(self, t_stop: float, limits: Limits) -> Stop:
        runner, steps0 = self.runner, self.counts["steps"]
        grid = call_grid(self.t, self.req[self.ir:], t_stop, self.spacing, self.chunk)
        try:
            grid, Y, YP, event = self.call(grid)
        except SolverError as err:
            if not str(err).startswith("CasADi IDAS failed"):
                raise
            # IDAS names only its flag: the loop adds what failed at the last accepted point
            return Stop("failed", self.t, self.counts["steps"] - steps0, message=str(err))
        j, triggered = -1, []
        if event is None and len(self.state_rel):
            j, triggered = runner.first_switch(runner.indicators(grid, Y, YP))
        rows: Rows = ([], [], [])
        if event is not None or j >= 0:  # state event in (grid[j-1], grid[j]]
            if event is None:
                a = (self.t, self.y, self.yp) if j == 0 else (float(grid[j - 1]), Y[:, j - 1], YP[:, j - 1])
                self.record(rows, a[0], grid, Y, YP)
                event = runner.locate(a, (float(grid[j]), Y[:, j], YP[:, j]), triggered)
            te, ye, ype, triggered = event
            self.record(rows, te, np.array([te]), ye[:, None], ype[:, None])
            self.t, self.y, self.yp = te, ye, ype
            self.chunk = min(runner.chunk_cap, FIRST_CHUNK)
            return Stop("root", te, self.counts["steps"] - steps0, rows, roots=triggered)
        self.record(rows, float(grid[-1]), grid, Y, YP)
        self.t, self.y, self.yp = float(grid[-1]), Y[:, -1].copy(), YP[:, -1].copy()
        self.chunk = min(runner.chunk_cap, 2 * self.chunk)
        return Stop("tstop" if self.t >= t_stop else "step", self.t, self.counts["steps"] - steps0, rows)

    def call(self, grid: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, Any]:
        """One integrator call from the current point over ``grid``, retried on shorter grids when it fails.

        Returns the grid reached, ``Y, YP`` on it, and a state event ``(t, y, yp, triggered)`` where IDAS could not
        pass a relation's switching point with the relation frozen (else None).
        """
        runner, t, y, yp = self.runner, self.t, self.y, self.yp
        first_error: SolverError | None = None
        budget = RETRY_STEPS if self.suspect else None
        tried_stuck = False
        while True:
            try:
                Y, YP = runner.run(t, y, yp, grid, budget=budget)
                return grid, Y, YP, None
            except SolverError as err:
                if "maximum number of steps" in str(err):
                    raise
                if not len(self.state_rel):
                    # keep every output up to the failure: halve the call (small step budget, so a blow-up is not
                    # integrated to IDAS's step limit again and again) until it succeeds (its rows are recorded and
                    # the run goes on from there) or a single output interval fails with the full budget
                    self.suspect = True
                    if len(grid) > 1:
                        grid = grid[: len(grid) // 2]
                        self.chunk, budget = len(grid), RETRY_STEPS
                        continue
                    if budget is not None:
                        budget = None
                        continue
                    raise
                # past an event inside the call the frozen relation values may drive the model where the solver
                # cannot follow (NaN, stiffness): retry shorter calls on a small step budget, which see the event
                # before that, then bisect for the point IDAS cannot pass; a single interval gets the full budget
                # before the run fails
                if tried_stuck and budget is None:
                    raise first_error or err from None
                first_error = first_error or err
                self.suspect = True
                if len(grid) > 1:
                    grid = grid[: len(grid) // 2]
                    self.chunk, budget = len(grid), RETRY_STEPS
                    continue
                if not tried_stuck:
                    tried_stuck = True
                    event = runner.stuck(t, y, yp, float(grid[0]))
                    if event is not None:
                        return grid, np.zeros((len(y), 0)), np.zeros((len(y), 0)), event
                budget = None

    def record(self, rows: Rows, t_lim: float, grid: np.ndarray, Y: np.ndarray, YP: np.ndarray) -> None:
        """Add the requested outputs ``<= t_lim`` to ``rows``; each is a column of ``grid``."""
        req, k = self.req, 0
        while self.ir < len(req) and req[self.ir] <= t_lim:
            while k < len(grid) and grid[k] < req[self.ir]:
                k += 1
            if k < len(grid) and grid[k] == req[self.ir]:
                rows[0].append(float(req[self.ir]))
                rows[1].append(np.array(Y[:, k], dtype=float))
                rows[2].append(np.array(YP[:, k], dtype=float))
            self.ir += 1

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        self.t, self.y, self.yp = t, np.array(y, dtype=float), np.array(yp, dtype=float)
        self.suspect = False

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.y, self.yp

    def accepted(self) -> tuple[float, Any, Any] | None:
        return self.t, self.y, self.yp

    def unsaved_rows(self) -> Rows:
        return [], [], []

    def last_step(self) -> None:
        return None

    def stats(self, wall: float) -> dict[str, Any]:
        return {"solver": self.name, "max_order": self.max_order, **self.counts}
