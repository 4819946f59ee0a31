"""Evaluating a model function over many recorded rows (result assembly, checks over a run).

A function ``f(t, y, yp, p)`` of the compiled model is evaluated for rows ``T, Y, YP, P`` (one row per
point, row-major) through FunctionBuffers straight into a preallocated C-ordered buffer: ``f`` mapped over
:data:`CHUNK` rows per call (row-major stacks of rows are exactly the column-major matrices the map takes,
so no copy or conversion), the remainder row by row (``docs/decisions/031-rows-evaluated-through-mapped-buffers.md``).
The mapped buffers are kept per model and function.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel

__all__ = ["CHUNK", "SETTLE_TOL", "RowEvaluator", "segments", "settle_derivative_level"]

#: Rows per call of the mapped function.
CHUNK = 256
#: Relative residual of a row above which its derivative-level unknowns are solved again (see
#: :func:`settle_derivative_level`).
SETTLE_TOL = 1e-3
#: Unknowns up to which the rows to settle are solved densely, all at once.
DENSE_SETTLE = 128
#: A large model's consecutive rows to settle that share one matrix's LU (chord steps, :func:`settle_rows`).
SHARE_LU = 20
#: Chord steps with a shared matrix before a row takes its own.
CHORD_ITERATIONS = 6


class RowEvaluator:
    """Evaluates model functions over rows, keeping the dense/mapped/single-row buffers it builds."""

    def __init__(self) -> None:
        self._cache: dict[tuple, Any] = {}

    def clear(self) -> None:
        """Forget every buffer (the model was rebuilt)."""
        self._cache.clear()

    def cached(self, model: CompiledModel, key: tuple, make: Any) -> Any:
        """The object kept for ``model`` under ``key`` (a function, a buffer), made by ``make()`` the first time."""
        entry = self._cache.get((id(model), *key))
        if entry is None or entry[0] is not model:
            entry = self._cache[(id(model), *key)] = (model, make())
        return entry[1]

    def keep_latest(self, model: CompiledModel, key: tuple) -> None:
        """Forget what is kept for ``model`` under keys that start like ``key[0]`` but differ in ``key[1]`` (buffers
        of a function made for other parameter values: a study's runs would otherwise pile them up)."""
        for k in [k for k in self._cache if k[0] == id(model) and len(k) > 2 and k[1] == key[0] and k[2] != key[1]]:
            del self._cache[k]

    def evaluate(self, model: CompiledModel, name: str, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                 P: np.ndarray) -> np.ndarray:
        """Function ``name`` of ``model`` at rows ``T`` (m,), ``Y``, ``YP`` (m × n), ``P`` (m × n_p): (m × n_out)."""
        fn = model.function(name)
        if not fn.sparsity_out(0).is_dense():  # structural zeros: the buffer needs every entry

            def dense(fn: ca.Function = fn) -> ca.Function:
                args = fn.sx_in()
                return ca.Function(f"{fn.name()}_dense", args, [ca.densify(fn(*args))])

            fn = self.cached(model, (name, "dense"), dense)
        return self.evaluate_function(fn, model, (name,), T, Y, YP, P)

    def evaluate_function(self, fn: ca.Function, model: CompiledModel, key: tuple, T: np.ndarray, Y: np.ndarray,
                          YP: np.ndarray, P: np.ndarray) -> np.ndarray:
        """A dense-output function ``fn(t, y, yp, p)`` of ``model`` (buffers kept under ``key``) at the rows."""
        name = key
        n_rows = len(T)
        values = np.zeros((n_rows, fn.nnz_out(0)))
        T, Y, YP, P = (np.ascontiguousarray(a, dtype=float) for a in (T, Y, YP, P))
        full = n_rows // CHUNK * CHUNK
        if full:
            buf, ev = self.cached(model, (*name, "map", CHUNK), lambda: fn.map(CHUNK).buffer())
            for a in range(0, full, CHUNK):
                b = a + CHUNK
                buf.set_arg(0, memoryview(T[a:b]))
                buf.set_arg(1, memoryview(Y[a:b]))
                buf.set_arg(2, memoryview(YP[a:b]))
                buf.set_arg(3, memoryview(P[a:b]))
                buf.set_res(0, memoryview(values[a:b]))
                ev()
        if full < n_rows:
            buf, ev = self.cached(model, (*name, "row"), fn.buffer)
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
    """The rows of a :class:`~flexlib.solve.trajectory.Trajectory` grouped by the model that produced them (state
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
        whole = len(rows) == len(T)  # one model for the whole run: every row, in order
        if whole:  # kept: stacked once for every reader of the run's rows
            Y, YP = traj.stacked()
            P = traj.stacked_parameters(pvec)
        else:
            Y = np.vstack([traj.y[i] for i in rows], dtype=float)
            YP = np.vstack([traj.yp[i] for i in rows], dtype=float)
            P = np.empty((len(rows), len(pvec) + rel.shape[1]))
            P[:, :len(pvec)] = pvec
            P[:, len(pvec):] = rel[rows]
        Y, YP = Y.reshape(len(rows), model.n), YP.reshape(len(rows), model.n)
        yield model, rows, T[rows], Y, YP, P


def settle_derivative_level(rows: RowEvaluator, model: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                            P: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """Recorded rows with their derivative-level unknowns checked, and made consistent where they are off.

    The derivative-level unknowns (cut forces, reactions, accelerations: ``CompiledModel.derivative_level``) are out of
    IDA's error test and, with their infinite tolerance, out of its Newton convergence test too (``docs/engine.md``,
    "Error-test policy"). Nothing then stops them from drifting: with a stale iteration matrix the corrector can leave
    them wrong, and the predictor's extrapolation of wrong values can grow them geometrically while every state stays
    right (``docs/decisions/009-derivative-level-unknowns-settled-in-results.md``). Each recorded row is therefore
    checked. With ``F0_i(t)`` the residual of equation ``i`` with the derivative-level unknowns set to zero (the terms
    IDA does control) and ``p_i = |F_i − F0_i|`` their terms, the equation's scale over the run is ``S_i = max(max_t
    |F0_i|, median_t p_i)`` and the row is off when some ``|F_i(t)| > SETTLE_TOL (p_i(t) + S_i) + 1e-6 max_i S_i``: more
    than 0.1 % of the equation's scale (below a millionth of the model's largest scale a residual is round-off of a
    quantity that is physically zero, e.g. an out-of-plane reaction of a planar motion). In such a row the states are
    kept and everything else is solved again from ``F(t, y, y') = 0`` — the states' derivatives and all algebraic
    unknowns (Newton on the index-1 system, at most four iterations), as a consistent initialisation would.

    ``Y`` and ``YP`` are repaired in place (the caller owns them; a failure of the repair leaves them as they were).

    Returns
    -------
    Y, YP : ndarray (m, n)
        The rows, repaired where needed.
    repaired : int
        Number of rows solved again.
    """
    D = np.flatnonzero(np.asarray(model.derivative_level, dtype=bool))
    if D.size == 0 or len(T) == 0:
        return Y, YP, 0
    colind = np.asarray(model.jac_colind)
    row_of = np.asarray(model.jac_row)
    col_of = np.repeat(np.arange(model.n), np.diff(colind))
    eqs = np.unique(row_of[np.isin(col_of, D)])  # the equations containing derivative-level unknowns
    if eqs.size == 0:
        return Y, YP, 0
    F = rows.evaluate(model, "res", T, Y, YP, P)[:, eqs]
    Y0 = np.array(Y, dtype=float, copy=True)
    Y0[:, D] = 0.0
    F0 = rows.evaluate(model, "res", T, Y0, YP, P)[:, eqs]  # the other terms: states, y', other algebraics
    part = np.abs(F - F0)  # the derivative-level terms' share
    # each equation's scale over the run from what IDA controls (not from the suspects themselves), or for an
    # equation of derivative-level unknowns only, their median magnitude
    scale = np.maximum(np.abs(F0).max(axis=0), np.median(part, axis=0))
    allowed = SETTLE_TOL * (part + scale) + 1e-6 * scale.max(initial=0.0)
    bad = np.flatnonzero((np.abs(F) > allowed).any(axis=1))
    if bad.size == 0:
        return Y, YP, 0
    recorded = (Y[bad], YP[bad])  # copies (fancy indexing)
    try:
        settle_rows(rows, model, T, Y, YP, P, bad)
    except BaseException:
        Y[bad], YP[bad] = recorded
        raise
    return Y, YP, int(bad.size)


def _settle_jacobian(model: CompiledModel) -> ca.Function:
    """``(t, y, yp, p) ->`` the Jacobian's nonzeros at ``c = 0`` (``∂F/∂y``) followed by those at ``c = 1``."""
    if model.n <= DENSE_SETTLE:  # small: the SX Jacobian expanded (the VM beats an MX call per row)
        fn = model.sx_function("jac")
        args = fn.sx_in()[:4]
    else:
        fn = model.function("jac")
        args = [ca.MX.sym(fn.name_in(k), fn.sparsity_in(k)) for k in range(4)]
    J0, J1 = fn(*args, 0.0), fn(*args, 1.0)
    return ca.Function("jac_settle_full", args, [ca.vertcat(ca.vec(J0.nz[:]), ca.vec(J1.nz[:]))])


def settle_rows(rows: RowEvaluator, model: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                P: np.ndarray, bad: np.ndarray) -> None:
    """``Y, YP`` with the rows ``bad`` solved again in place from ``F = 0``, states held: Newton on the unknowns
    ``y'`` of the states and ``y`` of the algebraic unknowns (the matrix has the Jacobian's pattern, a state's column
    from ``∂F/∂y'``, an algebraic unknown's from ``∂F/∂y``), to steps below 1e-12 of the row's largest unknown.

    A small model's rows: at most four Newton iterations, batched dense solves. A large model's rows take chord steps
    (the rows are consistent but for their derivative-level unknowns, in which the residual is nearly linear): the
    rows to settle come in runs of consecutive output times, and each run's rows share the sparse LU of the matrix of
    its first row (refreshed every :data:`SHARE_LU` rows), at most :data:`CHORD_ITERATIONS` steps; a row that has not
    converged then (or whose shared matrix was singular) is solved again with its own matrix's LU, at most four
    steps. A row whose own matrix is singular is left as it was."""
    if model.n <= DENSE_SETTLE:
        todo = bad
        for _ in range(4):
            if todo.size == 0:
                break
            r_all = rows.evaluate(model, "res", T[todo], Y[todo], YP[todo], P[todo])
            steps = _newton_steps(model, _settle_matrices(rows, model, T, Y, YP, P, todo), r_all)
            todo, _ = _apply_steps(model, Y, YP, todo, steps)
        return
    bad = np.sort(bad)
    recorded = (Y[bad], YP[bad])  # copies (fancy indexing)
    left, failed = _chord_pass(rows, model, T, Y, YP, P, bad, SHARE_LU, CHORD_ITERATIONS)
    again = np.union1d(left, failed)
    if again.size:
        _, singular = _chord_pass(rows, model, T, Y, YP, P, again, 1, 4)
        where = np.searchsorted(bad, singular)
        Y[singular], YP[singular] = recorded[0][where], recorded[1][where]


def _settle_matrices(rows: RowEvaluator, model: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                     P: np.ndarray, which: np.ndarray) -> np.ndarray:
    """The nonzeros (in the Jacobian's pattern) of the rows' Newton matrices: ``∂F/∂y'`` in a state's column,
    ``∂F/∂y`` in an algebraic unknown's."""
    col_of = np.repeat(np.arange(model.n), np.diff(np.asarray(model.jac_colind)))
    state_nz = np.asarray(model.differential, dtype=bool)[col_of]
    n_nz = col_of.size
    full_key = ("settle", "jac_full")
    full = rows.cached(model, full_key, lambda: _settle_jacobian(model))
    JV = rows.evaluate_function(full, model, full_key, T[which], Y[which], YP[which], P[which])
    return np.where(state_nz, JV[:, n_nz:] - JV[:, :n_nz], JV[:, :n_nz])


def _apply_steps(model: CompiledModel, Y: np.ndarray, YP: np.ndarray, todo: np.ndarray,
                 steps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows ``todo`` moved by their Newton ``steps`` (rows with a non-finite step are not moved): the rows still
    moving by more than 1e-12 of their largest unknown, and the rows not moved."""
    diff = np.asarray(model.differential, dtype=bool)
    ok = np.isfinite(steps).all(axis=1)
    rows_ok, steps = todo[ok], steps[ok]
    YP[np.ix_(rows_ok, diff)] -= steps[:, diff]
    Y[np.ix_(rows_ok, ~diff)] -= steps[:, ~diff]
    size = np.maximum(np.abs(YP[np.ix_(rows_ok, diff)]).max(axis=1, initial=0.0),
                      np.abs(Y[np.ix_(rows_ok, ~diff)]).max(axis=1, initial=0.0))
    return rows_ok[np.abs(steps).max(axis=1, initial=0.0) > 1e-12 * (size + 1e-300)], todo[~ok]


def _chord_pass(rows: RowEvaluator, model: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray,
                P: np.ndarray, todo: np.ndarray, share: int, iterations: int) -> tuple[np.ndarray, np.ndarray]:
    """Chord steps on the rows ``todo`` (sorted), each run of consecutive rows sharing the LU of its first row's
    matrix for ``share`` rows: the rows not converged after ``iterations`` steps, and the rows without a matrix
    (singular)."""
    k = np.arange(todo.size)
    run_start = np.r_[True, np.diff(todo) != 1]
    first = np.maximum.accumulate(np.where(run_start, k, 0))  # position of each row's run start
    leader = run_start | ((k - first) % share == 0)
    lead_of = np.maximum.accumulate(np.where(leader, k, 0))
    leaders = todo[leader]
    own = _factor_rows(model, _settle_matrices(rows, model, T, Y, YP, P, leaders), leaders)
    factors = {int(row): own.get(int(todo[lead_of[i]])) for i, row in enumerate(todo)}
    failed = np.empty(0, dtype=todo.dtype)
    for _ in range(iterations):
        if todo.size == 0:
            break
        r_all = rows.evaluate(model, "res", T[todo], Y[todo], YP[todo], P[todo])
        todo, not_moved = _apply_steps(model, Y, YP, todo, _chord_steps(factors, todo, r_all))
        failed = np.r_[failed, not_moved]
    return todo, np.sort(failed)


def _factor_rows(model: CompiledModel, data: np.ndarray, which: np.ndarray) -> dict[int, Any]:
    """Sparse LU of each row's matrix (nonzeros ``data`` in the Jacobian's pattern) by row number; a singular
    matrix has none."""
    import scipy.sparse as sp  # here: a result's reader imports this module and needs no sparse algebra (0.3 s)
    import scipy.sparse.linalg as spla

    colind, row_of = np.asarray(model.jac_colind), np.asarray(model.jac_row)
    out: dict[int, Any] = {}
    for k, row in enumerate(which):
        try:
            out[int(row)] = spla.splu(sp.csc_matrix((data[k], row_of, colind), shape=(model.n, model.n)))
        except RuntimeError:  # exactly singular
            continue
    return out


def _chord_steps(factors: dict[int, Any], todo: np.ndarray, r_all: np.ndarray) -> np.ndarray:
    """Steps of the rows ``todo`` with their kept LU factors (NaN for a row without one)."""
    steps = np.full(r_all.shape, np.nan)
    for k, row in enumerate(todo):
        lu = factors.get(int(row))
        if lu is not None:
            steps[k] = lu.solve(r_all[k])
    return steps


def _newton_steps(model: CompiledModel, data: np.ndarray, r_all: np.ndarray) -> np.ndarray:
    """Newton steps of a small model's rows (matrices of the Jacobian's pattern with the nonzeros ``data``; NaN where
    singular): one batched dense solve, rows that make it fail solved one by one (sparse LU)."""
    colind = np.asarray(model.jac_colind)
    row_of = np.asarray(model.jac_row)
    col_of = np.repeat(np.arange(model.n), np.diff(colind))
    steps = np.full((len(r_all), model.n), np.nan)
    A = np.zeros((len(r_all), model.n, model.n))
    A[:, row_of, col_of] = data
    try:
        steps = np.linalg.solve(A, r_all[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:  # a singular row: solve them one by one below
        steps[:] = np.nan
    redo = np.flatnonzero(~np.isfinite(steps).all(axis=1))
    for k, lu in _factor_rows(model, data[redo], redo).items():
        steps[k] = lu.solve(r_all[k])
    return steps
