"""Stage 6 — integrate with SUNDIALS IDA (scikit-sundae), with time and state events.

This is ``solver="ida-sksundae"`` and the fallback of the default ``solver="ida"`` when the C driver of
:mod:`flexlib.solve.ida_native` is unavailable (no gcc); the event handling, tolerances and diagnostics here
are shared with that driver.

The residual and the iteration matrix are CasADi functions called through
``Function.buffer()`` (no conversion per call), the Jacobian is passed as CSC nonzeros to
the sparse direct solver (SuperLU_MT), as the notes recommend. IDA is driven one internal
step at a time, which gives the step count, an exact stop at every time event (``tstop``),
output on a grid by IDA's own interpolation, a progress bar and a clean stop on Ctrl-C.

Events follow Modelica semantics: relation values are frozen between events; at a state
event (a zero crossing located by IDA's root finding) or a time event, the relation value
is switched, algebraic variables and derivatives are re-initialised with the states held,
the remaining relations are re-evaluated until nothing changes (event iteration), and IDA
is restarted.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import time as _time
import warnings
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
import scipy.sparse as sps
import sksundae as sun

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.environment import env_switch
from flexlib.errors import SimulationInterrupted, SolverError
from flexlib.solve.initialization import Initializer

__all__ = ["DENSE_MAX", "Progress", "Trajectory", "integrate"]

#: Systems up to this many unknowns use IDA's dense LU (faster than sparse LU there, measured in
#: benchmarks/ida_overhead.py); larger ones use SuperLU_MT with the CasADi sparsity pattern.
DENSE_MAX = 40

#: Newton iterations IDA may take per step before it declares a convergence failure (IDA's default 4; both IDA
#: routes; see docs/engine.md, "Newton iterations").
NEWTON_ITERS = 6


@dataclass
class Trajectory:
    """Raw solver output (``y``, ``y'`` and relation values per row) before it becomes a Result."""

    t: list[float] = field(default_factory=list)
    y: list[np.ndarray] = field(default_factory=list)
    yp: list[np.ndarray] = field(default_factory=list)
    rel: list[np.ndarray] = field(default_factory=list)
    events: list[tuple[float, str]] = field(default_factory=list)
    stats: dict[str, Any] = field(default_factory=dict)
    status: str = "success"
    message: str = ""
    models: list[CompiledModel] = field(default_factory=list)
    seg: list[int] = field(default_factory=list)

    def add(self, t: float, y: np.ndarray, yp: np.ndarray, rel: np.ndarray) -> None:
        """Append one output row (copies); rows belong to the last model in ``models``."""
        self.seg.append(len(self.models) - 1)
        self.t.append(float(t))
        self.y.append(np.array(y, dtype=float))
        self.yp.append(np.array(yp, dtype=float))
        self.rel.append(np.array(rel, dtype=float))

    def close(self, t: float, y: Any, yp: Any, rel: np.ndarray) -> None:
        """End the rows of a failed or interrupted run at its last accepted point ``(t, y, yp)`` when that is after
        the last row: a run recorded on an output grid kept only the grid times before the failure (``dt_out=0.1``
        and a failure at 0.99998 s ended at 0.9 s). Nothing is added without rows, at or before the last row's
        time (every step recorded, or an event's rows at ``t``) or for non-finite values."""
        if y is None or not self.t or not t > self.t[-1]:
            return
        y, yp = np.array(y, dtype=float), np.array(yp, dtype=float)
        if y.shape == yp.shape == self.y[-1].shape and np.all(np.isfinite(y)) and np.all(np.isfinite(yp)):
            self.add(t, y, yp, rel)

    def add_owned(self, t: float, y: np.ndarray, yp: np.ndarray, rel: np.ndarray) -> None:
        """Append one row without copying: ``y`` and ``yp`` are fresh arrays nobody else writes to (a
        scikit-sundae step result), ``rel`` is shared between rows until the next event changes it."""
        self.seg.append(len(self.models) - 1)
        self.t.append(t)
        self.y.append(y)
        self.yp.append(yp)
        self.rel.append(rel)


class _Callbacks:
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
            zc = ca.Function("zc", [t, y, yp, pp], [ca.vertcat(*[_off_zero(z[int(k)], model.relations[int(k)].strict)
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

    def jacfn(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray, cj: float, JJ: np.ndarray) -> None:
        self._tj[0] = t
        self._cj[0] = cj
        fj = self._fj
        fj.set_arg(1, memoryview(y))
        fj.set_arg(2, memoryview(yp))
        fj.set_res(0, memoryview(JJ))
        self._evj()

    def _jacfn_dense(self, t: float, y: np.ndarray, yp: np.ndarray, r: np.ndarray, cj: float,
                     JJ: np.ndarray) -> None:
        self._tj[0] = t
        self._cj[0] = cj
        fj = self._fj
        fj.set_arg(1, memoryview(y))
        fj.set_arg(2, memoryview(yp))
        fj.set_res(0, memoryview(self._nz))
        self._evj()
        JJ[self._rows, self._cols] = self._nz

    def eventsfn(self, t: float, y: np.ndarray, yp: np.ndarray, events: np.ndarray) -> None:
        self._tz[0] = t
        fz = self._fz
        fz.set_arg(1, memoryview(y))
        fz.set_arg(2, memoryview(yp))
        fz.set_res(0, memoryview(events))
        self._evz()


def _off_zero(z: ca.SX, strict: bool) -> ca.SX:
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


class Progress:
    """A tqdm progress bar over simulated time that appears once a run has taken ``delay`` seconds.

    Parameters
    ----------
    name : str
        Label (the model name).
    t0, t_end : float
        Simulated time span [s].
    show : bool or None
        True: from the start; False: never; None: after ``delay`` seconds of wall time.
    """

    def __init__(self, name: str, t0: float, t_end: float, show: bool | None, delay: float = 2.0) -> None:
        self.name, self.t0, self.t_end, self.show = name, t0, t_end, show
        self.deadline = _time.perf_counter() + (0.0 if show else delay)
        self.bar: Any = None

    def update(self, t: float) -> None:
        """Show simulated time ``t`` (creates the bar when due)."""
        if self.bar is None:
            if self.show is False or _time.perf_counter() < self.deadline:
                return
            from tqdm.auto import tqdm

            self.bar = tqdm(total=float(self.t_end - self.t0), unit="s", desc=self.name, leave=False,
                            bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s [{elapsed}<{remaining}]")
        self.bar.n = float(t - self.t0)
        self.bar.refresh()

    def close(self) -> None:
        """Remove the bar."""
        if self.bar is not None:
            self.bar.close()


def next_time_event(model: CompiledModel, p: np.ndarray, t: float, t_end: float) -> tuple[float, list[int]]:
    """Earliest time event after ``t`` (at most ``t_end``) and the relations switching there."""
    timed = [k for k, r in enumerate(model.relations) if r.time_event]
    if not timed:
        return t_end, []
    ab = np.asarray(model.function("tev")(p)).reshape(-1, 2)
    best, which = t_end, []
    tol = 1e-13 * max(1.0, abs(t))
    for k in timed:
        a, b = ab[k]
        if a == 0.0:
            continue
        te = -b / a
        if te > t + tol and te <= t_end:
            if te < best - tol:
                best, which = te, [k]
            elif abs(te - best) <= tol:
                which.append(k)
    return best, which


def integrate(model: CompiledModel, init: Initializer, p: np.ndarray, y0: np.ndarray, yp0: np.ndarray,
              t0: float, t_end: float, t_out: np.ndarray | None, *, rtol: float = 1e-6, atol: float = 1e-8,
              max_step: float = 0.0, max_steps: int = 5_000_000, progress: bool | None = None,
              monitor: Any = None, max_order: int = 5) -> Trajectory:
    """Integrate from consistent ``y0, yp0`` at ``t0`` to ``t_end``.

    Parameters
    ----------
    p : ndarray
        Parameters followed by relation values (updated in place at events).
    t_out : ndarray or None
        Output times; None records every internal step.
    rtol, atol : float
        Relative and absolute tolerance (``atol`` is scaled by each variable's nominal value).
    max_step : float
        Maximum step size [s] (0: unlimited).
    max_steps : int
        Maximum number of internal steps for the whole run.
    max_order : int
        Highest BDF order (1–5; ``IDASetMaxOrd``).
    progress : bool or None
        Show a progress bar; None shows one when the run takes longer than 2 s.
    monitor : StateSelectionMonitor, optional
        Dynamic state selection: checked after every step when the model has a choice of states.

    Returns
    -------
    Trajectory
        With ``status`` ``"success"``; failures raise :class:`SolverError` (``.result`` is set by
        the caller from ``err.trajectory``).
    """
    traj = Trajectory(models=[model])
    if monitor is not None:
        monitor.reset()
    n_par = model.n_params
    solver, _cb, ev_holder, state_rel = _make_solver(model, p, rtol, atol, max_step, max_order)
    stats = {"steps": 0, "nfev": 0, "njev": 0, "state_events": 0, "time_events": 0, "restarts": 0,
             "state_switches": 0, "max_order": int(max_order)}
    traj.stats = stats
    done = [0, 0]  # evaluations of finished IDA segments (IDAReInit resets the counters)
    cur = [0, 0]

    def rel_values() -> np.ndarray:
        return p[n_par:].copy()

    rel_now = rel_values()  # shared by the rows between events (p changes only at events and switches)
    add_owned = traj.add_owned
    step = solver.step
    watching = monitor is not None and model.has_state_choice
    pending_c = model.library_pending is not None  # C being compiled in the background: switch when ready

    solver.init_step(t0, y0, yp0)
    traj.add(t0, y0, yp0, rel_values())
    t = t0
    out_idx = 0
    if t_out is not None:
        t_out = np.asarray(t_out, dtype=float)
        while out_idx < len(t_out) and t_out[out_idx] <= t0:
            out_idx += 1
    outs = [] if t_out is None else [float(v) for v in t_out]  # Python floats: cheaper per-step comparisons
    n_out = len(outs)
    wall0 = _time.perf_counter()
    bar = Progress(model.name, t0, t_end, progress)
    tiny = 0
    interpolated = False
    watch = 2 if len(state_rel) else 0
    ind_fn = model.function("ind")
    last_event_t, burst = -np.inf, 0
    t_event, which = next_time_event(model, p, t, t_end)
    last: Any = None  # the last accepted step (its t, y, yp end the rows of a failed or interrupted run)
    try:
        while t < t_end:
            tstop = min(t_end, t_event)
            r = step(tstop, "onestep", tstop)
            cur = [r.nfev, r.njev]
            if r.status < 0:
                raise SolverError(failure_message(f"IDA failed at t = {r.t:.10g} s: {r.message} (status {r.status})",
                                                  model, p, r.t, r.y, r.yp, traj, rtol, atol))
            if r.t == t and r.status == 0 and interpolated:
                interpolated = False
                continue  # after an interpolated output IDA first returns its current point, no new step
            stats["steps"] += 1
            last = r
            # output points passed by this step (IDA interpolation)
            if t_out is not None:
                while out_idx < n_out and outs[out_idx] < r.t:
                    ri = _interpolate(solver, outs[out_idx])
                    add_owned(ri.t, ri.y, ri.yp, rel_now)
                    out_idx += 1
                    interpolated = True
                if out_idx < n_out and outs[out_idx] == r.t:
                    add_owned(r.t, r.y, r.yp, rel_now)
                    out_idx += 1
            elif r.t > traj.t[-1]:
                add_owned(r.t, r.y, r.yp, rel_now)
            tiny = tiny + 1 if r.t - t <= 1e-14 * max(1.0, abs(r.t)) else 0
            if tiny > 200:
                raise SolverError(failure_message(f"IDA step size underflow at t = {r.t:.10g} s (the model may be "
                                                  "stiff beyond repair, or discontinuous without an event)",
                                                  model, p, r.t, r.y, r.yp, traj, rtol, atol))
            t = r.t
            event_kind = None
            changed: list[int] = []
            triggered: list[tuple[int, bool]] = []
            time_hit = bool(which) and r.status in (1, 2) and t >= t_event
            if r.status == 2:
                info = ev_holder.last_roots()
                for j in np.flatnonzero(info):
                    triggered.append((int(state_rel[j]), bool(info[j] > 0)))
                event_kind = "state"
            if time_hit:  # also when a state event is found exactly at the time event
                ab = np.asarray(model.function("tev")(p)).reshape(-1, 2)
                triggered += [(k, bool(ab[k, 0] > 0)) for k in which]
                event_kind = event_kind or "time"
            elif r.status != 2 and watch > 0:
                # IDA ignores a root function that is zero at a restart until it leaves zero, so a
                # relation that re-crosses at once (sliding) is caught by checking its sign here
                watch -= 1
                z = np.asarray(ind_fn(t, r.y, r.yp, p)).ravel()
                triggered = [(int(k), model.relations[k].value(z[k])) for k in state_rel
                             if float(model.relations[k].value(z[k])) != p[n_par + k]]
                event_kind = "state" if triggered else None
            if event_kind:
                changed = [k for k, v in triggered if p[n_par + k] != float(v)]
                if changed:
                    done = [done[0] + cur[0], done[1] + cur[1]]
                    cur = [0, 0]
                    traj.add(t, r.y, r.yp, rel_values())
                    y1, yp1 = _event_iteration(model, init, p, t, r.y, r.yp, triggered)
                    stats["state_events" if event_kind == "state" else "time_events"] += 1
                    stats["restarts"] += 1
                    texts = ", ".join(model.relations[k].text for k, _ in triggered)
                    traj.events.append((t, f"{event_kind} event: {texts}"))
                    solver.init_step(t, y1, yp1)
                    rel_now = rel_values()
                    traj.add(t, y1, yp1, rel_now)
                    watch = 2 if len(state_rel) else 0
                    burst = burst + 1 if t - last_event_t <= 1e-10 * max(1.0, abs(t)) else 0
                    last_event_t = t
                    if burst > 100:
                        raise SolverError(
                            f"event chattering at t = {t:.10g} s: {texts} switches without time advancing")
                if time_hit:
                    t_event, which = next_time_event(model, p, t, t_end)
            if watching and monitor.needs_switch(model, t, r.y, r.yp, p):
                y_now, yp_now = (y1, yp1) if event_kind and changed else (r.y, r.yp)
                switched = monitor.switch(model, t, y_now, yp_now, p)
                if switched is not None:
                    done = [done[0] + cur[0], done[1] + cur[1]]
                    cur = [0, 0]
                    model, y1, yp1 = switched
                    init = Initializer(model)
                    y1, yp1 = init.reinit(t, y1, yp1, p)
                    solver, _cb, ev_holder, state_rel = _make_solver(model, p, rtol, atol, max_step, max_order)
                    step = solver.step
                    watching = model.has_state_choice
                    pending_c = False
                    ind_fn = model.function("ind")
                    solver.init_step(t, y1, yp1)
                    traj.models.append(model)
                    rel_now = rel_values()
                    traj.add(t, y1, yp1, rel_now)
                    stats["state_switches"] += 1
                    states = ", ".join(n for n, d in zip(model.y_names, model.differential, strict=True) if d)
                    traj.events.append((t, f"state selection: states are now {states}"))
            if stats["steps"] >= max_steps:
                raise SolverError(f"maximum number of steps ({max_steps}) reached at t = {t:.10g} s")
            if stats["steps"] % 32 == 0:
                bar.update(t)
                if pending_c and model.c_ready():
                    # the background gcc has finished: the callbacks evaluate the compiled residual and
                    # Jacobian from the next step on. No IDA restart: C performs the same operations in
                    # the same order as the SX virtual machine, so the trajectory does not change
                    pending_c = False
                    _cb.bind(model)
                    stats["compiled_at"] = t
    except KeyboardInterrupt:
        if last is not None:
            traj.close(last.t, last.y, last.yp, rel_now)
        traj.status, traj.message = "interrupted", f"interrupted by the user at t = {t:.10g} s"
        raise SimulationInterrupted(traj.message, traj) from None
    except SolverError as err:
        if last is not None:
            traj.close(last.t, last.y, last.yp, rel_now)
        traj.status, traj.message = "failed", str(err)
        err.result = traj
        raise
    except Exception as err:  # an exception inside a callback (e.g. a NaN check) aborts the step
        if last is not None:
            traj.close(last.t, last.y, last.yp, rel_now)
        traj.status, traj.message = "failed", f"error at t = {t:.10g} s: {err}"
        raise SolverError(traj.message, traj) from err
    finally:
        stats["nfev"], stats["njev"] = done[0] + cur[0], done[1] + cur[1]
        bar.close()
    stats["wall_integrate"] = _time.perf_counter() - wall0
    return traj


def absolute_tolerances(model: CompiledModel, atol: float) -> np.ndarray:
    """Per-unknown absolute tolerances: ``atol`` scaled by each nominal value, infinite for the
    derivative-level unknowns kept out of the error test (``structure.derivative_level``; both
    backends) unless ``FLEXLIB_ERROR_TEST_ALL=1``."""
    atol_vec = atol * np.asarray(model.nominal, dtype=float)
    if not env_switch("FLEXLIB_ERROR_TEST_ALL", False):
        atol_vec = np.where(model.derivative_level, 1e20, atol_vec)
    return atol_vec


def failure_message(head: str, model: CompiledModel, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
                    traj: Trajectory, rtol: float, atol: float) -> str:
    """``head`` followed by what failed (:func:`flexlib.solve.diagnose.step_failure_lines`): non-finite values
    at the last accepted point ``(t, y, yp)`` or just after it with the equation that produced them, and the
    unknowns that dominate the local error test, by component."""
    from flexlib.solve.diagnose import step_failure_lines

    times = [tt for tt in traj.t if tt < t]
    h = t - times[-1] if times else 1e-6 * max(1.0, abs(t))
    h = max(h, 1e-12 * max(1.0, abs(t)))
    try:
        lines = step_failure_lines(model, p, t, np.asarray(y, dtype=float), np.asarray(yp, dtype=float), rtol,
                                   absolute_tolerances(model, atol), h)
    except Exception as exc:  # the diagnosis must never hide the failure itself
        lines = [f"(no further diagnosis: {type(exc).__name__}: {exc})"]
    return head + ("\n" + "\n".join(lines) if lines else "")


def state_relations(model: CompiledModel) -> np.ndarray:
    """Indices of the relations IDA's root finding watches: not time events, and not constant during a run.

    A relation of parameters only (a cylinder's ``x_start >= 0`` asserted for run-time overrides) cannot
    change after the start, where it is evaluated; given to IDA as a root function it is identically zero
    when it holds with equality (``x_start = 0``), and SUNDIALS prints "some root functions identically 0"
    (IDARcheck1) on every run.
    """
    cand = [k for k, r in enumerate(model.relations) if not r.time_event]
    if not cand:
        return np.zeros(0, dtype=int)
    ind = model.sx_function("ind")
    t, y, yp = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
    pp = ca.SX.sym("p", model.n_params + model.n_relations)
    z = ind(t, y, yp, pp)
    txy = ca.vertcat(t, y, yp)
    return np.array([k for k in cand if ca.depends_on(z[k], txy)], dtype=int)


def _make_solver(model: CompiledModel, p: np.ndarray, rtol: float, atol: float,
                 max_step: float, max_order: int = 5) -> tuple[Any, _Callbacks, _EventsFn, np.ndarray]:
    """An IDA instance for ``model``: dense LU for small systems, SuperLU_MT with the CasADi pattern above."""
    state_rel = state_relations(model)
    dense = model.n <= DENSE_MAX
    cb = _Callbacks(model, p, state_rel, dense)
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
    ev_holder = _EventsFn(cb.eventsfn, cb.n_events)
    if cb.n_events:
        opts.update(eventsfn=ev_holder, num_events=cb.n_events)
    with warnings.catch_warnings():  # "sparsity ignored in favour of jacfn": we pass both on purpose
        warnings.simplefilter("ignore", UserWarning)
        solver = sun.ida.IDA(cb.resfn, **opts)
    return solver, cb, ev_holder, state_rel


def _interpolate(solver: Any, tq: float) -> Any:
    """IDA's interpolated solution at ``tq`` inside the last step (after a root return, IDA may first
    report the root once more; ask again)."""
    for _ in range(3):
        ri = solver.step(tq, "normal")
        if ri.t == tq and ri.status in (0, 1):
            return ri
    raise SolverError(f"internal: IDA did not return the interpolated solution at t = {tq:.10g} s")


class _EventsFn:
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


def _event_iteration(model: CompiledModel, init: Initializer, p: np.ndarray, t: float, y: np.ndarray,
                     yp: np.ndarray, triggered: list[tuple[int, bool]],
                     max_iter: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Switch the triggered relations, re-initialise, re-evaluate the others until consistent."""
    n_par = model.n_params
    fixed = {k for k, _ in triggered}
    for k, v in triggered:
        p[n_par + k] = float(v)
    ind = model.function("ind")
    for _ in range(max_iter):
        y1, yp1 = init.reinit(t, y, yp, p)
        z = np.asarray(ind(t, y1, yp1, p)).ravel()
        changed = False
        for k, rel in enumerate(model.relations):
            if k in fixed or rel.time_event:
                continue
            v = float(rel.value(z[k]))
            if v != p[n_par + k]:
                p[n_par + k] = v
                changed = True
        if not changed:
            check_assertions(model, p, t)
            return y1, yp1
        y, yp = y1, yp1
    raise SolverError(f"event iteration did not converge at t = {t:.10g} s")


def check_assertions(model: CompiledModel, p: np.ndarray, t: float) -> None:
    """Raise :class:`SolverError` if a relation declared with :func:`flexlib.assert_` is false."""
    n_par = model.n_params
    failed = [r for k, r in enumerate(model.relations) if r.assertion and p[n_par + k] != 1.0]
    if failed:
        lines = "\n".join(f"  {r.text}: {r.assertion}" for r in failed)
        raise SolverError(f"assertion failed at t = {t:.10g} s:\n{lines}")
