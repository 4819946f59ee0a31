"""Public option records of a run: :class:`Experiment` (a model class's defaults) and :class:`RunOptions` (the
arguments of :meth:`~flexlib.Simulation.run` as one frozen record). How a model is compiled is
:class:`~flexlib.compile.build_options.BuildOptions`; the integrator's own options are the solver objects of
:mod:`flexlib.solve.solvers`.
"""

from __future__ import annotations

import difflib
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from flexlib.errors import ModelError, RunArgumentError

__all__ = ["Experiment", "RunOptions", "experiment_of", "span_end"]


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


def experiment_of(model: Any) -> Experiment:
    """The ``experiment`` of a model instance (``Experiment()`` without one); :class:`~flexlib.errors.ModelError`
    naming it if it is something else (a dict, a number, the class ``Experiment`` itself), which failed with an
    AttributeError."""
    exp = getattr(model, "experiment", None)
    if exp is None:
        return Experiment()
    if not isinstance(exp, Experiment):
        shown = " ".join(repr(exp).split())
        shown = shown if len(shown) <= 80 else shown[:77] + "..."
        what = "the class itself, not an instance" if exp is Experiment else f"a {type(exp).__name__}"
        raise ModelError(f"{type(model).__name__}.experiment = {shown} is {what}; write experiment = "
                         "flexlib.Experiment(t_end=..., dt_out=..., rtol=..., atol=..., t_start=..., "
                         "max_order=...) (every field optional)")
    return exp


def span_end(t0: Any) -> Any:
    """A time after ``t0`` [s] by a span the argument check accepts (``t0 + 1``, more for a large ``|t0|``) for a
    finite number; anything else is passed on for the argument check to report."""
    try:
        start = float(t0)
    except (TypeError, ValueError):
        return t0
    return start + max(1.0, 1e-9 * abs(start)) if math.isfinite(start) else start + 1.0


@dataclass(frozen=True)
class RunOptions:
    """The settings of one run, as one record: ``sim.run(options=RunOptions(t_end=2.0, dt_out=0.01))``.

    Every field is an argument of :meth:`~flexlib.Simulation.run` of the same name and meaning (see there); a field
    left None takes the model's :class:`Experiment`. An argument given to ``run`` next to ``options`` replaces the
    record's field. The values are checked when the run starts, as the arguments are.

    Attributes
    ----------
    t_end, t_start : float or None
        Time span [s].
    dt_out : float or None
        Output interval [s].
    output_times : array_like or None
        Explicit output times [s].
    rtol, atol : float or None
        Tolerances (``atol`` scaled by each variable's nominal).
    max_step : float
        Largest step [s] (0: unlimited).
    max_steps : int
        Largest number of internal steps.
    params : mapping or None
        Parameter overrides ``{"component.parameter": value}``.
    steady_state, dynamic_states : bool
        Start in steady state; re-select states during the run.
    progress : bool or None
        Progress bar (None: after 2 s).
    result_file : str, os.PathLike or None
        HDF5 file to write the result to.
    solver : str or Solver
        ``"ida"`` (default), ``"ida-native"``, ``"ida-sksundae"``, ``"casadi-idas"`` or a solver object
        (:class:`flexlib.IDA`, :class:`flexlib.CasadiIDAS`).
    max_order : int or None
        Highest BDF order (1–5).
    outputs : str, list of str or None
        Variables the result file stores as columns besides the run's rows (names, array names, patterns with ``*``
        and ``?``); ``"all"``: every variable; None: the rows only, every variable derived when read.
    """

    t_end: float | None = None
    t_start: float | None = None
    dt_out: float | None = None
    output_times: Any = None
    rtol: float | None = None
    atol: float | None = None
    max_step: float = 0.0
    max_steps: int = 5_000_000
    params: Mapping[str, Any] | None = None
    steady_state: bool = False
    progress: bool | None = None
    result_file: str | os.PathLike | None = None
    solver: Any = "ida"
    dynamic_states: bool = True
    max_order: int | None = None
    outputs: Any = None

    def merged(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """The record's fields with the arguments in ``given`` (those differing from ``run``'s defaults) on top."""
        defaults = RunOptions()
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        for key, value in given.items():
            default = getattr(defaults, key)
            if value is not default and not _same(value, default):
                out[key] = value
        return out


def _same(a: Any, b: Any) -> bool:
    """``a == b`` for plain values (arrays, mappings and objects compare by identity)."""
    if isinstance(a, (np.ndarray, Mapping)) or isinstance(b, (np.ndarray, Mapping)):
        return a is b
    try:
        return bool(type(a) is type(b) and a == b)
    except Exception:
        return False
