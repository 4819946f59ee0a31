"""Piecewise-constant tables of time looked up without events: :func:`segment_row`.

A reference profile (a motion planner's knots, a cylinder-length profile refined to 1 µm) has hundreds of segments.
Selecting the segment that holds the time with relations costs one comparison and one selection per segment and
per column at every residual evaluation (CasADi's SX graphs evaluate every node), which makes such a profile the
dearest part of a machine's residual. A table is instead looked up by a binary search (a CasADi interpolant: the
segment index as ``floor`` of a linear interpolation of the index over the breaks, corrected by comparisons with
that segment's bounds, then the row at that index), at a cost that does not grow with the number of segments.

Interpolant call nodes are opaque to the symbolic stages, and CasADi's derivatives of expressions that hold them
keep unevaluated derivative calls (or NaN) instead of exact zeros, which would hide linear structure from the
index reduction and the explicit elimination. So the row of a table enters the equations as symbols of their own
(kind ``"table"``): piecewise constant, their time derivative is zero (:func:`flexlib.der`), and every stage sees
plain symbols. The compile stage (:mod:`flexlib.compile.codegen`) replaces them by the lookups in the functions it
builds, after every derivative has been taken (:func:`bind_tables`).

References
----------
Modelica Standard Library 4.0, ``Blocks.Tables.CombiTable1Ds`` / ``Blocks.Sources.CombiTimeTable``: tables as
external objects whose look-up is a function call the tool does not differentiate symbolically.
"""

from __future__ import annotations

from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from flexlib.core.equations import as_sx
from flexlib.core.variables import SymInfo, time
from flexlib.errors import ModelError

__all__ = ["CURRENT_TABLES", "SegmentTable", "bind_tables", "segment_row"]

#: Tables created while a component's equations() runs are recorded here by the flattener.
CURRENT_TABLES: ContextVar[list | None] = ContextVar("flexlib_tables", default=None)


@dataclass(eq=False)
class SegmentTable:
    """A table of rows, one per segment of the breaks, selected by an expression of time.

    Attributes
    ----------
    x : casadi.SX
        The selecting expression (of time only).
    breaks : ndarray, shape (N,)
        Strictly increasing break points.
    rows : ndarray, shape (N + 1, m)
        Row ``i`` holds for ``breaks[i-1] <= x < breaks[i]`` (row 0 below the first break, row N from the last on).
    symbols : list of casadi.SX
        The ``m`` symbols standing for the selected row in the equations.
    infos : list of SymInfo
        Their registry entries (kept alive with the table: the registry holds them weakly).
    """

    x: ca.SX
    breaks: np.ndarray
    rows: np.ndarray
    symbols: list[ca.SX] = field(default_factory=list)
    infos: list[SymInfo] = field(default_factory=list, repr=False)

    def lookup(self) -> list[ca.SX]:
        """The selected row as expressions of time: three interpolant calls (a binary search for the index, the
        segment's bounds to correct it within a rounding of a break, the row)."""
        b, table = self.breaks, self.rows
        if b.size == 1:  # one break: one selection (a varying column has at least two rows)
            return [ca.if_else(self.x < float(b[0]), float(lo), float(hi)) for lo, hi in zip(table[0], table[-1],
                                                                                               strict=True)]
        n, grid = b.size, np.arange(b.size + 1, dtype=float).tolist()
        index = ca.interpolant("flexlib_segment_index", "linear", [b.tolist()], np.arange(n, dtype=float).tolist(),
                               {"lookup_mode": ["binary"]})
        k = ca.fmin(ca.fmax(ca.floor(index(self.x)) + 1.0, 0.0), float(n))
        # the interpolated index may be one off within a rounding of a break: the segment's own bounds (exact values
        # of a table) correct it, so the selection is that of the comparisons `x < breaks[i]`
        lower = np.concatenate([[-np.finfo(float).max], b])
        upper = np.concatenate([b, [np.finfo(float).max]])
        bounds = ca.interpolant("flexlib_segment_bounds", "linear", [grid],
                                np.column_stack([lower, upper]).ravel().tolist(), {"lookup_mode": ["exact"]})(k)
        k = k - ca.if_else(self.x < bounds[0], 1.0, 0.0) + ca.if_else(self.x >= bounds[1], 1.0, 0.0)
        row = ca.interpolant("flexlib_segment_rows", "linear", [grid], table.ravel().tolist(),
                             {"lookup_mode": ["exact"]})(k)
        return [row[i] for i in range(table.shape[1])]


def segment_row(x: Any, breaks: Any, rows: Any) -> list[ca.SX]:
    """The row of ``rows`` for the segment of ``breaks`` that holds ``x``, without events, in O(log N).

    Segment 0 holds ``x < breaks[0]``, segment ``i`` holds ``breaks[i-1] <= x < breaks[i]``, segment ``N`` holds
    ``x >= breaks[N-1]``: the selection a chain of :func:`flexlib.no_event` over the breaks makes, looked up by a
    binary search instead (module docstring), so that its cost does not grow with the number of segments. The row
    is piecewise constant: its time derivative is zero, and no event stops the integrator at a break, so use it
    where what is computed from it is continuous across the breaks (a spline's coefficients with ``x − breaks[k]``)
    or where a jump is harmless. Only inside a component's ``equations()``.

    Parameters
    ----------
    x : expression
        The selecting expression, of :data:`flexlib.time` only (e.g. ``time`` or ``time + lead``) [s].
    breaks : array_like, shape (N,)
        Strictly increasing break points [s].
    rows : array_like, shape (N + 1, m)
        One row per segment.

    Returns
    -------
    list of casadi.SX
        The ``m`` entries of the selected row (a constant for a column with the same value in every row).
    """
    x = as_sx(x, "segment_row(): x")
    b = np.asarray(breaks, dtype=float).ravel()
    table = np.asarray(rows, dtype=float)
    if table.ndim != 2 or table.shape[0] != b.size + 1 or table.shape[1] < 1:
        raise ModelError(f"segment_row(): rows must be a table of len(breaks) + 1 = {b.size + 1} rows, got shape "
                         f"{table.shape}")
    if not (np.all(np.isfinite(b)) and np.all(np.isfinite(table)) and np.all(np.diff(b) > 0)):
        raise ModelError("segment_row(): breaks must be finite and strictly increasing, rows finite")
    if not x.is_scalar():
        raise ModelError(f"segment_row(): x must be a scalar expression, got shape {x.shape}")
    other = [s.name() for s in ca.symvar(x) if not ca.is_equal(s, time)]
    if other:
        raise ModelError(f"segment_row(): x must be an expression of time only, got one of {', '.join(other)}")
    sink = CURRENT_TABLES.get()
    if sink is None:
        raise ModelError("segment_row() may only be used inside equations()")
    # a column with one value in every segment is that constant (no lookup: the stages see a constant, as with a
    # chain of selections of equal values, e.g. a reference without moves)
    varying = [i for i in range(table.shape[1]) if np.any(table[:, i] != table[0, i])]
    out: list[ca.SX] = [ca.SX(float(table[0, i])) for i in range(table.shape[1])]
    if not varying:
        return out
    tbl = SegmentTable(x, b, table[:, varying])
    for i in varying:
        sym = ca.SX.sym(f"table{len(sink)}[{i}]")
        tbl.infos.append(SymInfo(sym, "table", name=f"segment_row(...)[{i}]"))
        tbl.symbols.append(sym)
        out[i] = sym
    sink.append(tbl)
    return out


def bind_tables(exprs: list[ca.SX], tables: list[SegmentTable]) -> list[ca.SX]:
    """``exprs`` with the symbols of ``tables`` replaced by their lookups (:meth:`SegmentTable.lookup`, made once
    here), in one substitution (the lookups shared). Take every derivative before (module docstring)."""
    syms = [s for tbl in tables for s in tbl.symbols]
    if not syms:
        return list(exprs)
    values = [v for tbl in tables for v in tbl.lookup()]
    return ca.substitute(list(exprs), [ca.vertcat(*syms)], [ca.vertcat(*values)])

