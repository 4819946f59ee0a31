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

Lookups of unknown names raise :class:`~flexlib.errors.RegistryError` naming the unknown name, the known ones
and the closest match.
"""

from __future__ import annotations

import difflib
import importlib
import json
import math
import os
import time as _time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from flexlib.errors import RegistryError, ResultFileError, ResultSaveWarning, RunArgumentError, SolverError

__all__ = ["RUN_OPTIONS", "ModelEntry", "RunRecord", "Scenario", "ScenarioRun", "get_model", "get_scenario", "models",
           "register_model", "register_scenario", "run_scenario", "run_settings"]

#: Keyword arguments of :meth:`flexlib.Simulation.run` a scenario may set in ``run``.
RUN_OPTIONS = ("t_start", "dt_out", "rtol", "atol", "max_step", "max_steps", "max_order", "solver",
               "steady_state", "dynamic_states")

#: Package searched for built-in registrations: each of its modules (subpackages included) whose source calls
#: ``register_model(`` is imported on the first lookup, so a new model (``models/pump_truck/``) only registers
#: itself beside its definition.
BUILTIN_PACKAGE = "flexlib.models"

#: Environment variable: further modules (comma-separated) imported before a lookup, so that a user's own
#: models and scenarios appear in ``flexlib list`` and can be run.
MODULES_ENV = "FLEXLIB_MODELS"


def _frozen(mapping: Mapping[str, Any] | None, what: str) -> Mapping[str, Any]:
    if mapping is None:
        return MappingProxyType({})
    if not isinstance(mapping, Mapping):
        raise RunArgumentError(f"{what} must be a mapping (dict), got {type(mapping).__name__}")
    bad = [k for k in mapping if not isinstance(k, str)]
    if bad:
        raise RunArgumentError(f"{what}: keys must be str, got {bad[0]!r}")
    return MappingProxyType(dict(mapping))


@dataclass(frozen=True)
class Scenario:
    """One way to run a model: data, not code.

    Parameters
    ----------
    name : str
        Scenario name (``expand-fold``).
    doc : str
        One-line description.
    t_end : float, optional
        End time [s] (default: the model's ``experiment``).
    params : mapping, optional
        Parameter overrides ``{"mass0.m": 2.0}`` (SI), applied without recompiling.
    run : mapping, optional
        Options of :meth:`flexlib.Simulation.run`, a subset of :data:`RUN_OPTIONS` (``rtol``, ``atol``,
        ``dt_out`` [s], ``solver``, ...).
    options : mapping, optional
        Model options passed to the factory as keyword arguments (``flexible=True``, ``n=4``); structural.
    data : mapping, optional
        Free-form data the model's factory interprets (joint targets over time, valve commands, ...).

    Raises
    ------
    RunArgumentError
        A field has the wrong type, ``t_end`` is not a positive finite number, or ``run`` has a key that is not
        one of :data:`RUN_OPTIONS` (the message names the scenario and the key).
    """

    name: str
    doc: str = ""
    t_end: float | None = None
    params: Mapping[str, float] = field(default_factory=dict)
    run: Mapping[str, Any] = field(default_factory=dict)
    options: Mapping[str, Any] = field(default_factory=dict)
    data: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise RunArgumentError(f"Scenario: name must be a non-empty str, got {self.name!r}")
        who = f"scenario {self.name!r}"
        if not isinstance(self.doc, str):
            raise RunArgumentError(f"{who}: doc must be a str, got {type(self.doc).__name__}")
        if self.t_end is not None:
            if isinstance(self.t_end, bool) or not isinstance(self.t_end, (int, float)) \
                    or not math.isfinite(self.t_end) or self.t_end <= 0:
                raise RunArgumentError(f"{who}: t_end must be a positive finite number of seconds, got {self.t_end!r}")
            object.__setattr__(self, "t_end", float(self.t_end))
        for key in ("params", "run", "options", "data"):
            object.__setattr__(self, key, _frozen(getattr(self, key), f"{who}: {key}"))
        unknown = [k for k in self.run if k not in RUN_OPTIONS]
        if unknown:
            close = difflib.get_close_matches(unknown[0], RUN_OPTIONS, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise RunArgumentError(f"{who}: unknown run option {unknown[0]!r} (allowed: {', '.join(RUN_OPTIONS)})"
                                   f"{hint}")
        for pname, value in self.params.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise RunArgumentError(f"{who}: parameter {pname!r} must be a number, got {value!r}")

    def to_dict(self) -> dict[str, Any]:
        """The scenario as plain JSON-compatible data (inverse of :meth:`from_dict`)."""
        return {"name": self.name, "doc": self.doc, "t_end": self.t_end, "params": dict(self.params),
                "run": dict(self.run), "options": dict(self.options), "data": dict(self.data)}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Scenario:
        """A scenario from plain data (a parsed JSON file); unknown keys are an error naming them."""
        if not isinstance(d, Mapping):
            raise RunArgumentError(f"a scenario must be a mapping (JSON object), got {type(d).__name__}")
        known = ("name", "doc", "t_end", "params", "run", "options", "data")
        extra = [k for k in d if k not in known]
        if extra:
            raise RunArgumentError(f"scenario {d.get('name', '?')!r}: unknown field {extra[0]!r} "
                                   f"(fields: {', '.join(known)})")
        if "name" not in d:
            raise RunArgumentError("a scenario needs a 'name'")
        return cls(**dict(d))

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> Scenario:
        """Read a scenario from a JSON file (:meth:`from_dict`); errors name the file."""
        try:
            with open(path, encoding="utf-8") as fh:
                raw = json.load(fh)
        except OSError as err:
            raise RunArgumentError(f"cannot read the scenario file {os.fspath(path)}: "
                                   f"{err.strerror or err}") from None
        except ValueError as err:
            raise RunArgumentError(f"the scenario file {os.fspath(path)} is not valid JSON: {err}") from None
        try:
            return cls.from_dict(raw)
        except RunArgumentError as err:
            raise RunArgumentError(f"{os.fspath(path)}: {err}") from None


#: A model's summary signals: variable names, or a function of the built model instance returning them.
SummarySignals = Sequence[str] | Callable[[Any], Sequence[str]]


@dataclass
class ModelEntry:
    """A registered model (see :func:`register_model`)."""

    name: str
    factory: Callable[[Scenario], Any]
    doc: str
    scenarios: dict[str, Scenario]
    summary_signals: SummarySignals = ()
    default_scenario: str = ""
    options: tuple[str, ...] = ()
    plots: Callable[[Any, Any, Path], list[Path]] | None = None

    def check_options(self, scenario: Scenario) -> None:
        """:class:`RunArgumentError` naming a model option of ``scenario`` the factory does not read."""
        for key in scenario.options:
            if key not in self.options:
                allowed = ", ".join(self.options) if self.options else "none"
                raise RunArgumentError(f"model {self.name!r}, scenario {scenario.name!r}: unknown model option "
                                       f"{key!r} (options of {self.name}: {allowed})")

    def scenario(self, name: str | None = None) -> Scenario:
        """The scenario ``name`` (default: the model's default scenario)."""
        name = name or self.default_scenario
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
                   options: Sequence[str] = (),
                   plots: Callable[[Any, Any, Path], list[Path]] | None = None) -> ModelEntry:
    """Register a runnable model.

    Parameters
    ----------
    name : str
        Name used on the command line (``pump-truck``).
    factory : callable
        ``factory(scenario) -> Model``: builds the model instance for a :class:`Scenario` (its ``options`` and
        ``data``).
    doc : str
        One-line description.
    scenarios : sequence of Scenario
        At least one; the first is the default unless ``default_scenario`` says otherwise.
    summary_signals : sequence of str or callable
        Variables whose peaks ``flexlib run`` prints (or ``f(model) -> names``).
    default_scenario : str, optional
        Name of the default scenario.
    options : sequence of str
        Names of the model options the factory reads (``flexible``, ``n``); a scenario with another one is an
        error naming it.
    plots : callable, optional
        ``plots(model, result, directory) -> [paths]``: writes the model's figures (PNG) of a run into
        ``directory``; ``flexlib run --plots DIR`` calls it.

    Returns
    -------
    ModelEntry

    Raises
    ------
    RegistryError
        The name is taken by another factory, two scenarios share a name, or there is no scenario.
    """
    if not isinstance(name, str) or not name.strip():
        raise RegistryError(f"register_model: name must be a non-empty str, got {name!r}")
    if not callable(factory):
        raise RegistryError(f"register_model({name!r}): factory must be callable, got {type(factory).__name__}")
    scen: dict[str, Scenario] = {}
    for s in scenarios:
        if not isinstance(s, Scenario):
            raise RegistryError(f"register_model({name!r}): scenarios must be Scenario records, got {s!r}")
        if s.name in scen:
            raise RegistryError(f"register_model({name!r}): two scenarios named {s.name!r}")
        scen[s.name] = s
    if not scen:
        raise RegistryError(f"register_model({name!r}): give at least one scenario")
    old = _MODELS.get(name)
    # the same module imported under two names (models.x and flexlib.models.x) registers the same factory twice
    if old is not None and getattr(old.factory, "__qualname__", None) != getattr(factory, "__qualname__", None):
        raise RegistryError(f"register_model: the name {name!r} is already registered by "
                            f"{getattr(old.factory, '__module__', '?')}.{getattr(old.factory, '__qualname__', '?')}")
    default = default_scenario or next(iter(scen))
    if default not in scen:
        raise RegistryError(f"register_model({name!r}): " + _unknown("default scenario " + repr(default), default,
                                                                        scen))
    if plots is not None and not callable(plots):
        raise RegistryError(f"register_model({name!r}): plots must be callable, got {type(plots).__name__}")
    entry = ModelEntry(name, factory, doc, scen, summary_signals, default, tuple(options), plots)
    for s in scen.values():
        entry.check_options(s)
    _MODELS[name] = entry
    return entry


def register_scenario(model: str, scenario: Scenario) -> None:
    """Add a scenario to a registered model (a user's own); a name already in use is replaced."""
    if not isinstance(scenario, Scenario):
        raise RegistryError(f"register_scenario({model!r}): expected a Scenario, got {scenario!r}")
    entry = get_model(model)
    entry.check_options(scenario)
    entry.scenarios[scenario.name] = scenario


def builtin_modules() -> list[str]:
    """Modules of :data:`BUILTIN_PACKAGE` whose source calls ``register_model(`` (sorted), found by reading the
    files, so that modules without registrations (examples, scripts) are not imported."""
    package = importlib.import_module(BUILTIN_PACKAGE)
    found = []
    for root in map(Path, package.__path__):
        for path in sorted(root.rglob("*.py")):
            rel = path.relative_to(root).with_suffix("")
            if any(part.startswith(".") for part in rel.parts):
                continue
            try:
                if "register_model(" not in path.read_text(encoding="utf-8"):
                    continue
            except (OSError, UnicodeDecodeError):
                continue
            parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
            found.append(".".join((BUILTIN_PACKAGE, *parts)))
    return sorted(set(found))


def _load() -> None:
    global _loaded
    if _loaded:
        return
    extra = [m.strip() for m in os.environ.get(MODULES_ENV, "").split(",") if m.strip()]
    for module in (*builtin_modules(), *extra):
        try:
            importlib.import_module(module)
        except ImportError as err:
            if module in extra:
                raise RegistryError(f"cannot import the model module {module!r} named in ${MODULES_ENV}: "
                                    f"{err}") from None
            raise
    _loaded = True  # only once every module imported: a failed import is retried (and reported) next time


def models() -> dict[str, ModelEntry]:
    """All registered models by name (imports the built-in model modules on first use)."""
    _load()
    return dict(sorted(_MODELS.items()))


def get_model(name: str) -> ModelEntry:
    """The registered model ``name``; :class:`RegistryError` naming it and the known models otherwise."""
    _load()
    if name not in _MODELS:
        raise RegistryError(_unknown(f"model {name!r}", name, _MODELS))
    return _MODELS[name]


def get_scenario(model: str, scenario: str | None = None) -> Scenario:
    """A scenario of a registered model (default: its default scenario)."""
    return get_model(model).scenario(scenario)


@dataclass(frozen=True)
class RunRecord:
    """What :func:`run_scenario` stores in a result (``result.metadata["run"]``, JSON) to repeat the run.

    Attributes
    ----------
    model : str
        Registered model name.
    scenario : dict
        The full scenario (:meth:`Scenario.to_dict`), so that a user's own scenario repeats too.
    params : dict
        Parameter overrides given on top of the scenario's.
    run : dict
        Options given on top of the scenario's (``t_end``, ``rtol``, ...).
    """

    model: str
    scenario: dict[str, Any]
    params: dict[str, float]
    run: dict[str, Any]

    def to_json(self) -> str:
        return json.dumps({"model": self.model, "scenario": self.scenario, "params": self.params, "run": self.run})


def run_settings(result: Any, source: str = "the result") -> RunRecord:
    """The run settings recorded by :func:`run_scenario` in a result (loaded with ``flexlib.load_result``).

    Raises
    ------
    ResultFileError
        The result holds no run record (it was not written by :func:`run_scenario` / ``flexlib run``) or the
        record is damaged; names ``source``.
    """
    raw = getattr(result, "metadata", {}).get("run")
    if raw is None:
        raise ResultFileError(f"{source} holds no run settings (it was not written by 'flexlib run' or "
                              "flexlib.registry.run_scenario)")
    try:
        d = json.loads(raw)
        return RunRecord(model=str(d["model"]), scenario=dict(d["scenario"]), params=dict(d["params"]),
                         run=dict(d["run"]))
    except (ValueError, KeyError, TypeError) as err:
        raise ResultFileError(f"{source}: the run settings (meta_run) are damaged: {err}") from None


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
        Write the result (with the run settings) to this HDF5 file, also when the run fails.
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
        An option is not one of :data:`RUN_OPTIONS`, or ``result_file`` cannot be written (checked before the
        build).
    ParameterError
        Unknown parameter or value out of bounds.
    SolverError
        The run failed; ``err.result`` holds the rows up to the failure, with the run settings.
    """
    from flexlib.solve.run_options import check_result_path
    from flexlib.solve.simulation import Simulation

    entry = get_model(model)
    scen = scenario if isinstance(scenario, Scenario) else entry.scenario(scenario)
    entry.check_options(scen)
    unknown = [k for k in run if k not in RUN_OPTIONS]
    if unknown:
        raise RunArgumentError(f"run_scenario: unknown run option {unknown[0]!r} (allowed: {', '.join(RUN_OPTIONS)})")
    out = check_result_path(result_file, "result_file") if result_file is not None else None
    given = {k: v for k, v in run.items() if v is not None}
    if t_end is not None:
        given["t_end"] = t_end
    record = RunRecord(model=entry.name, scenario=scen.to_dict(), params=dict(params or {}), run=given)
    opts = {**dict(scen.run), **{k: v for k, v in given.items() if k != "t_end"}}
    c0 = _time.process_time()
    try:
        instance = entry.factory(scen)
    except TypeError as err:  # options that do not fit the factory (a user's scenario file)
        raise RunArgumentError(f"model {entry.name!r}, scenario {scen.name!r}: the model options "
                               f"{dict(scen.options)} do not fit the model: {err}") from None
    sim = Simulation(instance)
    c1 = _time.process_time()
    try:
        result = sim.run(given.get("t_end", scen.t_end), params={**dict(scen.params), **dict(params or {})},
                         progress=progress, **opts)
    except SolverError as err:
        if err.result is not None:
            err.result.metadata["run"] = record.to_json()
            if out is not None:
                try:
                    err.result.save(out)
                except ResultFileError as save_err:
                    warnings.warn(f"the partial result was not saved: {save_err}", ResultSaveWarning, stacklevel=2)
        raise
    c2 = _time.process_time()
    result.metadata["run"] = record.to_json()
    if out is not None:
        result.save(out)
    return ScenarioRun(result, instance, entry, scen, c1 - c0, c2 - c1)
