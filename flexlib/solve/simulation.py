"""The front door: ``Simulation(model).run()``.

``Simulation`` runs stages 1–5 once (or loads them from the disk cache) and then any number
of runs with different parameters, tolerances and end times, without recompiling.
"""

from __future__ import annotations

import copy
import difflib
import hashlib
import math
import os
import platform
import time as _time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.compile import cache
from flexlib.compile.cache import gather_values
from flexlib.compile.codegen import CompiledModel
from flexlib.compile.constants import assumptions_hold, check_assumed
from flexlib.compile.index_reduction import IndexReport
from flexlib.compile.pipeline import Build, build, build_key, check_build_options, check_model
from flexlib.core.component import Component
from flexlib.core.variables import Parameter, numeric_array
from flexlib.errors import (
    ModelError,
    NativeSolverError,
    ParameterError,
    ResultCheckWarning,
    ResultFileError,
    ResultSaveWarning,
    RunArgumentError,
    SimulationInterrupted,
    SolverError,
    StructureChangedError,
)
from flexlib.results.hdf5 import save_result
from flexlib.results.result import Result
from flexlib.solve.build_checks import START_TOL, check_dropped_rows, run_tolerance
from flexlib.solve.events import check_assertions
from flexlib.solve.initialization import Initializer
from flexlib.solve.loop import run_loop
from flexlib.solve.rows import RowEvaluator, segments, settle_derivative_level
from flexlib.solve.run_options import check_params, check_run_arguments
from flexlib.solve.signals import sigterm_as_interrupt
from flexlib.solve.solvers import as_solver
from flexlib.solve.static import integrate_static
from flexlib.solve.trajectory import Trajectory

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
    max_order : int or None
        Highest BDF order of IDA (1–5); None: 5 (:meth:`Simulation.run`).

    Raises
    ------
    RunArgumentError
        An unknown field (Modelica's names ``StopTime``, ``Interval``, ``Tolerance``, ``StartTime`` are named with
        flexlib's). The values are checked when a run uses them, naming the experiment.
    """

    t_end: float = 1.0
    dt_out: float | None = None
    rtol: float = 1e-6
    atol: float = 1e-8
    t_start: float = 0.0
    max_order: int | None = None

    def __new__(cls, *args: Any, **kwargs: Any) -> Experiment:
        unknown = [k for k in kwargs if k not in _EXPERIMENT_FIELDS]
        if unknown:
            name = unknown[0]
            meant = _MODELICA_NAMES.get(name.replace("_", "").lower()) or next(
                iter(difflib.get_close_matches(name, _EXPERIMENT_FIELDS, n=1)), None)
            hint = f" (did you mean {meant}?)" if meant else ""
            raise RunArgumentError(f"Experiment(): unknown field {name!r}{hint}; the fields are "
                                   f"{', '.join(_EXPERIMENT_FIELDS)}")
        return super().__new__(cls)


_EXPERIMENT_FIELDS = ("t_end", "dt_out", "rtol", "atol", "t_start", "max_order")
#: Modelica's ``experiment`` annotation names (and common spellings, lower case without ``_``) -> flexlib's fields.
_MODELICA_NAMES = {"stoptime": "t_end", "tend": "t_end", "tstop": "t_end", "interval": "dt_out", "dt": "dt_out",
                   "tolerance": "rtol", "starttime": "t_start", "tstart": "t_start", "t0": "t_start",
                   "maxorder": "max_order"}


def _span_end(t0: Any) -> Any:
    """A time after ``t0`` by a span the argument check accepts (``t0 + 1``, more for a large ``|t0|``) for a finite
    number; anything else is passed on for the argument check to report."""
    try:
        start = float(t0)
    except (TypeError, ValueError):
        return t0
    return start + max(1.0, 1e-9 * abs(start)) if math.isfinite(start) else start + 1.0


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
    assume_zero_geometry : bool or None
        Treat zero-valued geometry parameters of frame components as the constant 0, which removes the
        out-of-plane unknowns of planar mechanisms (default: yes unless ``FLEXLIB_ZERO_GEOMETRY=0``). A run
        whose ``params`` make one of them non-zero raises :class:`~flexlib.errors.StructureChangedError`
        naming it; pass ``False`` to sweep such a parameter. See :func:`flexlib.build`.

    Raises
    ------
    ModelTypeError
        ``model`` is not a model instance (a model class: ``Simulation(Osc)``; a name); a ``TypeError``.
    RunArgumentError
        ``codegen``, ``use_cache`` or ``assume_zero_geometry`` is not one of its values (``"False"`` is refused,
        not taken as true).

    Attributes
    ----------
    build : Build
        Every stage's product (``sim.build.flat``, ``.simple``, ``.dae`` while in memory; see
        :mod:`flexlib.compile.pipeline`).
    compiled : CompiledModel
        The compiled model (``sim.build.compiled``).
    build_info : dict
        Build timings [s], ``cached`` and ``model_key`` (``sim.build.timings``).

    Examples
    --------
    >>> sim = Simulation(model)                      # doctest: +SKIP
    >>> res = sim.run(2.0, dt_out=0.01)              # doctest: +SKIP
    >>> res2 = sim.run(2.0, params={"mass.m": 2.0})  # no recompile   # doctest: +SKIP
    """

    def __init__(self, model: Component, *, codegen: bool | str = "auto", use_cache: bool = True,
                 assume_zero_geometry: bool | None = None) -> None:
        check_model(model, "Simulation()")
        check_build_options(codegen, use_cache, assume_zero_geometry, "Simulation()")
        codegen = "auto" if isinstance(codegen, str) else bool(codegen)
        self.model = model
        self._codegen = codegen
        self._use_cache = bool(use_cache)
        self.build: Build = build(model, codegen=codegen, use_cache=use_cache,
                                  assume_zero_geometry=assume_zero_geometry)
        self._zero_geometry = self.build.assume_zero_geometry
        self.compiled: CompiledModel = self.build.compiled
        self.build_info: dict[str, Any] = self.build.timings
        self.initializer = Initializer(self.compiled, lambda: self.build.structure(self.model))
        self._param_index = {n: k for k, n in enumerate(self.compiled.param_names)}
        self.init_cached = False
        self._rows = RowEvaluator()
        self._state_monitor: Any = None

    def with_model(self, model: Component) -> Simulation:
        """A Simulation of another instance of the same model, sharing this one's build.

        An instance that differs from this one only in values (start values, parameters: a machine in another
        pose, a sweep over initial conditions) has the same build: the new Simulation shares the compiled model
        and its initialisation functions instead of loading them from the cache again. Whether the structure is
        the same is checked, not assumed (the build's cache key, and the parameter assumptions the build made):
        an instance that differs in structure gets its own build, as ``Simulation(model)`` would give it.

        Parameters
        ----------
        model : Component
            The other instance.

        Returns
        -------
        Simulation

        Raises
        ------
        ModelTypeError
            ``model`` is not a model instance (a model class, a name); a ``TypeError``.
        """
        check_model(model, "Simulation.with_model()")
        options = {"codegen": self._codegen, "assume_zero_geometry": self._zero_geometry}
        key = self.build.key or build_key(self.model, **options)
        same = (type(model) is type(self.model) and build_key(model, **options) == key
                and assumptions_hold(self.compiled.assumed, model))
        if not same:
            return Simulation(model, use_cache=self._use_cache, **options)
        other = copy.copy(self)
        other.model = model
        other.init_cached = False
        other._rows = RowEvaluator()
        other._state_monitor = None
        return other

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
        """Parameter values from the model instance, with ``params`` overrides.

        Each overridden value passes the same checks as a value given to the component's constructor:
        the declared bounds of its parameter and the component's cross-parameter rules
        (:meth:`~flexlib.Component.check`) with the overridden values of that instance. An element
        override (``"body.I[0,0]"``) is checked together with the rest of its array.

        Parameters
        ----------
        params : dict, optional
            Overrides ``{"component.parameter": value}`` (as ``run(params=...)``).
        values : dict, optional
            Parameter values by name to start from (default: the model instance's).

        Returns
        -------
        ndarray
            One value per name of ``sim.compiled.param_names``.

        Raises
        ------
        RunArgumentError
            ``params`` is not a mapping with names (str) as keys, or ``values`` is not a mapping.
        ParameterError
            An unknown name (the message says what the name is instead: a variable, a component, an element of a
            scalar) or a value its declaration refuses.
        """
        params = check_params(params, caller="parameter_vector")
        if values is None:
            values, _ = gather_values(self.model)
        elif not isinstance(values, Mapping):
            raise RunArgumentError(f"parameter_vector(): values = {values!r:.80} is invalid: must be a dict "
                                   f"{{'component.parameter': value}}, got a {type(values).__name__}")
        m = self.compiled
        vec = np.array([values.get(n, d) for n, d in zip(m.param_names, m.param_defaults, strict=True)])
        touched: dict[int, tuple[Any, set[str]]] = {}
        for name, value in params.items():
            found = self._find_decl(name)
            if found is None:
                close = difflib.get_close_matches(name, m.param_names, n=3)
                hint = self._not_a_parameter(name) or (f"; did you mean {', '.join(close)}?" if close else "")
                raise ParameterError(f"unknown parameter {name!r} in model {m.name}{hint}")
            node, decl, elem = found
            decl_name = name.rpartition(".")[2].split("[")[0]
            if elem is None:  # the whole declaration (scalar or array)
                flat = np.asarray(decl.check(name, value), dtype=float).flatten(order="F")
                for (label, _), v in zip(decl.element_names(name), flat, strict=True):
                    vec[self._param_index[label]] = v
            else:  # one element of an array parameter: checked below with the rest of the array
                arr = numeric_array(value, f"{name}: parameter value", f"a real number [{decl.unit}]", ParameterError)
                if arr.ndim:
                    raise ParameterError(f"{name}: parameter value {value!r} is an array; give one element as a real "
                                         f"number [{decl.unit}]")
                vec[self._param_index[name]] = float(arr)
            touched.setdefault(id(node), (node, set()))[1].add(decl_name)
        for node, names in touched.values():
            current: dict[str, np.ndarray] = {}
            for pname, pdecl in node._decls.items():
                if not isinstance(pdecl, Parameter):
                    continue
                labels = [label for label, _ in pdecl.element_names(node._label(pname))]
                if all(label in self._param_index for label in labels):
                    arr = np.array([vec[self._param_index[label]] for label in labels])
                    arr = arr.reshape(pdecl.shape, order="F") if pdecl.shape else arr.reshape(())
                else:  # not a run-time parameter of the compiled model: the instance value holds
                    arr = node.parameter_value(pname)
                if pname in names:
                    arr = pdecl.check(node._label(pname), arr)
                current[pname] = arr
            node.validate(current)
        check_assumed(m.assumed, m.param_names, vec, m.name)
        return vec

    def _node(self, path: str) -> Any:
        """The component at the dotted ``path`` below the model (``""``: the model), or None."""
        node = self.model
        for part in path.split(".") if path else []:
            node = node._children.get(part) if part else None  # "", ".k", "a..k": an empty part names nothing
            if node is None:
                return None
        return node

    def _not_a_parameter(self, name: str) -> str:
        """What ``name`` (not a run-time parameter) is instead, as a hint for the error: a variable, a component,
        an element of a scalar, a name with a stray ``.``; ``""`` otherwise."""
        parts = name.split(".")
        if not all(parts):  # a stray "." (".k", "a..k", "a.k."): the name without the empty parts, if it is one
            joined = ".".join(part for part in parts if part)
            return (f"; the name has an empty part (a stray '.'): did you mean {joined!r}?"
                    if joined in self._param_index else "")
        path, _, leaf = name.rpartition(".")
        base = leaf.split("[")[0]
        node = self._node(path)
        if node is None or not base:
            return ""
        if base in node._children:
            inner = [n for n in self.compiled.param_names if n.startswith(f"{name}.")]
            listed = f" such as {', '.join(inner[:3])}" if inner else ""
            return f"; {name!r} is a component, not a parameter: name one of its parameters{listed}"
        decl = node._decls.get(base)
        if decl is None:
            return ""
        full = f"{path}.{base}" if path else base
        if not isinstance(decl, Parameter):
            return (f"; {full!r} is a {type(decl).__name__.lower()}, not a parameter: its start value is set with "
                    f"init={{{base!r}: ...}} on the component (or set_start), not with params")
        if "[" in leaf and [label for label, _ in decl.element_names(full)] == [full]:
            return f"; {full!r} is a scalar parameter: give {full!r} without an index"
        return ""  # an element outside an array: the close matches name its elements

    def _find_decl(self, name: str) -> tuple[Any, Parameter, Any] | None:
        if not all(name.split(".")):  # ".k", "a..k", "k.": an empty part names nothing
            return None
        path, _, leaf = name.rpartition(".")
        base = leaf.split("[")[0]
        node = self._node(path)
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
    def _experiment(self) -> Experiment:
        """The model's ``experiment`` (Experiment() without one); :class:`~flexlib.errors.ModelError` naming it if it
        is something else (a dict, a number, the class ``Experiment`` itself), which failed with an AttributeError."""
        exp = getattr(self.model, "experiment", None)
        if exp is None:
            return Experiment()
        if not isinstance(exp, Experiment):
            shown = " ".join(repr(exp).split())
            shown = shown if len(shown) <= 80 else shown[:77] + "..."
            what = "the class itself, not an instance" if exp is Experiment else f"a {type(exp).__name__}"
            raise ModelError(f"{type(self.model).__name__}.experiment = {shown} is {what}; write experiment = "
                             "flexlib.Experiment(t_end=..., dt_out=..., rtol=..., atol=..., t_start=..., "
                             "max_order=...) (every field optional)")
        return exp

    def run(
        self, t_end: float | None = None, *, t_start: float | None = None, dt_out: float | None = None,
        output_times: np.ndarray | None = None, rtol: float | None = None, atol: float | None = None,
        max_step: float = 0.0, max_steps: int = 5_000_000, params: dict[str, Any] | None = None,
        steady_state: bool = False, progress: bool | None = None, result_file: str | os.PathLike | None = None,
        solver: str = "ida", dynamic_states: bool = True, max_order: int | None = None,
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
            Explicit output times [s] (numbers, strictly increasing, inside the span). The result also has a row at
            the start and one at ``t_end`` (added when the times stop before it), as with ``dt_out``.
        rtol, atol : float, optional
            Relative and absolute tolerance (``atol`` scaled by each variable's ``nominal``); machine epsilon
            ``<= rtol < 1``, ``atol >= 1e-50``.
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
        result_file : str or os.PathLike, optional
            Write the result to this HDF5 file, also when the run fails or is interrupted (Ctrl-C, SIGTERM). An
            earlier result file is replaced; an existing file of another kind (text, another program's HDF5, a
            device), a name ending in a path separator or in another format's extension (``.csv``) is refused.
        solver : {"ida", "ida-native", "ida-sksundae", "casadi-idas"} or Solver
            A solver object carries its own options (``flexlib.IDA(max_order=2, linear_solver="klu")``,
            ``flexlib.CasadiIDAS()``; :mod:`flexlib.solve.solvers`); the strings stand for those objects.
            ``"ida"`` (default): SUNDIALS IDA with its step loop in C and the model evaluated in C, Python only
            at outputs, events and due state-selection checks (``"ida-native"``, see
            ``flexlib/solve/backends/ida_c.py``) when that driver is available (gcc on PATH builds it once per
            machine); otherwise — no compiler, a failed build, ``FLEXLIB_NATIVE=0`` in the environment — the
            same IDA stepped from Python through scikit-sundae, with no error.
            ``"ida-native"``: the C driver; :class:`~flexlib.errors.NativeSolverError` if it is unavailable.
            ``"ida-sksundae"``: IDA stepped from Python through scikit-sundae (``flexlib/solve/backends/sksundae.py``).
            ``"casadi-idas"``: CasADi's built-in IDAS, all in C, same results and events (see
            ``flexlib/solve/backends/casadi.py``).
        dynamic_states : bool
            Re-select the states during the run when the selected dummy-derivative blocks become
            ill-conditioned (the IDA backends; see ``flexlib/solve/state_selection.py``).
        max_order : int, optional
            Highest BDF order IDA may use, 1–5 (MATLAB ode15s' ``MaxOrder``); default: the model's
            ``experiment.max_order``, else 5. Orders above 2 are not A-stable: in a machine whose fast, lightly
            damped modes (elastic modes, oil springs) are not the subject of the run, IDA at a loose tolerance
            then cuts its steps and rings such a mode at the tolerance level, where BDF2 damps it. A run that
            resolves the vibration itself at a tight tolerance is faster at high order. See ``docs/engine.md``,
            "BDF order".

        Returns
        -------
        Result

        Raises
        ------
        RunArgumentError
            An argument is invalid (checked before any work; a ``ValueError``). See docs/results.md.
        SolverError
            The integration failed; ``err.result`` holds the result up to the failure, its last row at the last
            point the solver accepted (also on an output grid).
        SimulationInterrupted
            Ctrl-C or SIGTERM; ``err.result`` holds the result up to the interrupt, likewise.
        ModelError
            The model's ``experiment`` is not an :class:`Experiment`.

        Warns
        -----
        ResultSaveWarning
            ``result_file`` could not be written; the result is returned (or attached to the error) anyway.
        """
        exp = self._experiment()
        opts = check_run_arguments(
            exp, f"{type(self.model).__name__}.experiment", t_start=t_start, t_end=t_end, dt_out=dt_out,
            output_times=output_times, rtol=rtol, atol=atol, max_step=max_step, max_steps=max_steps, params=params,
            steady_state=steady_state, dynamic_states=dynamic_states, progress=progress, solver=solver,
            result_file=result_file, max_order=max_order)
        t0 = opts.t_start
        m = self.compiled
        starts, pvec, p = self._parameters(opts.params)
        with sigterm_as_interrupt() as stop:
            wall = _time.perf_counter()
            t_init = 0.0
            try:
                starts, pvec, p, y0, yp0 = self._start_on_fitting_build(t0, starts, pvec, p, opts.params,
                                                                      opts.steady_state)
                t_init = _time.perf_counter() - wall
                m = self.compiled  # (another build if the cached one did not fit this instance)
                check_assertions(m, p, t0)
                traj = self._integrate(opts, m, p, y0, yp0)
            except SolverError as err:
                stop.stopping = True
                traj = err.result if isinstance(err.result, Trajectory) else Trajectory(status="failed",
                                                                                        message=str(err))
                if isinstance(err, SimulationInterrupted) and stop.signalled:
                    traj.message = traj.message.replace("by the user", f"by {stop.by}")
                    err.args = (traj.message,)
                err.result = self._result(traj, pvec, t_init, opts.rtol, opts.atol)
                self._keep(err.result, opts.result_file)
                raise
            except KeyboardInterrupt:  # Ctrl-C or SIGTERM outside the backend's step loop (initialisation)
                stop.stopping = True
                where = "during initialisation" if not t_init else "before the first step"
                traj = Trajectory(status="interrupted", message=f"interrupted by {stop.by} {where} at t = {t0:.10g} s")
                result = self._result(traj, pvec, t_init, opts.rtol, opts.atol)
                self._keep(result, opts.result_file)
                raise SimulationInterrupted(traj.message, result) from None
            stop.stopping = True
            result = self._result(traj, pvec, t_init, opts.rtol, opts.atol)
            self._keep(result, opts.result_file)
        try:
            self._check_trajectory(traj, pvec, opts.rtol, opts.atol, opts.params)
        except StructureChangedError as err:
            err.result = result  # type: ignore[attr-defined]
            raise
        return result

    def _integrate(self, opts: Any, m: CompiledModel, p: np.ndarray, y0: np.ndarray, yp0: np.ndarray) -> Trajectory:
        """The run's integration from the consistent start: the solver's adapter driven by the run loop (the static
        rows of a model without unknowns), with the fallback of the default solver where the C driver cannot be set
        up for this model."""
        if m.n == 0:  # every variable is an expression of time and parameters: nothing to integrate
            return integrate_static(m, p, opts.t_start, opts.t_end, opts.grid)
        solver = as_solver(opts.solver)
        while True:
            integ = solver.integrator(rtol=opts.rtol, atol=opts.atol, max_step=opts.max_step,
                                      max_order=opts.max_order, max_steps=opts.max_steps)
            monitor = self._monitor() if m.has_state_choice and opts.dynamic_states and integ.monitors else None
            try:
                return run_loop(integ, m, self.initializer, p, y0, yp0, opts.t_start, opts.t_end, opts.grid,
                                max_steps=opts.max_steps, progress=opts.progress, monitor=monitor)
            except NativeSolverError:
                if solver.fallback is None:
                    raise
                solver = solver.fallback  # the C driver could not be set up for this model: IDA from Python

    def initialize(self, *, t_start: float | None = None, params: dict[str, Any] | None = None,
                   steady_state: bool = False) -> Result:
        """The consistent start alone, as a one-row :class:`Result` at ``t_start`` (what a Modelica tool returns
        for a simulation with stop time = start time): every variable, e.g. the holding pressures and hinge forces
        of a static start, without integrating.

        Parameters
        ----------
        t_start : float, optional
            Start time [s] (default: the model's ``experiment``).
        params : dict, optional
            Parameter overrides for this start (no recompile), as in :meth:`run`.
        steady_state : bool
            Initialise with ``der(x) = 0`` for every state without an initial condition of its own.

        Returns
        -------
        Result
            One row; ``stats["steps"]`` is 0.

        Raises
        ------
        RunArgumentError
            An argument is invalid.
        InitializationError
            No consistent start was found (the error names the equations and variables that fail).
        """
        exp = self._experiment()
        t0 = exp.t_start if t_start is None else t_start
        # the run's own argument checks (a one-second span stands in for the end time, which is not used), named
        # as this method's
        try:
            opts = check_run_arguments(
                exp, f"{type(self.model).__name__}.experiment", t_start=t0, t_end=_span_end(t0), dt_out=None,
                output_times=None, rtol=None, atol=None, max_step=0.0, max_steps=1, params=params,
                steady_state=steady_state, dynamic_states=False, progress=False, solver="ida", result_file=None,
                max_order=None)
        except RunArgumentError as err:
            message = str(err)
            if not message.startswith("run(): "):
                raise
            renamed = RunArgumentError("initialize(): " + message[len("run(): "):])
            renamed.argument = getattr(err, "argument", None)  # type: ignore[attr-defined]
            raise renamed from None
        starts, pvec, p = self._parameters(opts.params)
        wall = _time.perf_counter()
        starts, pvec, p, y0, yp0 = self._start_on_fitting_build(opts.t_start, starts, pvec, p, opts.params,
                                                                opts.steady_state)
        t_init = _time.perf_counter() - wall
        m = self.compiled
        check_assertions(m, p, opts.t_start)
        traj = Trajectory(models=[m])
        traj.stats = {"steps": 0, "nfev": 0, "njev": 0, "state_events": 0, "time_events": 0, "restarts": 0,
                      "state_switches": 0}
        traj.add(opts.t_start, y0, yp0, p[m.n_params:])
        return self._result(traj, pvec, t_init, opts.rtol, opts.atol)

    def _parameters(self, params: dict[str, Any] | None) -> tuple[dict, np.ndarray, np.ndarray]:
        """The instance's start values, its parameter vector with ``params`` applied, and that vector followed by
        the relation values (zero until the initialisation sets them)."""
        values, starts = gather_values(self.model)
        pvec = self.parameter_vector(params, values)
        return starts, pvec, np.concatenate([pvec, np.zeros(self.compiled.n_relations)])

    def _start_on_fitting_build(self, t0: float, starts: dict, pvec: np.ndarray, p: np.ndarray,
                                params: dict[str, Any] | None, steady_state: bool
                                ) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The consistent start ``y0, yp0`` at ``t0`` (with the start values and parameter vectors it used).

        A cached entry is keyed by structure, not values: one built at another instance's values may have dropped
        loop rows that do not hold for this one (:meth:`_stale_cached_build`). Then the model is built again at this
        instance's own values, without touching the entry, and the start is sought once more on that build, where
        violated rows are the user's override (:class:`~flexlib.errors.StructureChangedError`).
        """
        y0, yp0 = self._initialize(t0, p, starts, steady_state)
        if self._stale_cached_build(t0, y0, yp0, p, params):
            self._rebuild_uncached()
            starts, pvec, p = self._parameters(params)
            y0, yp0 = self._initialize(t0, p, starts, steady_state)
            self._stale_cached_build(t0, y0, yp0, p, params)  # a fresh build: raises if the rows still fail
        return starts, pvec, p, y0, yp0

    def _stale_cached_build(self, t0: float, y0: np.ndarray, yp0: np.ndarray, p: np.ndarray,
                            params: dict[str, Any] | None) -> bool:
        """Check the build's dropped loop rows at the consistent start; True if a cached entry made for other
        values must be rebuilt (a fresh build's violation is the user's override: StructureChangedError)."""
        try:
            check_dropped_rows(self.compiled, t0, y0, yp0, p, START_TOL, where="at the start", overrides=params)
        except StructureChangedError:
            if not self.build_info.get("cached"):
                raise
            return True
        return False

    @staticmethod
    def _keep(result: Result, path: Path | None) -> None:
        """Write ``result`` to ``path`` (if given) without ever losing it: a failed write is a
        :class:`ResultSaveWarning` naming the path and the reason; Ctrl-C during the write leaves no file
        (the write is atomic) and raises :class:`SimulationInterrupted` carrying the result."""
        if path is None:
            return
        try:
            save_result(result, path)
        except KeyboardInterrupt:
            raise SimulationInterrupted(f"interrupted while writing the result file {path} (not written; the "
                                        f"result is in err.result)", result) from None
        except Exception as err:  # any failure to write must not hide the result
            reason = str(err) if isinstance(err, ResultFileError) else f"{path}: {type(err).__name__}: {err}"
            warnings.warn(ResultSaveWarning(f"the result was not saved: {reason}; it is kept in memory "
                                            "(returned, or err.result of the solver error)"), stacklevel=3)

    def _rebuild_uncached(self) -> None:
        """Build again from this instance's own values (no cache read or write)."""
        self.build = build(self.model, codegen=self._codegen, use_cache=False, assume_zero_geometry=self._zero_geometry)
        self.compiled, self.build_info = self.build.compiled, self.build.timings
        self.initializer = Initializer(self.compiled, lambda: self.build.structure(self.model))
        self._param_index = {n: k for k, n in enumerate(self.compiled.param_names)}
        self._rows.clear()
        self._state_monitor = None

    def _check_trajectory(self, traj: Trajectory, pvec: np.ndarray, rtol: float, atol: float,
                          params: dict[str, Any] | None) -> None:
        """The dropped loop rows over every recorded row (a choice that held at the start by coincidence)."""
        for model, _, T, Y, YP, P in segments(traj, self.compiled, pvec):
            if model.check_labels:
                check_dropped_rows(model, T, Y.T, YP.T, P.T, run_tolerance(rtol, atol), where="during the run",
                                   overrides=params, rows=self._rows)

    def _monitor(self) -> Any:
        from flexlib.solve.state_selection import StateSelectionMonitor

        if self._state_monitor is None:
            # the same pipeline as the build (stages 1-3 again if the compiled model came from the cache)
            self._state_monitor = StateSelectionMonitor(lambda: self.build.structure(self.model))
        return self._state_monitor

    def _initialize(self, t0: float, p: np.ndarray, starts: dict, steady: bool) -> tuple[np.ndarray, np.ndarray]:
        """Stage 4, cached on disk by model key, parameters, start values and options.

        Cached values are used only if the residual at the run's parameters is as small as when they were
        stored; a damaged file or a failed check gives one :class:`~flexlib.errors.CacheWarning` naming the
        file, and a fresh initialisation replaces it.
        """
        key = self.build.key
        directory = cache.usable_cache_dir() if key else None
        path = None
        if directory is not None:
            h = hashlib.sha256(p.tobytes() + repr((sorted(starts.items()), steady, t0)).encode()).hexdigest()[:24]
            path = cache.entry_path(directory, self.compiled.name, f"{key}-init-{h}").with_suffix(".npz")
            try:
                data = cache.load_init(path)
                if data is not None:
                    problem = self._cached_start_problem(t0, p, data)
                    if problem is not None:
                        raise cache.CacheEntryError(path, problem)
                    p[:] = data["p"]
                    self.init_cached = True
                    return data["y"].copy(), data["yp"].copy()
            except cache.CacheEntryError as err:
                cache.warn_once(err.path, f"damaged cached initial values ({err.reason}); removing them and "
                                          "initialising afresh")
                cache.discard(err.path)
        self.init_cached = False
        y, yp = self._consistent_start(t0, p, starts, steady)
        if path is not None:
            residual = self._residual_norm(t0, y, yp, p)
            try:
                cache.store_init(path, y=y, yp=yp, p=p, residual=np.array([residual]))
            except OSError as exc:
                cache.warn_once(path, f"cannot store initial values ({exc})")
        return y, yp

    def _residual_norm(self, t0: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> float:
        F = np.asarray(self.compiled.function("res")(t0, y, yp, p), dtype=float).ravel()
        return float(np.max(np.abs(F))) if F.size else 0.0

    def _cached_start_problem(self, t0: float, p: np.ndarray, data: dict[str, np.ndarray]) -> str | None:
        """Why cached initial values must not be used for a run with parameter vector ``p`` (None: usable)."""
        m = self.compiled
        y, yp, pc, stored = data["y"], data["yp"], data["p"], data["residual"]
        if y.shape != (m.n,) or yp.shape != (m.n,) or pc.shape != p.shape or stored.shape != (1,):
            return "sizes do not match the model"
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(yp)) and np.all(np.isfinite(pc))):
            return "non-finite values"
        trial = np.concatenate([p[:m.n_params], pc[m.n_params:]])  # the run's parameters, cached relations
        residual = self._residual_norm(t0, y, yp, trial)
        limit = max(1e-10, 10.0 * float(stored[0]))
        if not residual <= limit:
            return f"largest residual {residual:.3g} at the run's parameters exceeds {limit:.3g}"
        return None

    def _consistent_start(self, t0: float, p: np.ndarray, starts: dict, steady: bool) -> tuple[np.ndarray, np.ndarray]:
        """Stage 4 proper: :meth:`flexlib.solve.initialization.Initializer.consistent_start`."""
        return self.initializer.consistent_start(t0, p, starts, steady)

    def _assemble(self, model: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                  P: np.ndarray) -> np.ndarray:
        """All variables (aliases and outputs rebuilt by the ``out`` function) for rows ``T, Y, YP, P``."""
        return self._rows.evaluate(model, "out", T, Y, YP, P)

    def _result(self, traj: Trajectory, pvec: np.ndarray, t_init: float, rtol: float, atol: float) -> Result:
        m = self.compiled
        names = [v.name for v in m.variables]
        if traj.t:
            T = np.array(traj.t)
            values = np.zeros((len(T), len(names)))
            repaired, settle_error = 0, ""
            for model, rows, Ts, Y, YP, P in segments(traj, m, pvec):
                try:
                    Y, YP, n_fixed = settle_derivative_level(self._rows, model, Ts, Y, YP, P)
                    repaired += n_fixed
                except Exception as exc:  # never lose a run's rows to the check: keep them as recorded
                    settle_error = f"{type(exc).__name__}: {exc}"
                values[rows] = self._assemble(model, Ts, Y, YP, P)
        else:
            T, values = np.zeros(0), np.zeros((0, len(names)))
        stats = dict(traj.stats)
        if traj.t and settle_error:
            stats["settle_error"] = settle_error
            warnings.warn(f"{m.name}: the derivative-level unknowns (forces, accelerations) of the recorded rows "
                          f"could not be checked ({settle_error}); they are as IDA left them", ResultCheckWarning,
                          stacklevel=3)
        stats.update({"rows_resettled": repaired if traj.t else 0,
                      "wall_init": t_init, "rtol": rtol, "atol": atol, "n_states": int(m.differential.sum()),
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
