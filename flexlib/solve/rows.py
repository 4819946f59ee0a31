"""Evaluating a model function over many recorded rows (result assembly, checks over a run).

A function ``f(t, y, yp, p)`` of the compiled model is evaluated for rows ``T, Y, YP, P`` (one row per
point, row-major) through FunctionBuffers straight into a preallocated C-ordered buffer: ``f`` mapped over
:data:`CHUNK` rows per call (row-major stacks of rows are exactly the column-major matrices the map takes,
so no copy or conversion), the remainder row by row. 18–40× cheaper than one DM call of ``f.map(rows)``
(measured in ``benchmarks/engine_speed.py``). The mapped buffers are kept per model and function.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel

__all__ = ["CHUNK", "RowEvaluator", "segments"]

#: Rows per call of the mapped function.
CHUNK = 256


class RowEvaluator:
    """Evaluates model functions over rows, keeping the dense/mapped/single-row buffers it builds."""

    def __init__(self) -> None:
        self._cache: dict[tuple, Any] = {}

    def clear(self) -> None:
        """Forget every buffer (the model was rebuilt)."""
        self._cache.clear()

    def _entry(self, model: CompiledModel, key: tuple, make: Any) -> Any:
        entry = self._cache.get((id(model), *key))
        if entry is None or entry[0] is not model:
            entry = self._cache[(id(model), *key)] = (model, make())
        return entry[1]

    def evaluate(self, model: CompiledModel, name: str, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                 P: np.ndarray) -> np.ndarray:
        """Function ``name`` of ``model`` at rows ``T`` (m,), ``Y``, ``YP`` (m × n), ``P`` (m × n_p): (m × n_out)."""
        fn = model.function(name)
        if not fn.sparsity_out(0).is_dense():  # structural zeros: the buffer needs every entry

            def dense(fn: ca.Function = fn) -> ca.Function:
                args = fn.sx_in()
                return ca.Function(f"{fn.name()}_dense", args, [ca.densify(fn(*args))])

            fn = self._entry(model, (name, "dense"), dense)
        n_rows = len(T)
        values = np.zeros((n_rows, fn.nnz_out(0)))
        T, Y, YP, P = (np.ascontiguousarray(a, dtype=float) for a in (T, Y, YP, P))
        full = n_rows // CHUNK * CHUNK
        if full:
            buf, ev = self._entry(model, (name, "map", CHUNK), lambda: fn.map(CHUNK).buffer())
            for a in range(0, full, CHUNK):
                b = a + CHUNK
                buf.set_arg(0, memoryview(T[a:b]))
                buf.set_arg(1, memoryview(Y[a:b]))
                buf.set_arg(2, memoryview(YP[a:b]))
                buf.set_arg(3, memoryview(P[a:b]))
                buf.set_res(0, memoryview(values[a:b]))
                ev()
        if full < n_rows:
            buf, ev = self._entry(model, (name, "row"), fn.buffer)
            for i in range(full, n_rows):
                buf.set_arg(0, memoryview(T[i:i + 1]))
                buf.set_arg(1, memoryview(Y[i]))
                buf.set_arg(2, memoryview(YP[i]))
                buf.set_arg(3, memoryview(P[i]))
                buf.set_res(0, memoryview(values[i]))
                ev()
        return values


def segments(traj: Any, default: CompiledModel,
             pvec: np.ndarray) -> Iterator[tuple[CompiledModel, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                 np.ndarray]]:
    """The rows of a :class:`~flexlib.solve.ida.Trajectory` grouped by the model that produced them (state
    switches change it): ``(model, rows, T, Y, YP, P)`` with row-major arrays and ``P`` = parameters
    ``pvec`` followed by each row's relation values."""
    if not traj.t:
        return
    T = np.array(traj.t)
    seg = np.array(traj.seg) if traj.seg else np.zeros(len(T), dtype=int)
    rel = np.array(traj.rel, dtype=float).reshape(len(T), -1)
    for k in np.unique(seg):
        rows = np.flatnonzero(seg == k)
        model = traj.models[k] if traj.models else default
        Y = np.array([traj.y[i] for i in rows], dtype=float).reshape(len(rows), model.n)
        YP = np.array([traj.yp[i] for i in rows], dtype=float).reshape(len(rows), model.n)
        P = np.empty((len(rows), len(pvec) + rel.shape[1]))
        P[:, :len(pvec)] = pvec
        P[:, len(pvec):] = rel[rows]
        yield model, rows, T[rows], Y, YP, P
