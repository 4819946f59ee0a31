"""The front door: ``Simulation(model).run()``.

``Simulation`` runs stages 1–5 once (or loads them from the disk cache) and then any number
of runs with different parameters, tolerances and end times, without recompiling.
"""

from __future__ import annotations

import copy
import dataclasses
import os
import time as _time
from collections.abc import Mapping
from typing import Any

import numpy as np

from flexlib.compile import pipeline
from flexlib.compile.build_options import BuildOptions
from flexlib.compile.codegen import CompiledModel
from flexlib.compile.constants import assumptions_hold
from flexlib.compile.index_reduction import IndexReport
from flexlib.compile.pipeline import Build, build_key, check_model
from flexlib.core.component import Component
from flexlib.errors import (
    NativeSolverError,
    RunArgumentError,
    SimulationInterrupted,
    SolverError,
    StructureChangedError,
)
from flexlib.results.hdf5 import keep_result
from flexlib.results.result import Result
from flexlib.solve.assemble import assemble_result
from flexlib.solve.build_checks import START_TOL, check_dropped_rows, run_tolerance
from flexlib.solve.events import check_assertions
from flexlib.solve.init.initializer import Initializer
from flexlib.solve.loop import run_loop
from flexlib.solve.options import Experiment, RunOptions, experiment_of, span_end
from flexlib.solve.parameters import ParameterTable
from flexlib.solve.rows import RowEvaluator, segments
from flexlib.solve.run_options import check_params, check_run_arguments
from flexlib.solve.sampling import sampled_blocks
from flexlib.solve.signals import sigterm_as_interrupt
from flexlib.solve.solvers import as_solver
from flexlib.solve.start_cache import load_start, store_start
from flexlib.solve.static import integrate_static
from flexlib.solve.trajectory import Trajectory

__all__ = ["Experiment", "Simulation", "StartPoint"]


@dataclasses.dataclass(frozen=True)
class StartPoint:
    """The consistent start as the integrator sees it (:meth:`Simulation.start_point`).

    Attributes
    ----------
    t : float
        Start time [s].
    p : numpy.ndarray
        The parameter vector (``compiled.param_names``, SI units) followed by the relation values (0/1) there.
    y, yp : numpy.ndarray
        The unknowns ``compiled.y_names`` and their time derivatives [SI units, per second].
    """

    t: float
    p: np.ndarray
    y: np.ndarray
    yp: np.ndarray


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
    build : BuildOptions, optional
        All build options as one record (instead of the three keywords; it also holds the compiler's options
        ``explicit`` and ``tree_frames``). A field left None takes its environment default, read once here.

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
    build_options : BuildOptions
        The build's options, resolved (no field None; ``sim.build.options``).

    Examples
    --------
    >>> sim = Simulation(model)                      # doctest: +SKIP
    >>> res = sim.run(2.0, dt_out=0.01)              # doctest: +SKIP
    >>> res2 = sim.run(2.0, params={"mass.m": 2.0})  # no recompile   # doctest: +SKIP
    """

    def __init__(self, model: Component, *, codegen: bool | str = "auto", use_cache: bool = True,
                 assume_zero_geometry: bool | None = None, build: BuildOptions | None = None) -> None:
        check_model(model, "Simulation()")
        #: The build's options, resolved once (every field left None set from its environment default)
        self.build_options = BuildOptions.from_arguments(codegen, use_cache, assume_zero_geometry, build,
                                                         "Simulation()").resolved()
        self.model = model
        self.build: Build = pipeline.build(model, options=self.build_options)
        self.compiled: CompiledModel = self.build.compiled
        self.build_info: dict[str, Any] = self.build.timings
        self.initializer = Initializer(self.compiled, self._structure)
        self.init_cached = False
        self._rows = RowEvaluator()
        self._state_monitor: Any = None
        self._run_checkers: list[Component] | None = None  # the components with a check_run (found at the first run)

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
        key = self.build.key or build_key(self.model, self.build_options)
        same = (type(model) is type(self.model) and build_key(model, self.build_options) == key
                and assumptions_hold(self.compiled.assumed, model))
        if not same:
            return Simulation(model, build=self.build_options)
        other = copy.copy(self)
        other.model = model
        other.init_cached = False
        other._rows = RowEvaluator()
        other._state_monitor = None
        other._run_checkers = None
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
            values, _ = self.model.values()
        elif not isinstance(values, Mapping):
            raise RunArgumentError(f"parameter_vector(): values = {values!r:.80} is invalid: must be a dict "
                                   f"{{'component.parameter': value}}, got a {type(values).__name__}")
        return ParameterTable(self.model, self.compiled).vector(params, values)

    # -- running -----------------------------------------------------------------------------------
    def run(
        self, t_end: float | None = None, *, t_start: float | None = None, dt_out: float | None = None,
        output_times: np.ndarray | None = None, rtol: float | None = None, atol: float | None = None,
        max_step: float = 0.0, max_steps: int = 5_000_000, params: dict[str, Any] | None = None,
        steady_state: bool = False, progress: bool | None = None, result_file: str | os.PathLike | None = None,
        solver: Any = "ida", dynamic_states: bool = True, max_order: int | None = None,
        outputs: str | list[str] | None = None, options: RunOptions | None = None,
    ) -> Result:
        """Initialise and integrate. An argument left out (None) takes the model's ``experiment``.

        Parameters
        ----------
        t_end, t_start : float, optional
            End and start time [s].
        dt_out : float, optional
            Output interval [s]; without it (and without ``output_times``) every step is recorded.
        output_times : array_like, optional
            Output times [s] (strictly increasing, inside the span). With either, rows at the start and at ``t_end``.
        rtol, atol : float, optional
            Tolerances (``atol`` scaled by each ``nominal``); machine epsilon ``<= rtol < 1``, ``atol >= 1e-50``.
        max_step : float
            Maximum step size [s]; 0: unlimited.
        max_steps : int
            Maximum number of internal steps.
        params : dict, optional
            Parameter overrides ``{"inertia1.J": 2.0}`` for this run (no recompile).
        steady_state : bool
            Initialise with ``der(x) = 0`` for every state without an initial condition of its own.
        progress : bool, optional
            Progress bar (default: shown for runs longer than about 2 s).
        result_file : str or os.PathLike, optional
            HDF5 file for the result, also of a failed or interrupted run (an earlier result file is replaced).
        solver : {"ida", "ida-native", "ida-sksundae", "casadi-idas"} or Solver
            ``"ida"``: IDA stepped in C where the driver builds (gcc; ``FLEXLIB_NATIVE=0`` turns it off), else
            through scikit-sundae; the others force one backend (:mod:`flexlib.solve.solvers`). A solver object
            carries its options: ``flexlib.IDA(max_order=2, linear_solver="klu")``, ``flexlib.CasadiIDAS()``.
        dynamic_states : bool
            Re-select the states when the selected dummy-derivative blocks become ill-conditioned.
        max_order : int, optional
            Highest BDF order, 1–5 (default: ``experiment.max_order``, else 5; ``docs/engine.md``, "BDF order").
        outputs : str or list of str, optional
            Variables (names, patterns) ``result_file`` stores as columns besides the run's rows, ``"all"``: every
            one (``docs/results.md``).
        options : RunOptions, optional
            All of the above as one record; an argument given next to it replaces its field.

        Returns
        -------
        Result

        Raises
        ------
        RunArgumentError
            An argument is invalid (checked before any work; a ``ValueError``); ``ModelError``: a bad ``experiment``.
        SolverError
            The integration failed; ``err.result`` holds the result up to the failure (its last row at the last
            point the solver accepted). ``SimulationInterrupted`` (Ctrl-C, SIGTERM) likewise. A ``result_file``
            that cannot be written is a ``ResultSaveWarning``; the result is kept.
        """
        given = dict(t_end=t_end, t_start=t_start, dt_out=dt_out, output_times=output_times, rtol=rtol, atol=atol,
                     max_step=max_step, max_steps=max_steps, params=params, steady_state=steady_state,
                     progress=progress, result_file=result_file, solver=solver, dynamic_states=dynamic_states,
                     max_order=max_order, outputs=outputs)
        if options is not None:
            if not isinstance(options, RunOptions):
                raise RunArgumentError(f"run(): options = {options!r:.80} is invalid: must be a flexlib.RunOptions")
            given = options.merged(given)
        opts = check_run_arguments(experiment_of(self.model), f"{type(self.model).__name__}.experiment", **given)
        starts, pvec, p = self._parameters(opts.params)
        with sigterm_as_interrupt() as stop:
            traj, pvec, t_init = self._initialize_and_integrate(opts, stop, starts, pvec, p)
            stop.stopping = True
            result = self._result(traj, pvec, t_init, opts.rtol, opts.atol)
            keep_result(result, opts.result_file, opts.outputs)
        try:
            self._check_trajectory(traj, pvec, opts.rtol, opts.atol, opts.params)
        except StructureChangedError as err:
            err.result = result  # type: ignore[attr-defined]
            raise
        return self._check_run(result)

    def _check_run(self, result: Result) -> Result:
        """``result`` after the components' checks of the run (:meth:`Component.check_run`, e.g. a modal body's
        validity monitors): their warnings, and their summaries in ``result.stats["validity"]``."""
        if self._run_checkers is None:
            base = Component.check_run
            self._run_checkers = [node for node in self.model.walk() if isinstance(node, Component)
                                  and getattr(type(node), "check_run", base) is not base]
        summaries = {}
        for node in self._run_checkers:
            summary = node.check_run(result)
            if summary is not None:
                summaries[node.path] = summary
        if summaries:
            result.stats["validity"] = summaries
        return result

    def _initialize_and_integrate(self, opts: Any, stop: Any, starts: dict, pvec: np.ndarray,
                                  p: np.ndarray) -> tuple[Trajectory, np.ndarray, float]:
        """The consistent start and the integration of :meth:`run`: the trajectory, the parameter vector used and
        the initialisation's wall time [s]. A failure or interrupt is raised with its result (written to the
        result file)."""
        t0 = opts.t_start
        wall = _time.perf_counter()
        t_init = 0.0
        try:
            starts, pvec, p, y0, yp0 = self._start_on_fitting_build(t0, starts, pvec, p, opts.params,
                                                                  opts.steady_state)
            t_init = _time.perf_counter() - wall
            m = self.compiled  # (another build if the cached one did not fit this instance)
            check_assertions(m, p, t0)
            return self._integrate(opts, m, p, y0, yp0), pvec, t_init
        except SolverError as err:
            stop.stopping = True
            traj = err.result if isinstance(err.result, Trajectory) else Trajectory(status="failed", message=str(err))
            if isinstance(err, SimulationInterrupted) and stop.signalled:
                traj.message = traj.message.replace("by the user", f"by {stop.by}")
                err.args = (traj.message,)
            err.result = self._result(traj, pvec, t_init, opts.rtol, opts.atol)
            keep_result(err.result, opts.result_file, opts.outputs)
            raise
        except KeyboardInterrupt:  # Ctrl-C or SIGTERM outside the backend's step loop (initialisation)
            stop.stopping = True
            where = "during initialisation" if not t_init else "before the first step"
            traj = Trajectory(status="interrupted", message=f"interrupted by {stop.by} {where} at t = {t0:.10g} s")
            result = self._result(traj, pvec, t_init, opts.rtol, opts.atol)
            keep_result(result, opts.result_file, opts.outputs)
            raise SimulationInterrupted(traj.message, result) from None

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
                                max_steps=opts.max_steps, progress=opts.progress, monitor=monitor,
                                sampled=sampled_blocks(self.model))
            except NativeSolverError:
                if solver.fallback is None:
                    raise
                solver = solver.fallback  # the C driver could not be set up for this model: IDA from Python

    def sensitivities(self, t_end: float | None, params: list[str], outputs: list[str], *,
                      values: dict[str, Any] | None = None, rtol: float = 1e-8, atol: float = 1e-10,
                      **run: Any) -> Any:
        """Forward sensitivities ``∂output/∂parameter`` over a run, through the DAE and its events
        (:mod:`flexlib.solve.sensitivities`: CasADi's IDAS on the model's residual, the event times' derivatives).

        Parameters
        ----------
        t_end : float or None
            End time [s] (None: the model's experiment).
        params : list of str
            Run-time parameters (names of ``compiled.param_names``, SI units).
        outputs : list of str
            Variables of the result.
        values : dict, optional
            Parameter values of the run, as ``params=`` of :meth:`run`.
        rtol, atol : float
            Tolerances of the run and of the sensitivity integration.
        **run
            Further arguments of :meth:`run` (``dt_out``, ``output_times``, ``t_start``, ``steady_state``).

        Returns
        -------
        Sensitivities
            ``sens[output, parameter]`` over ``sens.t``; ``sens.result`` the nominal run.
        """
        from flexlib.solve.sensitivities import forward_sensitivities

        return forward_sensitivities(self, t_end, params, outputs, values=values, rtol=rtol, atol=atol, **run)

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
        exp = experiment_of(self.model)
        t0 = exp.t_start if t_start is None else t_start
        # the run's own argument checks (a one-second span stands in for the end time, which is not used), named
        # as this method's
        try:
            opts = check_run_arguments(
                exp, f"{type(self.model).__name__}.experiment", t_start=t0, t_end=span_end(t0), dt_out=None,
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
        self._start = StartPoint(float(opts.t_start), p.copy(), y0.copy(), yp0.copy())
        m = self.compiled
        check_assertions(m, p, opts.t_start)
        traj = Trajectory(models=[m])
        traj.stats = {"steps": 0, "nfev": 0, "njev": 0, "state_events": 0, "time_events": 0, "restarts": 0,
                      "state_switches": 0}
        traj.add(opts.t_start, y0, yp0, p[m.n_params:])
        return self._result(traj, pvec, t_init, opts.rtol, opts.atol)

    def start_point(self, *, t_start: float | None = None, params: dict[str, Any] | None = None,
                    steady_state: bool = False) -> StartPoint:
        """The consistent start of :meth:`initialize` (arguments and errors as there) in the integrator's terms: the
        parameter and relation-value vector and the unknowns with their derivatives, for code that steps the compiled
        model itself (an exported FMU, :func:`flexlib.fmi.export_fmu`)."""
        self.initialize(t_start=t_start, params=params, steady_state=steady_state)
        return self._start

    def _parameters(self, params: dict[str, Any] | None) -> tuple[dict, np.ndarray, np.ndarray]:
        """The instance's start values, its parameter vector with ``params`` applied, and that vector followed by
        the relation values (zero until the initialisation sets them)."""
        values, starts = self.model.values()
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

    def _rebuild_uncached(self) -> None:
        """Build again from this instance's own values (no cache read or write)."""
        self.build = pipeline.build(self.model, options=dataclasses.replace(self.build_options, use_cache=False))
        self.compiled, self.build_info = self.build.compiled, self.build.timings
        self.initializer = Initializer(self.compiled, self._structure)
        self._rows.clear()
        self._state_monitor = None

    def _check_trajectory(self, traj: Trajectory, pvec: np.ndarray, rtol: float, atol: float,
                          params: dict[str, Any] | None) -> None:
        """The dropped loop rows over every recorded row (a choice that held at the start by coincidence)."""
        if not any(m.check_labels for m in (traj.models or [self.compiled])):
            return  # no dropped rows to check: the rows are not stacked for nothing
        for model, _, T, Y, YP, P in segments(traj, self.compiled, pvec):
            if model.check_labels:
                check_dropped_rows(model, T, Y.T, YP.T, P.T, run_tolerance(rtol, atol), where="during the run",
                                   overrides=params, rows=self._rows)

    def _structure(self) -> Any:
        """Stages 1–3 of this build again (a build loaded from the cache keeps only the compiled model)."""
        return self.build.structure(self.model)

    def _monitor(self) -> Any:
        from flexlib.solve.state_selection import StateSelectionMonitor

        if self._state_monitor is None:
            # the same pipeline as the build (stages 1-3 again if the compiled model came from the cache)
            self._state_monitor = StateSelectionMonitor(self._structure)
        return self._state_monitor

    def _initialize(self, t0: float, p: np.ndarray, starts: dict, steady: bool) -> tuple[np.ndarray, np.ndarray]:
        """Stage 4, cached on disk by model key, parameters, start values and options
        (:mod:`flexlib.solve.start_cache`)."""
        path, found = load_start(self.build.key, self.compiled, t0, p, starts, steady)
        self.init_cached = found is not None
        if found is not None:
            return found
        y, yp = self._consistent_start(t0, p, starts, steady)
        store_start(path, self.compiled, t0, y, yp, p)
        return y, yp

    def _consistent_start(self, t0: float, p: np.ndarray, starts: dict, steady: bool) -> tuple[np.ndarray, np.ndarray]:
        """Stage 4 proper: :meth:`flexlib.solve.init.initializer.Initializer.consistent_start`."""
        return self.initializer.consistent_start(t0, p, starts, steady)

    def _result(self, traj: Trajectory, pvec: np.ndarray, t_init: float, rtol: float, atol: float) -> Result:
        """The run's :class:`Result` (:func:`flexlib.solve.assemble.assemble_result`)."""
        return assemble_result(traj, self.compiled, pvec, self._rows, t_init, rtol, atol, self.build_info)
