"""Compare two results: their common signals in a tolerance tube around the reference (A), ranked by how far they
leave it, and everything that makes the comparison incomplete (``flexlib compare``, docs/cli.md).

The tube follows the regression testing of Modelica libraries (the reference-result comparison of the Modelica
Standard Library: a tolerance relative to each signal's range plus an absolute floor, time shifts at events
allowed): signal ``x`` of B is compared with A's ``x`` against ``tol = atol + rtol·base``, ``base`` the larger of
the range and the magnitude of the minimum of A's ``x`` (csv-compare's tube height: a pressure holding at 250 bar
that varies by 0.01 bar is measured against its 250 bar, not its 0.01 bar); its *deviation* at a time is the
smallest ``|B(t + s) − A(t)|`` over shifts ``|s| ≤ shift`` (0 except within a grid interval of an event of either
run), and the ranking is by ``max_t deviation/tol``. ``atol`` is the noise floor of the signal's unit: the larger of
``ATOL_SCALE`` times the largest magnitude of that unit's signals in the two results and ``NOISE_ATOL`` times the
runs' absolute solver tolerance (what the integration leaves undetermined). A signal whose two traces both lie
within it — a 1e-21 round-off of a quantity that is 0 in both (a reaction that does not exist, a closed valve's
opening), a creep at the solver's tolerance — is not ranked. ``rtol`` is ``RTOL``. Signals with the same traces in
both results (aliases) are ranked once, under a component's own variable rather than a connector's (``p_A``, not
``port_A.p``). The goldens (``models/pump_truck/goldens.py``) use :func:`tube` with their own tolerances per signal
and time shift.

A comparison only means something when it covers both runs. :func:`compare` therefore reports, beside the
differences, the *problems* that a regression check must not pass silently — signals that are NaN or inf in one
result where the other is finite, time spans that differ (a run that failed half-way: only the common span is
compared), variables in one result only (different models: nothing compared), the same name with different
units, runs with different status — and *notes* that are worth a line but do not make the comparison wrong.
"""

from __future__ import annotations

import fnmatch
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexlib.errors import EmptyResultError, ResultKeyError, RunArgumentError
from flexlib.results.result import event_rows

__all__ = ["ATOL_SCALE", "NOISE_ATOL", "RTOL", "Comparison", "compare", "compare_results", "select", "tube"]

#: Names listed in a message before "...".
_SHOWN = 5
#: Tube height relative to the reference signal's base: the larger of its range and the magnitude of its minimum.
RTOL = 1e-3
#: Absolute floor of the tube per unit, relative to the largest magnitude of that unit's signals in both results.
ATOL_SCALE = 1e-6
#: ... and at least this many times the runs' absolute solver tolerance (``stats["atol"]``, SI): local errors of
#: ``atol`` add up over a run to a global error some ten to a hundred times larger.
NOISE_ATOL = 100.0
#: Shifts tried per point where a time shift is allowed (evenly from −shift to +shift).
_SHIFTS = 9


def tube(grid: np.ndarray, reference: np.ndarray, sample: Any, tol: np.ndarray | float,
         shift: np.ndarray | float = 0.0, at_grid: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Deviation of a signal from a reference and that over its tolerance, per point of ``grid`` [s].

    The deviation at ``t`` is the smallest ``|sample(t + s) − reference(t)|`` over shifts ``|s| ≤ shift(t)``
    (``_SHIFTS`` of them, evenly spaced; only ``sample(t)`` where the shift is 0): a run whose event or correction
    burst comes a little earlier or later is inside the tube. NaN in ``sample`` where the reference is finite gives
    an infinite deviation.

    Parameters
    ----------
    grid : ndarray
        Times [s].
    reference : ndarray
        The reference signal at ``grid``.
    sample : callable
        ``sample(times) -> values`` of the compared signal.
    tol : ndarray or float
        Tolerance at each point (> 0).
    shift : ndarray or float
        Largest time shift at each point [s].
    at_grid : ndarray, optional
        ``sample(grid)``, if the caller has it.

    Returns
    -------
    deviation, ratio : ndarray
        Per point: the deviation and the deviation over ``tol``.
    """
    grid, reference = np.asarray(grid, dtype=float), np.asarray(reference, dtype=float)
    shift = np.broadcast_to(np.asarray(shift, dtype=float), grid.shape)
    dev = np.abs(np.asarray(sample(grid) if at_grid is None else at_grid, dtype=float) - reference)
    moved = np.flatnonzero(shift > 0)
    if moved.size:
        for f in np.linspace(-1.0, 1.0, _SHIFTS):
            if f == 0.0:
                continue
            dev[moved] = np.fmin(dev[moved], np.abs(np.asarray(sample(grid[moved] + f * shift[moved]), dtype=float)
                                                    - reference[moved]))
    dev = np.where(np.isnan(dev) & np.isfinite(reference), np.inf, dev)
    return dev, dev / np.asarray(tol, dtype=float)


@dataclass
class Comparison:
    """The outcome of :func:`compare`.

    Attributes
    ----------
    rows : list of dict
        One per compared signal, ranked: the signals that leave their tube most first (``ratio``), then those
        within their noise floor (``noise``). Keys: ``name``, ``unit``, ``ratio`` (the largest deviation from A over
        the tolerance, :func:`tube`), ``tol`` (the tolerance, SI), ``noise`` (True: both traces lie within the
        tube's absolute floor ``atol``, round-off of a quantity that is 0 in both: not ranked), ``same`` (the names
        of the later rows whose traces in both results are the same as this one's: aliases) and ``alias_of`` (the
        row that names this one in its ``same``, or None), ``abs`` (max
        ``|a − b|``, SI), ``rel`` (that over the larger of ``max |a|`` and ``max |b|``; 0 if both are 0), ``t`` [s]
        where it occurs, ``a`` and ``b`` there; ``nonfinite_a`` and ``nonfinite_b`` (compared points where that result
        is NaN or inf), ``mismatch`` (points where only one is, or they differ), ``mismatch_a`` / ``mismatch_b``
        (of those, where A / B is NaN or inf) and ``from_a`` / ``from_b`` (the first such time [s], or None).
        A signal with a mismatch has ``abs = rel = ratio = inf``, at its first mismatching point.
    span : (float, float)
        The compared time span [s] (common to both results).
    span_a, span_b : (float, float)
        The time spans [s] of the results.
    only_a, only_b : list of str
        Variables in one result only (all of them, also when ``signals`` selects some).
    problems : list of str
        What makes the comparison incomplete or untrustworthy (one sentence each, naming the signals, time
        spans or names); a pass/fail check (``--fail-above``) must fail on any of them.
    notes : list of str
        Worth saying, not wrong (both results NaN at the same points, different model classes with the same
        variables).
    """

    rows: list[dict[str, Any]]
    span: tuple[float, float]
    span_a: tuple[float, float]
    span_b: tuple[float, float]
    only_a: list[str] = field(default_factory=list)
    only_b: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def ranked(self) -> list[dict[str, Any]]:
        """The rows of signals outside their noise floor, the farthest out of their tube first, each trace once
        (a row's ``same`` names the signals with the same traces in both results: aliases)."""
        return [r for r in self.rows if not r["noise"] and r["alias_of"] is None]

    @property
    def worst(self) -> dict[str, Any] | None:
        """The row that leaves its tube most (None if no signal outside its noise floor was compared)."""
        ranked = self.ranked
        return ranked[0] if ranked else None


def _n(count: int, noun: str) -> str:
    return f"{count} {noun}" + ("" if count == 1 else "s")


def _listed(names: list[str]) -> str:
    shown = ", ".join(names[:_SHOWN])
    return shown + (f", ... ({len(names) - _SHOWN} more)" if len(names) > _SHOWN else "")


def _is_glob(pattern: str) -> bool:
    return "*" in pattern or "?" in pattern


def _glob(pattern: str) -> re.Pattern[str]:
    """``*`` and ``?`` are wildcards; ``[`` is literal (array elements are named ``r[0]``)."""
    return re.compile(fnmatch.translate(pattern.replace("[", "[[]")))


def _elements(res: Any, name: str) -> list[str]:
    return [n for n in res.names if n.startswith(name + "[")]


def _signal_list(signals: Any, who: str) -> list[str]:
    """``signals`` as a list: one name (str) or a non-empty list, tuple (or set) of names; a mapping, a number, an
    empty list (which would silently mean "every variable" or nothing) are refused naming them."""
    if isinstance(signals, str):
        return [signals]
    if isinstance(signals, (bytes, Mapping)) or not isinstance(signals, Iterable):
        raise RunArgumentError(f"{who}: signals must be a variable name or a list of names (str), got "
                               f"{type(signals).__name__} {signals!r:.80}")
    out = list(signals)
    if not out:
        raise RunArgumentError(f"{who}: signals is empty; give variable names or patterns, or None for every "
                               "variable")
    return out


def _check_result(res: Any, label: str, who: str) -> None:
    """:class:`RunArgumentError` unless ``res`` is a :class:`~flexlib.results.result.Result` (a path is named
    with how to read it)."""
    from flexlib.results.result import Result

    if not isinstance(res, Result):
        how = " (read a result file with flexlib.load_result(path))" if isinstance(res, (str, os.PathLike)) else ""
        raise RunArgumentError(f"{who}: {label} must be a Result{how}, got {type(res).__name__} {res!r:.80}")


def select(res: Any, signals: list[str] | str, label: str = "the result") -> list[str]:
    """The variables of one result named by ``signals``: names, array names (their elements) and patterns with
    ``*`` and ``?`` (``"mass?.s"``; ``"*"`` is every variable), each once, in the order asked.

    Raises
    ------
    ResultKeyError
        A name that is not in the result (with close matches), or a pattern that matches nothing; names
        ``label``.
    RunArgumentError
        ``res`` is not a Result (a path, for example), or ``signals`` is neither a name nor a non-empty list of
        names.
    """
    _check_result(res, label, "select")
    signals = _signal_list(signals, "select")
    names: list[str] = []
    for s in signals:
        if not isinstance(s, str) or not s.strip():
            raise ResultKeyError(f"signals: each signal is a variable name (str), got {s!r}")
        if _is_glob(s):
            rx = _glob(s)
            found = [n for n in res.names if rx.fullmatch(n)]
            if not found:
                raise ResultKeyError(f"signal pattern {s!r} matches no variable of {label} ({len(res.names)} "
                                     "variables)")
            names += found
        elif s in res.names:
            names.append(s)
        elif _elements(res, s):
            names += _elements(res, s)
        else:
            raise _not_in(res, s, label)
    return list(dict.fromkeys(names))


def _not_in(res: Any, name: str, label: str) -> ResultKeyError:
    if name in ("t", "time"):
        return ResultKeyError(f"signal {name!r}: the time is the axis of every signal, not a signal of {label}")
    return ResultKeyError(f"signal {name!r} is not in {label}: {res._unknown(name)}")


def _select(a: Any, b: Any, signals: list[str], labels: tuple[str, str]) -> tuple[list[str], list[str]]:
    """The variables named by ``signals`` (names, array names, ``*``/``?`` patterns) that are in both results,
    and the problems: variables a pattern matches in one result only."""
    names: list[str] = []
    problems: list[str] = []
    for s in signals:
        if not isinstance(s, str) or not s.strip():
            raise ResultKeyError(f"signals: each signal is a variable name (str), got {s!r}")
        if not _is_glob(s):  # a name or an array name: in both, with the same elements
            got_a, got_b = select(a, [s], labels[0]), select(b, [s], labels[1])
            if got_a != got_b:
                raise ResultKeyError(f"signal {s!r}: the array has the elements {_listed(got_a)} in {labels[0]} "
                                     f"but {_listed(got_b)} in {labels[1]}")
            names += got_a
            continue
        rx = _glob(s)
        found_a = [n for n in a.names if rx.fullmatch(n)]
        found_b = [n for n in b.names if rx.fullmatch(n)]
        in_b = set(found_b)
        both = [n for n in found_a if n in in_b]
        if not found_a and not found_b:
            raise ResultKeyError(f"signal pattern {s!r} matches no variable of {labels[0]} or {labels[1]}")
        if not both:
            one, other, found = (labels[0], labels[1], found_a) if found_a else (labels[1], labels[0], found_b)
            raise ResultKeyError(f"signal pattern {s!r} matches {_n(len(found), 'variable')} of {one} "
                                 f"({_listed(found)}) but none of {other}")
        in_a = set(found_a)
        for label, extra in ((labels[0], [n for n in found_a if n not in in_b]),
                             (labels[1], [n for n in found_b if n not in in_a])):
            if extra:
                problems.append(f"signal pattern {s!r} matches {_n(len(extra), 'variable')} only in {label} (not "
                                f"compared): {_listed(extra)}")
        names += both
    return list(dict.fromkeys(names)), problems  # each once, in the order asked


def _interp(grid: np.ndarray, t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Linear interpolation that keeps NaN and inf: a grid point on a non-finite sample, or inside an interval
    that touches one, takes that sample's value (np.interp would give NaN for an inf, or a number)."""
    finite = np.isfinite(x)
    if finite.all():
        return np.interp(grid, t, x)
    if len(t) == 1:
        return np.full(len(grid), x[0])
    out = np.interp(grid, t, np.where(finite, x, 0.0))
    right = np.clip(np.searchsorted(t, grid, side="right"), 1, len(t) - 1)
    left = right - 1
    at_r = grid == t[right]
    at_l = (grid == t[left]) & ~at_r
    inside = ~at_r & ~at_l
    src = np.where(at_r, right, np.where(at_l | (inside & ~finite[left]), left, right))
    bad = ~finite[src]
    out[bad] = x[src][bad]
    return out


def compare(a: Any, b: Any, signals: list[str] | str | None = None, *,
            labels: tuple[str, str] = ("A", "B"), rtol: float = RTOL) -> Comparison:
    """B's signals in a tolerance tube around A's, ranked by how far they leave it, with what the comparison does
    not cover (module docstring).

    Both results are interpolated linearly (right values at events) on the union of their time points inside
    the common time span.

    Parameters
    ----------
    a, b : Result
        The results.
    signals : list of str or str, optional
        Variables to compare: names, array names (expand to their elements) and patterns with ``*`` / ``?``;
        default: every variable in both.
    labels : (str, str)
        How messages name the results (``"A (run.h5)"``).
    rtol : float
        Tube height relative to each signal's base in A (default :data:`RTOL`; module docstring).

    Returns
    -------
    Comparison

    Raises
    ------
    ResultKeyError
        A requested signal is not in one of the results (names it, the result, and close matches), or a pattern
        matches no variable of both.
    EmptyResultError
        A result has no rows (names it and its status).
    RunArgumentError
        The results have no common time span (gives both); ``a`` or ``b`` is not a Result (a path: read it with
        ``flexlib.load_result``); ``signals`` is neither a name, a non-empty list of names nor None; ``labels``
        is not two str.
    """
    pair = tuple(labels) if isinstance(labels, (tuple, list)) else ()
    if len(pair) != 2 or not all(isinstance(x, str) for x in pair):
        raise RunArgumentError(f"compare: labels must be two str, how messages name the results (for example "
                               f"('A (run1.h5)', 'B (run2.h5)')), got {labels!r}")
    labels = (pair[0], pair[1])
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float)) or not 0.0 < float(rtol) < np.inf:
        raise RunArgumentError(f"compare: rtol must be a number > 0 (the tube's width relative to each signal's "
                               f"range, such as {RTOL:g}), got {rtol!r}")
    _check_result(a, f"a ({labels[0]})", "compare")
    _check_result(b, f"b ({labels[1]})", "compare")
    if signals is not None:
        signals = _signal_list(signals, "compare")
    for label, res in zip(labels, (a, b), strict=True):
        if not len(res.t):
            why = f": {' '.join(res.message.split())}" if res.message else ""
            raise EmptyResultError(f"cannot compare: {label} has no rows (the run of {res.model} is "
                                   f"{res.status}{why})")
    in_a, in_b = set(a.names), set(b.names)
    only_a = [n for n in a.names if n not in in_b]
    only_b = [n for n in b.names if n not in in_a]
    names, selected = _select(a, b, list(signals), labels) if signals else ([n for n in a.names if n in in_b], [])
    span_a, span_b = (float(a.t[0]), float(a.t[-1])), (float(b.t[0]), float(b.t[-1]))
    t0, t1 = max(span_a[0], span_b[0]), min(span_a[1], span_b[1])
    if t1 < t0:
        raise RunArgumentError(f"cannot compare: no common time span ({labels[0]} covers {span_a[0]:g} … "
                               f"{span_a[1]:g} s, {labels[1]} {span_b[0]:g} … {span_b[1]:g} s)")
    out = Comparison([], (t0, t1), span_a, span_b, only_a, only_b)
    _check_names(out, a, b, bool(signals), labels)
    out.problems += selected
    _check_span(out, a, b, labels)
    ia, ib = {n: k for k, n in enumerate(a.names)}, {n: k for k, n in enumerate(b.names)}
    units = [(n, a.units[ia[n]], b.units[ib[n]]) for n in names if a.units[ia[n]] != b.units[ib[n]]]
    if units:
        out.problems.append(f"{_n(len(units), 'signal')} with different units in {labels[0]} and {labels[1]}, not "
                            "compared: " + _listed([f"{n} ({ua or '1'} / {ub or '1'})" for n, ua, ub in units]))
        skip = {n for n, _, _ in units}
        names = [n for n in names if n not in skip]
    if not names and not out.problems:
        out.problems.append("0 signals compared")
    n_points = _rank(out, a, b, names, (ia, ib), float(rtol))
    _check_nonfinite(out, labels, n_points, ia)
    return out


#: Signals read at a time from each result (memory: this many columns × time points × 8 bytes per result).
_BLOCK = 256


def _rank(out: Comparison, a: Any, b: Any, names: list[str], columns: tuple[dict[str, int], dict[str, int]],
          rtol: float) -> int:
    """The rows of ``names`` (``columns``: their column in A and in B): each signal of B in its tube around A's
    (module docstring), ranked; returns the number of compared time points.

    The signals are read :data:`_BLOCK` at a time (a result file's variables are derived when read): one pass keeps,
    per signal, what its row needs — the largest deviation, the base of its tolerance, its magnitude and a digest of
    its traces — and the tolerances follow from the floors per unit once every signal is seen."""
    ia, ib = columns
    keep_a, keep_b = event_rows(a.t), event_rows(b.t)  # the right value at events, as Result.value
    (t0, t1), ta, tb = out.span, a.t[keep_a], b.t[keep_b]
    grid = np.union1d(ta, tb)
    grid = grid[(grid >= t0) & (grid <= t1)]
    shift = _event_shifts(grid, a.t, b.t)
    on_a, on_b = _on_grid(grid, ta), _on_grid(grid, tb)
    scale: dict[str, float] = {}
    seen: list[tuple[dict[str, Any], float, float, float]] = []  # row, largest deviation, base, magnitude
    groups: dict[tuple, list[str]] = {}  # the same values in A and in B (aliases by structure): read once
    sig_a, sig_b = _signatures(a), _signatures(b)
    for n in names:
        groups.setdefault((a.units[ia[n]], sig_a[ia[n]], sig_b[ib[n]]), []).append(n)
    first = [members[0] for members in groups.values()]
    others = {members[0]: members[1:] for members in groups.values()}
    for start in range(0, len(first), _BLOCK):
        block = first[start:start + _BLOCK]
        va = np.asfortranarray(a._read([ia[n] for n in block], keep=False))
        vb = np.asfortranarray(b._read([ib[n] for n in block], keep=False))
        for j, n in enumerate(block):
            unit = a.units[ia[n]]
            xa_rows, xb_rows = va[:, j][keep_a], vb[:, j][keep_b]
            xa = xa_rows[on_a] if on_a is not None else _interp(grid, ta, xa_rows)
            xb = xb_rows[on_b] if on_b is not None else _interp(grid, tb, xb_rows)
            row = _row(n, unit, grid, xa, xb)
            finite_a = xa[np.isfinite(xa)]
            base = max(float(np.ptp(finite_a)), abs(float(finite_a.min()))) if finite_a.size else 0.0
            dev = 0.0
            if not row["mismatch"]:
                d, _ = tube(grid, xa, lambda times, x=xb_rows: _interp(np.clip(times, t0, t1), tb, x), 1.0, shift,
                            at_grid=xb)
                d = d[np.isfinite(xa)]
                dev = float(np.max(d)) if d.size else 0.0
            magnitude = max(np.max(np.abs(x[np.isfinite(x)]), initial=0.0) for x in (xa, xb))
            scale[unit] = max(scale.get(unit, 0.0), float(np.max(np.abs(xb_rows[np.isfinite(xb_rows)]),
                                                                  initial=0.0)), float(magnitude))
            row["digest"] = _digest(unit, xa, xb_rows)
            seen.append((row, dev, base, magnitude))
            seen += [({**row, "name": alias}, dev, base, magnitude) for alias in others[n]]
    solver = max(float(r.stats.get("atol", 0.0) or 0.0) for r in (a, b))
    floors = _unit_floors(scale, NOISE_ATOL * solver)
    for row, dev, base, magnitude in seen:
        floor = floors[row["unit"]]
        tol = floor + rtol * base
        ratio = np.inf if row["mismatch"] else dev / tol
        out.rows.append({**row, "tol": tol, "ratio": ratio, "noise": bool(not row["mismatch"] and magnitude <= floor)})
    connector = {n: a.kinds[ia[n]] in ("potential", "flow") for n in names}  # aliases: the variable names them
    out.rows.sort(key=lambda r: (r["noise"], -r["ratio"], -r["rel"], -r["abs"], connector[r["name"]]))
    _group_aliases(out.rows)
    quiet = sum(r["noise"] for r in out.rows)
    if quiet:
        out.notes.append(f"{_n(quiet, 'signal')} within the noise floor in both results (|x| below the tube's "
                         "absolute floor throughout: round-off of a quantity that is 0 in both), not ranked")
    return len(grid)


def _on_grid(grid: np.ndarray, t: np.ndarray) -> np.ndarray | None:
    """The rows of a result's (right-value) times ``t`` that are the grid, if the grid is a run of them (the same
    output grid in both results): its values need no interpolation; None otherwise."""
    inside = np.flatnonzero((t >= grid[0]) & (t <= grid[-1])) if len(grid) else np.zeros(0, dtype=int)
    return inside if len(inside) == len(grid) and np.array_equal(t[inside], grid) else None


def _signatures(res: Any) -> list[Any]:
    """Per column of ``res``, a key shared by columns with the same values (its source's structure: aliases of one
    unknown or one expression), else the column itself."""
    keys = getattr(res.source, "signatures", None) if res._values is None else None
    return keys() if keys is not None else list(range(len(res.names)))


#: Random projections of a trace (by length) that key the alias table: equal traces give equal projections.
_PROJECTIONS: dict[int, np.ndarray] = {}


def _digest(unit: str, xa: np.ndarray, xb: np.ndarray) -> bytes:
    """A key of the traces ``xa`` (A on the grid) and ``xb`` (B's rows): four random projections of each (far cheaper
    than hashing every byte, and as telling for traces of a simulation), with the unit and the lengths."""
    parts = [unit.encode(), np.array([len(xa), len(xb)]).tobytes()]
    for x in (xa, xb):
        if len(x) not in _PROJECTIONS:
            _PROJECTIONS[len(x)] = np.random.default_rng(len(x)).standard_normal((4, len(x)))
        parts.append((_PROJECTIONS[len(x)] @ np.where(np.isnan(x), 0.0, x)).tobytes())
        parts.append(np.flatnonzero(~np.isfinite(x)).tobytes())
    return b"".join(parts)


def _group_aliases(rows: list[dict[str, Any]]) -> None:
    """Mark rows whose traces are the same in both results (aliases: the same ``digest``, removed from the row): the
    first (in rank order) lists the others in ``same``, each of them names it in ``alias_of``."""
    first: dict[bytes, dict[str, Any]] = {}
    for row in rows:
        key = row.pop("digest")
        row["same"], row["alias_of"] = [], None
        if key in first:
            first[key]["same"].append(row["name"])
            row["alias_of"] = first[key]["name"]
        else:
            first[key] = row


def _unit_floors(scale: Mapping[str, float], least: float) -> dict[str, float]:
    """The tube's absolute floor per unit: :data:`ATOL_SCALE` times the largest finite magnitude of that unit's
    signals in both results (``scale``), at least ``least`` (the smallest positive float if both are 0)."""
    return {u: max(ATOL_SCALE * s, least, np.finfo(float).tiny) for u, s in scale.items()}


def _event_shifts(grid: np.ndarray, *times: np.ndarray) -> np.ndarray:
    """Per grid point, the time shift the tube allows: one grid interval at the points next to an event of either
    run (a time recorded twice, left and right value), 0 elsewhere."""
    shift = np.zeros(len(grid))
    if len(grid) < 2:
        return shift
    step = np.diff(grid)
    for t in times:
        for te in np.asarray(t)[:-1][np.diff(t) == 0]:
            k = int(np.searchsorted(grid, te))
            for i in (k - 1, k, k + 1):
                if 0 <= i < len(grid):
                    shift[i] = max(shift[i], step[min(i, len(step) - 1)], step[max(i - 1, 0)])
    return shift


def _row(name: str, unit: str, grid: np.ndarray, xa: np.ndarray, xb: np.ndarray) -> dict[str, Any]:
    fa, fb = np.isfinite(xa), np.isfinite(xb)
    both = fa & fb
    same = ~fa & ~fb & ((xa == xb) | (np.isnan(xa) & np.isnan(xb)))  # NaN in both, or the same inf
    mismatch = ~both & ~same
    bad_a, bad_b = mismatch & ~fa, mismatch & ~fb  # this side NaN/inf where the other is not the same
    row = {"name": name, "unit": unit, "nonfinite_a": int((~fa).sum()), "nonfinite_b": int((~fb).sum()),
           "mismatch": int(mismatch.sum()), "mismatch_a": int(bad_a.sum()), "mismatch_b": int(bad_b.sum()),
           "from_a": float(grid[np.argmax(bad_a)]) if bad_a.any() else None,
           "from_b": float(grid[np.argmax(bad_b)]) if bad_b.any() else None}
    if mismatch.any():
        k = int(np.argmax(mismatch))
        return {**row, "abs": np.inf, "rel": np.inf, "t": float(grid[k]), "a": float(xa[k]), "b": float(xb[k])}
    if not both.any():  # nothing finite to compare: NaN (or the same inf) in both everywhere
        return {**row, "abs": 0.0, "rel": 0.0, "t": float(grid[0]), "a": float(xa[0]), "b": float(xb[0])}
    d = np.where(both, np.abs(xa - xb), 0.0)
    k = int(np.argmax(d))
    scale = max(float(np.max(np.abs(xa[both]))), float(np.max(np.abs(xb[both]))))
    rel = float(d[k]) / scale if scale else 0.0
    return {**row, "abs": float(d[k]), "rel": rel, "t": float(grid[k]), "a": float(xa[k]), "b": float(xb[k])}


def _check_names(out: Comparison, a: Any, b: Any, selected: bool, labels: tuple[str, str]) -> None:
    models = f"{labels[0]} is {a.model}, {labels[1]} is {b.model}"
    if not set(a.names) & set(b.names):
        out.problems.append(f"no variable in common, 0 signals compared ({models}); {_n(len(out.only_a), 'variable')} "
                            f"only in {labels[0]} ({_listed(out.only_a)}), {len(out.only_b)} only in {labels[1]} "
                            f"({_listed(out.only_b)})")
        return
    if not selected and (out.only_a or out.only_b):
        parts = [f"{len(names)} only in {label} ({_listed(names)})"
                 for label, names in ((labels[0], out.only_a), (labels[1], out.only_b)) if names]
        out.problems.append(f"not every variable is in both results: {'; '.join(parts)} (not compared; "
                            "--signals compares a chosen set)")
    if a.model != b.model:
        out.problems.append(f"different model classes: {models}")


def _check_span(out: Comparison, a: Any, b: Any, labels: tuple[str, str]) -> None:
    (a0, a1), (b0, b1) = out.span_a, out.span_b
    tol = 1e-9 * max(1.0, abs(a0), abs(a1), abs(b0), abs(b1))
    status = {label: res for label, res in zip(labels, (a, b), strict=True) if res.status != "success"}
    why = "; ".join(f"{label} is {res.status}" + (f": {' '.join(res.message.split())}" if res.message else "")
                    for label, res in status.items())
    if abs(a0 - b0) > tol or abs(a1 - b1) > tol:
        out.problems.append(f"only the common time span {out.span[0]:g} … {out.span[1]:g} s is compared: "
                            f"{labels[0]} covers {a0:g} … {a1:g} s, {labels[1]} {b0:g} … {b1:g} s"
                            + (f"; {why}" if why else ""))
    elif a.status != b.status:
        out.problems.append(f"the runs ended differently: {why}")
    elif status:
        out.notes.append(f"both runs are {a.status}: {why}")


def _check_nonfinite(out: Comparison, labels: tuple[str, str], n_points: int, order: Mapping[str, int]) -> None:
    for side, other, x in ((labels[1], labels[0], "b"), (labels[0], labels[1], "a")):
        count, start = f"mismatch_{x}", f"from_{x}"  # named in the model's order
        bad = sorted((r for r in out.rows if r[count]), key=lambda r: (r[start], -r[count], order[r["name"]]))
        if bad:
            most = max(r[count] for r in bad)
            out.problems.append(
                f"{_n(len(bad), 'signal')} NaN or inf in {side} where {other} is finite, from t = {bad[0][start]:g} "
                f"s: {_listed([r['name'] for r in bad])} (up to {most} of {n_points} compared points)")
    same = [r["name"] for r in out.rows if not r["mismatch"] and (r["nonfinite_a"] or r["nonfinite_b"])]
    if same:
        out.notes.append(f"{_n(len(same), 'signal')} NaN or inf at the same points in both results (compared on the "
                         f"finite points only): {_listed(same)}")


def compare_results(a: Any, b: Any, signals: list[str] | str | None = None) -> list[dict[str, Any]]:
    """The rows of :func:`compare` (ranked: farthest out of the tube first); see :class:`Comparison` for the keys.

    Use :func:`compare` to also get what the comparison does not cover (NaN, different time spans, variables in
    one result only).
    """
    return compare(a, b, signals).rows
