"""The :class:`~flexlib.results.result.Result` of a run, assembled from the run loop's
:class:`~flexlib.solve.trajectory.Trajectory`."""

from __future__ import annotations

import platform
import time as _time
import warnings
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import ResultCheckWarning
from flexlib.results.indeterminate import from_rows
from flexlib.results.result import Result
from flexlib.results.stored import (
    OutputMap,
    RowDefinitions,
    StoredPart,
    fold_parameters,
    output_graph,
    output_map,
    signatures,
)
from flexlib.solve.rows import RowEvaluator, segments, settle_derivative_level
from flexlib.solve.trajectory import Trajectory

__all__ = ["RowColumns", "assemble_result", "row_definitions_of"]


class RowColumns:
    """The named variables of a run's rows, evaluated when they are read.

    A run records its rows (``y``, ``y'``, relation values); every named variable (aliases, outputs, forces, frame
    matrices: thousands in a machine) is a column of the model's ``out`` function of a row. Evaluating all of them
    for every row costs more than the integration on a large model (the pump truck's expand-fold: 7 487 variables
    at 11 212 rows, 670 MB), so a :class:`~flexlib.results.result.Result` asks for them when it is read:
    :meth:`columns` evaluates the ``out`` entries of some variables only (an SX function of those outputs, the part
    of ``out``'s graph they need, mapped over the rows), :meth:`all` every one (the run's compiled ``out``).

    Parameters
    ----------
    rows : RowEvaluator
        The run's function buffers.
    parts : list of (CompiledModel, ndarray, ndarray, ndarray, ndarray, ndarray)
        Per model of the run (a state switch changes it): the model, its rows' indices, ``T``, ``Y``, ``YP`` and
        relation values, row-major (settled: :func:`~flexlib.solve.rows.settle_derivative_level`).
    pvec : ndarray
        Parameter vector of the run.
    n_rows, n_cols : int
        Rows and variables of the result.
    """

    def __init__(self, rows: RowEvaluator, parts: list[tuple[CompiledModel, np.ndarray, np.ndarray, np.ndarray,
                                                               np.ndarray, np.ndarray]],
                 pvec: np.ndarray, n_rows: int, n_cols: int) -> None:
        self.rows, self.parts, self.pvec, self.n_rows, self.n_cols = rows, parts, pvec, n_rows, n_cols
        self._signatures: list[tuple] | None = None

    def _P(self, rel: np.ndarray) -> np.ndarray:
        P = np.empty((len(rel), len(self.pvec) + rel.shape[1]))
        P[:, :len(self.pvec)] = self.pvec
        P[:, len(self.pvec):] = rel
        return P

    def all(self) -> np.ndarray:
        """Every variable at every row: ``(n_rows, n_cols)``."""
        values = np.empty((self.n_rows, self.n_cols))
        for model, idx, T, Y, YP, rel in self.parts:
            values[idx] = self.rows.evaluate(model, "out", T, Y, YP, self._P(rel))
        return values

    def _graph(self, model: CompiledModel) -> tuple[list[ca.SX], ca.SX]:
        """The graph of ``model``'s ``out`` (:func:`~flexlib.results.stored.output_graph`), made once per model."""
        return self.rows.cached(model, ("out_sx",), lambda: output_graph(model.sx_function("out")))

    def _map(self, model: CompiledModel) -> OutputMap:
        """How ``model``'s outputs are got from a row (:func:`~flexlib.results.stored.output_map`), once per model."""
        return self.rows.cached(model, ("out_map",), lambda: output_map(self._graph(model)))

    def stored_parts(self) -> list[StoredPart]:
        """The rows as a result file stores them (:mod:`flexlib.results.stored`), with the definitions of the
        unknowns that rows give (not stored)."""
        parts = []
        for model, idx, T, Y, YP, rel in self.parts:
            defs = row_definitions_of(model)
            parts.append(StoredPart(model.sx_function("out"), idx, T, Y, YP, rel, self.pvec, self._map(model),
                                    defs if defs.fn is not None else None))
        return parts

    def signatures(self) -> list[tuple]:
        """Per variable, a key that is the same for variables with the same values (aliases): what it is in the
        output function of each part (:func:`flexlib.results.stored.signatures`)."""
        if self._signatures is None:
            per_part = [signatures(self._map(model).source, self._map(model).constant,
                                   lambda model=model: self._graph(model)[1]) for model, *_ in self.parts]
            self._signatures = [tuple(sig[i] for sig in per_part) for i in range(self.n_cols)]
        return self._signatures

    def columns(self, cols: list[int]) -> np.ndarray:
        """The variables ``cols`` (indices into the result's names) at every row: ``(n_rows, len(cols))``."""
        # the run's parameters are folded into the function: they are part of the key (a later run of the same
        # simulation with other parameters makes its own, and the earlier ones are dropped)
        key = ("out_columns", self.pvec.tobytes(), tuple(int(c) for c in cols))
        values = np.empty((self.n_rows, len(cols)))
        for model, idx, T, Y, YP, rel in self.parts:
            self.rows.keep_latest(model, key[:2])
            fn = self.rows.cached(model, key, lambda model=model: self._out_columns(model, key[2]))
            REL = rel if rel.shape[1] else np.zeros((len(T), 1))
            values[idx] = self.rows.evaluate_function(fn, model, key, T, Y, YP, REL)
        return values

    def _bound(self, model: CompiledModel) -> tuple[list[ca.SX], ca.SX]:
        """``([t, y, yp, rel], out)``: ``model``'s ``out`` with the run's parameters put in (constant parts folded, as
        a result file's reader has it: :meth:`~flexlib.results.stored.FilePart.bound`), made once per model."""
        key = ("out_bound", self.pvec.tobytes())
        self.rows.keep_latest(model, key)

        def make() -> tuple[list[ca.SX], ca.SX]:
            (t, y, yp, _), _ = self._graph(model)
            rel, out = fold_parameters(model.sx_function("out"), self.pvec, t, y, yp)
            return [t, y, yp, rel], out

        return self.rows.cached(model, key, make)

    def _out_columns(self, model: CompiledModel, cols: tuple[int, ...]) -> ca.Function:
        """``(t, y, yp, rel) ->`` the entries ``cols`` of ``out``, dense: only the part of ``out``'s graph they
        need, the run's parameters folded in (:meth:`_bound`)."""
        args, out = self._bound(model)
        return ca.Function("flexlib_out_columns", args, [ca.densify(out[list(cols)])])


def row_definitions_of(model: CompiledModel) -> RowDefinitions:
    """``model``'s unknowns given explicitly by rows and their definitions (found when it was compiled:
    :func:`~flexlib.compile.explicit.row_definitions`)."""
    given = np.asarray(model.given, dtype=np.int64)
    return RowDefinitions(np.setdiff1d(np.arange(model.n), given), given,
                          model.sx_function("defs") if given.size else None)


def _bound_definitions(defs: RowDefinitions, pvec: np.ndarray) -> ca.Function:
    """``(t, y, yp, rel) -> y[given]`` on the graph a result file's reader evaluates (:meth:`RowDefinitions.bound`)."""
    args, values = defs.bound(np.asarray(pvec, dtype=float))
    return ca.Function("flexlib_row_definitions_bound", args, [values])


def assemble_result(traj: Trajectory, m: CompiledModel, pvec: np.ndarray, rows: RowEvaluator, t_init: float,
                    rtol: float, atol: float, build_info: dict[str, Any]) -> Result:
    """The :class:`Result` of a run: its rows, the derivative-level unknowns of the rows checked and settled
    (:func:`~flexlib.solve.rows.settle_derivative_level`), the unknowns that rows give explicitly set by those rows
    (:func:`row_definitions_of`: a result file derives them by the same), every variable readable by name (aliases
    and outputs rebuilt by the ``out`` function of the model of each row's segment when they are read:
    :class:`RowColumns`), the statistics, events and metadata.

    ``m`` is the run's compiled model (its variables name the columns), ``pvec`` the parameter vector, ``t_init``
    the initialisation's wall time [s] and ``build_info`` the build's timings.
    """
    names = [v.name for v in m.variables]
    source = None
    if traj.t:
        T = np.array(traj.t)
        values = None
        repaired, settle_error, parts = 0, "", []
        for model, idx, Ts, Y, YP, P in segments(traj, m, pvec):
            # the run's rows become this result's: settled and set in place (a failed repair leaves them as recorded)
            try:
                Y, YP, n_fixed = settle_derivative_level(rows, model, Ts, Y, YP, P)
                repaired += n_fixed
            except Exception as exc:  # never lose a run's rows to the check: keep them as recorded
                settle_error = f"{type(exc).__name__}: {exc}"
            defs = row_definitions_of(model)
            if defs.fn is not None:  # the explicitly given unknowns by their rows (what a file derives them by)
                key = ("row_definitions", np.asarray(pvec, dtype=float).tobytes())
                rows.keep_latest(model, key)
                fn = rows.cached(model, key, lambda defs=defs: _bound_definitions(defs, pvec))
                REL = P[:, len(pvec):] if P.shape[1] > len(pvec) else np.zeros((len(Ts), 1))
                Y[:, defs.given] = rows.evaluate_function(fn, model, key, Ts, Y, YP, REL)
            parts.append((model, idx, Ts, Y, YP, np.array(P[:, len(pvec):])))
        source = RowColumns(rows, parts, np.array(pvec, dtype=float), len(T), len(names))
    else:
        T, values = np.zeros(0), np.zeros((0, len(names)))
    stats = dict(traj.stats)
    if traj.t and settle_error:
        stats["settle_error"] = settle_error
        warnings.warn(f"{m.name}: the derivative-level unknowns (forces, accelerations) of the recorded rows "
                      f"could not be checked ({settle_error}); they are as IDA left them", ResultCheckWarning,
                      stacklevel=4)
    stats.update({"rows_resettled": repaired if traj.t else 0,
                  "wall_init": t_init, "rtol": rtol, "atol": atol, "n_states": int(m.differential.sum()),
                  "n_unknowns": m.n, "build_cached": bool(build_info.get("cached")),
                  "wall_build": float(build_info.get("total", 0.0))})
    import importlib.metadata

    import casadi

    from flexlib import __version__

    meta = {"flexlib": __version__, "casadi": casadi.__version__,
            "scikit-sundae": importlib.metadata.version("scikit-sundae"),
            "numpy": np.__version__, "python": platform.python_version(),
            "created": _time.strftime("%Y-%m-%dT%H:%M:%S")}
    return Result(
        model=m.name, t=T, names=names, values=values, units=[v.unit for v in m.variables],
        docs=[v.doc for v in m.variables], kinds=[v.kind for v in m.variables],
        parameters={n: (float(v), u) for n, v, u in zip(m.param_names, pvec, m.param_units, strict=True)},
        stats=stats, status=traj.status, message=traj.message, events=list(traj.events),
        index_report=str(m.report), metadata=meta, source=source,
        indeterminate=from_rows(m.indeterminate, m.report.redundant),
    )
