"""Registry of runnable models and their scenarios (what ``flexlib list`` shows and ``flexlib run`` runs).

A model registers itself beside its definition (``models/<name>.py``) with :func:`register_model`: a name,
a factory that builds the model instance for a :class:`Scenario`, a one-line doc, its scenarios and the
signals whose peaks the command line summarises. A scenario is data — end time, parameter overrides, run
options (tolerances, output interval, solver), model options (``flexible``, ...) and free-form ``data`` the
factory interprets (joint targets over time, valve commands, ...) — so a user writes their own, in Python
(:func:`register_scenario`) or as a JSON file (:meth:`Scenario.from_dict`, ``flexlib run MODEL --scenario
my.json``).

:func:`run_scenario` builds and runs a registered model and records the run settings (model, scenario,
parameter overrides, run options) in the result's metadata (``meta_run`` in the HDF5 file, JSON), so that
:func:`run_settings` and ``flexlib run --from FILE`` repeat the run.

A model declares its options where it registers (:class:`ModelOption`: name, type, default, accepted values or
range, doc); every value — a registered scenario's, a JSON file's, the command line's ``--option NAME=VALUE`` text
— is checked against that declaration once, before the factory runs, and an unknown name gets the closest match.

Lookups of unknown names raise :class:`~flexlib.errors.RegistryError` naming the unknown name, the known ones
and the closest match.

This module is the front door for model authors (``from flexlib.registry import ModelOption, Scenario,
register_model``); the records live in :mod:`flexlib.scenario` (:class:`Scenario`, :class:`ModelOption`) and
:mod:`flexlib.run_record` (:class:`RunRecord`, :func:`run_settings`), the module discovery in
:mod:`flexlib.model_modules`.
"""

from __future__ import annotations

import difflib
import importlib
import os
import time as _time
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from flexlib.errors import (
    FlexlibError,
    InitializationError,
    ModelError,
    ParameterError,
    RegistryError,
    ResultFileError,
    ResultSaveWarning,
    RunArgumentError,
    SolverError,
)
from flexlib.model_modules import (
    MODULES_ENV,
    builtin_modules,
    import_failure,
    import_user_module,
    module_hint,
)
from flexlib.run_record import RunRecord, record_json, run_settings
from flexlib.scenario import RUN_OPTIONS, ModelOption, Scenario, check_params, frozen_mapping

__all__ = ["RUN_OPTIONS", "ModelEntry", "ModelOption", "RunRecord", "Scenario", "ScenarioRun", "get_model",
           "get_scenario", "import_user_module", "models", "register_model", "register_scenario", "run_scenario",
           "run_settings", "scenario_model"]



#: A model's summary signals: variable names, or a function of the built model instance returning them.
SummarySignals = Sequence[str] | Callable[[Any], Sequence[str]]


@dataclass
class ModelEntry:
    """A registered model (see :func:`register_model`).

    ``options`` holds the declarations of the model options (:class:`ModelOption`; an option registered by name
    alone is untyped: any value, read as JSON on the command line); ``data`` the keys of ``Scenario.data`` the
    factory reads, or ``None`` if the model does not declare them (not checked).
    """

    name: str
    factory: Callable[[Scenario], Any]
    doc: str
    scenarios: dict[str, Scenario]
    summary_signals: SummarySignals = ()
    default_scenario: str = ""
    options: tuple[ModelOption, ...] = ()
    plots: Callable[[Any, Any, Path], list[Path]] | None = None
    data: tuple[str, ...] | None = None

    @property
    def option_names(self) -> tuple[str, ...]:
        """Names of the declared model options."""
        return tuple(o.name for o in self.options)

    def option(self, name: str, where: str = "") -> ModelOption:
        """The declaration of option ``name``; :class:`RunArgumentError` naming an unknown one, the closest
        match and every option with its accepted values."""
        for o in self.options:
            if o.name == name:
                return o
        known = self.option_names
        close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        if not close and "." in name:  # 'mass0.m': a parameter given where a model option goes
            hint = f"; {name!r} looks like a parameter (component.parameter): give it as a parameter override"
        listed = "; ".join(f"{o.name} ({o.accepted()})" for o in self.options) or "none"
        raise RunArgumentError(f"{where}unknown model option {name!r}{hint} (options of {self.name}: {listed})")

    def check_options(self, scenario: Scenario) -> dict[str, Any]:
        """The model options of ``scenario`` checked against their declarations and normalised.

        Raises
        ------
        RunArgumentError
            An option the model does not declare (with the closest match) or a value its declaration refuses;
            the message names the model, the scenario (and its file), the option, the value and what is accepted.
        """
        if not isinstance(scenario, Scenario):
            raise RunArgumentError(f"model {self.name!r}: check_options takes a Scenario record, got "
                                   f"{scenario!r} ({type(scenario).__name__})")
        where = f"model {self.name!r}, {scenario.label}: "
        return {key: self.option(key, where).validate(value, where, label=f"option {key!r}")
                for key, value in scenario.options.items()}

    def check_data(self, scenario: Scenario) -> None:
        """:class:`RunArgumentError` naming a key of ``scenario.data`` the model does not read (if it declares
        its data keys)."""
        if self.data is None:
            return
        for key in scenario.data:
            if key not in self.data:
                close = difflib.get_close_matches(key, self.data, n=1, cutoff=0.6)
                hint = f"; did you mean {close[0]!r}?" if close else ""
                known = ", ".join(self.data) if self.data else f"none: {self.name} reads no data"
                raise RunArgumentError(f"model {self.name!r}, {scenario.label}: unknown data {key!r}{hint} "
                                       f"(data of {self.name}: {known})")

    def checked(self, scenario: Scenario) -> Scenario:
        """``scenario`` with its options checked and normalised (:meth:`check_options`) and its data keys
        checked (:meth:`check_data`)."""
        options = self.check_options(scenario)
        self.check_data(scenario)
        return scenario if options == dict(scenario.options) else replace(scenario, options=options)

    def parse_options(self, items: Mapping[str, str], where: str = "--option ") -> dict[str, Any]:
        """Command-line option texts ``{name: "VALUE"}`` converted by their declared types and checked
        (:meth:`ModelOption.parse`).

        Raises
        ------
        RunArgumentError
            An unknown option (with the closest match) or a value its declaration refuses, naming the option
            (as ``--option NAME=VALUE``), the model, the value and what is accepted.
        """
        if not isinstance(items, Mapping):
            raise RunArgumentError(f"model {self.name!r}: parse_options takes the option texts by name "
                                   f"({{'n': '4'}}), got {items!r} ({type(items).__name__})")
        out: dict[str, Any] = {}
        for key, text in items.items():
            spec = self.option(key, f"{where}{key}={text}: model {self.name!r}: ")
            out[key] = spec.parse(text, f"{where}{key}={text}: ", label=f"option {key!r} of model {self.name!r}")
        return out

    def scenario(self, name: str | None = None) -> Scenario:
        """The scenario ``name`` (``None``: the model's default scenario); :class:`RegistryError` naming an
        unknown one, the known ones and the closest match."""
        if name is None:
            name = self.default_scenario
        elif not isinstance(name, str) or not name.strip():
            raise RegistryError(f"model {self.name!r}: a scenario is named by a non-empty str (known: "
                                f"{', '.join(sorted(self.scenarios))}), got {name!r}")
        if name not in self.scenarios:
            raise RegistryError(_unknown(f"scenario {name!r} of model {self.name!r}", name, self.scenarios))
        return self.scenarios[name]

    def signals(self, model: Any) -> list[str]:
        """The summary signals for a built model instance."""
        sig = self.summary_signals(model) if callable(self.summary_signals) else self.summary_signals
        return [str(s) for s in sig]


_MODELS: dict[str, ModelEntry] = {}
_loaded = False


def _unknown(what: str, name: str, known: Mapping[str, Any] | Sequence[str]) -> str:
    names = sorted(known)
    close = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    return f"unknown {what} (known: {', '.join(names) if names else 'none'}){hint}"


def register_model(name: str, factory: Callable[[Scenario], Any], *, doc: str, scenarios: Sequence[Scenario],
                   summary_signals: SummarySignals = (), default_scenario: str | None = None,
                   options: Sequence[ModelOption | str] = (),
                   plots: Callable[[Any, Any, Path], list[Path]] | None = None,
                   data: Sequence[str] | None = None) -> ModelEntry:
    """Register a runnable model.

    Parameters
    ----------
    name : str
        Name used on the command line (``pump-truck``).
    factory : callable
        ``factory(scenario) -> Model``: builds the model instance for a :class:`Scenario` (its ``options``, checked
        and normalised by their declarations, and ``data``).
    doc : str
        One-line description.
    scenarios : sequence of Scenario
        At least one; the first is the default unless ``default_scenario`` says otherwise.
    summary_signals : sequence of str or callable
        Variables whose peaks ``flexlib run`` prints (or ``f(model) -> names``).
    default_scenario : str, optional
        Name of the default scenario.
    options : sequence of ModelOption or str
        The model options the factory reads, declared with type, default, accepted values and doc
        (:class:`ModelOption`); a scenario with another one, or with a value the declaration refuses, is an error
        naming it. A bare name declares an untyped option (any value; its factory must check it).
    plots : callable, optional
        ``plots(model, result, directory) -> [paths]``: writes the model's figures (PNG) of a run into
        ``directory``; ``flexlib run --plots DIR`` calls it.
    data : sequence of str, optional
        The keys of ``Scenario.data`` the factory reads (``()``: none); a scenario with another key is an error
        naming it. Default ``None``: not declared, not checked.

    Returns
    -------
    ModelEntry

    Raises
    ------
    RegistryError
        The name is taken by another factory, two scenarios or two options share a name, there is no scenario,
        an option declaration is malformed, ``doc`` is not a str, ``scenarios``, ``options``, ``data`` or
        ``summary_signals`` is not a sequence (a lone item, a str, a mapping), or ``default_scenario`` is not
        one of the scenarios' names.
    RunArgumentError
        A scenario's model option or data key is unknown, or a value its declaration refuses.
    """
    _check_registration(name, factory, doc, scenarios, options, data, summary_signals, default_scenario)
    scen = _scenarios_by_name(name, scenarios)
    specs = _options_by_name(name, options)
    if data is not None and (isinstance(data, (str, Mapping)) or not all(isinstance(k, str) for k in data)):
        raise RegistryError(f"register_model({name!r}): data must be a sequence of key names, got {data!r}")
    old = _MODELS.get(name)
    if old is not None:
        raise RegistryError(f"register_model: the name {name!r} is already registered by "
                            f"{getattr(old.factory, '__module__', '?')}.{getattr(old.factory, '__qualname__', '?')}")
    default = next(iter(scen)) if default_scenario is None else default_scenario
    if default not in scen:
        raise RegistryError(f"register_model({name!r}): " + _unknown("default scenario " + repr(default), default,
                                                                        scen))
    if plots is not None and not callable(plots):
        raise RegistryError(f"register_model({name!r}): plots must be callable, got {type(plots).__name__}")
    entry = ModelEntry(name, factory, doc, scen, summary_signals, default, tuple(specs.values()), plots,
                       None if data is None else tuple(data))
    for key, s in scen.items():
        scen[key] = entry.checked(s)
    _MODELS[name] = entry
    return entry


def _check_registration(name: Any, factory: Any, doc: Any, scenarios: Any, options: Any, data: Any,
                        summary_signals: Any, default_scenario: Any) -> None:
    """The types of :func:`register_model`'s arguments (a :class:`RegistryError` naming the first wrong one)."""
    if not isinstance(name, str) or not name.strip():
        raise RegistryError(f"register_model: name must be a non-empty str, got {name!r}")
    if not callable(factory):
        raise RegistryError(f"register_model({name!r}): factory must be callable, got {type(factory).__name__}")
    who = f"register_model({name!r})"
    if not isinstance(doc, str):
        raise RegistryError(f"{who}: doc must be a str (one line), got {doc!r}")
    _check_sequence(scenarios, f"{who}: scenarios", "Scenario records")
    _check_sequence(options, f"{who}: options", "ModelOption")
    if data is not None:
        _check_sequence(data, f"{who}: data", "key names (str)")
    if not callable(summary_signals):
        _check_sequence(summary_signals, f"{who}: summary_signals", "variable names (or a function of the built "
                        "model returning them)")
        bad = [x for x in summary_signals if not isinstance(x, str) or not x.strip()]
        if bad:
            raise RegistryError(f"{who}: summary_signals must be variable names (str), got {bad[0]!r}")
    if default_scenario is not None and (not isinstance(default_scenario, str) or not default_scenario.strip()):
        raise RegistryError(f"{who}: default_scenario must be the name of one of its scenarios (or None: the "
                            f"first), got {default_scenario!r}")


def _scenarios_by_name(name: str, scenarios: Iterable[Any]) -> dict[str, Scenario]:
    """``{name: scenario}`` of a model's scenarios: Scenario records with distinct names, at least one."""
    scen: dict[str, Scenario] = {}
    for s in scenarios:
        if not isinstance(s, Scenario):
            raise RegistryError(f"register_model({name!r}): scenarios must be Scenario records, got {s!r}")
        if s.name in scen:
            raise RegistryError(f"register_model({name!r}): two scenarios named {s.name!r}")
        scen[s.name] = s
    if not scen:
        raise RegistryError(f"register_model({name!r}): give at least one scenario")
    return scen


def _options_by_name(name: str, options: Iterable[Any]) -> dict[str, ModelOption]:
    """``{name: declaration}`` of a model's options (a bare name declares an untyped option), distinct names."""
    specs: dict[str, ModelOption] = {}
    for o in options:
        spec = ModelOption(o, None, doc="(untyped)") if isinstance(o, str) else o
        if not isinstance(spec, ModelOption):
            raise RegistryError(f"register_model({name!r}): options must be ModelOption declarations (or names), "
                                f"got {o!r}")
        if spec.name in specs:
            raise RegistryError(f"register_model({name!r}): two options named {spec.name!r}")
        specs[spec.name] = spec
    return specs


def _check_sequence(value: Any, what: str, items: str) -> None:
    """:class:`RegistryError` unless ``value`` is a list, tuple or other iterable collection (a lone item, a str
    or a mapping is refused: iterating it would register its characters or keys)."""
    if isinstance(value, (str, bytes, Mapping, Scenario, ModelOption)) or not isinstance(value, Iterable):
        raise RegistryError(f"{what} must be a sequence of {items}, got {type(value).__name__} {value!r}")


def register_scenario(model: str, scenario: Scenario) -> None:
    """Add a scenario to a registered model (a user's own); a name already in use is replaced."""
    if not isinstance(scenario, Scenario):
        raise RegistryError(f"register_scenario({model!r}): expected a Scenario, got {scenario!r}")
    entry = get_model(model)
    entry.scenarios[scenario.name] = entry.checked(scenario)


def _load() -> None:
    global _loaded
    if _loaded:
        return
    extra = [m.strip() for m in os.environ.get(MODULES_ENV, "").split(",") if m.strip()]
    for module in builtin_modules():
        importlib.import_module(module)
    for module in extra:
        try:
            import_user_module(module)
        except Exception as err:  # any failure of the user's module: one message naming it, the error, file:line
            raise RegistryError(f"${MODULES_ENV}: cannot import the model module {module!r}: "
                                f"{import_failure(err)}{module_hint(module)}") from None
    _loaded = True  # only once every module imported: a failed import is retried (and reported) next time


def models() -> dict[str, ModelEntry]:
    """All registered models by name (imports the built-in model modules on first use)."""
    _load()
    return dict(sorted(_MODELS.items()))


def get_model(name: str) -> ModelEntry:
    """The registered model ``name``; :class:`RegistryError` naming it and the known models otherwise."""
    _load()
    if not isinstance(name, str) or not name.strip():
        from flexlib.core.component import Component

        hint = "; a model instance runs with flexlib.Simulation(model).run()" if isinstance(name, Component) else ""
        raise RegistryError(f"a model is named by a non-empty str (known: {', '.join(sorted(_MODELS))}), got "
                            f"{name!r} ({type(name).__name__}){hint}")
    if name not in _MODELS:
        raise RegistryError(_unknown(f"model {name!r}", name, _MODELS))
    return _MODELS[name]


def get_scenario(model: str, scenario: str | None = None) -> Scenario:
    """A scenario of a registered model (default: its default scenario)."""
    return get_model(model).scenario(scenario)


def _overrides_note(scen: Scenario, params: Mapping[str, float] | None) -> str:
    """Names the parameter overrides of a run whose start failed: a value that changes a loop's geometry can make
    its closure impossible or change its rank from what the build analysed."""
    parts = []
    if scen.params:
        parts.append(f"{scen.label}: " + ", ".join(f"{k} = {v!r}" for k, v in scen.params.items()))
    if params:
        parts.append("given: " + ", ".join(f"{k} = {v!r}" for k, v in params.items()))
    return ("The start was sought with parameter overrides (" + "; ".join(parts) + "). A value that changes a "
            "loop's geometry can leave the loop unable to close, or change its rank from the one the build "
            "analysed: check these values, or build the model with them.")


@dataclass
class ScenarioRun:
    """What :func:`run_scenario` returns: the result, the built model and timings [s] (process CPU time)."""

    result: Any
    model: Any
    entry: ModelEntry
    scenario: Scenario
    cpu_build: float
    cpu_run: float


def run_scenario(model: str, scenario: str | Scenario | None = None, *, params: Mapping[str, float] | None = None,
                 t_end: float | None = None, progress: bool | None = None,
                 result_file: str | os.PathLike | None = None, **run: Any) -> ScenarioRun:
    """Build and run a registered model in one of its scenarios, recording the run settings in the result.

    Parameters
    ----------
    model : str
        Registered model name.
    scenario : str or Scenario, optional
        Scenario name, or a :class:`Scenario` record (a user's own); default: the model's default scenario.
    params : mapping, optional
        Parameter overrides on top of the scenario's.
    t_end : float, optional
        End time [s] instead of the scenario's.
    progress : bool, optional
        Progress bar (the engine's tqdm).
    result_file : path, optional
        Write the result (with the run settings) to this HDF5 file, also when the run fails. Checked before the
        build; a write that fails after the run is a :class:`~flexlib.errors.ResultSaveWarning` and the result
        is returned (or stays on ``err.result``) all the same.
    **run
        Further options of :meth:`flexlib.Simulation.run` (:data:`RUN_OPTIONS`) on top of the scenario's.

    Returns
    -------
    ScenarioRun

    Raises
    ------
    RegistryError
        Unknown model or scenario.
    RunArgumentError
        An option is not one of :data:`RUN_OPTIONS`, a model option or data key the model does not declare, a
        model option's value its declaration refuses (:class:`ModelOption`), a parameter override that is not a
        finite number or is a model option's name, a scenario value the run record (JSON) cannot hold,
        ``result_file`` cannot be written, or a value of ``t_end`` or a run option the run refuses (named with the
        scenario when it comes from there); all checked before the build.
    ParameterError
        Unknown parameter or value out of bounds; a bad value in the scenario's data (named with the scenario).
    ModelError
        The model's factory failed otherwise, or returned something other than a flexlib model (named with the
        model and the scenario; the cause chained).
    InitializationError
        No consistent start; with parameter overrides the message names them (a value that changes a loop's
        geometry can make the loop impossible to close or change its rank).
    SolverError
        The run failed; ``err.result`` holds the rows up to the failure, with the run settings.

    Warns
    -----
    ResultSaveWarning
        ``result_file`` could not be written after the run; the result is returned (or on ``err.result``).
    """
    from flexlib.solve.simulation import Simulation

    entry = get_model(model)
    scen, params, out, given, recorded = _checked_request(entry, scenario, params, t_end, result_file, run)
    overrides = {**dict(scen.params), **dict(params or {})}
    opts = {**dict(scen.run), **{k: v for k, v in given.items() if k != "t_end"}}
    c0 = _time.process_time()
    instance = _build_instance(entry, scen)
    _check_run_values(entry, scen, instance, given, opts, overrides, progress)  # before the build
    sim = Simulation(instance)
    c1 = _time.process_time()
    try:
        result = sim.run(given.get("t_end", scen.t_end), params=overrides, progress=progress, **opts)
    except InitializationError as err:
        if not overrides:
            raise
        raise InitializationError(f"{err}\n{_overrides_note(scen, params)}") from None
    except SolverError as err:
        if err.result is not None:
            err.result.metadata["run"] = recorded
            _save_kept(err.result, out, "the partial result", opts.get("outputs"))
        raise
    c2 = _time.process_time()
    result.metadata["run"] = recorded
    _save_kept(result, out, "the result", opts.get("outputs"))
    return ScenarioRun(result, instance, entry, scen, c1 - c0, c2 - c1)


def scenario_model(model: str, scenario: str | Scenario | None = None) -> tuple[Any, Scenario]:
    """The model instance a scenario of a registered model runs (``entry.factory``; its failures name the model and
    the scenario) and the scenario, checked against the model: for code that uses the model otherwise than by
    :func:`run_scenario` (``flexlib export-fmu``). The scenario's parameter overrides are ``scenario.params``."""
    entry = get_model(model)
    scen = entry.checked(scenario if isinstance(scenario, Scenario) else entry.scenario(scenario))
    return _build_instance(entry, scen), scen


def _checked_request(entry: ModelEntry, scenario: str | Scenario | None, params: Mapping[str, float] | None,
                     t_end: float | None, result_file: str | os.PathLike | None,
                     run: Mapping[str, Any]) -> tuple[Scenario, dict | None, Path | None, dict, str]:
    """The arguments of :func:`run_scenario` checked before anything is built: ``(scenario checked against the
    model, parameter overrides, result file, the options given on top of the scenario's, the run record as
    JSON)``."""
    from flexlib.solve.run_options import check_result_target

    if scenario is not None and not isinstance(scenario, (str, Scenario)):
        raise RunArgumentError(f"run_scenario: scenario must be a scenario name or a Scenario record, got "
                               f"{type(scenario).__name__}")
    scen = entry.checked(scenario if isinstance(scenario, Scenario) else entry.scenario(scenario))
    if params is not None:
        params = check_params(frozen_mapping(params, "run_scenario: params"), "run_scenario")
    unknown = [k for k in run if k not in RUN_OPTIONS]
    if unknown:
        raise RunArgumentError(f"run_scenario: unknown run option {unknown[0]!r} (allowed: {', '.join(RUN_OPTIONS)})")
    out = check_result_target(result_file, "result_file") if result_file is not None else None
    given = {k: v for k, v in run.items() if v is not None}
    if t_end is not None:
        given["t_end"] = t_end
    options_as_params = [k for k in {**dict(scen.params), **dict(params or {})} if k in entry.option_names]
    if options_as_params:
        k = options_as_params[0]
        raise RunArgumentError(f"model {entry.name!r}: {k!r} is given as a parameter override, but it is a model "
                               f"option ({entry.option(k).accepted()}): give it as an option (--option {k}=VALUE, "
                               f"or in the scenario's options)")
    record = RunRecord(model=entry.name, scenario=scen.to_dict(), params=dict(params or {}), run=given)
    # before the build: a value JSON cannot hold must not fail after the run
    return scen, params, out, given, record_json(record, scen)


def _build_instance(entry: ModelEntry, scen: Scenario) -> Any:
    """``entry.factory(scen)``; every failure names the model and the scenario (a model's own error keeps its
    class, any other failure of the factory is a :class:`ModelError`), and so does a factory that returns
    something other than a flexlib model."""
    from flexlib.core.component import Component

    where = f"model {entry.name!r}, {scen.label}"
    try:
        instance = entry.factory(scen)
    except ParameterError as err:  # a bad value in the scenario's data (or an undeclared option): name the scenario
        raise ParameterError(f"{where}: {err}") from None
    except TypeError as err:  # an undeclared option that does not fit the factory, or a value of the wrong type
        raise RunArgumentError(f"{where}: the model could not be built from the options {dict(scen.options)} and "
                               f"the data {sorted(scen.data)}: {err}") from None
    except FlexlibError:
        raise
    except Exception as err:  # the factory's own failure: one message naming the model, the cause chained
        raise ModelError(f"{where}: its factory failed: {type(err).__name__}: {err}") from err
    if not isinstance(instance, Component):
        raise ModelError(f"{where}: its factory returned {type(instance).__name__} {instance!r:.60}, not a flexlib "
                         "model (a Component)")
    return instance


def _check_run_values(entry: ModelEntry, scen: Scenario, instance: Any, given: Mapping[str, Any],
                      opts: Mapping[str, Any], overrides: Mapping[str, Any], progress: Any) -> None:
    """The run's own argument checks (:func:`~flexlib.solve.run_options.check_run_arguments`), done before the
    build; a value that comes from the scenario (its ``t_end`` or ``run``) is named with the scenario (and its
    file)."""
    import inspect

    from flexlib.solve.options import Experiment
    from flexlib.solve.run_options import check_run_arguments
    from flexlib.solve.simulation import Simulation

    defaults = {k: p.default for k, p in inspect.signature(Simulation.run).parameters.items()
                if p.default is not inspect.Parameter.empty}
    args = {**defaults, **opts, "t_end": given.get("t_end", scen.t_end), "params": dict(overrides),
            "progress": progress, "result_file": None}
    names = [k for k in inspect.signature(check_run_arguments).parameters if k not in ("experiment", "source")]
    if any(k not in args for k in names):  # Simulation.run's defaults not found (a wrapped run): the run checks
        return
    exp = getattr(instance, "experiment", None)
    if not isinstance(exp, Experiment):  # none, or not a record: the run names it (Simulation._experiment)
        if exp is not None:
            return
        exp = Experiment()
    try:
        check_run_arguments(exp, f"{type(instance).__name__}.experiment", **{k: args[k] for k in names})
    except RunArgumentError as err:
        arg = getattr(err, "argument", None)
        from_scenario = arg not in given and (arg in scen.run or (arg == "t_end" and scen.t_end is not None))
        if not from_scenario:
            raise
        field_ = "t_end" if arg == "t_end" else f"run option {arg}"
        raise RunArgumentError(f"model {entry.name!r}, {scen.label}: {err} (the value is the scenario's "
                               f"{field_})") from None


def _save_kept(result: Any, out: Path | None, what: str, outputs: Any = None) -> None:
    """Write ``result`` to ``out`` (if given) without ever losing it: a failed write (directory removed during
    the run, disk full) is a :class:`ResultSaveWarning` naming the file and the reason, and the result is kept
    (returned, or on ``err.result``), as ``Simulation.run(result_file=...)`` does."""
    if out is None:
        return
    from flexlib.results.hdf5 import keep_outputs

    try:
        result.save(out, outputs=keep_outputs(result, outputs, out))
    except Exception as err:  # any failure to write must not hide the finished run
        reason = str(err) if isinstance(err, ResultFileError) else f"{out}: {type(err).__name__}: {err}"
        warnings.warn(ResultSaveWarning(f"{what} was not saved: {reason}; it is kept in memory (returned, or "
                                        "err.result of the solver error)"), stacklevel=3)
