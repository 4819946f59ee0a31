"""The :class:`~flexlib.results.result.Result` of a run, assembled from the run loop's
:class:`~flexlib.solve.trajectory.Trajectory`."""

from __future__ import annotations

import platform
import time as _time
import warnings
from typing import Any

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import ResultCheckWarning
from flexlib.results.result import Result
from flexlib.solve.rows import RowEvaluator, segments, settle_derivative_level
from flexlib.solve.trajectory import Trajectory

__all__ = ["assemble_result"]


def assemble_result(traj: Trajectory, m: CompiledModel, pvec: np.ndarray, rows: RowEvaluator, t_init: float,
                    rtol: float, atol: float, build_info: dict[str, Any]) -> Result:
    """The :class:`Result` of a run: every variable of every row (aliases and outputs rebuilt by the ``out``
    function of the model of each row's segment), the derivative-level unknowns of the rows checked and settled
    (:func:`~flexlib.solve.rows.settle_derivative_level`), the statistics, events and metadata.

    ``m`` is the run's compiled model (its variables name the columns), ``pvec`` the parameter vector, ``t_init``
    the initialisation's wall time [s], ``build_info`` the build's timings.
    """
    names = [v.name for v in m.variables]
    if traj.t:
        T = np.array(traj.t)
        values = np.zeros((len(T), len(names)))
        repaired, settle_error = 0, ""
        for model, idx, Ts, Y, YP, P in segments(traj, m, pvec):
            try:
                Y, YP, n_fixed = settle_derivative_level(rows, model, Ts, Y, YP, P)
                repaired += n_fixed
            except Exception as exc:  # never lose a run's rows to the check: keep them as recorded
                settle_error = f"{type(exc).__name__}: {exc}"
            values[idx] = rows.evaluate(model, "out", Ts, Y, YP, P)
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
    import casadi
    import sksundae

    from flexlib import __version__

    meta = {"flexlib": __version__, "casadi": casadi.__version__, "scikit-sundae": sksundae.__version__,
            "numpy": np.__version__, "python": platform.python_version(),
            "created": _time.strftime("%Y-%m-%dT%H:%M:%S")}
    return Result(
        model=m.name, t=T, names=names, values=values, units=[v.unit for v in m.variables],
        docs=[v.doc for v in m.variables], kinds=[v.kind for v in m.variables],
        parameters={n: (float(v), u) for n, v, u in zip(m.param_names, pvec, m.param_units, strict=True)},
        stats=stats, status=traj.status, message=traj.message, events=list(traj.events),
        index_report=str(m.report), metadata=meta,
    )
