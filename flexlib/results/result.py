"""Stage 7 — results: time plus every variable by hierarchical name, solver statistics, plots."""

from __future__ import annotations

import difflib
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexlib.errors import EmptyResultError, ResultKeyError, RunArgumentError
from flexlib.results import indeterminate as _indeterminate

__all__ = ["DISPLAY_UNITS", "Result", "event_rows"]

#: Units shown in plots and summaries instead of SI, as engineers read them: ``{SI unit: (unit, factor)}``
#: (value shown = SI value × factor). Results themselves stay in SI.
DISPLAY_UNITS: dict[str, tuple[str, float]] = {
    "m3/s": ("L/min", 60000.0),
    "Pa": ("bar", 1e-5),
    "rad/s": ("rpm", 60.0 / (2.0 * np.pi)),
}


@dataclass
class Result:
    """Simulation result.

    ``result["inertia2.w"]`` is the time series of a variable (aliases included);
    ``result.t`` the time points (grid points, plus the left and right values at every event);
    ``result.value(name, t)`` interpolates; ``result.stats`` holds solver statistics.

    Attributes
    ----------
    model : str
        Model (class) name.
    t : ndarray
        Time [s].
    names : list of str
        Variable names, in column order of ``values``.
    values : ndarray
        ``(len(t), len(names))`` array. A run's result evaluates it when it is first read (and a single variable,
        ``result[name]``, alone): ``source`` computes the columns from the recorded rows.
    units, docs, kinds : list of str
        Per-variable metadata.
    parameters : dict
        ``{name: (value, unit)}`` used in the run.
    stats : dict
        Solver statistics (steps, residual and Jacobian evaluations, events, timings).
    status : str
        ``"success"``, ``"failed"`` or ``"interrupted"``.
    message : str
        Solver message.
    events : list of (float, str)
        Event times and what triggered them.
    index_report : str
        Index reduction report (which equations were differentiated, which variables are states).
    source : object, optional
        Where the values come from when ``values`` is None: ``source.columns(cols)`` (some variables, by column)
        and ``source.all()`` (every one), each ``(len(t), ·)`` (:class:`flexlib.solve.assemble.RowColumns`).
    indeterminate : dict of str to tuple of str
        The variables (element names, ``"j5.frame_a.f[0]"``) that the over-constrained rigid model does not
        determine, each with the redundant loop rows the build dropped that leave it free (``docs/engine.md``,
        "Statically indeterminate reactions"). Reading one by name warns once
        (:class:`~flexlib.errors.IndeterminateReactionWarning`); :meth:`summary` and :meth:`plot` mark them.
    """

    model: str
    t: np.ndarray
    names: list[str]
    values: np.ndarray
    units: list[str]
    docs: list[str]
    kinds: list[str]
    parameters: dict[str, tuple[float, str]]
    stats: dict[str, Any]
    status: str = "success"
    message: str = ""
    events: list[tuple[float, str]] = field(default_factory=list)
    index_report: str = ""
    metadata: dict[str, str] = field(default_factory=dict)
    source: Any = field(default=None, repr=False, compare=False)
    indeterminate: dict[str, tuple[str, ...]] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        if self._values is None and self.source is None:
            raise ValueError(f"Result of {self.model}: give values or a source of them")
        if self._values is not None:  # values given (dataclasses.replace(result, values=...)): they define the result
            self.source = None
        self._columns: dict[int, np.ndarray] = {}  # variables read one by one from the source
        self._warned: set[str] = set()  # indeterminate variables whose read has warned
        self._index = {n: k for k, n in enumerate(self.names)}
        self._arrays: dict[str, list[int]] = {}  # "frame.r" -> columns of r[0], r[1], ... (in column order)
        for k, n in enumerate(self.names):
            base, bracket, _ = n.partition("[")
            if bracket:
                self._arrays.setdefault(base, []).append(k)
        self._matrices = {base: m for base, cols in self._arrays.items()
                          if (m := _matrix_layout(base, [self.names[k] for k in cols])) is not None}

    def __getstate__(self) -> dict[str, Any]:
        """A pickled (or deep-copied) result stands alone: its values evaluated, without the run's functions."""
        state = self.__dict__.copy()
        if state.get("_values") is None and self.source is not None:
            state["_values"] = self.values
        state["source"], state["_columns"] = None, {}
        return state

    @property
    def success(self) -> bool:
        """True if the run reached its end time."""
        return self.status == "success"

    def _col(self, name: str) -> int:
        try:
            return self._index[name]
        except KeyError:
            raise self._unknown(name) from None

    def _unknown(self, name: Any) -> ResultKeyError:
        if not isinstance(name, str):
            return ResultKeyError(f"result of {self.model}: variables are looked up by name (str), got {name!r} "
                                  f"({type(name).__name__})")
        pool = sorted({n.split("[")[0] for n in self.names} | set(self.names))
        inside = [n for n in pool if n.startswith(name + ".")] if name else []
        if inside:  # a component (instance path), not a variable: name its variables
            shown = ", ".join(inside[:8]) + (f", ... ({len(inside) - 8} more)" if len(inside) > 8 else "")
            return ResultKeyError(f"no variable {name!r} in the result of {self.model}: {name!r} is a component; "
                                  f"its variables are {shown}")
        same_case = [n for n in pool if n.lower() == name.lower()]  # 'Mass0.S': the case is the only difference
        close = same_case + [n for n in difflib.get_close_matches(name, pool, n=5, cutoff=0.6) if n not in same_case]
        if not close:  # a wrong component path with the right variable: match on the last part
            leaf = name.rpartition(".")[2]
            close = [n for n in pool if n.rpartition(".")[2] == leaf][:5]
        close = close[:5]
        hint = f"; did you mean {close[0]!r}? (close matches: {', '.join(close)})" if close else ""
        return ResultKeyError(f"no variable {name!r} in the result of {self.model} "
                              f"({len(self.names)} variables){hint}")

    def __getitem__(self, name: str) -> np.ndarray:
        if not isinstance(name, str):
            raise self._unknown(name)
        if name in ("time", "t"):
            return self.t
        if name in self._index:
            if name in self.indeterminate:
                self._warn_indeterminate([name])
            return self._read([self._index[name]])[:, 0]
        # array variables: "frame.r" -> columns r[0], r[1], ... as (len(t), 3); "frame.T" -> T[i,j] as (len(t), 3, 3)
        cols = self._arrays.get(name)
        if cols:
            if self.indeterminate:
                self._warn_indeterminate([self.names[k] for k in cols])
            data = self._read(cols)
            if name not in self._matrices:
                return data
            shape, rows, columns = self._matrices[name]
            out = np.empty((len(data), *shape))
            out[:, rows, columns] = data
            return out
        raise self._unknown(name)

    def _warn_indeterminate(self, names: list[str]) -> None:
        """Warn once per variable that ``names`` (element names) read are indeterminate (:attr:`indeterminate`)."""
        if self.indeterminate:
            _indeterminate.warn_read(self.model, names, self.indeterminate, self._warned)

    def _element_names(self, names: tuple[str, ...]) -> list[str]:
        """The element names of ``names`` (scalars as they are, arrays by element; unknown names skipped)."""
        return [n for name in names for n in ([name] if name in self._index else
                                                [self.names[k] for k in self._arrays.get(name, [])])]

    def prefetch(self, *names: str) -> None:
        """Evaluate the variables ``names`` (names or array names; unknown ones are skipped) together, in one pass
        over the rows, and keep them: reading them afterwards costs nothing (a summary, a plot of many signals)."""
        cols = [k for name in names if isinstance(name, str)
                for k in ([self._index[name]] if name in self._index else self._arrays.get(name, []))]
        if cols and self._values is None:
            self._evaluate(cols)

    def _read(self, cols: list[int], keep: bool = True) -> np.ndarray:
        """Columns ``cols`` of :attr:`values` (``(len(t), len(cols))``), from the source alone if the values are not
        evaluated yet (each column evaluated once, and kept unless ``keep`` is False: a pass over every variable,
        as ``compare`` makes, holds a block at a time)."""
        if self._values is not None:
            return self._values[:, cols]
        if not keep:
            known = [c for c in cols if c in self._columns]
            if not known:
                return self.source.columns(list(cols))
        self._evaluate(cols)
        return np.column_stack([self._columns[c] for c in cols]) if cols else np.zeros((len(self.t), 0))

    def _evaluate(self, cols: list[int]) -> None:
        """Evaluate the columns ``cols`` not evaluated yet from the source, in one pass, and keep them."""
        todo = [c for c in dict.fromkeys(cols) if c not in self._columns]
        if todo:
            for c, col in zip(todo, self.source.columns(todo).T, strict=True):
                self._columns[c] = col

    def _require_rows(self, what: str) -> None:
        if not len(self.t):
            why = f" ({self.message})" if self.message else ""
            raise EmptyResultError(f"{what}: the result of {self.model} has no rows; the run is {self.status}{why}")

    def __contains__(self, name: str) -> bool:
        return isinstance(name, str) and name in self._index

    def unit(self, name: str) -> str:
        """Unit of a variable (of its first element for an array variable)."""
        if not isinstance(name, str):
            raise self._unknown(name)
        if name in ("time", "t"):
            return "s"
        if name not in self._index:
            elem = next((n for n in self.names if n.startswith(name + "[")), None)
            if elem is not None:
                return self.units[self._index[elem]]
        return self.units[self._col(name)]

    def _check_times(self, what: str, t: Any) -> np.ndarray:
        """``t`` as float array, or :class:`RunArgumentError` if it is not a finite time inside the result's span
        (a value past the end of a run that failed half-way would otherwise be its last row, silently)."""
        arr = np.asarray(t) if not isinstance(t, str) else np.asarray([t])
        if arr.dtype.kind not in "iuf":
            raise RunArgumentError(f"{what}: t must be a time [s] (a number or an array of numbers), got {t!r} "
                                   f"({type(t).__name__})")
        tt = arr.astype(float)
        bad = ~np.isfinite(tt)
        if bad.any():
            raise RunArgumentError(f"{what}: t must be finite, got {tt[bad][0]:g}")
        t0, t1 = float(self.t[0]), float(self.t[-1])
        tol = 1e-9 * max(1.0, abs(t0), abs(t1))
        out = (tt < t0 - tol) | (tt > t1 + tol)
        if out.any():
            why = f"; the run is {self.status}" + (f": {' '.join(self.message.split())}" if self.message else "") \
                if not self.success else ""
            raise RunArgumentError(f"{what}: t = {tt[out][0]:g} s is outside the result of {self.model}, which "
                                   f"covers {t0:g} … {t1:g} s{why}")
        return tt

    def value(self, name: str, t: float | np.ndarray, side: str = "right") -> float | np.ndarray:
        """Linear interpolation of variable ``name`` at time(s) ``t`` [s]; for an array variable its elements in their
        shape (``"frame.r"``: ``(3,)`` at one time, ``(len(t), 3)``; ``"frame.T"``: ``(3, 3)``, ``(len(t), 3, 3)``).

        At an event time the result holds several rows (the values before and after the event, and any in between
        when events coincide): ``side="right"`` (default) gives the last, the value after the event, ``"left"`` the
        first, the value before it; between rows both interpolate the same.

        Raises
        ------
        ResultKeyError
            No such variable.
        EmptyResultError
            The result has no rows.
        RunArgumentError
            ``t`` is not a number (or array of numbers), not finite, or outside the result's time span (a run that
            failed half-way has no values after its failure); ``side`` is not ``"left"`` or ``"right"``.
        """
        x = self[name]
        self._require_rows(f"value({name!r}, t)")
        self._check_times(f"value({name!r}, t)", t)
        keep = self._side_rows(f"value({name!r}, t)", side)
        if x.ndim == 1:
            return np.interp(t, self.t[keep], x[keep])
        flat = x[keep].reshape(int(keep.sum()), -1)
        out = np.stack([np.interp(t, self.t[keep], col) for col in flat.T], axis=-1)
        return out.reshape(np.shape(t) + x.shape[1:])

    def row(self, t: float, side: str = "right") -> np.ndarray:
        """Every variable (columns of :attr:`values`) interpolated linearly at one time ``t`` [s] (at an event the
        value after it, or before it with ``side="left"``, as :meth:`value`); :class:`RunArgumentError` for a ``t``
        outside the result's span, as :meth:`value`, or for several times."""
        self._require_rows(f"row({t!r})")
        self._check_times(f"row({t!r})", t)
        if np.ndim(t):
            raise RunArgumentError(f"row(t): t must be one time [s] (a number), got {t!r}; for several times "
                                   "call row once per time, or value(name, times) per variable")
        t = float(t)
        keep = self._side_rows(f"row({t!r})", side)
        tk, vals = self.t[keep], self.values[keep]
        if len(tk) == 1:
            return vals[0].astype(float)
        k = int(np.clip(np.searchsorted(tk, t, side="right"), 1, len(tk) - 1))
        w = float(np.clip((t - tk[k - 1]) / (tk[k] - tk[k - 1]), 0.0, 1.0))
        return (1.0 - w) * vals[k - 1] + w * vals[k]

    def _side_rows(self, what: str, side: Any) -> np.ndarray:
        """:func:`event_rows` of this result, ``side`` checked."""
        if side not in ("right", "left"):
            raise RunArgumentError(f"{what}: side must be 'right' (the value after an event) or 'left' (before "
                                   f"it), got {side!r}")
        return event_rows(self.t, side)

    def final(self, name: str) -> float | np.ndarray:
        """Value of ``name`` at the end of the run (an array variable: its elements); :class:`EmptyResultError` if
        the result has no rows."""
        x = self[name]
        self._require_rows(f"final({name!r})")
        return float(x[-1]) if x.ndim == 1 else np.array(x[-1], dtype=float)

    def elements(self, name: str) -> list[str]:
        """The element names of an array variable, in column order (``"frame.T"`` → ``T[0,0]``, ``T[1,0]``, …:
        column-major, 0-based), or ``[name]`` for a scalar variable."""
        if isinstance(name, str) and name in self._index:
            return [name]
        if isinstance(name, str) and name in self._arrays:
            return [self.names[k] for k in self._arrays[name]]
        raise self._unknown(name)

    def display(self, name: str) -> tuple[np.ndarray, str]:
        """Values of ``name`` in its display unit (:data:`DISPLAY_UNITS`: L/min, bar, rpm) and that unit."""
        unit = self.unit(name)
        shown, factor = DISPLAY_UNITS.get(unit, (unit, 1.0))
        return self[name] * factor, shown

    def plot(self, *names: str, ax: Any = None, title: str | None = None, si: bool = False) -> Any:
        """Plot variables against time with matplotlib (display units unless ``si``; an array variable: a line per
        element); returns the Axes. A statically indeterminate variable (:attr:`indeterminate`) has
        ``(indeterminate)`` in its legend entry.

        Raises
        ------
        ResultKeyError
            A name that is not in the result, or a list given where the names go (``plot(*names)``).
        RunArgumentError
            ``ax`` is not an Axes, ``si`` not a bool, ``title`` not a str.
        """
        import matplotlib.pyplot as plt

        self._check_names("plot", names)
        if ax is not None and not callable(getattr(ax, "plot", None)):
            raise RunArgumentError(f"plot: ax must be a matplotlib Axes (or None: a new figure), got {ax!r} "
                                   f"({type(ax).__name__})")
        if not isinstance(si, (bool, np.bool_)):
            raise RunArgumentError(f"plot: si must be True (SI units) or False (display units), got {si!r}")
        if title is not None and not isinstance(title, str):
            raise RunArgumentError(f"plot: title must be a str (or None: the model's name), got {title!r}")
        if ax is None:
            _, ax = plt.subplots(figsize=(8, 4.5))
        units = []
        self._warn_indeterminate(self._element_names(names))  # one warning for the plot; the legend marks them
        for name in names:
            values, unit = (self[name], self.unit(name)) if si else self.display(name)
            if values.ndim == 1:
                labels = [name]
            elif values.ndim == 2:  # a vector: its elements
                labels = self.elements(name)
            else:  # a matrix: its elements, row by row
                labels = [f"{name}[{i},{j}]" for i in range(values.shape[1]) for j in range(values.shape[2])]
                values = values.reshape(len(values), int(np.prod(values.shape[1:])))
            for label, column in zip(labels, values.reshape(len(values), len(labels)).T, strict=True):
                mark = f" {_indeterminate.MARK}" if label in self.indeterminate else ""
                ax.plot(self.t, column, label=f"{label} [{unit}]{mark}")
            units.append(unit)
        ax.set_xlabel("time [s]")
        if len(set(units)) == 1:  # one unit: the axis says it (a legend relabelled by the caller keeps it)
            ax.set_ylabel(f"{names[0]} [{units[0]}]" if len(names) == 1 else f"[{units[0]}]")
        ax.set_title(title or (self.model if len(self.t) else f"{self.model} (no rows: run {self.status})"))
        ax.grid(True, alpha=0.3)
        if names:
            ax.legend()
        return ax

    def to_dataframe(self, *names: str, display: bool = False) -> Any:
        """The variables ``names`` (default: every one) as a pandas DataFrame (pandas is optional: ``pip install
        pandas``): one column per variable (an array variable: one per element), indexed by time [s] (an event's
        left and right rows share its time); SI values, or with ``display=True`` in display units (bar, L/min,
        rpm). ``frame.attrs["units"]`` maps each column to its unit, ``frame.attrs["indeterminate"]`` lists the
        statically indeterminate columns (:attr:`indeterminate`; reading them warns once).

        Raises
        ------
        ResultKeyError
            A name that is not in the result (as indexing).
        ImportError
            pandas is not installed (says how to install it).
        """
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Result.to_dataframe needs pandas: pip install pandas") from None
        self._check_names("to_dataframe", names)
        columns: list[str] = []
        for name in names or tuple(self.names):
            if name in self._index:
                columns.append(name)
            elif name in self._arrays:
                columns += [self.names[k] for k in self._arrays[name]]
            else:
                raise self._unknown(name)
        data, units = {}, {}
        self._warn_indeterminate(columns)  # one warning for the frame
        for name in columns:
            values, unit = self.display(name) if display else (self[name], self.unit(name))
            data[name], units[name] = np.asarray(values, dtype=float), unit
        frame = pd.DataFrame(data, index=pd.Index(np.asarray(self.t, dtype=float), name="time [s]"))
        frame.attrs["units"] = units
        frame.attrs["indeterminate"] = [n for n in columns if n in self.indeterminate]
        return frame

    def summary(self, *names: str) -> str:
        """Table of final, minimum and maximum values in display units (flows in L/min, pressures in bar).

        A result without rows (a run that failed at its start) gives the table with ``-`` and a line saying
        why; a result that did not succeed says so in its last line. A statically indeterminate variable
        (:attr:`indeterminate`) has ``(indeterminate)`` at the end of its row and a footnote says what it means."""
        self._check_names("summary", names)
        rows = [f"{'variable':<36} {'unit':>7} {'final':>12} {'min':>12} {'max':>12}"]
        self._warn_indeterminate(self._element_names(names))  # one warning for the table; its rows mark them

        def mark(n: str) -> str:
            return f"  {_indeterminate.MARK}" if n in self.indeterminate else ""

        for name in names:
            values, unit = self.display(name)
            if values.ndim > 1:  # array variable: one row per element
                elems = [n for n in self.names if n.startswith(name + "[")]
                rows += [self._summary_row(n, *self.display(n)) + mark(n) for n in elems]
            else:
                rows.append(self._summary_row(name, values, unit) + mark(name))
        if any(mark(n) for n in self._element_names(names)):
            rows.append(_indeterminate.FOOTNOTE)
        if not self.success:
            message = " ".join(self.message.split())
            rows.append(f"({self.status}: {message})" if message else f"({self.status})")
        return "\n".join(rows)

    def _check_names(self, what: str, names: tuple[Any, ...]) -> None:
        """The variable names given to :meth:`plot` or :meth:`summary`, each a str (a list is named with how to
        pass it: ``summary(*names)``); unknown names raise as indexing does."""
        for name in names:
            if isinstance(name, (list, tuple)):
                raise ResultKeyError(f"{what}: give the variable names as separate arguments, "
                                     f"{what}('a', 'b') or {what}(*names), got the {type(name).__name__} {name!r}")
            if not isinstance(name, str):
                raise self._unknown(name)

    @staticmethod
    def _summary_row(name: str, values: np.ndarray, unit: str) -> str:
        if not len(values):
            return f"{name:<36} {unit:>7} {'-':>12} {'-':>12} {'-':>12}"
        return f"{name:<36} {unit:>7} {values[-1]:>12.5g} {values.min():>12.5g} {values.max():>12.5g}"

    def save(self, path: str | os.PathLike, outputs: str | list[str] | None = None) -> None:
        """Write the result to an HDF5 file (atomically; layout in docs/results.md).

        The file stores the run's rows and derives every other variable when read; ``outputs`` names variables
        (names, array names, patterns with ``*`` and ``?``) to store as columns as well, ``"all"`` every one.

        Raises
        ------
        ResultFileError
            The file cannot be written; names the path and the reason. Nothing partial is left behind.
        """
        from flexlib.results.hdf5 import save_result

        save_result(self, path, outputs)

    def __repr__(self) -> str:
        return (f"<Result {self.model}: {self.status}, t = {self.t[0] if len(self.t) else 0:g} … "
                f"{self.t[-1] if len(self.t) else 0:g} s, {len(self.t)} points, {len(self.names)} variables>")


def _values(self: Result) -> np.ndarray:
    """Every variable at every time, ``(len(t), len(names))`` (evaluated from the source when first read)."""
    if self._values is None:
        self._values = np.asarray(self.source.all(), dtype=float)
        self._columns = {}
    return self._values


def _set_values(self: Result, values: np.ndarray | None) -> None:
    self._values = values


# the dataclass field ``values`` (its constructor argument) read through a property: a run's values are evaluated
# when first needed
Result.values = property(_values, _set_values, doc=_values.__doc__)  # type: ignore[assignment,method-assign]


def event_rows(t: np.ndarray, side: str = "right") -> np.ndarray:
    """Mask of the rows to interpolate: at an event time a result holds several rows (the values before and after
    it); the last at each time is kept (``side="right"``), or the first (``"left"``)."""
    keep = np.ones(len(t), dtype=bool)
    if side == "right":
        keep[:-1] = t[1:] != t[:-1]
    else:
        keep[1:] = t[1:] != t[:-1]
    return keep


def _matrix_layout(base: str, elements: list[str]) -> tuple[tuple[int, int], np.ndarray, np.ndarray] | None:
    """``(shape, rows, columns)`` of a matrix variable from its element names ``base[i,j]`` (in column order), or None
    if they are not the complete elements of one matrix (a vector ``base[i]``, or indices that are not integers)."""
    index = []
    for name in elements:
        inside = name[len(base) + 1:-1].split(",") if name.endswith("]") else []
        if len(inside) != 2 or not all(i.strip().isdigit() for i in inside):
            return None
        index.append((int(inside[0]), int(inside[1])))
    if not index:
        return None
    rows, columns = (np.array(x, dtype=np.int64) for x in zip(*index, strict=True))
    shape = (int(rows.max()) + 1, int(columns.max()) + 1)
    if len(set(index)) != len(index) or len(index) != shape[0] * shape[1]:
        return None
    return shape, rows, columns
