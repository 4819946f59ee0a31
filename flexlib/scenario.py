"""What a run is: a :class:`Scenario` (data: end time, parameter overrides, run and model options, free-form data)
and the :class:`ModelOption` declarations its model options are checked against.

Both are records a user writes in Python or JSON (:meth:`Scenario.from_dict`, :meth:`Scenario.from_json`); the
registry (:mod:`flexlib.registry`) checks a scenario against the model it runs and is where model authors import
them from.
"""

from __future__ import annotations

import difflib
import json
import math
import numbers
import os
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from flexlib.errors import RegistryError, RunArgumentError

__all__ = ["BOOL_WORDS", "NONE_WORDS", "RUN_OPTIONS", "ModelOption", "Scenario", "check_params", "frozen_mapping"]

#: Keyword arguments of :meth:`flexlib.Simulation.run` a scenario may set in ``run``.
RUN_OPTIONS = ("t_start", "dt_out", "rtol", "atol", "max_step", "max_steps", "max_order", "solver",
               "steady_state", "dynamic_states", "outputs")

def frozen_mapping(mapping: Mapping[str, Any] | None, what: str) -> Mapping[str, Any]:
    """A read-only copy of ``mapping`` (``None``: empty) with str keys; :class:`RunArgumentError` naming ``what``
    otherwise."""
    if mapping is None:
        return MappingProxyType({})
    if not isinstance(mapping, Mapping):
        raise RunArgumentError(f"{what} must be a mapping (dict), got {type(mapping).__name__}")
    bad = [k for k in mapping if not isinstance(k, str)]
    if bad:
        raise RunArgumentError(f"{what}: keys must be str, got {bad[0]!r}")
    return MappingProxyType(dict(mapping))


def check_params(params: Mapping[str, Any], who: str) -> dict[str, float]:
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
            object.__setattr__(self, key, frozen_mapping(getattr(self, key), f"{who}: {key}"))
        unknown = [k for k in self.run if k not in RUN_OPTIONS]
        if unknown:
            close = difflib.get_close_matches(unknown[0], RUN_OPTIONS, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            if unknown[0] == "t_end":
                hint = "; the end time is the scenario's own field t_end, beside run"
            raise RunArgumentError(f"{who}: unknown run option {unknown[0]!r} (allowed: {', '.join(RUN_OPTIONS)})"
                                   f"{hint}")
        object.__setattr__(self, "params", MappingProxyType(check_params(self.params, who)))

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
