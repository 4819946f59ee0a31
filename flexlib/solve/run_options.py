"""Checks of the arguments of :meth:`Simulation.run`, done before any work.

Every check raises :class:`~flexlib.errors.RunArgumentError` (a ``ValueError``) whose message names the
argument, the value given and what is allowed, so that a run cannot fail minutes later (or report success)
because of an argument: a zero output interval, an end time of ``inf``, output times past the end, a
``max_step`` too small to reach the end within ``max_steps``, an unwritable result file.
"""

from __future__ import annotations

import math
import numbers
import os
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.errors import RunArgumentError

__all__ = ["MAX_OUTPUT_POINTS", "SOLVERS", "RunOptions", "check_result_path", "check_run_arguments"]

#: Shortest run span [s], and at least 1e-12 of |t| (about 4500 units in the last place): below it IDA's first
#: step and error norms underflow, or the times cannot be told apart
MIN_SPAN = 1e-100
#: Largest output grid accepted (points); a larger one is almost certainly a unit mistake in ``dt_out``
#: (10 million rows of a 500-variable model are 40 GB).
MAX_OUTPUT_POINTS = 10_000_000

#: Integrator back ends accepted by ``run(solver=...)``.
SOLVERS = ("ida", "casadi-idas", "ida-native", "ida-sksundae")


@dataclass(frozen=True)
class RunOptions:
    """The checked and resolved arguments of one run.

    Attributes
    ----------
    t_start, t_end : float
        Time span [s], finite, ``t_end > t_start``.
    grid : ndarray or None
        Output times [s] (strictly increasing, inside the span), or None to record every step.
    rtol, atol : float
        Tolerances (``0 < rtol < 1``, ``atol > 0``).
    max_step : float
        Largest step [s] (0: unlimited).
    max_steps : int
        Largest number of steps.
    max_order : int
        Highest BDF order (1–5): as given, else the experiment's, else 5.
    params : dict
        Parameter overrides (string keys; values are checked by the parameter declarations).
    steady_state, dynamic_states : bool
        As given.
    progress : bool or None
        As given.
    solver : str
        One of :data:`SOLVERS`.
    result_file : Path or None
        Where the result will be written.
    """

    t_start: float
    t_end: float
    grid: np.ndarray | None
    rtol: float
    atol: float
    max_step: float
    max_steps: int
    max_order: int
    params: dict[str, Any]
    steady_state: bool
    dynamic_states: bool
    progress: bool | None
    solver: str
    result_file: Path | None


def _bad(name: str, value: Any, allowed: str, hint: str = "") -> RunArgumentError:
    shown = f"<array of shape {value.shape}>" if isinstance(value, np.ndarray) else " ".join(repr(value).split())
    if len(shown) > 80:
        shown = shown[:77] + "..."
    err = RunArgumentError(f"run(): {name} = {shown} is invalid: {allowed}{'; ' + hint if hint else ''}")
    err.argument = name  # type: ignore[attr-defined]
    return err


def _real(name: str, value: Any, allowed: str) -> float:
    """``value`` as a float; refuses bools, strings, arrays and other non-numbers."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise _bad(name, value, f"{allowed} (got a {type(value).__name__})")
    return float(value)


def _flag(name: str, value: Any, allow_none: bool = False) -> bool | None:
    if value is None and allow_none:
        return None
    if not isinstance(value, (bool, np.bool_)):
        allowed = "True, False or None" if allow_none else "True or False"
        raise _bad(name, value, f"must be {allowed} (got a {type(value).__name__})")
    return bool(value)


def check_result_path(result_file: Any, name: str = "result_file") -> Path:
    """Check that ``result_file`` names a file that can be written: a ``str`` or path-like, not a directory,
    inside a directory that exists and is writable or can be created. Writes and removes a probe file in
    the nearest existing directory. Raises :class:`RunArgumentError` otherwise."""
    if isinstance(result_file, bytes) or not isinstance(result_file, (str, os.PathLike)):
        raise _bad(name, result_file, f"must be a file path (str or os.PathLike), got a {type(result_file).__name__}")
    if not os.fspath(result_file).strip():
        raise _bad(name, result_file, "must be a file path, got an empty string")
    path = Path(os.fspath(result_file)).expanduser()
    if path.is_dir():
        raise _bad(name, result_file, f"{path} is a directory; give a file name such as {path / 'run.h5'}")
    existing = path.parent.absolute()
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise _bad(name, result_file, f"its directory cannot be created: {existing} is a file, not a directory")
    try:
        with tempfile.NamedTemporaryFile(dir=existing, prefix=".flexlib-probe-"):
            pass
    except OSError as err:
        reason = err.strerror or str(err)
        raise _bad(name, result_file, f"cannot write in {existing}: {reason}") from None
    return path


def _output_grid(t0: float, t1: float, dt_out: Any, output_times: Any) -> np.ndarray | None:
    if dt_out is not None and output_times is not None:
        raise _bad("dt_out", dt_out, "give either dt_out or output_times, not both")
    if output_times is not None:
        try:
            grid = np.array(output_times, dtype=float)
        except (TypeError, ValueError):
            raise _bad("output_times", output_times, "must be a 1-D sequence of times [s]") from None
        if grid.ndim != 1:
            raise _bad("output_times", output_times, f"must be 1-D, got shape {grid.shape}")
        if grid.size == 0:
            raise _bad("output_times", output_times, "must contain at least one time [s] (omit it to record "
                       "every solver step)")
        bad = np.flatnonzero(~np.isfinite(grid))
        if bad.size:
            raise _bad("output_times", output_times, f"must be finite; output_times[{bad[0]}] = {grid[bad[0]]}")
        slack = 1e-12 * max(1.0, abs(t0), abs(t1))
        if grid[0] < t0 - slack:
            raise _bad("output_times", output_times,
                       f"output_times[0] = {grid[0]:g} s is before t_start = {t0:g} s")
        if grid[-1] > t1 + slack:
            late = int(np.count_nonzero(grid > t1 + slack))
            raise _bad("output_times", output_times,
                       f"{late} time(s) after t_end = {t1:g} s (the last is {grid[-1]:g} s); raise t_end or drop them")
        grid = np.clip(grid, t0, t1)
        step = np.diff(grid)
        if np.any(step <= 0):
            k = int(np.flatnonzero(step <= 0)[0])
            raise _bad("output_times", output_times, f"must be strictly increasing; output_times[{k}] = "
                       f"{grid[k]:g} s and output_times[{k + 1}] = {grid[k + 1]:g} s (sort them, drop duplicates)")
        return grid
    if dt_out is None:
        return None
    dt = _real("dt_out", dt_out, "must be a positive number [s]")
    if not (math.isfinite(dt) and dt > 0.0):
        raise _bad("dt_out", dt_out, "must be a positive finite number [s]; omit it to record every solver step")
    points = (t1 - t0) / dt + 1.0
    if not points <= MAX_OUTPUT_POINTS:
        raise _bad("dt_out", dt_out, f"gives {points:.0f} output points over [{t0:g}, {t1:g}] s, more than "
                   f"{MAX_OUTPUT_POINTS}",
                   "use a larger dt_out, give the times you need as output_times, or omit dt_out to record "
                   "every solver step")
    # t0, t0 + dt, ... and always t1 itself as the last point. A multiple of dt within round-off of t1
    # (0.1 * 7 = 0.7000000000000001 for t_end = 0.7) is t1, not a point past the end: it is replaced by t1
    # exactly, so the run ends with a row at t_end whatever the floating-point ratio t_end / dt_out
    n = int(np.floor((t1 - t0) / dt + 1e-9))
    grid = t0 + dt * np.arange(n + 1)
    grid = grid[grid < t1 - 1e-9 * dt]
    return np.append(grid, t1)


def check_run_arguments(experiment: Any, source: str, *, t_start: Any, t_end: Any, dt_out: Any, output_times: Any,
                        rtol: Any, atol: Any, max_step: Any, max_steps: Any, params: Any, steady_state: Any,
                        dynamic_states: Any, progress: Any, solver: Any, result_file: Any,
                        max_order: Any = None) -> RunOptions:
    """Check every argument of a run and build the output grid.

    Parameters
    ----------
    experiment : Experiment
        The model's defaults for ``t_start``, ``t_end``, ``dt_out``, ``rtol`` and ``atol`` (``None`` given).
        ``dt_out`` is taken from it only when neither ``t_end``, ``dt_out`` nor ``output_times`` is given.
    source : str
        Where ``experiment`` comes from (``"Model.experiment"``), named when one of its values is invalid.
    t_start, t_end, dt_out, output_times, rtol, atol, max_step, max_steps, params, steady_state, \
dynamic_states, progress, solver, result_file, max_order
        As given to :meth:`Simulation.run` (``max_order`` None: the experiment's, if it has one).

    Returns
    -------
    RunOptions

    Raises
    ------
    RunArgumentError
        Naming the argument, the value and what is allowed.
    """
    defaulted = {name for name, given in (("t_start", t_start), ("t_end", t_end), ("rtol", rtol), ("atol", atol))
                 if given is None}
    if dt_out is None and output_times is None and t_end is None and experiment.dt_out is not None:
        dt_out = experiment.dt_out
        defaulted.add("dt_out")
    try:
        return _check(
            t_start=experiment.t_start if t_start is None else t_start,
            t_end=experiment.t_end if t_end is None else t_end, dt_out=dt_out, output_times=output_times,
            rtol=experiment.rtol if rtol is None else rtol, atol=experiment.atol if atol is None else atol,
            max_step=max_step, max_steps=max_steps, params=params, steady_state=steady_state,
            dynamic_states=dynamic_states, progress=progress, solver=solver, result_file=result_file,
            max_order=getattr(experiment, "max_order", None) if max_order is None else max_order)
    except RunArgumentError as err:
        if getattr(err, "argument", None) in defaulted:
            raise RunArgumentError(f"{err} (the value comes from {source})") from None
        raise


def _check(*, t_start: Any, t_end: Any, dt_out: Any, output_times: Any, rtol: Any, atol: Any, max_step: Any,
           max_steps: Any, params: Any, steady_state: Any, dynamic_states: Any, progress: Any, solver: Any,
           result_file: Any, max_order: Any = None) -> RunOptions:
    t0 = _real("t_start", t_start, "must be a finite time [s]")
    t1 = _real("t_end", t_end, "must be a finite time [s]")
    if not math.isfinite(t0):
        raise _bad("t_start", t_start, "must be a finite time [s]")
    if not math.isfinite(t1):
        raise _bad("t_end", t_end, "must be a finite time [s] greater than t_start")
    if not t1 > t0:
        raise _bad("t_end", t_end, f"t_end ({t1:g}) must be greater than t_start ({t0:g})")
    shortest = max(MIN_SPAN, 1e-12 * max(abs(t0), abs(t1)))
    if t1 - t0 < shortest:
        raise _bad("t_end", t_end, f"the span t_end - t_start = {t1 - t0:g} s is too short to integrate from "
                   f"t_start = {t0:g} s (at least {shortest:g} s: below it the step sizes underflow or the times "
                   "cannot be told apart in floating point)")
    grid = _output_grid(t0, t1, dt_out, output_times)
    r = _real("rtol", rtol, "must be a number with 0 < rtol < 1")
    if not (math.isfinite(r) and 0.0 < r < 1.0):
        raise _bad("rtol", rtol, "must satisfy 0 < rtol < 1 (typical 1e-6)")
    a = _real("atol", atol, "must be a positive finite number")
    if not (math.isfinite(a) and a > 0.0):
        raise _bad("atol", atol, "must be a positive finite number (typical 1e-8; scaled by each nominal)")
    if isinstance(max_steps, (bool, np.bool_)) or not isinstance(max_steps, numbers.Real) \
            or not float(max_steps).is_integer() or max_steps <= 0:
        raise _bad("max_steps", max_steps, "must be a positive integer")
    n_steps = int(max_steps)
    h = _real("max_step", max_step, "must be a finite number >= 0 [s] (0: unlimited)")
    if not (math.isfinite(h) and h >= 0.0):
        raise _bad("max_step", max_step, "must be a finite number >= 0 [s] (0: unlimited)")
    if h > 0.0 and (t1 - t0) / h > n_steps:
        raise _bad("max_step", max_step,
                   f"reaching t_end = {t1:g} s from t_start = {t0:g} s needs at least {(t1 - t0) / h:.3g} steps, "
                   f"more than max_steps = {n_steps}", "raise max_step or max_steps")
    if params is None:
        params = {}
    if not isinstance(params, Mapping):
        raise _bad("params", params, f"must be a dict {{'component.parameter': value}}, got a {type(params).__name__}")
    wrong = [k for k in params if not isinstance(k, str)]
    if wrong:
        raise _bad("params", params, f"keys must be parameter names (str) such as 'mass.m', got {wrong[0]!r}")
    if not isinstance(solver, str) or solver not in SOLVERS:
        close = ""
        if isinstance(solver, str):
            import difflib

            match = difflib.get_close_matches(solver.lower(), SOLVERS, n=1)
            close = f"did you mean {match[0]!r}?" if match else ""
        raise _bad("solver", solver, f"must be one of {', '.join(repr(s) for s in SOLVERS)}", close)
    if max_order is not None and (isinstance(max_order, (bool, np.bool_)) or not isinstance(max_order, numbers.Real)
                                  or not float(max_order).is_integer() or not 1 <= max_order <= 5):
        raise _bad("max_order", max_order, "must be an integer 1 ... 5 (the highest BDF order) or None")
    steady = _flag("steady_state", steady_state)
    dynamic = _flag("dynamic_states", dynamic_states)
    bar = _flag("progress", progress, allow_none=True)
    path = None if result_file is None else check_result_path(result_file)
    return RunOptions(t_start=t0, t_end=t1, grid=grid, rtol=r, atol=a, max_step=h, max_steps=n_steps,
                      max_order=5 if max_order is None else int(max_order),
                      params=dict(params), steady_state=bool(steady), dynamic_states=bool(dynamic), progress=bar,
                      solver=solver, result_file=path)
