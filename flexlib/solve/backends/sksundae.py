"""SUNDIALS IDA stepped from Python through scikit-sundae (``solver="ida-sksundae"``, and the fallback of the
default ``solver="ida"`` when the C driver of :mod:`flexlib.solve.backends.ida_c` is unavailable).

The residual and the iteration matrix are CasADi functions called through ``Function.buffer()`` (no conversion per
call); the Jacobian is passed as CSC nonzeros to the sparse direct solver (SuperLU_MT), dense LU up to
:data:`~flexlib.solve.backends.base.DENSE_MAX` unknowns. IDA is driven one internal step per
:meth:`SkSundae.advance`, which gives an exact stop at every time event (``tstop``), output on a grid by IDA's own
interpolation and the state events of IDA's root finding.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import warnings
from typing import Any

import numpy as np
import sksundae as sun

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import SolverError
from flexlib.solve.backends.base import DENSE_MAX, NEWTON_ITERS, Limits, Stop, absolute_tolerances
from flexlib.solve.events import state_relations
from flexlib.solve.sundae_callbacks import Callbacks

__all__ = ["PENDING_CHECK", "EventsFn", "SkSundae", "make_solver"]

#: Every this many steps: whether C compiled in the background is ready (and the progress bar)
PENDING_CHECK = 32


class EventsFn:
    """Callable wrapper so scikit-sundae can attach its bookkeeping; keeps only the last root info."""

    def __init__(self, fn: Any, n: int) -> None:
        self._fn = fn
        self.terminal = [False] * n
        self.direction = [0] * n

    def __call__(self, t: float, y: np.ndarray, yp: np.ndarray, events: np.ndarray) -> None:
        self._fn(t, y, yp, events)

    def last_roots(self) -> np.ndarray:
        info = np.array(self._i[-1]) if self._i else np.zeros(len(self.direction))
        for lst in (self._i, self._t, self._y, self._yp):
            lst.clear()
        return info


class SkSundae:
    """scikit-sundae's IDA behind :class:`~flexlib.solve.backends.base.Integrator`: one step per call."""

    name = "ida-sksundae"
    watch_steps = 2
    settles_roots = False
    monitors = True
    progress_every = PENDING_CHECK
    error_test_all: bool | None = None

    def __init__(self, rtol: float = 1e-6, atol: float = 1e-8, max_step: float = 0.0, max_order: int = 5) -> None:
        self.rtol, self.atol, self.max_step, self.max_order = rtol, atol, max_step, int(max_order)
        self.solver: Any = None
        self.done, self.cur = [0, 0], [0, 0]  # evaluations of finished IDA segments (IDAReInit resets the counters)
        self.last: Any = None  # the last accepted step (its t, y, yp end the rows of a failed or interrupted run)
        self.r: Any = None
        self.extra: dict[str, Any] = {}
        self.n_steps = self.tiny = 0
        self.interpolated = False

    def start(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
              grid: np.ndarray | None, t_end: float) -> None:
        first = self.solver is None
        if first:
            self.outs = [] if grid is None else [float(v) for v in grid]  # Python floats: cheaper comparisons
            self.out_idx, self.every_step = 0, grid is None
        self.model, self.p = model, p
        self.done, self.cur = [self.done[0] + self.cur[0], self.done[1] + self.cur[1]], [0, 0]
        self.solver, self.cb, self.ev_holder, self.state_rel = make_solver(model, p, self.rtol, self.atol,
                                                                           self.max_step, self.max_order,
                                                                           self.error_test_all)
        self.pending_c = first and model.library_pending is not None  # C compiled in the background
        self.solver.init_step(t, y, yp)
        self.t = self.t_row = t

    def advance(self, t_stop: float, limits: Limits) -> Stop:
        while True:
            r = self.r = self.solver.step(t_stop, "onestep", t_stop)
            self.cur = [r.nfev, r.njev]
            if r.status < 0:
                return Stop("failed", r.t, message=f"IDA failed at t = {r.t:.10g} s: {r.message} (status {r.status})")
            if not (r.t == self.t and r.status == 0 and self.interpolated):
                break
            self.interpolated = False  # after an interpolated output IDA first returns its current point
        self.last = r
        rows = self.rows(r)
        self.tiny = self.tiny + 1 if r.t - self.t <= 1e-14 * max(1.0, abs(r.t)) else 0
        if self.tiny > 200:
            return Stop("failed", r.t, 1, rows, message=f"IDA step size underflow at t = {r.t:.10g} s (the model "
                        "may be stiff beyond repair, or discontinuous without an event)")
        self.t = r.t
        self.n_steps += 1
        if self.n_steps % PENDING_CHECK == 0 and self.pending_c and self.model.c_ready():
            # the background gcc has finished: the callbacks evaluate the compiled residual and Jacobian from the
            # next step on. No IDA restart: C performs the same operations in the same order as the SX virtual
            # machine, so the trajectory does not change
            self.pending_c = False
            self.cb.bind(self.model)
            self.extra["compiled_at"] = r.t
        if r.status == 2:
            info = self.ev_holder.last_roots()
            roots = [(int(self.state_rel[j]), bool(info[j] > 0)) for j in np.flatnonzero(info)]
            return Stop("root", r.t, 1, rows, roots=roots)
        return Stop("tstop" if r.status == 1 else "step", r.t, 1, rows)

    def rows(self, r: Any) -> tuple[list[float], list[np.ndarray], list[np.ndarray]] | None:
        """The output rows the step ``r`` passed (IDA's interpolation), or the step itself without a grid."""
        T: list[float] = []
        Y: list[np.ndarray] = []
        YP: list[np.ndarray] = []
        if self.every_step:
            if r.t > self.t_row:
                T, Y, YP = [r.t], [r.y], [r.yp]
        else:
            outs = self.outs
            while self.out_idx < len(outs) and outs[self.out_idx] < r.t:
                ri = interpolate(self.solver, outs[self.out_idx])
                T.append(ri.t)
                Y.append(ri.y)
                YP.append(ri.yp)
                self.out_idx += 1
                self.interpolated = True
            if self.out_idx < len(outs) and outs[self.out_idx] == r.t:
                T.append(r.t)
                Y.append(r.y)
                YP.append(r.yp)
                self.out_idx += 1
        if not T:
            return None
        self.t_row = T[-1]
        return T, Y, YP

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        self.done, self.cur = [self.done[0] + self.cur[0], self.done[1] + self.cur[1]], [0, 0]
        self.solver.init_step(t, y, yp)
        self.t = self.t_row = t

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.r.y, self.r.yp

    def accepted(self) -> tuple[float, Any, Any] | None:
        return None if self.last is None else (self.last.t, self.last.y, self.last.yp)

    def unsaved_rows(self) -> tuple[list[float], list[np.ndarray], list[np.ndarray]]:
        return [], [], []

    def last_step(self) -> None:
        return None

    def stats(self, wall: float) -> dict[str, Any]:
        return {"solver": self.name, "max_order": self.max_order, "nfev": self.done[0] + self.cur[0],
                "njev": self.done[1] + self.cur[1], **self.extra}


def make_solver(model: CompiledModel, p: np.ndarray, rtol: float, atol: float, max_step: float, max_order: int = 5,
                error_test_all: bool | None = None) -> tuple[Any, Callbacks, EventsFn, np.ndarray]:
    """An IDA instance for ``model``: dense LU for small systems, SuperLU_MT with the CasADi pattern above
    (``error_test_all``: :func:`~flexlib.solve.backends.base.absolute_tolerances`'s)."""
    state_rel = state_relations(model)
    dense = model.n <= DENSE_MAX
    cb = Callbacks(model, p, state_rel, dense)
    opts: dict[str, Any] = dict(
        rtol=rtol, atol=absolute_tolerances(model, atol, error_test_all),
        algebraic_idx=[int(i) for i in np.flatnonzero(~model.differential)],
        jacfn=cb.jacfn, max_step=max_step, max_num_steps=100000, max_order=int(max_order),
        max_nonlin_iters=NEWTON_ITERS,
    )
    if dense:
        opts["linsolver"] = "dense"
    else:
        opts.update(linsolver="sparse", sparsity=cb.pattern)
    ev_holder = EventsFn(cb.eventsfn, cb.n_events)
    if cb.n_events:
        opts.update(eventsfn=ev_holder, num_events=cb.n_events)
    with warnings.catch_warnings():  # "sparsity ignored in favour of jacfn": we pass both on purpose
        warnings.simplefilter("ignore", UserWarning)
        solver = sun.ida.IDA(cb.resfn, **opts)
    return solver, cb, ev_holder, state_rel


def interpolate(solver: Any, tq: float) -> Any:
    """IDA's interpolated solution at ``tq`` inside the last step (after a root return, IDA may first
    report the root once more; ask again)."""
    for _ in range(3):
        ri = solver.step(tq, "normal")
        if ri.t == tq and ri.status in (0, 1):
            return ri
    raise SolverError(f"internal: IDA did not return the interpolated solution at t = {tq:.10g} s")
