"""SUNDIALS IDA driven from C (``solver="ida-native"``, the default ``"ida"`` where the driver builds).

The step loop runs in C (``flexlib/solve/native/ida_driver.c``): the same SUNDIALS 7.9 IDA that scikit-sundae
bundles, with the residual, the iteration matrix (CSC nonzeros; the linear solver by :func:`linear_solver`: dense LU
up to :data:`KLU_MIN` unknowns, KLU above) and the event indicators evaluated in C — the model's generated library
when it has one, CasADi's SX virtual machine through its C API otherwise. No Python runs per residual, Jacobian or
step. One :meth:`IdaC.advance` runs many steps and returns to the run loop only

* when a chunk of output rows is ready (IDA's own interpolation onto the output grid, or every internal step when
  there is no grid), copied from a buffer in one block;
* at time events (IDA's ``tstop``) and state events (IDA's root finding);
* every :data:`CHUNK_STEPS` steps or :data:`CHUNK_WALL` seconds (progress, ``max_steps``, Ctrl-C/SIGTERM), or
  when the state-selection monitor's schedule (:class:`~flexlib.solve.backends.base.Limits`) says a check is due.

At a failure the message names the unknowns with the largest weighted local error estimates
(``IDAGetEstLocalErrors`` × ``IDAGetErrWeights``). ``stats`` gains the split of the integration wall time:
``wall_model`` (residual, Jacobian and indicator evaluations; also ``wall_res``, ``wall_jac``, ``wall_root``),
``wall_ida`` (the rest of the C step loop: IDA, linear algebra, interpolation) and ``wall_python``.
"""

from __future__ import annotations

import time as _time
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.environment import env_default
from flexlib.errors import RunArgumentError
from flexlib.solve.backends.base import DENSE_MAX, NEWTON_ITERS, Limits, Stop, absolute_tolerances
from flexlib.solve.events import off_zero, watched_relations
from flexlib.solve.native import (
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

__all__ = ["CHUNK_STEPS", "CHUNK_WALL", "KLU_MIN", "RECOVERABLE", "IdaC", "indicator_function", "linear_solver",
           "make_driver", "zc_function"]

#: IDA failures after which the run restarts from the last accepted point (``IDA_ERR_FAIL``, ``IDA_CONV_FAIL``)
RECOVERABLE = {-3: "IDA_ERR_FAIL", -4: "IDA_CONV_FAIL"}
#: Up to this many unknowns the driver factorises dense (SUNDIALS dense LU); above, KLU when installed
KLU_MIN = 40
#: The C loop returns to Python at least every this many steps (progress bar, Ctrl-C, ``max_steps``)
CHUNK_STEPS = 256
#: ... and after this much wall time [s] (a signal that arrives during C steps takes effect when the block returns)
CHUNK_WALL = 0.05
#: Output rows buffered in C before Python copies them (per driver, at most ~8 MB per array).
ROW_BUFFER_VALUES = 1_000_000


class IdaC:
    """The C driver behind :class:`~flexlib.solve.backends.base.Integrator` (options as ``IDA``'s)."""

    name = "ida-native"
    watch_steps = 2
    settles_roots = True
    monitors = True
    error_test_all: bool | None = None

    def __init__(self, rtol: float = 1e-6, atol: float = 1e-8, max_step: float = 0.0, max_order: int = 5,
                 linear_solver: str | None = None) -> None:
        self.rtol, self.atol, self.max_step, self.max_order = rtol, atol, max_step, int(max_order)
        self.linsol = linear_solver
        self.drv: Driver | None = None
        self.retired: list[dict[str, float]] = []  # counters of drivers replaced at state switches
        self.extra: dict[str, Any] = {}
        self.clock = _time.thread_time if cpu_clock() else _time.perf_counter  # the clock the driver times with

    @property
    def progress_every(self) -> int:
        return CHUNK_STEPS

    def start(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
              grid: np.ndarray | None, t_end: float) -> None:
        if p.dtype != np.float64 or not p.flags.c_contiguous:
            raise TypeError("ida-native: p must be a C-contiguous float64 array (updated in place)")
        first = self.drv is None
        if not first:  # a state switch: the grid goes on where the old driver stood
            pos = self.drv.grid_pos()
            self.retired.append(self.drv.stats())
            grid = None if self.grid is None else np.ascontiguousarray(self.grid[pos:])
        self.model, self.p, self.grid = model, p, grid
        self.drv, self.state_rel = make_driver(model, p, self.rtol, self.atol, self.max_step, t, y, yp,
                                               self.max_order, self.linsol, self.error_test_all)
        self.drv.set_grid(grid)
        self.limits = (np.inf, 0.0)
        if first:
            cap = max(16, ROW_BUFFER_VALUES // max(model.n, 1))
            if grid is not None:
                cap = max(1, min(cap, len(grid)))
            self.T = np.empty(cap)
        self.Y, self.YP = np.empty((len(self.T), model.n)), np.empty((len(self.T), model.n))
        self.pending_c = first and model.library_pending is not None  # C compiled in the background
        self.extra["linear_solver"] = self.drv.linsol

    def advance(self, t_stop: float, limits: Limits) -> Stop:
        drv = self.drv
        if (limits.t_check, limits.h_min) != self.limits:
            self.limits = (limits.t_check, limits.h_min)
            drv.set_limits(*self.limits)
        code, k, t, nsteps = drv.advance(t_stop, min(limits.steps, CHUNK_STEPS), self.T, self.Y, self.YP)
        rows = (self.T[:k].tolist(), list(self.Y[:k].copy()), list(self.YP[:k].copy())) if k else None
        if self.pending_c and self.model.c_ready():
            # the background gcc has finished: the residual and Jacobian are evaluated by the compiled library
            # from the next step on, without a restart (the same operations in the same order as the SX
            # virtual machine, so the trajectory does not change)
            self.pending_c = False
            drv.rebind(evaluators(self.model, zc_function(self.model, self.p, self.state_rel)))
            self.extra["compiled_at"] = t
        return self.stop(code, t, nsteps, rows)

    def stop(self, code: int, t: float, nsteps: int, rows: Any) -> Stop:
        """The :class:`Stop` of the driver's return ``code`` at ``t`` after ``nsteps`` steps with ``rows``."""
        if code < 0:
            kind = "recover" if code in RECOVERABLE else "failed"
            return Stop(kind, t, nsteps, rows, message=self.failure_head(code, t), flag=RECOVERABLE.get(code, ""))
        if code == FD_TINY:
            return Stop("failed", t, nsteps, rows, message=f"IDA step size underflow at t = {t:.10g} s (the model "
                        "may be stiff beyond repair, or discontinuous without an event)" + self.dominant())
        if code == FD_ROOT:
            info = self.drv.roots()
            roots = [(int(self.state_rel[j]), bool(info[j] > 0)) for j in np.flatnonzero(info)]
            return Stop("root", t, nsteps, rows, roots=roots)
        kind = "full" if code == FD_FULL else "tstop" if code == FD_TSTOP else "step"
        return Stop(kind, t, nsteps, rows)

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        self.drv.reinit(t, y, yp)

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.drv.state()

    def accepted(self) -> tuple[float, Any, Any] | None:
        if self.drv is None:
            return None
        _, t_now = self.drv.last_advance()
        return (t_now, *self.drv.state())

    def unsaved_rows(self) -> tuple[list[float], list[np.ndarray], list[np.ndarray]]:
        rows, _ = self.drv.last_advance() if self.drv is not None else (0, 0.0)
        n = min(rows, len(self.T)) if self.drv is not None else 0
        return [float(v) for v in self.T[:n]], list(self.Y[:n]), list(self.YP[:n])

    def last_step(self) -> float:
        return self.drv.last_step()

    def stats(self, wall: float) -> dict[str, Any]:
        """Evaluation counts and the wall-time split (model / IDA / Python) over all drivers of the run."""
        parts = [*self.retired, self.drv.stats()] if self.drv is not None else list(self.retired)
        out: dict[str, Any] = {"solver": self.name, "max_order": self.max_order, **self.extra}
        for key in ("nfev", "njev", "n_lsetup", "n_lsolve", "n_factor_full", "n_newton", "n_newton_fail",
                    "n_err_fail", "nonfinite"):
            out[key] = sum(int(s[key]) for s in parts)
        total = {key: sum(s[key] for s in parts) for key in ("t_res", "t_jac", "t_root", "t_advance", "t_lsetup",
                                                             "t_lsolve")}
        model_s = total["t_res"] + total["t_jac"] + total["t_root"]
        out.update(wall_model=model_s, wall_res=total["t_res"], wall_jac=total["t_jac"], wall_root=total["t_root"],
                   wall_ida=max(total["t_advance"] - model_s, 0.0), wall_python=max(wall - total["t_advance"], 0.0),
                   wall_lsetup=total["t_lsetup"], wall_lsolve=total["t_lsolve"])
        return out

    def failure_head(self, code: int, t: float) -> str:
        """IDA's failure, with the unknowns whose weighted local error estimates dominate."""
        head = f"IDA failed at t = {t:.10g} s: {self.drv.flag_name(code)} (status {code})" + self.dominant()
        bad = int(self.drv.stats().get("nonfinite", 0))
        if bad:  # IDA counts a non-finite residual at a Newton iterate as a convergence failure
            head += f"; {bad} residual evaluations during the run were not finite (retried with smaller steps)"
        return head

    def dominant(self, top: int = 3) -> str:
        """``"; largest weighted local error estimates: x (…), …"`` from IDA's last step, or ``""``."""
        ewt, ele = self.drv.diagnostics()
        w = np.abs(ewt * ele)
        if not (np.all(np.isfinite(w)) and w.max(initial=0.0) > 0.0):
            return ""
        order = np.argsort(w)[::-1][:top]
        names = ", ".join(f"{self.model.y_names[i]} ({w[i]:.3g})" for i in order if w[i] > 0.0)
        return f"; largest weighted local error estimates: {names}"


def zc_function(model: CompiledModel, p: np.ndarray, state_rel: np.ndarray) -> ca.Function | None:
    """IDA's root functions: the indicators of the relations ``state_rel`` (cached with the evaluators)."""
    if not len(state_rel):
        return None
    cached = model._functions.get("ida_native")
    if cached is not None and cached.get("zc_fn") is not None:
        return cached["zc_fn"]
    return indicator_function(model, len(p), state_rel)


def indicator_function(model: CompiledModel, n_p: int, relations: Any) -> ca.Function:
    """``flexlib_zc(t, y, y', p)``: the indicators of ``relations`` (indices into ``model.relations``), an exact zero
    handed over as ±1e-300 on the side of the relation's value there (:func:`~flexlib.solve.events.off_zero`), so that
    an indicator's sign is its relation's value; ``n_p``: the length of ``p`` (parameters and relation values)."""
    ind = model.sx_function("ind")
    t, y, yp = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
    pp = ca.SX.sym("p", n_p)
    z = ind(t, y, yp, pp)
    return ca.Function("flexlib_zc", [t, y, yp, pp],
                       [ca.vertcat(*[off_zero(z[int(k)], model.relations[int(k)].strict, pp[model.n_params + int(k)])
                                     for k in relations])])


def linear_solver(model: CompiledModel, forced: str | None = None) -> str:
    """The driver's linear solver for ``model``: ``"klu"``, ``"dense"`` or ``"superlumt"``.

    Rule (measured per factorisation and solve on the models' own iteration matrices, ``benchmarks/linear_solvers.py``):
    KLU (BTF + AMD ordering once per driver, then one numeric factorisation with threshold partial pivoting per IDA
    setup) when the model has more than :data:`KLU_MIN` unknowns and kvxopt's KLU is installed; dense LU at or below
    :data:`KLU_MIN` (and up to :data:`~flexlib.solve.backends.base.DENSE_MAX` without KLU); SuperLU_MT (SUNDIALS'
    sparse solver) otherwise. ``forced`` (``IDA(linear_solver=...)``), else its environment default
    ``FLEXLIB_LINSOL=dense|klu|superlumt`` (:func:`flexlib.compile.environment.env_default`), overrides the rule.
    """
    forced = forced or env_default("linear_solver")
    if forced:
        if forced not in LINEAR_SOLVERS:
            raise RunArgumentError(f"linear_solver={forced!r}: expected one of {', '.join(LINEAR_SOLVERS)}")
        return forced
    if model.n <= KLU_MIN:
        return "dense"
    if klu_available():
        return "klu"
    return "dense" if model.n <= DENSE_MAX else "superlumt"


def make_driver(model: CompiledModel, p: np.ndarray, rtol: float, atol: float, max_step: float, t0: float,
                y0: np.ndarray, yp0: np.ndarray, max_order: int = 5, linsol: str | None = None,
                error_test_all: bool | None = None) -> tuple[Driver, np.ndarray]:
    """A C driver for ``model`` (indicators of the state relations as IDA root functions; ``linsol``:
    :func:`linear_solver`'s ``forced``; ``error_test_all``: as for
    :func:`~flexlib.solve.backends.base.absolute_tolerances`)."""
    state_rel = watched_relations(model)
    ev = evaluators(model, zc_function(model, p, state_rel))
    drv = Driver(model, p, ev, len(state_rel), linear_solver(model, linsol), rtol,
                 absolute_tolerances(model, atol, error_test_all),
                 max_step, t0, y0, yp0)
    drv.set_wall_chunk(CHUNK_WALL)
    drv.set_max_order(max_order)
    drv.set_newton(max_iters=NEWTON_ITERS)
    return drv, state_rel
