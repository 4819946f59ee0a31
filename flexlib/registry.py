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
"""

from __future__ import annotations

import difflib
import importlib
import json
import math
import numbers
import os
import sys
import time as _time
import traceback
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

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

__all__ = ["RUN_OPTIONS", "ModelEntry", "ModelOption", "RunRecord", "Scenario", "ScenarioRun", "get_model",
           "get_scenario", "import_user_module", "models", "register_model", "register_scenario", "run_scenario",
           "run_settings"]

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


def _check_params(params: Mapping[str, Any], who: str) -> dict[str, float]:
    """Parameter overrides, each a finite number (an int kept, any other real as float: JSON-ready); the name and
    the bounds are checked by the run."""
    for pname, value in params.items():
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise RunArgumentError(f"{who}: parameter {pname!r} must be a finite number (SI units), got {value!r}")
    return {k: v if isinstance(v, int) else float(v) for k, v in params.items()}


class _DuplicateKey(ValueError):
    """A JSON object with a key given twice (raised by :func:`_no_duplicate_keys`)."""


def _no_duplicate_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """``object_pairs_hook`` of :func:`json.load` refusing a key given twice in one object."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise _DuplicateKey(key)
        out[key] = value
    return out


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
    source : str, optional
        The file the scenario was read from (:meth:`from_file`), named in error messages; not part of
        :meth:`to_dict`.

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
    source: str = field(default="", compare=False, repr=False)

    @property
    def label(self) -> str:
        """``scenario 'name'`` and, for a scenario read from a file, ``(file PATH)``: how messages name it."""
        return f"scenario {self.name!r}" + (f" (file {self.source})" if self.source else "")

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise RunArgumentError(f"Scenario: name must be a non-empty str, got {self.name!r}")
        if not isinstance(self.source, str):
            raise RunArgumentError(f"scenario {self.name!r}: source must be a str (a file path), got "
                                   f"{type(self.source).__name__}")
        who = self.label
        if not isinstance(self.doc, str):
            raise RunArgumentError(f"{who}: doc must be a str, got {type(self.doc).__name__}")
        if self.t_end is not None:
            if _is_bool(self.t_end) or not isinstance(self.t_end, numbers.Real) \
                    or not math.isfinite(self.t_end) or self.t_end <= 0:
                raise RunArgumentError(f"{who}: t_end must be a positive finite number of seconds, got {self.t_end!r}")
            object.__setattr__(self, "t_end", float(self.t_end))
        for key in ("params", "run", "options", "data"):
            object.__setattr__(self, key, _frozen(getattr(self, key), f"{who}: {key}"))
        unknown = [k for k in self.run if k not in RUN_OPTIONS]
        if unknown:
            close = difflib.get_close_matches(unknown[0], RUN_OPTIONS, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            if unknown[0] == "t_end":
                hint = "; the end time is the scenario's own field t_end, beside run"
            raise RunArgumentError(f"{who}: unknown run option {unknown[0]!r} (allowed: {', '.join(RUN_OPTIONS)})"
                                   f"{hint}")
        object.__setattr__(self, "params", MappingProxyType(_check_params(self.params, who)))

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
            raise RunArgumentError(f"a scenario needs a 'name' (fields: {', '.join(known)})")
        return cls(**dict(d))

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> Scenario:
        """Read a scenario from a JSON file (:meth:`from_dict`); errors name the file.

        The file is UTF-8 (a byte-order mark is allowed); a key given twice in one object (a hand edit that
        JSON readers would resolve silently, keeping the last) is an error naming it.

        Raises
        ------
        RunArgumentError
            ``path`` is not a path, the file cannot be read, is not JSON, repeats a key or is not a scenario
            (:meth:`from_dict`); the message names the file.
        """
        if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)) or not os.fspath(path):
            raise RunArgumentError(f"Scenario.from_file: the path of a JSON scenario file must be a non-empty str "
                                   f"or os.PathLike, got {path!r} ({type(path).__name__})")
        try:
            with open(path, encoding="utf-8-sig") as fh:
                raw = json.load(fh, object_pairs_hook=_no_duplicate_keys)
        except OSError as err:
            raise RunArgumentError(f"cannot read the scenario file {os.fspath(path)}: "
                                   f"{err.strerror or err}") from None
        except _DuplicateKey as err:
            raise RunArgumentError(f"the scenario file {os.fspath(path)}: the key {err.args[0]!r} is given twice "
                                   "in one object; give it once") from None
        except ValueError as err:
            raise RunArgumentError(f"the scenario file {os.fspath(path)} is not valid JSON: {err}") from None
        try:
            scenario = cls.from_dict(raw)
        except RunArgumentError as err:
            raise RunArgumentError(f"{os.fspath(path)}: {err}") from None
        return replace(scenario, source=os.fspath(path))


#: Command-line words of a ``bool`` option (case-insensitive).
BOOL_WORDS = {"true": True, "yes": True, "1": True, "false": False, "no": False, "0": False}
#: Command-line words of ``None`` for an option declared with ``allow_none``.
NONE_WORDS = ("none", "null")
_OPTION_TYPES = (bool, int, float, str, None)


def _is_bool(value: Any) -> bool:
    return isinstance(value, (bool, np.bool_))


@dataclass(frozen=True)
class ModelOption:
    """Declaration of one model option (``register_model(..., options=[ModelOption(...), ...])``).

    A scenario's value (Python, a JSON file) and the command line's ``--option NAME=VALUE`` text are checked
    against the declaration once, before the model's factory runs (:meth:`ModelEntry.check_options`,
    :meth:`ModelEntry.parse_options`); a model class may check its own keyword with the same declaration
    (:meth:`validate` with ``error=ParameterError``).

    Parameters
    ----------
    name : str
        The keyword the factory reads (``n``, ``filled``).
    type : {bool, int, float, str} or None
        ``bool``: ``True``/``False`` (on the command line ``true/false/yes/no/1/0``, any case; nothing else);
        ``int``: an integer, not a bool; ``float``: a finite int or float, not a bool (returned as ``float``);
        ``str``: text; ``None``: any value ``check`` accepts (on the command line read as JSON, else as text).
    default : Any
        What the model uses when the option is not given (shown by :meth:`describe`); must pass the declaration.
    doc : str
        One-line description.
    choices : sequence, optional
        The accepted values, all others refused.
    low, high : float, optional
        Bounds of an ``int`` or ``float`` value, inclusive unless ``low_open`` / ``high_open``.
    unit : str
        SI unit of a number (``"m2"``), named in messages.
    allow_none : bool
        ``None`` (JSON ``null``; ``none`` or ``null`` on the command line) is accepted: the model's own choice.
    check : callable, optional
        ``check(value) -> value``: a further check or normalisation after the type's; raises ``ValueError`` whose
        text completes the sentence "<name> ...", e.g. ``"must give every section 1-5 (missing [2])"``.
    accepts : str, optional
        What is accepted, for messages (default: from the type, the choices and the bounds).

    Raises
    ------
    RegistryError
        The declaration itself is malformed (a type other than those above, bounds on a non-number or that leave
        no value, ``choices`` that is not a sequence, ``doc``/``unit``/``accepts`` not a str, a flag not a bool, a
        default the declaration refuses).
    """

    name: str
    type: Any
    default: Any = None
    doc: str = ""
    choices: tuple[Any, ...] = ()
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    unit: str = ""
    allow_none: bool = False
    check: Callable[[Any], Any] | None = None
    accepts: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise RegistryError(f"ModelOption: name must be a Python identifier (a keyword), got {self.name!r}")
        who = f"ModelOption({self.name!r})"
        if self.type not in _OPTION_TYPES:
            raise RegistryError(f"{who}: type must be bool, int, float, str or None, got {self.type!r}")
        for text in ("doc", "unit", "accepts"):
            if not isinstance(getattr(self, text), str):
                raise RegistryError(f"{who}: {text} must be a str, got {getattr(self, text)!r}")
        for flag in ("low_open", "high_open", "allow_none"):
            if not _is_bool(getattr(self, flag)):
                raise RegistryError(f"{who}: {flag} must be True or False, got {getattr(self, flag)!r}")
        if isinstance(self.choices, (str, bytes, Mapping)) or not isinstance(self.choices, Iterable):
            raise RegistryError(f"{who}: choices must be a sequence of the accepted values (a list or tuple), got "
                                f"{self.choices!r}")
        object.__setattr__(self, "choices", tuple(self.choices))
        if (self.low is not None or self.high is not None) and self.type not in (int, float):
            raise RegistryError(f"{who}: low/high bound an int or float option, not {self.type}")
        for bound in ("low", "high"):
            value = getattr(self, bound)
            if value is not None and (_is_bool(value) or not isinstance(value, numbers.Real) or math.isnan(value)):
                raise RegistryError(f"{who}: {bound} must be a number, got {value!r}")
        if self.low is not None and self.high is not None and (
                self.low > self.high or (self.low == self.high and (self.low_open or self.high_open))):
            raise RegistryError(f"{who}: the bounds low = {self.low!r} and high = {self.high!r} leave no value "
                                "accepted")
        if self.check is not None and not callable(self.check):
            raise RegistryError(f"{who}: check must be callable, got {type(self.check).__name__}")
        if self.default is not None or not self.allow_none:
            try:
                self.validate(self.default)
            except RunArgumentError as err:
                raise RegistryError(f"{who}: the default is refused by the declaration: {err}") from None

    def accepted(self) -> str:
        """What the option accepts, in words (``"an integer >= 1"``, ``"a number in (0, 1] [m2]"``)."""
        if self.accepts:
            text = self.accepts
        elif self.choices:
            text = "one of " + ", ".join(repr(c) for c in self.choices)
        elif self.type is bool:
            text = "true or false"
        elif self.type in (int, float):
            text = ("an integer" if self.type is int else "a finite number") + self._range()
            text += f" [{self.unit}]" if self.unit else ""
        elif self.type is str:
            text = "a string"
        else:
            text = "any value"
        return text + (" or none (the model's default)" if self.allow_none else "")

    def _range(self) -> str:
        lo, hi = self.low, self.high
        if lo is not None and hi is not None:
            return f" in {'(' if self.low_open else '['}{lo:g}, {hi:g}{')' if self.high_open else ']'}"
        if lo is not None:
            return f" {'>' if self.low_open else '>='} {lo:g}"
        if hi is not None:
            return f" {'<' if self.high_open else '<='} {hi:g}"
        return ""

    def describe(self) -> str:
        """One line: ``name: accepted values (default ...): doc``."""
        return f"{self.name}: {self.accepted()} (default {self.default!r})" + (f": {self.doc}" if self.doc else "")

    def validate(self, value: Any, where: str = "", *, error: type[Exception] = RunArgumentError,
                 label: str | None = None) -> Any:
        """``value`` checked against the declaration and normalised (``float`` for a float option).

        Parameters
        ----------
        value : Any
            The option's value.
        where : str
            Prefix of the message (``"model 'n-mass-chain', scenario 'short': "``).
        error : exception class
            Raised for a refused value (default :class:`~flexlib.errors.RunArgumentError`; a model class checking
            its own keyword passes :class:`~flexlib.errors.ParameterError`).
        label : str, optional
            How the message names the option (default its name).

        Raises
        ------
        error
            Naming the option, the value given and what is accepted.
        """
        label = self.name if label is None else label

        def refused() -> Exception:
            return error(f"{where}{label} must be {self.accepted()}, got {value!r}")

        if value is None:
            if self.allow_none or (self.type is None and self.check is None):  # an untyped option: any value
                return None
            raise refused()
        t = self.type
        if t is bool:
            if not _is_bool(value):
                raise refused()
            value = bool(value)
        elif t is int:
            if _is_bool(value) or not isinstance(value, numbers.Integral):
                raise refused()
            value = int(value)
        elif t is float:
            if _is_bool(value) or not isinstance(value, numbers.Real) or not math.isfinite(value):
                raise refused()
            value = float(value)
        elif t is str and not isinstance(value, str):
            raise refused()
        if self.choices and not any(value == c and type(value) is type(c) for c in self.choices):
            raise refused()
        if t in (int, float):
            lo, hi = self.low, self.high
            if lo is not None and (value <= lo if self.low_open else value < lo):
                raise refused()
            if hi is not None and (value >= hi if self.high_open else value > hi):
                raise refused()
        if self.check is not None:
            try:
                value = self.check(value)
            except (ValueError, TypeError) as err:
                raise error(f"{where}{label} {err}") from None
            except Exception as err:  # a check that fails otherwise: a bug of the declaration, named as such
                raise error(f"{where}{label}: the option's check failed on {value!r}: {type(err).__name__}: "
                            f"{err}") from err
        return value

    def parse(self, text: str, where: str = "", *, error: type[Exception] = RunArgumentError,
              label: str | None = None) -> Any:
        """The command line's text of the option converted by the declared type, then :meth:`validate`.

        ``bool``: ``true/false/yes/no/1/0`` (any case); ``int`` and ``float``: Python's literal; ``str``: the
        text; type ``None``: JSON, else the text; ``none`` or ``null`` where ``allow_none``.
        """
        label = self.name if label is None else label
        if not isinstance(text, str):
            raise error(f"{where}{label}: parse reads the command line's text (a str), got {text!r} "
                        f"({type(text).__name__}); a Python value is checked with validate()")
        s = text.strip()
        if self.allow_none and s.lower() in NONE_WORDS:
            return None
        t = self.type
        value: Any = s
        try:
            if t is bool:
                value = BOOL_WORDS[s.lower()]
            elif t is int:
                value = int(s)
            elif t is float:
                value = float(s)
        except (KeyError, ValueError):
            accepted = self.accepted()
            if t is bool and not self.accepts:
                accepted = "true or false (true/false/yes/no/1/0, any case)" + (" or none" if self.allow_none else "")
            raise error(f"{where}{label} must be {accepted}, got {text!r}") from None
        if t is None:
            try:
                value = json.loads(s)
            except ValueError:
                value = s
        return self.validate(value, where, error=error, label=label)


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
    scen: dict[str, Scenario] = {}
    for s in scenarios:
        if not isinstance(s, Scenario):
            raise RegistryError(f"register_model({name!r}): scenarios must be Scenario records, got {s!r}")
        if s.name in scen:
            raise RegistryError(f"register_model({name!r}): two scenarios named {s.name!r}")
        scen[s.name] = s
    if not scen:
        raise RegistryError(f"register_model({name!r}): give at least one scenario")
    specs: dict[str, ModelOption] = {}
    for o in options:
        spec = ModelOption(o, None, doc="(untyped)") if isinstance(o, str) else o
        if not isinstance(spec, ModelOption):
            raise RegistryError(f"register_model({name!r}): options must be ModelOption declarations (or names), "
                                f"got {o!r}")
        if spec.name in specs:
            raise RegistryError(f"register_model({name!r}): two options named {spec.name!r}")
        specs[spec.name] = spec
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


def _import_failure(err: BaseException) -> str:
    """``Type: message (file:line)`` of an import failure: for a SyntaxError the offending line of the module,
    otherwise the innermost frame of the traceback outside the import machinery."""
    text = f"{type(err).__name__}: {err.msg if isinstance(err, SyntaxError) else err}"
    if isinstance(err, SyntaxError) and err.filename:
        return f"{text} ({err.filename}:{err.lineno})"
    machinery = (os.path.abspath(__file__), os.path.abspath(importlib.__file__))
    frames = [f for f in traceback.extract_tb(err.__traceback__)
              if not f.filename.startswith("<frozen") and os.path.abspath(f.filename) not in machinery]
    return f"{text} ({frames[-1].filename}:{frames[-1].lineno})" if frames else text


def module_hint(module: str) -> str:
    """A hint for a model module given as a file (``my_models.py``, ``./my_models``): what to give instead; ``""``
    for a module name."""
    if not (module.endswith(".py") or "/" in module or os.sep in module):
        return ""
    name = Path(module).name.removesuffix(".py")
    return (f" (give the module's name, {name!r}, not its file: run from its directory or put that directory on "
            "PYTHONPATH)")


def import_user_module(module: str) -> None:
    """Import a user's model module (``$FLEXLIB_MODELS``, ``flexlib --models``), also from the working directory
    (searched after the installed packages); its errors propagate (the callers name the module and the source of
    the name)."""
    if "" not in sys.path:
        sys.path.append("")
    importlib.import_module(module)


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
                                f"{_import_failure(err)}{module_hint(module)}") from None
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
        """The record as JSON (numpy arrays and scalars as lists and numbers); ``TypeError`` for a value JSON
        cannot hold."""
        return json.dumps({"model": self.model, "scenario": self.scenario, "params": self.params, "run": self.run},
                          default=_json_value)


def _json_value(value: Any) -> Any:
    """``json.dumps(default=...)``: a numpy array as a list, a numpy scalar as a number; ``TypeError`` otherwise."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} {value!r} cannot be written as JSON")


def _record_json(record: RunRecord, scen: Scenario) -> str:
    """``record.to_json()``, checked before the build: a scenario value JSON cannot hold (an object, a
    function) is a :class:`RunArgumentError` naming the scenario and the field, not a failure after the run."""
    try:
        return record.to_json()
    except (TypeError, ValueError) as err:
        fields = {"options": scen.options, "data": scen.data, "run": scen.run}
        for key, mapping in fields.items():
            for name, value in mapping.items():
                try:
                    json.dumps(value, default=_json_value)
                except (TypeError, ValueError) as sub:
                    raise RunArgumentError(f"{scen.label}: {key}[{name!r}] cannot be recorded in the result (the "
                                           f"run settings are JSON: lists, numbers, str, bool, None and dicts with "
                                           f"str keys): {sub}") from None
        raise RunArgumentError(f"{scen.label}: the run settings cannot be recorded as JSON: {err}") from None


def run_settings(result: Any, source: str = "the result") -> RunRecord:
    """The run settings recorded by :func:`run_scenario` in a result (loaded with ``flexlib.load_result``).

    Raises
    ------
    ResultFileError
        The result holds no run record (it was not written by :func:`run_scenario` / ``flexlib run``) or the
        record is damaged (not JSON, a field missing or of the wrong type, named); names ``source``.
    RunArgumentError
        ``result`` is not a Result (a path: read it with ``flexlib.load_result``).
    """
    metadata = getattr(result, "metadata", None)
    if isinstance(result, (str, bytes, os.PathLike)) or not isinstance(metadata, Mapping):
        raise RunArgumentError(f"run_settings takes a Result (read a file with flexlib.load_result(path)), got "
                               f"{result!r} ({type(result).__name__})")
    raw = metadata.get("run")
    if raw is None:
        raise ResultFileError(f"{source} holds no run settings (it was not written by 'flexlib run' or "
                              "flexlib.registry.run_scenario)")
    damaged = f"{source}: the run settings (meta_run) are damaged"
    try:
        d = json.loads(raw)
    except (ValueError, TypeError) as err:
        raise ResultFileError(f"{damaged}: not JSON ({err})") from None
    if not isinstance(d, dict):
        raise ResultFileError(f"{damaged}: a JSON object with model, scenario, params and run is expected, got "
                              f"{type(d).__name__}")
    missing = [k for k in ("model", "scenario", "params", "run") if k not in d]
    if missing:
        raise ResultFileError(f"{damaged}: the field {missing[0]!r} is missing")
    if not isinstance(d["model"], str):
        raise ResultFileError(f"{damaged}: the field 'model' must be a model name (str), got {d['model']!r}")
    for key in ("scenario", "params", "run"):
        if not isinstance(d[key], dict):
            raise ResultFileError(f"{damaged}: the field {key!r} must be a JSON object, got {d[key]!r}")
    return RunRecord(model=d["model"], scenario=d["scenario"], params=d["params"], run=d["run"])


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
    from flexlib.solve.run_options import check_result_target
    from flexlib.solve.simulation import Simulation

    entry = get_model(model)
    if scenario is not None and not isinstance(scenario, (str, Scenario)):
        raise RunArgumentError(f"run_scenario: scenario must be a scenario name or a Scenario record, got "
                               f"{type(scenario).__name__}")
    scen = entry.checked(scenario if isinstance(scenario, Scenario) else entry.scenario(scenario))
    if params is not None:
        params = _check_params(_frozen(params, "run_scenario: params"), "run_scenario")
    unknown = [k for k in run if k not in RUN_OPTIONS]
    if unknown:
        raise RunArgumentError(f"run_scenario: unknown run option {unknown[0]!r} (allowed: {', '.join(RUN_OPTIONS)})")
    out = check_result_target(result_file, "result_file") if result_file is not None else None
    given = {k: v for k, v in run.items() if v is not None}
    if t_end is not None:
        given["t_end"] = t_end
    overrides = {**dict(scen.params), **dict(params or {})}
    options_as_params = [k for k in overrides if k in entry.option_names]
    if options_as_params:
        k = options_as_params[0]
        raise RunArgumentError(f"model {entry.name!r}: {k!r} is given as a parameter override, but it is a model "
                               f"option ({entry.option(k).accepted()}): give it as an option (--option {k}=VALUE, "
                               f"or in the scenario's options)")
    record = RunRecord(model=entry.name, scenario=scen.to_dict(), params=dict(params or {}), run=given)
    recorded = _record_json(record, scen)  # before the build: a value JSON cannot hold must not fail after the run
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
            _save_kept(err.result, out, "the partial result")
        raise
    c2 = _time.process_time()
    result.metadata["run"] = recorded
    _save_kept(result, out, "the result")
    return ScenarioRun(result, instance, entry, scen, c1 - c0, c2 - c1)


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

    from flexlib.solve.run_options import check_run_arguments
    from flexlib.solve.simulation import Experiment, Simulation

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


def _save_kept(result: Any, out: Path | None, what: str) -> None:
    """Write ``result`` to ``out`` (if given) without ever losing it: a failed write (directory removed during
    the run, disk full) is a :class:`ResultSaveWarning` naming the file and the reason, and the result is kept
    (returned, or on ``err.result``), as ``Simulation.run(result_file=...)`` does."""
    if out is None:
        return
    try:
        result.save(out)
    except Exception as err:  # any failure to write must not hide the finished run
        reason = str(err) if isinstance(err, ResultFileError) else f"{out}: {type(err).__name__}: {err}"
        warnings.warn(ResultSaveWarning(f"{what} was not saved: {reason}; it is kept in memory (returned, or "
                                        "err.result of the solver error)"), stacklevel=3)
