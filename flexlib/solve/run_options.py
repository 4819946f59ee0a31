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
import stat
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.errors import RunArgumentError
from flexlib.solve.solvers import SOLVERS, Solver, as_solver

__all__ = ["MAX_OUTPUT_POINTS", "MIN_ATOL", "MIN_RTOL", "RunOptions", "check_params", "check_result_path",
           "check_result_target", "check_run_arguments"]

#: Shortest run span [s], and at least 1e-12 of |t| (about 4500 units in the last place): below it IDA's first
#: step and error norms underflow, or the times cannot be told apart
MIN_SPAN = 1e-100
#: Largest output grid accepted (points); a larger one is almost certainly a unit mistake in ``dt_out``
#: (10 million rows of a 500-variable model are 40 GB).
MAX_OUTPUT_POINTS = 10_000_000

#: Smallest ``rtol``: machine epsilon (a relative error below it cannot be met in double precision; IDA ran on as if
#: it could, and the result claimed it).
MIN_RTOL = float(np.finfo(float).eps)
#: Smallest ``atol`` (scaled by each variable's nominal): far below the resolution of any physical quantity. Below
#: about 1e-100 IDA's error weights overflow or its first step underflows, and the failure did not name ``atol``.
MIN_ATOL = 1e-50

#: File name endings of other formats: a result file is HDF5, and ``run(result_file="out.csv")`` wrote HDF5 into
#: ``out.csv`` without a word.
OTHER_FORMATS = (".csv", ".tsv", ".txt", ".dat", ".json", ".yaml", ".yml", ".toml", ".mat", ".npz", ".npy", ".pkl",
                 ".pickle", ".parquet", ".xlsx", ".xls", ".png", ".pdf", ".svg", ".jpg", ".jpeg", ".py", ".ipynb",
                 ".mo", ".md", ".html", ".log", ".zip", ".gz")


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
    solver : str or Solver
        One of :data:`SOLVERS`, or a solver object (:mod:`flexlib.solve.solvers`).
    result_file : Path or None
        Where the result will be written.
    outputs : str, tuple of str or None
        What the result file stores besides the run's rows (``"all"``, names and patterns, or None).
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
    solver: Any
    result_file: Path | None
    outputs: str | tuple[str, ...] | None = None


def _bad(name: str, value: Any, allowed: str, hint: str = "", caller: str = "run") -> RunArgumentError:
    shown = f"<array of shape {value.shape}>" if isinstance(value, np.ndarray) else " ".join(repr(value).split())
    if len(shown) > 80:
        shown = shown[:77] + "..."
    err = RunArgumentError(f"{caller}(): {name} = {shown} is invalid: {allowed}{'; ' + hint if hint else ''}")
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
    """Check that ``result_file`` names a file that can be written: a ``str`` or path-like, not a directory (nor a
    name ending in a path separator), without a NUL character, a name the file system accepts (not too long), inside
    a directory that exists and is writable or can be created. Writes and removes a probe file in the nearest
    existing directory. Raises :class:`RunArgumentError` otherwise."""
    if isinstance(result_file, bytes) or not isinstance(result_file, (str, os.PathLike)):
        raise _bad(name, result_file, f"must be a file path (str or os.PathLike), got a {type(result_file).__name__}")
    text = os.fspath(result_file)
    if not str(text).strip():
        raise _bad(name, result_file, "must be a file path, got an empty string")
    if "\x00" in str(text):
        raise _bad(name, result_file, "contains a NUL character, which no file name can hold")
    if str(text).endswith(("/", os.sep)) or (os.altsep and str(text).endswith(os.altsep)):
        raise _bad(name, result_file, f"ends with a path separator, so it names a directory; give a file name such "
                   f"as {os.path.join(text, 'run.h5')}")
    path = Path(text).expanduser()
    try:
        if path.is_dir():
            raise _bad(name, result_file, f"{path} is a directory; give a file name such as {path / 'run.h5'}")
        existing = path.parent.absolute()
        while not existing.exists() and existing != existing.parent:
            existing = existing.parent
        if not existing.is_dir():
            raise _bad(name, result_file, f"its directory cannot be created: {existing} is a file, not a directory")
    except OSError as err:  # a name too long for the file system, a parent that cannot be read
        raise _bad(name, result_file, f"cannot be used as a file name: {err.strerror or err}") from None
    try:
        with tempfile.NamedTemporaryFile(dir=existing, prefix=".flexlib-probe-"):
            pass
    except OSError as err:
        reason = err.strerror or str(err)
        raise _bad(name, result_file, f"cannot write in {existing}: {reason}") from None
    return path


def _kind(mode: int) -> str:
    for test, what in ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISFIFO, "a named pipe"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return what
    return "not a regular file"


def check_result_target(result_file: Any, name: str = "result_file") -> Path:
    """:func:`check_result_path`, and a place a result file may replace: not an existing device, pipe or socket (the
    atomic replace of the write would put a regular file in its place, e.g. ``result_file="/dev/null"`` run as root),
    not an existing file that is not a flexlib result (a user's CSV, notes or source file), and not a name ending in
    another format's extension (``out.csv``). Raises :class:`RunArgumentError` naming the file and what it is."""
    path = check_result_path(result_file, name)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        mode = None
    except OSError as err:
        raise _bad(name, result_file, f"cannot be examined: {err.strerror or err}") from None
    if mode is not None and not stat.S_ISREG(mode):
        raise _bad(name, result_file, f"{path} exists and is {_kind(mode)}; a result file replaces the file at its "
                   "path, so give the name of a regular file")
    if mode is not None:
        from flexlib.results.hdf5 import not_a_result

        what = not_a_result(path)
        if what is not None:
            raise _bad(name, result_file, f"{path} exists and is {what}, not a flexlib result file; it is not replaced "
                       "(give another name, or remove the file first)")
    if path.suffix.lower() in OTHER_FORMATS:
        raise _bad(name, result_file, f"a result file is HDF5 (read back with flexlib.load_result), not "
                   f"{path.suffix.lower()}; give a name ending in .h5 such as {path.with_suffix('.h5')}")
    return path


def check_params(params: Any, caller: str = "run") -> dict[str, Any]:
    """``params`` as a dict (None: empty): a mapping with parameter names (str) as keys, else
    :class:`RunArgumentError`. The values are checked by the parameter declarations."""
    if params is None:
        return {}
    if not isinstance(params, Mapping):
        raise _bad("params", params, f"must be a dict {{'component.parameter': value}}, got a {type(params).__name__}",
                   caller=caller)
    wrong = [k for k in params if not isinstance(k, str)]
    if wrong:
        raise _bad("params", params, f"keys must be parameter names (str) such as 'mass.m', got {wrong[0]!r}",
                   caller=caller)
    return dict(params)


def _output_grid(t0: float, t1: float, dt_out: Any, output_times: Any) -> np.ndarray | None:
    if dt_out is not None and output_times is not None:
        raise _bad("dt_out", dt_out, "give either dt_out or output_times, not both")
    if output_times is not None:
        try:
            given = np.asarray(output_times)
        except (TypeError, ValueError):  # ragged nesting
            raise _bad("output_times", output_times, "must be a 1-D sequence of times [s]") from None
        if given.dtype.kind in "US" or (given.dtype.kind == "O" and given.ndim == 1 and any(
                isinstance(v, (str, bytes)) for v in given)):
            raise _bad("output_times", output_times, "must be a 1-D sequence of times [s] given as numbers, not "
                       "text (numbers as strings are not converted)")
        if given.dtype.kind == "b" or (given.dtype.kind == "O" and given.ndim == 1 and any(
                isinstance(v, (bool, np.bool_)) for v in given)):
            raise _bad("output_times", output_times, "must be times [s], not True/False")
        if given.dtype.kind == "O" and given.ndim == 0:  # a set, a dict, a generator: no order or no length
            raise _bad("output_times", output_times, f"must be a 1-D sequence of times [s] (a list or an array), got "
                       f"a {type(output_times).__name__}")
        if given.dtype.kind not in "iufO" or (given.dtype.kind == "O" and not all(
                isinstance(v, numbers.Real) for v in given.ravel())):
            raise _bad("output_times", output_times, f"must be real numbers [s] (got {given.dtype.name} values)")
        try:
            grid = np.array(given, dtype=float)
        except (TypeError, ValueError):
            raise _bad("output_times", output_times, "must be a 1-D sequence of times [s]") from None
        if grid.ndim == 0:
            raise _bad("output_times", output_times, f"must be a 1-D sequence of times [s], got a single number; "
                       f"give [{float(grid):g}] for one output time, or dt_out for a regular grid")
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
        # the run always ends with a row at t_end (as with dt_out, or without a grid): a last time within round-off
        # of t_end is t_end, and t_end is added when the times stop before it (the state at the end was integrated
        # and then dropped; the integration itself does not depend on the output times)
        if t1 - grid[-1] <= slack:
            grid[-1] = t1
        else:
            grid = np.append(grid, t1)
        return grid
    if dt_out is None:
        return None
    dt = _real("dt_out", dt_out, "must be a positive number [s]")
    if not (math.isfinite(dt) and dt > 0.0):
        raise _bad("dt_out", dt_out, "must be a positive finite number [s]; omit it to record every solver step")
    points = (t1 - t0) / dt + 1.0
    if not points <= MAX_OUTPUT_POINTS:
        count = f"{points:.0f}" if points < 1e15 else f"{points:.3g}"  # (t_end = 1e300: not 300 digits)
        raise _bad("dt_out", dt_out, f"gives {count} output points over [{t0:g}, {t1:g}] s, more than "
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
                        max_order: Any = None, outputs: Any = None) -> RunOptions:
    """Check every argument of a run and build the output grid.

    Parameters
    ----------
    experiment : Experiment
        The model's defaults for ``t_start``, ``t_end``, ``dt_out``, ``rtol`` and ``atol`` (``None`` given).
        ``dt_out`` is taken from it only when neither ``t_end``, ``dt_out`` nor ``output_times`` is given.
    source : str
        Where ``experiment`` comes from (``"Model.experiment"``), named when one of its values is invalid.
    t_start, t_end, dt_out, output_times, rtol, atol, max_step, max_steps, params, steady_state, \
dynamic_states, progress, solver, result_file, max_order, outputs
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
    if max_order is None and getattr(experiment, "max_order", None) is not None:
        defaulted.add("max_order")
    try:
        return _check(
            t_start=experiment.t_start if t_start is None else t_start,
            t_end=experiment.t_end if t_end is None else t_end, dt_out=dt_out, output_times=output_times,
            rtol=experiment.rtol if rtol is None else rtol, atol=experiment.atol if atol is None else atol,
            max_step=max_step, max_steps=max_steps, params=params, steady_state=steady_state,
            dynamic_states=dynamic_states, progress=progress, solver=solver, result_file=result_file,
            max_order=getattr(experiment, "max_order", None) if max_order is None else max_order, outputs=outputs)
    except RunArgumentError as err:
        argument = getattr(err, "argument", None)
        message = str(err)
        if argument in defaulted:
            message += f" (the value comes from {source})"
        elif argument in ("t_end", "output_times", "dt_out", "max_step") and "t_start" in defaulted \
                and experiment.t_start != 0:
            message += f" (t_start = {experiment.t_start!r} s comes from {source})"
        if message == str(err):
            raise
        new = RunArgumentError(message)
        new.argument = argument  # type: ignore[attr-defined]
        raise new from None


def _check(*, t_start: Any, t_end: Any, dt_out: Any, output_times: Any, rtol: Any, atol: Any, max_step: Any,
           max_steps: Any, params: Any, steady_state: Any, dynamic_states: Any, progress: Any, solver: Any,
           result_file: Any, max_order: Any = None, outputs: Any = None) -> RunOptions:
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
    if r < MIN_RTOL:
        raise _bad("rtol", rtol, f"is below the machine epsilon {MIN_RTOL:.3g}: no relative accuracy beyond double "
                   "precision can be met (typical 1e-6; 1e-12 for a reference solution)")
    a = _real("atol", atol, "must be a positive finite number")
    if not (math.isfinite(a) and a > 0.0):
        raise _bad("atol", atol, "must be a positive finite number (typical 1e-8; scaled by each nominal)")
    if a < MIN_ATOL:
        raise _bad("atol", atol, f"must be at least {MIN_ATOL:g} (typical 1e-8; it is scaled by each variable's "
                   "nominal): below that IDA's error weights overflow or its first step underflows")
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
    params = check_params(params)
    if isinstance(solver, Mapping):
        solver = as_solver(solver)  # a record: checked as the object it stands for
    if not isinstance(solver, Solver) and (not isinstance(solver, str) or solver not in SOLVERS):
        close = ""
        if isinstance(solver, str):
            import difflib

            match = difflib.get_close_matches(solver.lower(), SOLVERS, n=1)
            close = f"did you mean {match[0]!r}?" if match else ""
        raise _bad("solver", solver, f"must be one of {', '.join(repr(s) for s in SOLVERS)}, a solver object "
                   "(flexlib.IDA(...), flexlib.CasadiIDAS(...), flexlib.FixedStep(...)) or its record "
                   "({'kind': 'fixed-step', 'h': 0.001})", close)
    if max_order is not None and (isinstance(max_order, (bool, np.bool_)) or not isinstance(max_order, numbers.Real)
                                  or not float(max_order).is_integer() or not 1 <= max_order <= 5):
        raise _bad("max_order", max_order, "must be an integer 1 ... 5 (the highest BDF order) or None")
    steady = _flag("steady_state", steady_state)
    dynamic = _flag("dynamic_states", dynamic_states)
    bar = _flag("progress", progress, allow_none=True)
    path = None if result_file is None else check_result_target(result_file)
    return RunOptions(t_start=t0, t_end=t1, grid=grid, rtol=r, atol=a, max_step=h, max_steps=n_steps,
                      max_order=5 if max_order is None else int(max_order),
                      params=params, steady_state=bool(steady), dynamic_states=bool(dynamic), progress=bar,
                      solver=solver, result_file=path, outputs=check_outputs(outputs))


def check_outputs(outputs: Any, caller: str = "run") -> str | tuple[str, ...] | None:
    """``outputs`` of a run checked: None, ``"all"``, or variable names and patterns (a str or a list of them).
    Whether each matches a variable is known once the model is built; one that matches none is named when the file
    is written (the file is written without it, nothing lost)."""
    if outputs is None or (isinstance(outputs, str) and outputs == "all"):
        return outputs
    names = [outputs] if isinstance(outputs, str) else outputs
    if isinstance(names, (list, tuple)) and names and all(isinstance(n, str) and n.strip() for n in names):
        return tuple(n.strip() for n in names)
    raise _bad("outputs", outputs, "must be None (store the run's rows; every variable is derived when read), 'all' "
               "(store every variable) or variable names and patterns such as ['axis*.cylinder.p_A', "
               "'joint*.frame_b.f']", caller=caller)
