"""The front door: ``Simulation(model).run()``.

``Simulation`` runs stages 1–5 once (or loads them from the disk cache) and then any number
of runs with different parameters, tolerances and end times, without recompiling.
"""

from __future__ import annotations

import difflib
import hashlib
import os
import platform
import tempfile
import time as _time
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.cache import build, cache_dir, gather_values
from flexlib.compile.codegen import CompiledModel
from flexlib.compile.index_reduction import IndexReport
from flexlib.core.component import Component
from flexlib.core.variables import Parameter
from flexlib.errors import InitializationError, ParameterError, SolverError
from flexlib.results.result import Result
from flexlib.solve.ida import Trajectory, check_assertions, integrate
from flexlib.solve.initialization import Initializer

__all__ = ["Experiment", "Simulation"]


@dataclass(frozen=True)
class Experiment:
    """Default run settings of a model class (Modelica ``experiment`` annotation).

    Parameters
    ----------
    t_end : float
        End time [s].
    dt_out : float or None
        Output interval [s]; None records every solver step.
    rtol, atol : float
        Tolerances.
    t_start : float
        Start time [s].
    """

    t_end: float = 1.0
    dt_out: float | None = None
    rtol: float = 1e-6
    atol: float = 1e-8
    t_start: float = 0.0


class Simulation:
    """Compile a model once and run it.

    Parameters
    ----------
    model : Component
        The top-level model instance.
    codegen : bool or "auto"
        Generate C code for the residual and Jacobian (``"auto"``: above 300 unknowns, compiled in
        the background while runs start on the SX virtual machine; see ``flexlib.compile.codegen``).
    use_cache : bool
        Use the disk cache (``$FLEXLIB_CACHE_DIR``, default ``~/.cache/flexlib``).

    Examples
    --------
    >>> sim = Simulation(model)                      # doctest: +SKIP
    >>> res = sim.run(2.0, dt_out=0.01)              # doctest: +SKIP
    >>> res2 = sim.run(2.0, params={"mass.m": 2.0})  # no recompile   # doctest: +SKIP
    """

    def __init__(self, model: Component, *, codegen: bool | str = "auto", use_cache: bool = True) -> None:
        if not isinstance(model, Component):
            raise TypeError(f"Simulation expects a flexlib Component, got {type(model).__name__}")
        self.model = model
        self.compiled: CompiledModel
        self.compiled, self.build_info = build(model, codegen=codegen, use_cache=use_cache)
        self.initializer = Initializer(self.compiled)
        self._param_index = {n: k for k, n in enumerate(self.compiled.param_names)}
        self.init_cached = False
        self._maps: dict[tuple, Any] = {}
        self._state_monitor: Any = None

    @property
    def report(self) -> IndexReport:
        """Index reduction report: differentiated equations, states, dummy derivatives."""
        return self.compiled.report

    @property
    def states(self) -> list[str]:
        """Names of the state variables."""
        return [n for n, d in zip(self.compiled.y_names, self.compiled.differential, strict=True) if d]

    # -- parameters -------------------------------------------------------------------------------
    def parameter_vector(self, params: dict[str, Any] | None = None,
                         values: dict[str, float] | None = None) -> np.ndarray:
        """Parameter values from the model instance, with ``params`` overrides (validated)."""
        if values is None:
            values, _ = gather_values(self.model)
        m = self.compiled
        vec = np.array([values.get(n, d) for n, d in zip(m.param_names, m.param_defaults, strict=True)])
        for name, value in (params or {}).items():
            found = self._find_decl(name)
            if found is None:
                close = difflib.get_close_matches(name, m.param_names, n=3)
                hint = f"; did you mean {', '.join(close)}?" if close else ""
                raise ParameterError(f"unknown parameter {name!r} in model {m.name}{hint}")
            _, decl, elem = found
            if elem is None:  # the whole declaration (scalar or array)
                flat = np.asarray(decl.check(name, value), dtype=float).flatten(order="F")
                for (label, _), v in zip(decl.element_names(name), flat, strict=True):
                    vec[self._param_index[label]] = v
            else:  # one element of an array parameter
                v = float(np.asarray(value, dtype=float))
                if (decl.min is not None and v < decl.min) or (decl.max is not None and v > decl.max) \
                        or not np.isfinite(v):
                    raise ParameterError(f"{name} = {v!r} [{decl.unit}] is outside [{decl.min}, {decl.max}]")
                vec[self._param_index[name]] = v
        return vec

    def _find_decl(self, name: str) -> tuple[Any, Parameter, Any] | None:
        path, _, leaf = name.rpartition(".")
        base = leaf.split("[")[0]
        node = self.model
        for part in path.split(".") if path else []:
            node = node._children.get(part)
            if node is None:
                return None
        decl = node._decls.get(base)
        if not isinstance(decl, Parameter):
            return None
        elem = None if "[" not in leaf else leaf
        if elem is not None and name not in self._param_index:
            return None
        return node, decl, elem

    # -- running -----------------------------------------------------------------------------------
    def run(
        self, t_end: float | None = None, *, t_start: float | None = None, dt_out: float | None = None,
        output_times: np.ndarray | None = None, rtol: float | None = None, atol: float | None = None,
        max_step: float = 0.0, max_steps: int = 5_000_000, params: dict[str, Any] | None = None,
        steady_state: bool = False, progress: bool | None = None, result_file: str | None = None,
        solver: str = "ida", dynamic_states: bool = True,
    ) -> Result:
        """Initialise and integrate.

        Parameters
        ----------
        t_end : float, optional
            End time [s] (default: the model's ``experiment``).
        t_start : float, optional
            Start time [s].
        dt_out : float, optional
            Output interval [s]; without it (and without ``output_times``) every step is recorded.
        output_times : array_like, optional
            Explicit output times [s].
        rtol, atol : float, optional
            Relative and absolute tolerance (``atol`` scaled by each variable's ``nominal``).
        max_step : float
            Maximum step size [s]; 0 means unlimited.
        max_steps : int
            Maximum number of internal steps.
        params : dict, optional
            Parameter overrides ``{"inertia1.J": 2.0}`` for this run (no recompile).
        steady_state : bool
            Initialise with ``der(x) = 0`` for every state without an initial condition of its own.
        progress : bool, optional
            Progress bar (default: shown for runs longer than about 2 s).
        result_file : str, optional
            Write the result to this HDF5 file, also when the run fails or is interrupted.
        solver : {"ida", "casadi-idas"}
            ``"ida"``: SUNDIALS IDA through scikit-sundae (default; every step, progress bar).
            ``"casadi-idas"``: CasADi's built-in IDAS, all in C — faster for small models, same
            results and events (see ``flexlib/solve/casadi_idas.py``).
        dynamic_states : bool
            Re-select the states during the run when the selected dummy-derivative blocks become
            ill-conditioned (default backend only; see ``flexlib/solve/state_selection.py``).

        Returns
        -------
        Result

        Raises
        ------
        SolverError
            The integration failed; ``err.result`` holds the result up to the failure.
        SimulationInterrupted
            Ctrl-C; ``err.result`` holds the result up to the interrupt.
        """
        exp = getattr(self.model, "experiment", None) or Experiment()
        t0 = exp.t_start if t_start is None else float(t_start)
        t1 = exp.t_end if t_end is None else float(t_end)
        if not t1 > t0:
            raise ValueError(f"t_end ({t1}) must be greater than t_start ({t0})")
        dt = dt_out if dt_out is not None else (exp.dt_out if output_times is None and t_end is None else None)
        rtol = exp.rtol if rtol is None else rtol
        atol = exp.atol if atol is None else atol
        if output_times is not None:
            grid = np.asarray(output_times, dtype=float)
        elif dt is not None:
            n = int(np.floor((t1 - t0) / dt + 1e-9))
            grid = t0 + dt * np.arange(n + 1)
            if grid[-1] < t1 - 1e-12 * max(1.0, abs(t1)):
                grid = np.append(grid, t1)
        else:
            grid = None
        m = self.compiled
        values, starts = gather_values(self.model)
        pvec = self.parameter_vector(params, values)
        p = np.concatenate([pvec, np.zeros(m.n_relations)])
        wall = _time.perf_counter()
        y0, yp0 = self._initialize(t0, p, starts, steady_state)
        t_init = _time.perf_counter() - wall
        extra: dict[str, Any] = {}
        if solver == "ida":
            backend = integrate
            if m.has_state_choice and dynamic_states:
                extra["monitor"] = self._monitor()
        elif solver == "casadi-idas":
            from flexlib.solve.casadi_idas import integrate_casadi as backend
        else:
            raise ValueError(f"solver must be 'ida' or 'casadi-idas', got {solver!r}")
        try:
            check_assertions(m, p, t0)
            traj = backend(m, self.initializer, p, y0, yp0, t0, t1, grid, rtol=rtol, atol=atol,
                             max_step=max_step, max_steps=max_steps, progress=progress, **extra)
        except SolverError as err:
            traj = err.result if isinstance(err.result, Trajectory) else Trajectory()
            err.result = self._result(traj, pvec, t_init, rtol, atol)
            if result_file:
                err.result.save(result_file)
            raise
        result = self._result(traj, pvec, t_init, rtol, atol)
        if result_file:
            result.save(result_file)
        return result

    def _monitor(self) -> Any:
        from flexlib.compile.cache import prepare
        from flexlib.compile.flatten import flatten
        from flexlib.compile.index_reduction import reduce_index
        from flexlib.solve.state_selection import StateSelectionMonitor

        if self._state_monitor is None:
            def rebuild() -> Any:
                flat = flatten(self.model)
                params = {q.sym.element_hash(): q.value for q in flat.parameters}
                return reduce_index(prepare(flat, params), params).structure

            self._state_monitor = StateSelectionMonitor(rebuild)
        return self._state_monitor

    def _initialize(self, t0: float, p: np.ndarray, starts: dict, steady: bool) -> tuple[np.ndarray, np.ndarray]:
        """Stage 4, cached on disk by model key, parameters, start values and options."""
        key = self.build_info.get("model_key")
        path = None
        if key:
            h = hashlib.sha256(p.tobytes() + repr((sorted(starts.items()), steady, t0)).encode()).hexdigest()[:24]
            path = cache_dir() / f"{self.compiled.name}-{key}-init-{h}.npz"
            if path.exists():
                try:
                    with np.load(path) as data:
                        p[:] = data["p"]
                        self.init_cached = True
                        return data["y"].copy(), data["yp"].copy()
                except (OSError, KeyError, ValueError):
                    pass
        self.init_cached = False
        y, yp = self._consistent_start(t0, p, starts, steady)
        if path is not None:
            fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".npz")
            os.close(fd)
            np.savez(tmp, y=y, yp=yp, p=p)
            os.replace(tmp, path)
        return y, yp

    def _consistent_start(self, t0: float, p: np.ndarray, starts: dict, steady: bool) -> tuple[np.ndarray, np.ndarray]:
        m = self.compiled
        n_par = m.n_params
        y, yp = self.initializer.guess(starts), np.zeros(m.n)
        if m.n_relations:
            ind = m.function("ind")
            z = np.asarray(ind(t0, y, yp, p)).ravel()
            ab = np.asarray(m.function("tev")(p)).reshape(-1, 2)
            for k, rel in enumerate(m.relations):
                if rel.time_event and z[k] == 0.0:
                    p[n_par + k] = float(ab[k, 0] > 0)
                else:
                    p[n_par + k] = float(rel.value(z[k]))
        failed: InitializationError | None = None
        for _ in range(20):
            try:
                y, yp = self.initializer.initial(t0, p, starts, steady)
                failed = None
            except InitializationError as err:
                failed = err
                # no solution with these relation values: re-evaluate the relations at the best point
                # found (the start guesses may lie on the wrong side of a limiter) and try again
                point = getattr(err, "point", None)
                if not m.n_relations or point is None:
                    raise
                z = np.asarray(m.function("ind")(t0, point[0], point[1], p)).ravel()
                flipped = False
                for k, rel in enumerate(m.relations):
                    v = float(rel.value(z[k]))
                    if not rel.time_event and v != p[n_par + k]:
                        p[n_par + k], flipped = v, True
                if not flipped:
                    return self._start_by_flipping(t0, p, starts, steady, err)
                continue
            if not m.n_relations:
                break
            z = np.asarray(m.function("ind")(t0, y, yp, p)).ravel()
            changed = False
            for k, rel in enumerate(m.relations):
                if rel.time_event:
                    continue
                v = float(rel.value(z[k]))
                if v != p[n_par + k]:
                    p[n_par + k], changed = v, True
            if not changed:
                break
        if failed is not None:
            raise failed
        return y, yp

    def _start_by_flipping(self, t0: float, p: np.ndarray, starts: dict, steady: bool,
                           err: InitializationError, most: int = 16) -> tuple[np.ndarray, np.ndarray]:
        """Try the start with one state relation switched at a time (a start guess on the wrong side of a
        limiter gives a branch without solution); accept a switch whose solution agrees with it."""
        m = self.compiled
        n_par = m.n_params
        state_rel = [k for k, rel in enumerate(m.relations) if not rel.time_event][:most]
        for k in state_rel:
            trial = p.copy()
            trial[n_par + k] = 1.0 - trial[n_par + k]
            try:
                y, yp = self.initializer.initial(t0, trial, starts, steady)
            except InitializationError:
                continue
            z = np.asarray(m.function("ind")(t0, y, yp, trial)).ravel()
            if all(float(m.relations[j].value(z[j])) == trial[n_par + j] for j in state_rel):
                p[:] = trial
                return y, yp
        raise err

    #: rows per call of the mapped output function in :meth:`_assemble`
    _CHUNK = 256

    def _assemble(self, model: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                  P: np.ndarray) -> np.ndarray:
        """All variables (aliases and outputs rebuilt by the ``out`` function) for rows ``T, Y, YP, P``.

        Evaluated through FunctionBuffers straight into a preallocated C-ordered buffer: ``out``
        mapped over ``_CHUNK`` rows per call (row-major stacks of rows are exactly the column-major
        matrices the map takes, so no copy or conversion), the remainder row by row. 18–40× cheaper
        than one DM call of ``out.map(len(rows))`` (measured in ``benchmarks/engine_speed.py``).
        """
        n_rows = len(T)
        out_fn = model.function("out")
        if not out_fn.sparsity_out(0).is_dense():  # structural zeros: the buffer needs every entry
            key = (id(model), "dense")
            entry = self._maps.get(key)
            if entry is None or entry[0] is not model:
                args = out_fn.sx_in()
                entry = self._maps[key] = (model, ca.Function("flexlib_out_dense", args,
                                                              [ca.densify(out_fn(*args))]))
            out_fn = entry[1]
        n_out = out_fn.nnz_out(0)
        values = np.zeros((n_rows, n_out))
        T = np.ascontiguousarray(T, dtype=float)
        chunk = self._CHUNK
        full = n_rows // chunk * chunk
        if full:
            key = (id(model), "map", chunk)
            entry = self._maps.get(key)
            if entry is None or entry[0] is not model:
                entry = self._maps[key] = (model, out_fn.map(chunk).buffer())
            buf, ev = entry[1]
            for a in range(0, full, chunk):
                b = a + chunk
                buf.set_arg(0, memoryview(T[a:b]))
                buf.set_arg(1, memoryview(Y[a:b]))
                buf.set_arg(2, memoryview(YP[a:b]))
                buf.set_arg(3, memoryview(P[a:b]))
                buf.set_res(0, memoryview(values[a:b]))
                ev()
        if full < n_rows:
            key = (id(model), "row")
            entry = self._maps.get(key)
            if entry is None or entry[0] is not model:
                entry = self._maps[key] = (model, out_fn.buffer())
            buf, ev = entry[1]
            for i in range(full, n_rows):
                buf.set_arg(0, memoryview(T[i:i + 1]))
                buf.set_arg(1, memoryview(Y[i]))
                buf.set_arg(2, memoryview(YP[i]))
                buf.set_arg(3, memoryview(P[i]))
                buf.set_res(0, memoryview(values[i]))
                ev()
        return values

    def _result(self, traj: Trajectory, pvec: np.ndarray, t_init: float, rtol: float, atol: float) -> Result:
        m = self.compiled
        names = [v.name for v in m.variables]
        if traj.t:
            T = np.array(traj.t)
            values = np.zeros((len(T), len(names)))
            seg = np.array(traj.seg) if traj.seg else np.zeros(len(T), dtype=int)
            rel = np.array(traj.rel, dtype=float).reshape(len(T), m.n_relations)
            for k in np.unique(seg):
                rows = np.flatnonzero(seg == k)
                model = traj.models[k] if traj.models else m
                Y = np.array([traj.y[i] for i in rows], dtype=float).reshape(len(rows), model.n)
                YP = np.array([traj.yp[i] for i in rows], dtype=float).reshape(len(rows), model.n)
                P = np.empty((len(rows), len(pvec) + m.n_relations))
                P[:, :len(pvec)] = pvec
                P[:, len(pvec):] = rel[rows]
                values[rows] = self._assemble(model, T[rows], Y, YP, P)
        else:
            T, values = np.zeros(0), np.zeros((0, len(names)))
        stats = dict(traj.stats)
        stats.update({"wall_init": t_init, "rtol": rtol, "atol": atol, "n_states": int(m.differential.sum()),
                      "n_unknowns": m.n, "build_cached": bool(self.build_info.get("cached")),
                      "wall_build": float(self.build_info.get("total", 0.0))})
        import casadi
        import sksundae

        from flexlib import __version__

        meta = {"flexlib": __version__, "casadi": casadi.__version__, "scikit-sundae": sksundae.__version__,
                "numpy": np.__version__, "python": platform.python_version(),
                "created": _time.strftime("%Y-%m-%dT%H:%M:%S")}
        return Result(
            model=m.name, t=T, names=names, values=values, units=[v.unit for v in m.variables],
            docs=[v.doc for v in m.variables], kinds=[v.kind for v in m.variables],
            parameters={n: (float(v), u) for n, v, u in zip(m.param_names, pvec, m.param_units, strict=True)},
            stats=stats, status=traj.status, message=traj.message, events=list(traj.events),
            index_report=str(m.report), metadata=meta,
        )
