"""Integrator backend ``solver="ida-native"``: SUNDIALS IDA driven from C, Python only at outputs and events.

:func:`integrate_native` has the signature, semantics and return type of
:func:`flexlib.solve.ida.integrate` (same :class:`~flexlib.solve.ida.Trajectory`, stats keys,
errors, events), but the step loop runs in C (``flexlib/solve/native/ida_driver.c``): the same
SUNDIALS 7.9 IDA that scikit-sundae bundles, with the residual, the iteration matrix (CSC
nonzeros; the linear solver by :func:`linear_solver`: dense LU up to :data:`KLU_MIN` unknowns, KLU above) and
the event indicators evaluated in C — the model's generated library when it has one, CasADi's
SX virtual machine through its C API otherwise. No Python runs per residual, Jacobian or step.

Python is called back only

* when a chunk of output rows is ready (IDA's own interpolation onto the output grid, or every
  internal step when there is no grid), copied from a buffer in one block;
* at time events (IDA's ``tstop``) and state events (IDA's root finding), which are handled
  exactly as in :mod:`flexlib.solve.ida` (:func:`~flexlib.solve.ida._event_iteration`,
  :func:`~flexlib.solve.ida.next_time_event`, the sign check of the state relations for two
  steps after a restart) followed by ``IDAReInit``;
* every :data:`CHUNK_STEPS` steps or :data:`CHUNK_WALL` seconds, to show progress, enforce ``max_steps`` and let
  Ctrl-C/SIGTERM in;
* when the state-selection ``monitor`` is due: the C loop runs as many steps as the monitor's schedule
  (:meth:`~flexlib.solve.state_selection.StateSelectionMonitor.steps_allowed`) lets pass unchecked, and
  stops early after a step that reaches the scheduled time or collapses in size.

At a failure the rows produced so far are kept, and the message names the unknowns with the
largest weighted local error estimates (``IDAGetEstLocalErrors`` × ``IDAGetErrWeights``), which
scikit-sundae does not expose. ``stats`` gains the split of the integration wall time:
``wall_model`` (residual, Jacobian and indicator evaluations; also ``wall_res``, ``wall_jac``,
``wall_root`` separately), ``wall_ida`` (the rest of the C
step loop: IDA, linear algebra, interpolation) and ``wall_python``.
"""

from __future__ import annotations

import os
import time as _time
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import RunArgumentError, SimulationInterrupted, SolverError
from flexlib.solve.ida import (
    DENSE_MAX,
    NEWTON_ITERS,
    Progress,
    Trajectory,
    _event_iteration,
    absolute_tolerances,
    failure_message,
    next_time_event,
)
from flexlib.solve.initialization import Initializer
from flexlib.solve.native import (
    FD_CHUNK,
    FD_FULL,
    FD_ROOT,
    FD_TINY,
    FD_TSTOP,
    LINEAR_SOLVERS,
    Driver,
    cpu_clock,
    evaluators,
    klu_available,
)

#: IDA failures after which the run restarts once from the last accepted point (``IDA_ERR_FAIL``, ``IDA_CONV_FAIL``)
RECOVERABLE = {-3: "IDA_ERR_FAIL", -4: "IDA_CONV_FAIL"}
#: ... at most this many times per run
MAX_RECOVERIES = 10

__all__ = ["CHUNK_STEPS", "KLU_MIN", "integrate_native", "linear_solver"]

#: Up to this many unknowns the driver factorises dense (SUNDIALS dense LU); above, KLU when installed
KLU_MIN = 40

#: The C loop returns to Python at least every this many steps (progress bar, Ctrl-C, ``max_steps``)
CHUNK_STEPS = 256
#: ... and after this much wall time [s] (a signal that arrives during C steps takes effect when the block returns)
CHUNK_WALL = 0.05
#: Output rows buffered in C before Python copies them (per driver, at most ~8 MB per array).
ROW_BUFFER_VALUES = 1_000_000


def integrate_native(model: CompiledModel, init: Initializer, p: np.ndarray, y0: np.ndarray, yp0: np.ndarray,
                     t0: float, t_end: float, t_out: np.ndarray | None, *, rtol: float = 1e-6, atol: float = 1e-8,
                     max_step: float = 0.0, max_steps: int = 5_000_000, progress: bool | None = None,
                     monitor: Any = None, max_order: int = 5) -> Trajectory:
    """Integrate from consistent ``y0, yp0`` at ``t0`` to ``t_end`` with the C-driven IDA.

    Parameters
    ----------
    model : CompiledModel
        The compiled model (generated C is used when ``model.library`` exists).
    init : Initializer
        Re-initialisation at events.
    p : ndarray
        Parameters followed by relation values (updated in place at events; the C driver reads this
        array's memory, so it must stay the same array).
    t_out : ndarray or None
        Output times [s]; None records every internal step.
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
        Dynamic state selection, checked on the monitor's schedule (the C loop returns when a check is due).

    Returns
    -------
    Trajectory
        With ``status`` ``"success"``; failures raise :class:`SolverError` with ``.result`` the
        trajectory up to the failure (set by the caller from ``err.trajectory``).
    """
    if p.dtype != np.float64 or not p.flags.c_contiguous:
        raise TypeError("integrate_native: p must be a C-contiguous float64 array (updated in place)")
    traj = Trajectory(models=[model])
    n_par = model.n_params
    stats: dict[str, Any] = {"steps": 0, "nfev": 0, "njev": 0, "state_events": 0, "time_events": 0, "restarts": 0,
                             "state_switches": 0, "recoveries": 0}
    traj.stats = stats
    grid = None
    if t_out is not None:
        grid = np.asarray(t_out, dtype=float)
        grid = np.ascontiguousarray(grid[grid > t0])
    drv, state_rel = _make_driver(model, p, rtol, atol, max_step, t0, y0, yp0, max_order)
    stats["linear_solver"] = drv.linsol
    stats["max_order"] = int(max_order)
    drv.set_grid(grid)
    retired: list[dict[str, float]] = []  # counters of drivers replaced at state switches
    traj.add(t0, y0, yp0, p[n_par:].copy())
    cap = max(16, ROW_BUFFER_VALUES // max(model.n, 1))
    if grid is not None:
        cap = max(1, min(cap, len(grid)))
    T, Y, YP = np.empty(cap), np.empty((cap, model.n)), np.empty((cap, model.n))
    t = t0
    clock = _time.thread_time if cpu_clock() else _time.perf_counter  # the clock the driver times with
    wall0 = clock()
    bar = Progress(model.name, t0, t_end, progress)
    watch = 2 if len(state_rel) else 0
    rooted: set[int] = set()
    ind_fn = model.function("ind")
    last_event_t, burst = -np.inf, 0
    last_recovery_t = -np.inf
    t_event, which = next_time_event(model, p, t, t_end)
    use_monitor = monitor is not None and model.has_state_choice
    if monitor is not None:
        monitor.reset()
    unseen = 0  # steps taken since the monitor last saw one
    pending_c = model.library_pending is not None  # C being compiled in the background: switch when ready

    def flush(k: int) -> None:
        if k:
            rel = p[n_par:].copy()
            traj.t.extend(T[:k].tolist())
            traj.y.extend(Y[:k].copy())
            traj.yp.extend(YP[:k].copy())
            traj.rel.extend([rel] * k)
            traj.seg.extend([len(traj.models) - 1] * k)

    try:
        while t < t_end:
            tstop = min(t_end, t_event)
            chunk = 1 if watch > 0 else CHUNK_STEPS
            if use_monitor:  # as many steps as the monitor's schedule lets pass unchecked
                allowed, t_next, h_min = monitor.steps_allowed()
                chunk = min(chunk, allowed - unseen) if allowed > unseen else 1
                drv.set_limits(t_next, h_min)
            chunk = max(1, min(chunk, max_steps - stats["steps"]))
            code, k, t, nsteps = drv.advance(tstop, chunk, T, Y, YP)
            stats["steps"] += nsteps
            unseen += nsteps
            flush(k)
            if pending_c and model.c_ready():
                # the background gcc has finished: the residual and Jacobian are evaluated by the compiled library
                # from the next step on, without a restart (the same operations in the same order as the SX
                # virtual machine, so the trajectory does not change)
                pending_c = False
                drv.rebind(evaluators(model, _zc_function(model, p, state_rel)))
                stats["compiled_at"] = t
            if code in RECOVERABLE and t > last_recovery_t and stats["recoveries"] < MAX_RECOVERIES:
                # IDA's corrector or error test failed repeatedly with the step shrinking (a valve snapping open
                # at the limit of the iteration matrix's reuse): restart from the last accepted point, made
                # consistent, with IDA's history reset (order 1, a new Jacobian) — once per point reached, and at
                # most MAX_RECOVERIES times in a run
                y_now, yp_now = drv.state()
                try:
                    y_now, yp_now = _event_iteration(model, init, p, t, y_now, yp_now, [])
                except SolverError:
                    raise SolverError(_failure_message(model, drv, code, t, p, traj, rtol, atol)) from None
                last_recovery_t = t
                stats["recoveries"] += 1
                traj.events.append((t, f"restart after {RECOVERABLE[code]} (IDA re-initialised at the last "
                                       "accepted point)"))
                drv.reinit(t, y_now, yp_now)
                traj.add(t, y_now, yp_now, p[n_par:].copy())
                watch, rooted = (2 if len(state_rel) else 0), set()
                continue
            if code < 0:
                raise SolverError(_failure_message(model, drv, code, t, p, traj, rtol, atol))
            if stats["steps"] % CHUNK_STEPS < nsteps or code == FD_CHUNK:
                bar.update(t)
            if code == FD_FULL:
                continue  # rows copied; the step (and any event it ended on) is reported by the next call
            if code == FD_TINY:
                y_now, yp_now = drv.state()
                raise SolverError(failure_message(
                    f"IDA step size underflow at t = {t:.10g} s (the model may be stiff beyond repair, or "
                    "discontinuous without an event)" + _dominant(model, drv), model, p, t, y_now, yp_now, traj,
                    rtol, atol))
            y_now = yp_now = None
            event_kind = None
            changed: list[int] = []
            triggered: list[tuple[int, bool]] = []
            time_hit = bool(which) and code in (FD_TSTOP, FD_ROOT) and t >= t_event
            if code == FD_ROOT:
                info = drv.roots()
                triggered = [(int(state_rel[j]), bool(info[j] > 0)) for j in np.flatnonzero(info)]
                event_kind = "state"
            if time_hit:  # also when a state event is found exactly at the time event
                ab = np.asarray(model.function("tev")(p)).reshape(-1, 2)
                triggered += [(k, bool(ab[k, 0] > 0)) for k in which]
                event_kind = event_kind or "time"
            elif code != FD_ROOT and watch > 0:
                # IDA ignores a root function that is zero at a restart until it leaves zero, so a relation
                # that re-crosses at once (sliding) is caught by checking its sign (as the scikit-sundae
                # path) — except the relations IDA's root finding switched and that start on their new
                # side (``_settled``): IDA watches those itself, and their sign here is Newton noise
                watch -= 1
                y_now, yp_now = drv.state()
                z = np.asarray(ind_fn(t, y_now, yp_now, p)).ravel()
                triggered = [(int(k), model.relations[k].value(z[k])) for k in state_rel
                             if k not in rooted and float(model.relations[k].value(z[k])) != p[n_par + k]]
                event_kind = "state" if triggered else None
            if event_kind:
                changed = [k for k, v in triggered if p[n_par + k] != float(v)]
                if changed:
                    if y_now is None:
                        y_now, yp_now = drv.state()
                    traj.add(t, y_now, yp_now, p[n_par:].copy())
                    y_now, yp_now = _event_iteration(model, init, p, t, y_now, yp_now, triggered)
                    stats["state_events" if event_kind == "state" else "time_events"] += 1
                    stats["restarts"] += 1
                    texts = ", ".join(model.relations[k].text for k, _ in triggered)
                    traj.events.append((t, f"{event_kind} event: {texts}"))
                    drv.reinit(t, y_now, yp_now)
                    traj.add(t, y_now, yp_now, p[n_par:].copy())
                    watch = 2 if len(state_rel) else 0
                    rooted = _settled(model, ind_fn, p, t, y_now, yp_now, triggered) if code == FD_ROOT else set()
                    burst = burst + 1 if t - last_event_t <= 1e-10 * max(1.0, abs(t)) else 0
                    last_event_t = t
                    if burst > 100:
                        raise SolverError(
                            f"event chattering at t = {t:.10g} s: {texts} switches without time advancing")
                if time_hit:
                    t_event, which = next_time_event(model, p, t, t_end)
            if use_monitor and unseen:
                if y_now is None:
                    y_now, yp_now = drv.state()
                skipped, unseen = unseen - 1, 0
                if monitor.needs_switch(model, t, y_now, yp_now, p, skipped=skipped, h=drv.last_step()):
                    switched = monitor.switch(model, t, y_now, yp_now, p)
                    if switched is not None:
                        model, y1, yp1 = switched
                        init = Initializer(model)
                        y1, yp1 = init.reinit(t, y1, yp1, p)
                        pos = drv.grid_pos()
                        retired.append(drv.stats())
                        drv, state_rel = _make_driver(model, p, rtol, atol, max_step, t, y1, yp1, max_order)
                        if grid is not None:
                            grid = np.ascontiguousarray(grid[pos:])
                        drv.set_grid(grid)
                        Y, YP = np.empty((cap, model.n)), np.empty((cap, model.n))
                        ind_fn = model.function("ind")
                        traj.models.append(model)
                        traj.add(t, y1, yp1, p[n_par:].copy())
                        stats["state_switches"] += 1
                        states = ", ".join(n for n, d in zip(model.y_names, model.differential, strict=True) if d)
                        traj.events.append((t, f"state selection: states are now {states}"))
                        watch = 2 if len(state_rel) else 0
                        use_monitor = model.has_state_choice
                        pending_c = False
                        if not use_monitor:
                            drv.set_limits(np.inf, 0.0)
            if stats["steps"] >= max_steps and t < t_end:
                raise SolverError(f"maximum number of steps ({max_steps}) reached at t = {t:.10g} s")
    except KeyboardInterrupt:
        _trim(traj)  # the interrupt may have come in the middle of a block copy
        t = max(t, _close(traj, drv, p[n_par:].copy(), (T, Y, YP)))  # rows the interrupt kept from being copied
        traj.status, traj.message = "interrupted", f"interrupted by the user at t = {t:.10g} s"
        raise SimulationInterrupted(traj.message, traj) from None
    except SolverError as err:
        _close(traj, drv, p[n_par:].copy())
        traj.status, traj.message = "failed", str(err)
        err.result = traj
        raise
    except Exception as err:  # e.g. an event iteration that raises
        _close(traj, drv, p[n_par:].copy())
        traj.status, traj.message = "failed", f"error at t = {t:.10g} s: {err}"
        raise SolverError(traj.message, traj) from err
    finally:
        _collect(stats, [*retired, drv.stats()], clock() - wall0)
        bar.close()
    stats["wall_integrate"] = clock() - wall0
    return traj


def _close(traj: Trajectory, drv: Driver, rel: np.ndarray,
           buffers: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> float:
    """End the rows of a failed or interrupted run at the driver's last accepted point (its time and solution as of
    its last return; :meth:`Trajectory.close` adds it only after the last row) and return the time of the last row.

    ``buffers``: the row buffers of the last :meth:`Driver.advance`. An interrupt that arrives as the call returns,
    before its rows are copied, would otherwise lose them; its rows after the last copied one are copied here."""
    rows, t_now = drv.last_advance()
    try:
        if buffers is not None and traj.t:
            T, Y, YP = buffers
            for i in range(min(rows, len(T))):
                if T[i] > traj.t[-1] and Y[i].shape == traj.y[-1].shape:
                    traj.add(T[i], Y[i], YP[i], rel)
        y, yp = drv.state()
        traj.close(t_now, y, yp, rel)
    except Exception:  # never let the extra rows hide the failure itself
        pass
    return traj.t[-1] if traj.t else t_now


def _zc_function(model: CompiledModel, p: np.ndarray, state_rel: np.ndarray) -> ca.Function | None:
    """IDA's root functions: the indicators of the relations ``state_rel`` (cached with the evaluators)."""
    if not len(state_rel):
        return None
    cached = model._functions.get("ida_native")
    if cached is not None and cached.get("zc_fn") is not None:
        return cached["zc_fn"]
    ind = model.sx_function("ind")
    t, y, yp = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
    pp = ca.SX.sym("p", len(p))
    z = ind(t, y, yp, pp)
    return ca.Function("flexlib_zc", [t, y, yp, pp], [ca.vertcat(*[z[int(k)] for k in state_rel])])


def _settled(model: CompiledModel, ind_fn: Any, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
             triggered: list[tuple[int, bool]]) -> set[int]:
    """The relations switched at an IDA root whose indicator at the restart point ``(t, y, yp)`` moves towards the
    side of their new value (``dz/dt = ∂z/∂t + ∂z/∂y·y'`` has the sign of that side).

    A root located by IDA lies within its interpolation error (order ``rtol``) of the true crossing: after the
    event iteration the indicator can still be on the old side by that much, and in the first steps after the
    restart its sign follows the Newton corrector's noise (``docs/decisions/018-relation-recheck-after-restart.md``).
    Such a relation is still heading across, and IDA's root finding
    watches it from the restart (a root function that is exactly zero there becomes active once it leaves zero).
    A relation whose indicator turns back at once (a contact that bounces, sliding) is left to the check by sign.
    """
    n_par = model.n_params
    dz = model._functions.get("ida_native_dzdt")
    if dz is None:
        ind = model.sx_function("ind")
        ts, ys, yps = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
        ps = ca.SX.sym("p", n_par + model.n_relations)
        z = ind(ts, ys, yps, ps)
        rate = ca.jtimes(z, ca.vertcat(ts, ys), ca.vertcat(1.0, yps))
        dz = ca.Function("flexlib_dzdt", [ts, ys, yps, ps], [rate])
        model._functions["ida_native_dzdt"] = dz  # type: ignore[assignment]
    with np.errstate(all="ignore"):
        rate = np.asarray(dz(t, y, yp, p)).ravel()
    out = set()
    for k, _ in triggered:
        rel = model.relations[k]
        if np.isfinite(rate[k]) and rate[k] != 0.0 and float(rel.value(rate[k])) == p[n_par + k]:
            out.add(k)
    return out


def _trim(traj: Trajectory) -> None:
    """Cut the row lists to their common length (rows complete in every list are kept)."""
    n = min(len(traj.t), len(traj.y), len(traj.yp), len(traj.rel), len(traj.seg))
    for rows in (traj.t, traj.y, traj.yp, traj.rel, traj.seg):
        del rows[n:]


def _collect(stats: dict[str, Any], parts: list[dict[str, float]], wall: float) -> None:
    """Evaluation counts and the wall-time split (model / IDA / Python) over all drivers of the run."""
    stats["nfev"] = sum(int(s["nfev"]) for s in parts)
    stats["njev"] = sum(int(s["njev"]) for s in parts)
    model_s = sum(s["t_res"] + s["t_jac"] + s["t_root"] for s in parts)
    advance_s = sum(s["t_advance"] for s in parts)
    stats["wall_model"] = model_s
    stats["wall_res"] = sum(s["t_res"] for s in parts)
    stats["wall_jac"] = sum(s["t_jac"] for s in parts)
    stats["wall_root"] = sum(s["t_root"] for s in parts)
    stats["wall_ida"] = max(advance_s - model_s, 0.0)
    stats["wall_python"] = max(wall - advance_s, 0.0)
    for key in ("n_lsetup", "n_lsolve", "n_factor_full", "n_newton", "n_newton_fail", "n_err_fail", "nonfinite"):
        stats[key] = sum(int(s[key]) for s in parts)
    stats["wall_lsetup"] = sum(s["t_lsetup"] for s in parts)
    stats["wall_lsolve"] = sum(s["t_lsolve"] for s in parts)


def linear_solver(model: CompiledModel) -> str:
    """The driver's linear solver for ``model``: ``"klu"``, ``"dense"`` or ``"superlumt"``.

    Rule (measured per factorisation and solve on the models' own iteration matrices, ``benchmarks/linear_solvers.py``):
    KLU (BTF + AMD ordering once per driver, then one numeric factorisation with threshold partial pivoting per IDA
    setup) when the model has more than :data:`KLU_MIN` unknowns and kvxopt's KLU is installed; dense LU at or below
    :data:`KLU_MIN` (and up to :data:`~flexlib.solve.ida.DENSE_MAX` without KLU); SuperLU_MT (SUNDIALS' sparse
    solver) otherwise.
    ``FLEXLIB_LINSOL=dense|klu|superlumt`` in the environment overrides the rule (for comparisons).
    """
    forced = os.environ.get("FLEXLIB_LINSOL", "")
    if forced:
        if forced not in LINEAR_SOLVERS:
            raise RunArgumentError(f"FLEXLIB_LINSOL={forced!r}: expected one of {', '.join(LINEAR_SOLVERS)}")
        return forced
    if model.n <= KLU_MIN:
        return "dense"
    if klu_available():
        return "klu"
    return "dense" if model.n <= DENSE_MAX else "superlumt"


def _make_driver(model: CompiledModel, p: np.ndarray, rtol: float, atol: float, max_step: float, t0: float,
                 y0: np.ndarray, yp0: np.ndarray, max_order: int = 5) -> tuple[Driver, np.ndarray]:
    """A C driver for ``model`` (indicators of the state relations as IDA root functions)."""
    state_rel = np.array([k for k, r in enumerate(model.relations) if not r.time_event], dtype=int)
    ev = evaluators(model, _zc_function(model, p, state_rel))
    drv = Driver(model, p, ev, len(state_rel), linear_solver(model), rtol, absolute_tolerances(model, atol),
                 max_step, t0, y0, yp0)
    drv.set_wall_chunk(CHUNK_WALL)
    drv.set_max_order(max_order)
    drv.set_newton(max_iters=NEWTON_ITERS)
    return drv, state_rel


def _failure_message(model: CompiledModel, drv: Driver, code: int, t: float, p: np.ndarray, traj: Trajectory,
                     rtol: float, atol: float) -> str:
    """IDA's failure, with the unknowns whose weighted local error estimates dominate (IDA's own error weights
    and local errors), followed by what :func:`flexlib.solve.ida.failure_message` finds at the last accepted
    point: non-finite values with their equation, a singular iteration matrix, the fastest-changing unknowns."""
    y, yp = drv.state()
    head = f"IDA failed at t = {t:.10g} s: {drv.flag_name(code)} (status {code})" + _dominant(model, drv)
    bad = int(drv.stats().get("nonfinite", 0))
    if bad:  # IDA counts a non-finite residual at a Newton iterate as a convergence failure
        head += f"; {bad} residual evaluations during the run were not finite (retried with smaller steps)"
    return failure_message(head, model, p, t, y, yp, traj, rtol, atol)


def _dominant(model: CompiledModel, drv: Driver, top: int = 3) -> str:
    """``"; largest weighted local error estimates: x (…), …"`` from IDA's last step, or ``""``."""
    ewt, ele = drv.diagnostics()
    w = np.abs(ewt * ele)
    if not (np.all(np.isfinite(w)) and w.max(initial=0.0) > 0.0):
        return ""
    order = np.argsort(w)[::-1][:top]
    names = ", ".join(f"{model.y_names[i]} ({w[i]:.3g})" for i in order if w[i] > 0.0)
    return f"; largest weighted local error estimates: {names}"
