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

import casadi as ca
import numpy as np
import scipy.sparse as sps
import sksundae as sun

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import SolverError
from flexlib.solve.backends.base import DENSE_MAX, NEWTON_ITERS, Limits, Stop, absolute_tolerances
from flexlib.solve.events import state_relations

__all__ = ["PENDING_CHECK", "SkSundae", "off_zero"]

#: Every this many steps: whether C compiled in the background is ready (and the progress bar)
PENDING_CHECK = 32


class Callbacks:
    """IDA callbacks on CasADi FunctionBuffers sharing one parameter array."""

    def __init__(self, model: CompiledModel, p: np.ndarray, state_rel: np.ndarray, dense: bool) -> None:
        self.p = p
        self._tr, self._tj, self._cj = np.zeros(1), np.zeros(1), np.zeros(1)
        self.bind(model)
        self.pattern = sps.csc_matrix((np.ones(len(model.jac_row)), model.jac_row, model.jac_colind),
                                      shape=(model.n, model.n))
        self.pattern.indices = self.pattern.indices.astype(np.int32)
        self.pattern.indptr = self.pattern.indptr.astype(np.int32)
        if dense:  # dense LU: evaluate the CSC nonzeros into a buffer, scatter into IDA's 2-D matrix
            self._nz = np.zeros(len(model.jac_row))
            self._rows = np.asarray(model.jac_row, dtype=np.intp)
            self._cols = np.repeat(np.arange(model.n), np.diff(model.jac_colind))
            self.jacfn = self._jacfn_dense  # type: ignore[method-assign]
        self.n_events = len(state_rel)
        if self.n_events:
            ind = model.sx_function("ind")
            t, y, yp = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
            pp = ca.SX.sym("p", len(p))
            z = ind(t, y, yp, pp)
            zc = ca.Function("zc", [t, y, yp, pp], [ca.vertcat(*[off_zero(z[int(k)], model.relations[int(k)].strict)
                                                                 for k in state_rel])])
            self._zc = zc
            self._fz, self._evz = zc.buffer()
            self._tz = np.zeros(1)
            self._fz.set_arg(0, memoryview(self._tz))
            self._fz.set_arg(3, memoryview(p))

    def bind(self, model: CompiledModel) -> None:
        """(Re)bind the residual and Jacobian buffers to ``model``'s current functions: called again when
        C compiled in the background becomes ready, without restarting IDA (same values either way)."""
        res, jac = model.function("res"), model.function("jac")
        self._fr, self._evr = res.buffer()
        self._fj, self._evj = jac.buffer()
        self._fr.set_arg(0, memoryview(self._tr))
        self._fr.set_arg(3, memoryview(self.p))
        self._fj.set_arg(0, memoryview(self._tj))
        self._fj.set_arg(3, memoryview(self.p))
        self._fj.set_arg(4, memoryview(self._cj))

    def resfn(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray) -> None:
        self._tr[0] = t
        fr = self._fr
        fr.set_arg(1, memoryview(y))
        fr.set_arg(2, memoryview(yp))
        fr.set_res(0, memoryview(r))
        self._evr()

    def _jac_into(self, t: float, y: np.ndarray, yp: np.ndarray, cj: float, out: np.ndarray) -> None:
        self._tj[0] = t
        self._cj[0] = cj
        fj = self._fj
        fj.set_arg(1, memoryview(y))
        fj.set_arg(2, memoryview(yp))
        fj.set_res(0, memoryview(out))
        self._evj()

    def jacfn(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray, cj: float, JJ: np.ndarray) -> None:
        self._jac_into(t, y, yp, cj, JJ)

    def _jacfn_dense(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray, cj: float,
                     JJ: np.ndarray) -> None:
        self._jac_into(t, y, yp, cj, self._nz)
        JJ[self._rows, self._cols] = self._nz

    def eventsfn(self, t: float, y: np.ndarray, yp: np.ndarray, events: np.ndarray) -> None:
        self._tz[0] = t
        fz = self._fz
        fz.set_arg(1, memoryview(y))
        fz.set_arg(2, memoryview(yp))
        fz.set_res(0, memoryview(events))
        self._evz()


def off_zero(z: ca.SX, strict: bool) -> ca.SX:
    """The indicator ``z`` for IDA's root finding, with an exact zero replaced by ±1e-300: the side of the
    relation's value at zero (``z > 0`` is false there, ``z >= 0`` true).

    IDA only needs a sign change where the relation's value changes. An exact zero gives it nothing more, but
    one that stays zero over the first step (a body at rest on its contact, x = 0) makes SUNDIALS print "some
    root functions identically 0" (IDARcheck1; ``IDASetNoInactiveRootWarn`` is not exposed by
    scikit-sundae). With the sign of the value at zero, an indicator reaching zero from the other side is
    still a sign change (the relation switches there), one leaving zero to the same side is none — exactly
    the relation's events. Part of the compiled event function: no cost per call in Python.
    """
    return ca.if_else(z == 0, -1e-300 if strict else 1e-300, z)


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
                                                                           self.max_step, self.max_order)
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


def make_solver(model: CompiledModel, p: np.ndarray, rtol: float, atol: float,
                max_step: float, max_order: int = 5) -> tuple[Any, Callbacks, EventsFn, np.ndarray]:
    """An IDA instance for ``model``: dense LU for small systems, SuperLU_MT with the CasADi pattern above."""
    state_rel = state_relations(model)
    dense = model.n <= DENSE_MAX
    cb = Callbacks(model, p, state_rel, dense)
    opts: dict[str, Any] = dict(
        rtol=rtol, atol=absolute_tolerances(model, atol),
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
