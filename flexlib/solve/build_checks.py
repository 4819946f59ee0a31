"""Re-check, at the start of every run, the numeric choices a build made at its own values.

A build makes numeric choices at the parameter and start values it sees (``compile/passes/multibody/redundancy.py``
drops loop-closure rows that are dependent there; ``compile/index_reduction.py`` picks dummy
derivatives by pivoted QR there). Neither the parameter values of ``run(params=...)`` nor the
start values of another instance built from a cached entry need agree with them: a planar
four-bar whose rocker axis is tilted through ``params`` is a spatial loop whose dropped rows no
longer hold — integrated as built it reports success with a gap in the loop.

This module checks those choices at the run's actual consistent start point:

* **dropped loop rows** (the compiled ``chk`` function) must still vanish; they are consequences of
  the kept rows exactly when the build's rank decision still holds;

and, after the run, over every recorded row (a choice that held at the start by coincidence).
A violated choice raises :class:`flexlib.StructureChangedError` naming the rows and the size of the
violation; :class:`flexlib.Simulation` first rebuilds a cached model at the instance's own values
(see ``Simulation.run``), so only a run-time override that changes the structure reaches the user.
"""

from __future__ import annotations

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.redundancy import BRANCH_SUFFIX
from flexlib.errors import InitializationError, StructureChangedError
from flexlib.solve.rows import RowEvaluator

__all__ = ["START_TOL", "check_dropped_rows", "dropped_row_values", "run_tolerance"]

#: Largest dropped-row residual accepted at the consistent start [m for position rows, rad for orientation
#: rows]: the start is solved to ~1e-10, so a redundant row is zero to that order; a real gap is macroscopic.
START_TOL = 1e-6


def run_tolerance(rtol: float, atol: float) -> float:
    """Largest dropped-row residual accepted over a run: the kept rows are held to the integration
    tolerance, so a truly redundant row follows them to that order (with a wide margin)."""
    return START_TOL + 1e3 * (rtol + atol)


def dropped_row_values(model: CompiledModel, t: np.ndarray, y: np.ndarray, yp: np.ndarray,
                       p: np.ndarray, rows: RowEvaluator | None = None) -> np.ndarray:
    """Residuals of the dropped loop rows, one column per point (``y``, ``yp``, ``p`` as columns); several
    points are evaluated through ``rows`` (:class:`~flexlib.solve.rows.RowEvaluator`, its buffers kept)."""
    if not model.check_labels:
        return np.zeros((0, np.atleast_1d(t).size))
    t = np.atleast_1d(np.asarray(t, dtype=float))
    if t.size == 1:
        return np.asarray(model.function("chk")(float(t[0]), y, yp, p)).reshape(-1, 1)
    rows = rows if rows is not None else RowEvaluator()
    return rows.evaluate(model, "chk", t, *(np.asarray(a, dtype=float).T for a in (y, yp, p))).T


def check_dropped_rows(model: CompiledModel, t: np.ndarray, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
                       tol: float, *, where: str, overrides: dict | None = None,
                       rows: RowEvaluator | None = None) -> None:
    """Raise :class:`StructureChangedError` if a loop row dropped as redundant at build time is violated.

    Parameters
    ----------
    t, y, yp, p
        One point (``t`` scalar, vectors) or several (``t`` of length m, arrays with m columns).
    tol : float
        Largest accepted residual [m or rad].
    where : str
        Where the check ran, for the message ("at the start", "during the run").
    overrides : dict, optional
        The run's ``params`` overrides, named in the message.
    rows : RowEvaluator, optional
        Keeps the evaluation buffers between runs.
    """
    values = dropped_row_values(model, t, y, yp, p, rows)
    if values.size == 0:
        return
    worst = np.nanmax(np.abs(values), axis=1) if values.shape[1] else np.zeros(len(model.check_labels))
    bad = [(label, float(w)) for label, w in zip(model.check_labels, worst, strict=True)
           if not (w <= tol)]
    if not bad:
        return
    tt = np.atleast_1d(np.asarray(t, dtype=float))
    first = int(np.argmax(np.any(~(np.abs(values) <= tol), axis=0))) if tt.size > 1 else 0
    flipped = [(label[:-len(BRANCH_SUFFIX)], w) for label, w in bad if label.endswith(BRANCH_SUFFIX)]
    if flipped:
        lines = "\n".join(f"  {label}: relative rotation of the cut frames "
                          f"{np.degrees(np.arccos(-min(w, 1.0))):.1f} deg" for label, w in flipped)
        text = (f"{model.name}: a kinematic loop is closed in its mirrored branch {where} (first at "
                f"t = {tt[first]:.10g} s): the orientation residue of a loop closure (the sine part of the cut "
                "frames' relative rotation, as Modelica's equalityConstraint) vanishes at a half-turn too, and "
                "there the forces and torques across the cut act in reversed axes, so the results would be "
                f"wrong.\n{lines}\nGive the loop's joint angles start values near the intended assembly (init= or "
                "guess= of the joints).")
        raise (InitializationError if where == "at the start" else StructureChangedError)(text)
    lines = "\n".join(f"  {label}: |residual| up to {w:.3g}" for label, w in bad)
    cause = (f" The run overrides {', '.join(sorted(overrides))}; build the model with these values instead "
             "(a Simulation of an instance constructed with them) so the redundancy analysis sees them."
             if overrides else "")
    raise StructureChangedError(
        f"{model.name}: loop-closure rows that the build dropped as redundant do not hold {where} "
        f"(first at t = {tt[first]:.10g} s); the loop is not the one the build analysed, and its results would "
        f"show a gap. Violated rows (tolerance {tol:.3g}):\n{lines}\n{cause}".rstrip())
