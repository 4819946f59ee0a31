"""CasADi's own (C) IDAS through ``casadi.integrator``: the integrator calls behind
:class:`flexlib.solve.backends.casadi.CasadiIdas` (``solver="casadi-idas"``).

Every integration step runs inside CasADi's C interface to SUNDIALS IDAS: no Python callback per residual or
Jacobian evaluation. The run loop (:mod:`flexlib.solve.loop`) handles the events between integrator calls; this
module builds the integrators, calls them, and brackets and locates state events on their output grids.

Design
------
*Fully implicit DAE in CasADi's semi-explicit form* (notes §5): with ``d`` the differential
and ``a`` the algebraic entries of ``y``, the integrator sees

    x = [T; y_d],   z = [w; y_a],   u = Δt (one value per output interval),
    dx/dτ = [u; u·w],   0 = F(T, y(y_d, y_a), y'(w, 0), p)

in a *normalised time* ``τ``: the output grid of every integrator is ``τ = 1, 2, …, K`` and the
physical length of interval ``k`` is the piecewise-constant control ``u_k``; physical time ``T``
is a state (``dT/dτ = u``). One integrator per grid size ``K`` therefore serves any start time
and any (non-uniform) output times, so integrators are built once per model, options and ``K``
and cached in ``model._functions["casadi_idas"]`` (dropped when the model is pickled).
Parameters and relation values are the integrator's ``p`` input (run-time, no rebuild).
CasADi stops IDAS (``tstop``) wherever ``u`` changes, and since ``dx/dτ`` jumps there, IDAS's step
history no longer fits: a uniform grid costs nothing, every change of spacing a few rejected
steps (round-off differences of ``np.diff(grid)`` are removed first). Grids are therefore never
padded to a common size: padding with ``u = 0`` costs extra factorisations, building an integrator for the
exact size costs ~80 ms once at 3000 unknowns.
*Model evaluation*: where the model has a compiled library (generated C, ``CompiledModel.library``), the
residual is the library's ``flexlib_res`` and its Jacobian comes from ``flexlib_jac`` through a small
companion library (:func:`compiled_residual`); otherwise CasADi's SX virtual machine evaluates the symbolic
residual. A backend built on the SX residual while gcc still compiles in the background is rebuilt on C at
the next run once the library is there.

Linear solver: ``csparse`` (sparse LU with partial pivoting, no fill-reducing ordering of its own), so the
entries of ``x`` and ``z`` and the rows of ``F`` are ordered once by COLAMD on the structure of the iteration
matrix (:func:`flexlib.solve.casadi_dae.fill_reducing_order`; ``w`` and the algebraic entries interleave in
``z``). CasADi's ``qr``
plugin is not used: round-off of QR leaves ~1e-35 where LU gives exact zeros (a contact force at rest in
``tests/test_casadi_idas.py``). Error control: ``w``
(the derivatives added by the implicit trick) is excluded from IDA's local error test (absolute tolerance
1e10), so the test covers ``y`` exactly as in the default backend; ``atol`` is scaled by each variable's
``nominal``.

*Start of a call*: every integrator call is a fresh IDAS start (``IDAReInit`` + ``IDACalcIC``); a call that
fails is repeated with the fall-backs of :data:`START_VARIANTS` (without ``IDACalcIC``, then with ``w`` in the
error test) before it counts as failed. Without ``IDACalcIC`` CasADi starts from ``dx/dτ = 0`` (its
``init_xdot``), so that variant is a fall-back only.

*Time events* are hit exactly: the run is cut into segments ending at
:func:`~flexlib.solve.events.next_time_event`; each segment is one or more integrator calls
whose last grid point is the event time.

*State events*: CasADi 3.8.2's own event support (DAE ``zero`` output) was not used: it only
detects crossings from positive to negative, checks them only at output times, handles the
event inside C (a ``transition`` function, which cannot run flexlib's event iteration or
switch the relation values in ``p``), prints "Event support is experimental", and fails when one output
interval spans several steps (``IDA_ILL_INPUT``, "tout too far back"). Instead the
indicators of the state relations are evaluated at every grid point after a call; the first
point where a relation would change value brackets the event, and the bracket is narrowed by
re-running the integrator from its left end with :data:`SUB_GRID` uniform sub-points, until it
is shorter than ``EVENT_TOL·max(1, |t|)`` (3–4 calls of ~20–50 steps each). The event time
is the right end of the final bracket (the first point where the relation has switched, as
IDA's root finder reports it), and :func:`flexlib.solve.events.event_iteration` re-initialises
before the restart. A zero crossing that reverts between two grid points is not seen: with
state relations, grid intervals are subdivided to at most ``(t_end − t0)/DETECT_POINTS``.
A call also integrates on past an event it contains, with the old (frozen) relation values,
up to its end: after a state event calls are short (:data:`FIRST_CHUNK` points) and double
while no event occurs. If a model cannot be integrated past the event with the frozen values
(``if_else(x < 1, sqrt(1 - x), 0)`` gives NaN for ``x > 1``), the call fails: it is retried on
half its grid with a small step budget (:data:`RETRY_STEPS`) until it stops before the event,
and if even one interval fails, the last reachable time is found by bisection; a state
relation whose indicator is ~0 there (:data:`STUCK_TOL`) is switched as the event, otherwise
the run fails with the first error.

*Output*: on the requested grid ``t_out`` (IDAS's own interpolation). IDAS's individual steps
are not accessible through ``casadi.integrator``, so ``t_out=None`` (every step) is replaced
by a uniform grid of :data:`DENSE_POINTS` intervals (plus the event instants).

Trade-offs (measurements: ``docs/decisions/019-casadi-idas-backend.md``)
-----------------------------------------------------------------------
* No Python in the integration loop; the default backend steps IDA in C as well (``flexlib/solve/native``),
  so the two cost about the same, and this one needs no C compiler for its loop.
* Every integrator call is a cold IDAS start (``IDAReInit`` + ``IDACalcIC``, order 1, small first
  step). A call covers the output grid up to :data:`MAX_GRID` points, so restarts cost only at events: a state event
  costs the call that passes it plus 3–4 locating calls. CasADi's ``Function`` interface keeps no IDAS memory between
  calls, so a restart after an event cannot be avoided here; the default backend restarts there too.
* Integrator construction (symbolic Jacobian): ~1 ms at 30 unknowns, ~10 ms at 300, ~80 ms at
  3000, per grid size and options, once per process.
* A failing integrator call raises inside CasADi without partial results. The failing call is
  therefore halved and retried until its first half succeeds (those rows are kept and the run
  goes on from there) or a single output interval fails: a failed run keeps every output up to
  within one output interval of the failure (at the cost of about ``log2(K)`` repeated
  integrations up to the failure point, ``K`` the points of the call).
* Every relation switch is an event, also in a sliding mode: the thermostat of
  ``tests/test_engine_events.py`` (heater off above 295 K, but cooling below it at once) stops
  with "event chattering" here, where the default backend misses the immediate re-crossing and
  keeps the heater off below 295 K.
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

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import SolverError
from flexlib.solve.backends.base import absolute_tolerances
from flexlib.solve.casadi_dae import compiled_residual, fill_reducing_order, unknowns_from_xz
from flexlib.solve.signals import interrupted

__all__ = ["DENSE_POINTS", "DETECT_POINTS", "EVENT_TOL", "FIRST_CHUNK", "LINEAR_SOLVER", "MAX_GRID", "RETRY_STEPS",
           "START_VARIANTS", "STUCK_TOL", "SUB_GRID", "USE_LIBRARY", "Runner", "backend", "call_grid"]

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
#: IDAS steps per output interval allowed in the retries after a failed call.
RETRY_STEPS = 500
#: An indicator within this (relative) distance of zero where IDAS cannot proceed is taken as an event.
STUCK_TOL = 1e-6
#: Start variants tried in turn when an integrator call fails (:meth:`_Backend.integrator`): the same call is
#: repeated without ``IDACalcIC``, then with the derivatives ``w`` in the error test (a short call with a fine grid
#: at an end-stop contact can fail its first step after ``IDACalcIC``; ``docs/decisions/019-casadi-idas-backend.md``).
START_VARIANTS = (0, 1, 2)
#: Integrators kept per model (one per grid size and options).
MAX_INTEGRATORS = 64
_CACHE_KEY = "casadi_idas"
#: Evaluate the model's compiled library (generated C) where it has one; False: CasADi's SX virtual machine
#: (for benchmarks comparing the two; the choice is made when a model's integrators are first built).
USE_LIBRARY = True
#: CasADi linear solver plugin of the integrators (see the measurements in the module docstring).
LINEAR_SOLVER = "csparse"


@dataclass
class _Backend:
    """Per-model CasADi objects: the normalised-time DAE and the integrators built from it."""

    dae: dict[str, Any]
    x_idx: np.ndarray  # y entries that are x (after T), in x order
    z_idx: np.ndarray  # y entries of z, in z order: y' of a differential entry (w) or y of an algebraic one
    z_w: np.ndarray  # True where the z entry is a derivative w (of a differential y entry)
    model: CompiledModel
    integrators: dict[tuple, ca.Function] = field(default_factory=dict)
    ind_maps: dict[int, ca.Function] = field(default_factory=dict)
    build_time: float = 0.0
    compiled: bool = False  # the residual is the compiled library's (else CasADi's SX virtual machine)
    want_c: bool = False  # C was available when this backend was built (rebuilt when that changes)

    @property
    def nd(self) -> int:
        return len(self.x_idx)

    def integrator(self, K: int, rtol: float, atol: float, capped: bool, max_num_steps: int,
                   variant: int = 0, max_order: int = 5, error_test_all: bool | None = None) -> ca.Function:
        """Integrator over the normalised grid ``τ = 1..K`` (built once per options and ``K``).

        ``variant`` 0 is the ordinary start (``IDACalcIC`` for consistent ``z`` and ``dx/dτ``, ``w`` outside
        the error test); the fall-backs for a call that fails (see :data:`START_VARIANTS`) are 1: no
        ``IDACalcIC`` (the given ``y, y'`` are consistent already), 2: ``w`` in the error test with
        ``atol·nominal`` per second. ``error_test_all``: :func:`~flexlib.solve.backends.base.absolute_tolerances`'s.
        """
        tol = absolute_tolerances(self.model, atol, error_test_all)
        key = (K, float(rtol), float(atol), bool(capped), int(max_num_steps), int(variant), int(max_order),
               tol.tobytes())
        F = self.integrators.get(key)
        if F is None:
            wall = _time.perf_counter()
            w_tol = tol[self.z_idx] if variant == 2 else np.full(len(self.z_idx), 1e10)
            abstolv = np.concatenate([[atol], tol[self.x_idx], np.where(self.z_w, w_tol, tol[self.z_idx])])
            opts: dict[str, Any] = {
                "linear_solver": LINEAR_SOLVER, "reltol": float(rtol), "abstol": float(atol),
                "abstolv": abstolv.tolist(), "max_num_steps": int(max_num_steps),
                "disable_internal_warnings": True, "show_eval_warnings": False, "calc_ic": variant != 1,
                "max_order": float(max_order),
            }
            if capped:
                opts["max_step_size"] = 1.0  # one grid interval; the grid is refined to max_step
            F = ca.integrator("flexlib_idas", "idas", self.dae, 0.0, [float(k) for k in range(1, K + 1)], opts)
            if len(self.integrators) >= MAX_INTEGRATORS:  # bounded cache: drop the oldest
                self.integrators.pop(next(iter(self.integrators)))
            self.integrators[key] = F
            self.build_time += _time.perf_counter() - wall
        return F


def backend(model: CompiledModel) -> _Backend:
    be = model._functions.get(_CACHE_KEY)
    want_c = USE_LIBRARY and (model.library is not None or bool(getattr(model, "c_ready", lambda: False)()))
    if be is not None and be.want_c != want_c:
        be = None  # C has become available (gcc finished in the background), or the choice was switched
    if be is None:
        be = _build_backend(model)
        be.want_c = want_c
        model._functions[_CACHE_KEY] = be  # type: ignore[assignment]
    return be


def _build_backend(model: CompiledModel) -> _Backend:
    wall = _time.perf_counter()
    res = compiled_residual(model) if USE_LIBRARY else None
    sym: Any = ca.SX if res is None else ca.MX
    if res is None:
        res = model.sx_function("res") if hasattr(model, "sx_function") else model.function("res")
    sx = model.sx_function("res") if hasattr(model, "sx_function") else model.function("res")
    x_idx, z_idx, z_w, rows = fill_reducing_order(model, sx)
    nd, nz = len(x_idx), len(z_idx)
    T, tau, u = sym.sym("T"), sym.sym("tau"), sym.sym("u")
    xd, z = sym.sym("x", nd), sym.sym("z", nz)
    p = sym.sym("p", model.n_params + model.n_relations)
    y, yp, w = unknowns_from_xz(model.n, x_idx, z_idx, z_w, xd, z, sym)
    F = res(T, y, yp, p)
    F = F[[int(r) for r in rows]] if model.n else F
    dae = {"t": tau, "x": ca.vertcat(T, xd), "z": z, "p": p, "u": u, "ode": ca.vertcat(u, u * w), "alg": F}
    be = _Backend(dae=dae, x_idx=x_idx, z_idx=z_idx, z_w=z_w, model=model, compiled=sym is ca.MX)
    be.build_time = _time.perf_counter() - wall
    return be


_BUFFERS: dict[int, tuple[Any, Any, ca.Function, dict[str, float]]] = {}
_COUNTERS = ("n_call_daeF", "n_call_jacF")


def _evaluate(f: ca.Function, args: list[np.ndarray]) -> tuple[list[np.ndarray], dict[str, Any]]:
    """``f(*args)`` through a FunctionBuffer kept per function: dense inputs and outputs are read and written
    straight from and into numpy arrays, without converting ``DM`` results (``docs/decisions/019-*``). Raises
    ``RuntimeError`` as the ordinary call does.

    Returns the outputs (2-D arrays, rows × columns) and the statistics of this call (the buffer's call
    counters ``n_call_*`` accumulate over its lifetime: the differences are returned).
    """
    entry = _BUFFERS.get(id(f))
    if entry is None or entry[2] is not f:
        buf, ev = f.buffer()
        entry = _BUFFERS[id(f)] = (buf, ev, f, {})
        if len(_BUFFERS) > 4 * MAX_INTEGRATORS:
            _BUFFERS.pop(next(iter(_BUFFERS)))
    buf, ev, _, last = entry
    keep = []
    for i, a in enumerate(args):
        col_major = np.ascontiguousarray(np.asarray(a, dtype=float).reshape(f.size_in(i), order="F").T)
        keep.append(col_major)
        buf.set_arg(i, memoryview(col_major.ravel()))
    outs = []
    for i in range(f.n_out()):
        r, c = f.size_out(i)
        o = np.empty((c, r))
        buf.set_res(i, memoryview(o.ravel()))
        outs.append(o)
    ev()
    st = dict(buf.stats())
    for k in _COUNTERS:
        if k in st:
            total = st[k]
            st[k] = total - last.get(k, 0)
            last[k] = total
    return [o.T for o in outs], st


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


class Runner:
    """One run: calls the cached integrators, converts their output, counts statistics."""

    def __init__(self, model: CompiledModel, be: _Backend, p: np.ndarray, stats: dict[str, Any], rtol: float,
                 atol: float, capped: bool, max_steps: int, state_rel: np.ndarray, max_order: int = 5,
                 error_test_all: bool | None = None) -> None:
        self.model, self.be, self.p, self.stats = model, be, p, stats
        self.error_test_all = error_test_all
        self.max_order = int(max_order)
        self.rtol, self.atol, self.capped = rtol, atol, capped
        self.max_steps = max_steps
        self.mns = int(min(max_steps, 100_000))  # IDAS steps per output interval
        self.state_rel = state_rel
        self.n_par = model.n_params
        self.strict = np.array([model.relations[k].strict for k in state_rel], dtype=bool)
        self.ind = model.function("ind")
        self.chunk_cap = max(1, min(MAX_GRID, MAX_FLOATS // max(1, 2 * model.n + 1)))

    def run(self, t: float, y: np.ndarray, yp: np.ndarray, grid: np.ndarray,
            steps: np.ndarray | None = None, budget: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Integrate from ``(t, y, yp)`` through the increasing times ``grid``; returns ``Y, YP`` (n × K).

        ``steps`` are the interval lengths (default: differences of the grid, with round-off removed);
        ``budget`` limits the IDAS steps per output interval (default: ``min(max_steps, 100000)``).
        """
        be = self.be
        mns = self.mns if budget is None else min(self.mns, budget)
        u = (_snap(np.diff(np.concatenate([[t], grid])), t) if steps is None else steps)[None, :]
        x0 = np.concatenate([[t], y[be.x_idx]])
        z0 = np.where(be.z_w, yp[be.z_idx], y[be.z_idx])
        first: RuntimeError | None = None
        for variant in START_VARIANTS:
            F = be.integrator(len(grid), self.rtol, self.atol, self.capped, mns, variant, self.max_order,
                              self.error_test_all)
            self.stats["integrator_calls"] += 1
            try:
                (X, Z, *_), st = _evaluate(F, [x0, z0, self.p, u])
            except RuntimeError as err:
                if interrupted():  # Ctrl-C / SIGTERM inside IDAS: its residual failed on the KeyboardInterrupt
                    raise KeyboardInterrupt from None
                if "IDA_TOO_MUCH_WORK" in str(err):
                    first = err
                    break
                first = first or err
                continue
            # (a failed call's statistics are not available: its work is not counted)
            self.stats["steps"] += int(st.get("nsteps", 0))
            self.stats["nfev"] += int(st.get("n_call_daeF", 0))
            self.stats["njev"] += int(st.get("n_call_jacF", 0))
            if variant:
                self.stats["fallback_calls"] = self.stats.get("fallback_calls", 0) + 1
            first = None
            break
        if first is not None:
            text = str(first)
            if "IDA_TOO_MUCH_WORK" in text and mns >= self.max_steps:
                raise SolverError(f"maximum number of steps ({self.max_steps}) reached between t = {t:.10g} s "
                                  f"and t = {grid[-1]:.10g} s") from first
            flag = re.search(r"IDA_[A-Z_]+", text)
            short = flag.group(0) if flag else text.strip().splitlines()[-1] if text.strip() else "error"
            raise SolverError(f"CasADi IDAS failed between t = {t:.10g} s and t = {grid[-1]:.10g} s "
                              f"({short})") from first
        n, K = self.model.n, len(grid)
        Y, YP = np.empty((n, K)), np.zeros((n, K))
        Y[be.x_idx] = X[1:]
        Y[be.z_idx[~be.z_w]] = Z[~be.z_w]
        YP[be.z_idx[be.z_w]] = Z[be.z_w]
        return Y, YP

    def indicators(self, grid: np.ndarray, Y: np.ndarray, YP: np.ndarray) -> np.ndarray:
        """Indicators of the state relations at the grid columns (relations × columns)."""
        K = len(grid)
        f = self.be.ind_maps.get(K)
        if f is None:  # the parameters are shared by the K columns (reduce_in)
            f = self.be.ind_maps[K] = self.ind.map(f"ind_{K}", "serial", K, [3], [])
        (Zi,), _ = _evaluate(f, [np.asarray(grid)[None, :], Y, YP, self.p])
        return Zi.reshape(-1, K)[self.state_rel]

    def first_switch(self, Zi: np.ndarray) -> tuple[int, list[tuple[int, bool]]]:
        """First column of ``Zi`` where a state relation changes value, and the relations switching there."""
        new = np.where(self.strict[:, None], Zi > 0.0, Zi >= 0.0)
        cur = self.p[self.n_par + self.state_rel][:, None] != 0.0
        hit = np.flatnonzero(np.any(new != cur, axis=0))
        if not len(hit):
            return -1, []
        j = int(hit[0])
        return j, [(int(k), bool(v)) for k, v, c in zip(self.state_rel, new[:, j], cur[:, 0], strict=True) if v != c]

    def locate(self, a: tuple[float, np.ndarray, np.ndarray], b: tuple[float, np.ndarray, np.ndarray],
               triggered: list[tuple[int, bool]]) -> tuple[float, np.ndarray, np.ndarray, list[tuple[int, bool]]]:
        """Narrow the bracket ``(a, b]`` (time, y, y') of a state event by re-running the integrator from ``a``.

        Each call has a uniform sub-grid of ``SUB_GRID`` points (uniform: a change of the interval
        length ``u`` would stop IDAS and break its step history) and keeps the first sub-interval
        where a relation switches, so the earliest of several crossings is found; about
        ``log(width/tol)/log(SUB_GRID)`` calls (a non-uniform ``u``, such as points clustered around a
        secant estimate, costs far more steps per call than a uniform one).
        Returns the event time (the first point where a relation has switched), the state there
        and the switching relations.
        """
        ta, ya, ypa = a
        tb, yb, ypb = b
        tol = EVENT_TOL * max(1.0, abs(tb))
        while tb - ta > tol:
            m = max(2, min(SUB_GRID, self.chunk_cap))
            h = (tb - ta) / m
            grid = ta + h * np.arange(1, m + 1)
            grid[-1] = tb
            steps = np.full(m, h)
            Y, YP = self.run(ta, ya, ypa, grid, steps)
            Zi = self.indicators(grid, Y, YP)
            j, trig = self.first_switch(Zi)
            if j < 0:  # the re-run does not switch at all (noise at the tolerance level): keep b
                break
            if j > 0:
                ta, ya, ypa = float(grid[j - 1]), Y[:, j - 1], YP[:, j - 1]
            tb, yb, ypb, triggered = float(grid[j]), Y[:, j], YP[:, j], trig
        return tb, yb, ypb, triggered

    def stuck(self, t: float, y: np.ndarray, yp: np.ndarray,
              t1: float) -> tuple[float, np.ndarray, np.ndarray, list[tuple[int, bool]]] | None:
        """After IDAS failed on ``(t, t1]``, bisect for the last time it can reach.

        A relation that switches before that point is an ordinary event (located as usual). If
        none does but a state-relation indicator is ~0 where IDAS gets stuck (e.g. ``sqrt(1 - x)``
        in the branch of ``if_else(x < 1, …)``, evaluated with the relation frozen), that relation
        is switched there. Returns None (a genuine failure) otherwise.
        """
        z0 = self.indicators(np.array([t]), y[:, None], yp[:, None])[:, 0]
        lo, ylo, yplo, hi = t, y, yp, t1
        tol = EVENT_TOL * max(1.0, abs(t1))
        while hi - lo > tol:
            mid = 0.5 * (lo + hi)
            try:
                Y, YP = self.run(lo, ylo, yplo, np.array([mid]), budget=RETRY_STEPS)
            except SolverError:
                hi = mid
                continue
            j, trig = self.first_switch(self.indicators(np.array([mid]), Y, YP))
            if j == 0:
                return self.locate((lo, ylo, yplo), (mid, Y[:, 0], YP[:, 0]), trig)
            lo, ylo, yplo = mid, Y[:, 0], YP[:, 0]
        z = self.indicators(np.array([lo]), ylo[:, None], yplo[:, None])[:, 0]
        scale = np.maximum(np.abs(z0), 1.0)
        k = int(np.argmin(np.abs(z) / scale))
        if lo == t or abs(z[k]) > STUCK_TOL * scale[k]:
            return None
        rel = int(self.state_rel[k])
        return lo, ylo, yplo, [(rel, not bool(self.p[self.n_par + rel]))]


def call_grid(t: float, req: np.ndarray, t_seg: float, spacing: float, cap: int) -> np.ndarray:
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
