"""Alternative integrator backend: CasADi's own (C) IDAS through ``casadi.integrator``.

:func:`integrate_casadi` has the signature and semantics of :func:`flexlib.solve.ida.integrate`
(same :class:`~flexlib.solve.ida.Trajectory`, same stats keys, same errors), but every
integration step runs inside CasADi's C interface to SUNDIALS IDAS: no Python callback per
residual or Jacobian evaluation. Events are handled in Python between integrator calls.

Design
------
*Fully implicit DAE in CasADi's semi-explicit form* (notes §5): with ``d`` the differential
and ``a`` the algebraic entries of ``y``, the integrator sees

    x = [T; y_d],   z = [w; y_a],   u = Δt (one value per output interval),
    dx/dτ = [u; u·w],   0 = F(T, y(y_d, y_a), y'(w, 0), p)

in a *normalised time* ``τ``: the output grid of every integrator is ``τ = 1, 2, …, K`` and the
physical length of interval ``k`` is the piecewise-constant control ``u_k``; physical time ``T``
is a state (``dT/dτ = u``). One integrator per grid size ``K`` therefore serves any start time
and any (non-uniform) output times, so integrators are built once per model and options and
cached in ``model._functions["casadi_idas"]`` (dropped when the model is pickled). ``K`` is
rounded up to a power of two and the unused intervals get ``u = 0`` (CasADi stops exactly at
the last real point, because ``u`` changes there; the padding costs a few cheap steps).
Parameters and relation values are the integrator's ``p`` input (run-time, no rebuild).
Linear solver: ``csparse`` (sparse LU, *natural* ordering), so the columns of ``z`` and the
rows of ``F`` are permuted once (maximum transversal, then reverse Cuthill–McKee) to keep the
fill-in low. Error control: ``w`` (the derivatives added by the implicit trick) is excluded
from IDA's local error test (absolute tolerance 1e10), so the test covers ``y`` exactly as in
the default backend; ``atol`` is scaled by each variable's ``nominal``.

*Time events* are hit exactly: the run is cut into segments ending at
:func:`~flexlib.solve.ida.next_time_event`; each segment is one or more integrator calls
whose last grid point is the event time.

*State events*: CasADi 3.8.2's own event support (DAE ``zero`` output) was not used: it only
detects crossings from positive to negative, checks them only at output times, and
handles the event inside C (a ``transition`` function), which cannot run flexlib's event
iteration (``Initializer.reinit``) or switch the relation values in ``p``. Instead the
indicators of the state relations are evaluated at every grid point after a call; the first
point where a relation would change value brackets the event, and the bracket is narrowed by
re-running the integrator from its left end with :data:`SUB_GRID` uniform sub-points, until it
is shorter than ``EVENT_TOL·max(1, |t|)`` (about 7 calls for a 0.01 s bracket). The event time
is the right end of the final bracket (the first point where the relation has switched, as
IDA's root finder reports it), and :func:`flexlib.solve.ida._event_iteration` re-initialises
before the restart. A zero crossing that reverts between two grid points is not seen: with
state relations, grid intervals are subdivided to at most ``(t_end − t0)/DETECT_POINTS``.

*Output*: on the requested grid ``t_out`` (IDAS's own interpolation). IDAS's individual steps
are not accessible through ``casadi.integrator``, so ``t_out=None`` (every step) is replaced
by a uniform grid of :data:`DENSE_POINTS` intervals (plus the event instants).

Measured trade-offs (2-core VM, chain benchmark ``benchmarks/chain.py``, rtol 1e-6)
------------------------------------------------------------------------------------
* Every integrator call is a cold IDAS start (``IDAReInit`` + ``IDACalcIC``, order 1, small
  first step), so each event and each chunk boundary costs a few dozen steps more than the
  default backend, which re-initialises only at events.
* CasADi evaluates the residual with its SX virtual machine, not with flexlib's generated C
  code: at 3001 unknowns the residual costs about 75 µs per call here against a few µs
  compiled; and the implicit trick doubles the size of the linear system. For large models
  this backend is therefore *slower* than the default one (see ``benchmarks/README.md``);
  it pays off for small models, where the default backend's Python callbacks dominate.
* Integrator construction (symbolic Jacobian): ~10 ms at 300 unknowns, ~80 ms at 3000, per
  grid-size bucket, once per process.
* A failing integrator call raises inside CasADi without partial results, so the trajectory
  of a failed run ends at the last successful call.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import math
import re
import time as _time
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
import scipy.sparse as sps
from scipy.sparse.csgraph import maximum_bipartite_matching, reverse_cuthill_mckee

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import SimulationInterrupted, SolverError
from flexlib.solve.ida import Trajectory, _event_iteration, next_time_event
from flexlib.solve.initialization import Initializer

__all__ = ["DENSE_POINTS", "DETECT_POINTS", "EVENT_TOL", "FIRST_CHUNK", "SUB_GRID", "integrate_casadi"]

#: Number of output intervals used when ``t_out`` is None (CasADi does not expose single steps).
DENSE_POINTS = 1000
#: With state relations, grid intervals are at most ``(t_end - t0) / DETECT_POINTS`` long.
DETECT_POINTS = 500
#: Sub-points per refinement call when locating a state event.
SUB_GRID = 1024
#: Relative width of the final bracket of a state event.
EVENT_TOL = 1e-12
#: Points of the first integrator call after a state event (doubled after every call without one).
FIRST_CHUNK = 32
#: Largest grid (points per integrator call); larger grids are split into several calls.
MAX_GRID = 1024
#: Memory cap: grid points × (size of x + size of z) per call.
MAX_FLOATS = 4_000_000
#: Integrators kept per model (one per grid size and options).
MAX_INTEGRATORS = 64
_CACHE_KEY = "casadi_idas"


@dataclass
class _Backend:
    """Per-model CasADi objects: the normalised-time DAE and the integrators built from it."""

    dae: dict[str, ca.SX]
    x_idx: np.ndarray  # y entries that are x (after T), in x order
    a_idx: np.ndarray  # y entries that are algebraic z (after w), in z order
    nominal: np.ndarray
    integrators: dict[tuple, ca.Function] = field(default_factory=dict)
    ind_maps: dict[int, ca.Function] = field(default_factory=dict)
    build_time: float = 0.0

    @property
    def nd(self) -> int:
        return len(self.x_idx)

    def integrator(self, K: int, rtol: float, atol: float, capped: bool, max_num_steps: int) -> ca.Function:
        """Integrator over the normalised grid ``τ = 1..K`` (built once per options and ``K``)."""
        key = (K, float(rtol), float(atol), bool(capped), int(max_num_steps))
        F = self.integrators.get(key)
        if F is None:
            wall = _time.perf_counter()
            nd = self.nd
            abstolv = np.concatenate([[atol], atol * self.nominal[self.x_idx], np.full(nd, 1e10),
                                      atol * self.nominal[self.a_idx]])
            opts: dict[str, Any] = {
                "linear_solver": "csparse", "reltol": float(rtol), "abstol": float(atol),
                "abstolv": abstolv.tolist(), "max_num_steps": int(max_num_steps),
                "disable_internal_warnings": True,
            }
            if capped:
                opts["max_step_size"] = 1.0  # one grid interval; the grid is refined to max_step
            F = ca.integrator("flexlib_idas", "idas", self.dae, 0.0, [float(k) for k in range(1, K + 1)], opts)
            if len(self.integrators) >= MAX_INTEGRATORS:  # bounded cache: drop the oldest
                self.integrators.pop(next(iter(self.integrators)))
            self.integrators[key] = F
            self.build_time += _time.perf_counter() - wall
        return F


def _backend(model: CompiledModel) -> _Backend:
    be = model._functions.get(_CACHE_KEY)
    if be is None:
        be = _build_backend(model)
        model._functions[_CACHE_KEY] = be  # type: ignore[assignment]
    return be


def _fill_reducing_order(model: CompiledModel) -> tuple[np.ndarray, np.ndarray]:
    """Column order (entries of ``y``) and row order (equations) for csparse's natural-order LU."""
    n = model.n
    J = sps.csc_matrix((np.ones(len(model.jac_row)), model.jac_row, model.jac_colind), shape=(n, n)).tocsr()
    match = maximum_bipartite_matching(J, perm_type="column")  # match[row] = column
    if n == 0 or np.any(match < 0):
        return np.arange(n), np.arange(n)
    row_of = np.empty(n, dtype=int)
    row_of[match] = np.arange(n)  # row_of[column] = matched row
    A = J[row_of, :]  # structurally non-zero diagonal
    S = (abs(A) + abs(A.T)).tocsr()
    perm = reverse_cuthill_mckee(S, symmetric_mode=True)
    return np.asarray(perm, dtype=int), row_of[perm]


def _build_backend(model: CompiledModel) -> _Backend:
    wall = _time.perf_counter()
    res = model.sx_function("res") if hasattr(model, "sx_function") else model.function("res")
    cols, rows = _fill_reducing_order(model)
    diff = model.differential
    x_idx = np.array([i for i in cols if diff[i]], dtype=int)
    a_idx = np.array([i for i in cols if not diff[i]], dtype=int)
    nd, na = len(x_idx), len(a_idx)
    T, tau, u = ca.SX.sym("T"), ca.SX.sym("tau"), ca.SX.sym("u")
    xd, w, ya = ca.SX.sym("x", nd), ca.SX.sym("w", nd), ca.SX.sym("ya", na)
    p = ca.SX.sym("p", model.n_params + model.n_relations)
    y_parts: list[Any] = [None] * model.n
    yp_parts: list[Any] = [ca.SX(0.0)] * model.n
    for k, i in enumerate(x_idx):
        y_parts[i], yp_parts[i] = xd[k], w[k]
    for k, i in enumerate(a_idx):
        y_parts[i] = ya[k]
    y = ca.vertcat(*y_parts) if model.n else ca.SX(0, 1)
    yp = ca.vertcat(*yp_parts) if model.n else ca.SX(0, 1)
    F = res(T, y, yp, p)
    F = F[[int(r) for r in rows]] if model.n else F
    dae = {"t": tau, "x": ca.vertcat(T, xd), "z": ca.vertcat(w, ya), "p": p, "u": u,
           "ode": ca.vertcat(u, u * w), "alg": F}
    be = _Backend(dae=dae, x_idx=x_idx, a_idx=a_idx, nominal=np.asarray(model.nominal, dtype=float))
    be.build_time = _time.perf_counter() - wall
    return be


def _snap(u: np.ndarray, t: float) -> np.ndarray:
    """Interval lengths with round-off differences removed.

    CasADi stops IDAS (``tstop``) wherever the control ``u`` changes, so the last-bit noise of
    ``np.diff(np.linspace(...))`` would force a step end at every output point.
    """
    if len(u) < 2:
        return u
    same = np.abs(np.diff(u)) <= 1e-9 * np.maximum(np.abs(u[1:]), np.abs(u[:-1]))
    idx = np.arange(len(u))
    idx[1:][same] = 0
    np.maximum.accumulate(idx, out=idx)
    snapped = u[idx]
    if np.max(np.abs(np.cumsum(snapped) - np.cumsum(u))) > 1e-13 * max(1.0, abs(t) + float(np.sum(np.abs(u)))):
        return u  # a genuinely non-uniform grid: keep the exact lengths
    return snapped


class _Runner:
    """One run: calls the cached integrators, converts their output, counts statistics."""

    def __init__(self, model: CompiledModel, be: _Backend, p: np.ndarray, stats: dict[str, Any], rtol: float,
                 atol: float, capped: bool, max_steps: int, state_rel: np.ndarray) -> None:
        self.model, self.be, self.p, self.stats = model, be, p, stats
        self.rtol, self.atol, self.capped = rtol, atol, capped
        self.max_steps = max_steps
        self.mns = int(min(max_steps, 100_000))  # IDAS steps per output interval
        self.state_rel = state_rel
        self.n_par = model.n_params
        self.strict = np.array([model.relations[k].strict for k in state_rel], dtype=bool)
        self.ind = model.function("ind")
        self.chunk_cap = max(1, min(MAX_GRID, MAX_FLOATS // max(1, 2 * model.n + 1)))

    def run(self, t: float, y: np.ndarray, yp: np.ndarray, grid: np.ndarray,
            steps: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Integrate from ``(t, y, yp)`` through the increasing times ``grid``; returns ``Y, YP`` (n × K).

        ``steps`` are the interval lengths (default: differences of the grid, with round-off removed).
        """
        be = self.be
        F = be.integrator(len(grid), self.rtol, self.atol, self.capped, self.mns)
        u = (_snap(np.diff(np.concatenate([[t], grid])), t) if steps is None else steps)[None, :]
        x0 = np.concatenate([[t], y[be.x_idx]])
        z0 = np.concatenate([yp[be.x_idx], y[be.a_idx]])
        try:
            out = F(x0=x0, z0=z0, p=self.p, u=u)
        except RuntimeError as err:
            text = str(err)
            if "IDA_TOO_MUCH_WORK" in text and self.mns >= self.max_steps:
                raise SolverError(f"maximum number of steps ({self.max_steps}) reached between t = {t:.10g} s "
                                  f"and t = {grid[-1]:.10g} s") from err
            flag = re.search(r"IDA_[A-Z_]+", text)
            short = flag.group(0) if flag else text.strip().splitlines()[-1] if text.strip() else "error"
            raise SolverError(f"CasADi IDAS failed between t = {t:.10g} s and t = {grid[-1]:.10g} s ({short})") from err
        finally:
            st = F.stats()
            self.stats["steps"] += int(st.get("nsteps", 0))
            self.stats["nfev"] += int(st.get("n_call_daeF", 0))
            self.stats["njev"] += int(st.get("n_call_jacF", 0))
            self.stats["integrator_calls"] += 1
        X = np.asarray(out["xf"]).reshape(-1, len(grid))
        Z = np.asarray(out["zf"]).reshape(-1, len(grid))
        n, nd, K = self.model.n, be.nd, len(grid)
        Y, YP = np.empty((n, K)), np.zeros((n, K))
        Y[be.x_idx] = X[1:]
        Y[be.a_idx] = Z[nd:]
        YP[be.x_idx] = Z[:nd]
        return Y, YP

    def first_switch(self, grid: np.ndarray, Y: np.ndarray, YP: np.ndarray) -> tuple[int, list[tuple[int, bool]]]:
        """First grid column where a state relation changes value, and the relations switching there."""
        if not len(self.state_rel):
            return -1, []
        K = len(grid)
        f = self.be.ind_maps.get(K)
        if f is None:
            f = self.be.ind_maps[K] = self.ind.map(K)
        P = np.repeat(self.p[:, None], K, axis=1)
        Zi = np.asarray(f(grid[None, :], Y, YP, P)).reshape(-1, K)[self.state_rel]
        new = np.where(self.strict[:, None], Zi > 0.0, Zi >= 0.0)
        cur = self.p[self.n_par + self.state_rel][:, None] != 0.0
        hit = np.flatnonzero(np.any(new != cur, axis=0))
        if not len(hit):
            return -1, []
        j = int(hit[0])
        return j, [(int(k), bool(v)) for k, v, c in zip(self.state_rel, new[:, j], cur[:, 0], strict=True) if v != c]

    def locate(self, a: tuple[float, np.ndarray, np.ndarray], b: tuple[float, np.ndarray, np.ndarray],
               triggered: list[tuple[int, bool]]) -> tuple[float, np.ndarray, np.ndarray, list[tuple[int, bool]]]:
        """Narrow the bracket ``(a, b]`` of a state event by re-running sub-grids from ``a``."""
        ta, ya, ypa = a
        tb, yb, ypb = b
        tol = EVENT_TOL * max(1.0, abs(tb))
        while tb - ta > tol:
            m = max(2, min(SUB_GRID, self.chunk_cap))
            h = (tb - ta) / m
            grid = ta + h * np.arange(1, m + 1)
            grid[-1] = tb
            Y, YP = self.run(ta, ya, ypa, grid, np.full(m, h))
            j, trig = self.first_switch(grid, Y, YP)
            if j < 0:  # the re-run does not switch (noise at the tolerance level): keep the bracket end
                break
            if j > 0:
                ta, ya, ypa = float(grid[j - 1]), Y[:, j - 1], YP[:, j - 1]
            tb, yb, ypb, triggered = float(grid[j]), Y[:, j], YP[:, j], trig
        return tb, yb, ypb, triggered


def integrate_casadi(model: CompiledModel, init: Initializer, p: np.ndarray, y0: np.ndarray, yp0: np.ndarray,
                     t0: float, t_end: float, t_out: np.ndarray | None, *, rtol: float = 1e-6, atol: float = 1e-8,
                     max_step: float = 0.0, max_steps: int = 5_000_000, progress: bool | None = None) -> Trajectory:
    """Integrate from consistent ``y0, yp0`` at ``t0`` to ``t_end`` with CasADi's IDAS.

    Same arguments, result and errors as :func:`flexlib.solve.ida.integrate`.

    Parameters
    ----------
    p : ndarray
        Parameters followed by relation values (updated in place at events).
    t_out : ndarray or None
        Output times; None gives a uniform grid of :data:`DENSE_POINTS` intervals (CasADi's
        integrator does not expose single steps).
    rtol, atol : float
        Relative and absolute tolerance (``atol`` is scaled by each variable's nominal value).
    max_step : float
        Maximum step size [s] (0: unlimited). Implemented by refining the grid to ``max_step`` and
        limiting each step to one grid interval, so steps are also limited by the output spacing.
    max_steps : int
        Maximum number of internal steps for the whole run (checked after each integrator call;
        one call may take at most ``min(max_steps, 100000)`` steps per output interval).
    progress : bool or None
        Show a progress bar; None shows one when the run takes longer than 2 s.

    Returns
    -------
    Trajectory
        With ``status`` ``"success"``; failures raise :class:`SolverError` with ``.result`` set to
        the trajectory up to the last successful integrator call.
    """
    traj = Trajectory()
    stats: dict[str, Any] = {"steps": 0, "nfev": 0, "njev": 0, "state_events": 0, "time_events": 0, "restarts": 0,
                             "integrator_calls": 0, "solver": "casadi-idas"}
    traj.stats = stats
    wall0 = _time.perf_counter()
    n_par = model.n_params
    state_rel = np.array([k for k, r in enumerate(model.relations) if not r.time_event], dtype=int)
    be = _backend(model)
    capped = max_step > 0.0
    runner = _Runner(model, be, p, stats, rtol, atol, capped, int(max_steps), state_rel)

    y, yp = np.array(y0, dtype=float), np.array(yp0, dtype=float)
    traj.add(t0, y, yp, p[n_par:].copy())
    if t_out is None:
        req = t0 + (t_end - t0) * np.arange(1, DENSE_POINTS + 1) / DENSE_POINTS
        req[-1] = t_end
    else:
        req = np.asarray(t_out, dtype=float)
        req = req[(req > t0) & (req <= t_end)]
    spacing = (t_end - t0) / DETECT_POINTS if len(state_rel) else np.inf
    if capped:
        spacing = min(spacing, max_step)
    # With state relations, a call runs on with frozen (wrong) relation values after an event it
    # contains, until its end: short calls right after events, doubling while none occurs.
    chunk = runner.chunk_cap if not len(state_rel) else min(runner.chunk_cap, FIRST_CHUNK)
    t = float(t0)
    ir = 0  # next requested output
    bar = None
    last_event_t, burst = -np.inf, 0

    def record(t_lim: float, grid: np.ndarray, Y: np.ndarray, YP: np.ndarray) -> None:
        """Record the requested outputs ``<= t_lim``; each is a column of ``grid``."""
        nonlocal ir
        k = 0
        while ir < len(req) and req[ir] <= t_lim:
            while k < len(grid) and grid[k] < req[ir]:
                k += 1
            if k < len(grid) and grid[k] == req[ir]:
                traj.add(req[ir], Y[:, k], YP[:, k], p[n_par:].copy())
            ir += 1

    def handle_event(kind: str, te: float, ye: np.ndarray, ype: np.ndarray,
                     triggered: list[tuple[int, bool]]) -> tuple[np.ndarray, np.ndarray]:
        nonlocal last_event_t, burst
        traj.add(te, ye, ype, p[n_par:].copy())
        y1, yp1 = _event_iteration(model, init, p, te, ye, ype, triggered)
        stats["state_events" if kind == "state" else "time_events"] += 1
        stats["restarts"] += 1
        texts = ", ".join(model.relations[k].text for k, _ in triggered)
        traj.events.append((te, f"{kind} event: {texts}"))
        traj.add(te, y1, yp1, p[n_par:].copy())
        burst = burst + 1 if te - last_event_t <= 1e-10 * max(1.0, abs(te)) else 0
        last_event_t = te
        if burst > 100:
            raise SolverError(f"event chattering at t = {te:.10g} s: {texts} switches without time advancing")
        return y1, yp1

    def time_event(te: float, ye: np.ndarray, ype: np.ndarray, which: list[int]) -> tuple[np.ndarray, np.ndarray]:
        ab = np.asarray(model.function("tev")(p)).reshape(-1, 2)
        trig = [(k, bool(ab[k, 0] > 0)) for k in which]
        if any(p[n_par + k] != float(v) for k, v in trig):
            return handle_event("time", te, ye, ype, trig)
        return ye, ype

    try:
        while t < t_end:
            t_ev, which = next_time_event(model, p, t, t_end)
            grid = _call_grid(t, req[ir:], t_ev, spacing, chunk)
            while True:
                try:
                    Y, YP = runner.run(t, y, yp, grid)
                    break
                except SolverError:
                    # after an undetected event the frozen relations may drive the model somewhere the
                    # solver cannot follow: retry a shorter call, which sees the event before that
                    if not len(state_rel) or len(grid) == 1:
                        raise
                    grid = grid[: len(grid) // 2]
                    chunk = len(grid)
            j, triggered = runner.first_switch(grid, Y, YP)
            if j >= 0:  # state event in (grid[j-1], grid[j]]
                a = (t, y, yp) if j == 0 else (float(grid[j - 1]), Y[:, j - 1], YP[:, j - 1])
                record(a[0], grid, Y, YP)
                te, ye, ype, triggered = runner.locate(a, (float(grid[j]), Y[:, j], YP[:, j]), triggered)
                record(te, np.array([te]), ye[:, None], ype[:, None])
                y, yp = handle_event("state", te, ye, ype, triggered)
                t = te
                if which and t == t_ev:  # a time event at the same instant
                    y, yp = time_event(t, y, yp, which)
                chunk = min(runner.chunk_cap, FIRST_CHUNK)
            else:
                record(float(grid[-1]), grid, Y, YP)
                t, y, yp = float(grid[-1]), Y[:, -1].copy(), YP[:, -1].copy()
                if which and t == t_ev:
                    y, yp = time_event(t, y, yp, which)
                chunk = min(runner.chunk_cap, 2 * chunk)
            if stats["steps"] >= max_steps:
                raise SolverError(f"maximum number of steps ({max_steps}) reached at t = {t:.10g} s")
            if bar is None and progress is not False:
                if progress or _time.perf_counter() - wall0 > 2.0:
                    from tqdm.auto import tqdm

                    bar = tqdm(total=float(t_end - t0), unit="s", desc=model.name, leave=False,
                               bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s [{elapsed}<{remaining}]")
            if bar is not None:
                bar.n = float(t - t0)
                bar.refresh()
    except KeyboardInterrupt:
        traj.status, traj.message = "interrupted", f"interrupted by the user at t = {t:.10g} s"
        raise SimulationInterrupted(traj.message, traj) from None
    except SolverError as err:
        traj.status, traj.message = "failed", str(err)
        err.result = traj
        raise
    except Exception as err:  # e.g. an InitializationError in the event iteration
        traj.status, traj.message = "failed", f"error at t = {t:.10g} s: {err}"
        raise SolverError(traj.message, traj) from err
    finally:
        if bar is not None:
            bar.close()
    stats["wall_integrate"] = _time.perf_counter() - wall0
    return traj


def _call_grid(t: float, req: np.ndarray, t_seg: float, spacing: float, cap: int) -> np.ndarray:
    """Grid of one integrator call from ``t``: the requested outputs up to the segment end ``t_seg``
    and ``t_seg`` itself, intervals subdivided to at most ``spacing``, at most ``cap`` points."""
    pts = req[req <= t_seg]
    pts = np.unique(np.concatenate([pts[pts > t], [t_seg]]))
    out: list[float] = []
    prev = t
    for q in pts:
        nsub = max(1, math.ceil((q - prev) / spacing - 1e-9)) if np.isfinite(spacing) else 1
        room = cap - len(out)
        if nsub > room:  # the call ends inside this interval (not on a requested point)
            out.extend(prev + (q - prev) * np.arange(1, room + 1) / nsub)
            break
        out.extend(prev + (q - prev) * np.arange(1, nsub) / nsub)
        out.append(float(q))
        prev = q
        if len(out) >= cap:
            break
    return np.array(out)
