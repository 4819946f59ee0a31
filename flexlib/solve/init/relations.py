"""The relation values at the start: iterated with the consistent start until they agree with it, and switched one
at a time when the branch the start guesses chose has no solution (a limiter's guess on the wrong side)."""

from __future__ import annotations

from typing import Any

import numpy as np

from flexlib.errors import InitializationError
from flexlib.solve.events import event_iteration

__all__ = ["consistent_start", "start_by_flipping"]


def consistent_start(init: Any, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                     steady: bool) -> tuple[np.ndarray, np.ndarray]:
    """Consistent ``y(t0)``, ``y'(t0)`` together with the relation values in ``p`` (updated in place).

    Relations start from their values at the start guesses and are iterated to agree with the solution;
    when the branch chosen by the guesses has no solution (a limiter's guess on the wrong side), the
    relations are re-evaluated at the best point found, then switched one at a time
    (:func:`start_by_flipping`), before the failure is reported.
    """
    m = init.model
    n_par = m.n_params
    y, yp = init.guess(starts), np.zeros(m.n)
    first = [n_par + k for k, rel in enumerate(m.relations) if rel.initial]  # initial(): 1 during the start, then 0
    if not first:
        return _consistent(init, t0, p, starts, steady, y, yp)
    p[first] = 1.0
    try:
        y, yp = _consistent(init, t0, p, starts, steady, y, yp)
    finally:
        p[first] = 0.0
    # the event iteration that follows the start (initial() now false), with the states held, as Modelica's
    return event_iteration(m, init, p, t0, y, yp, [])


def _consistent(init: Any, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]], steady: bool,
                y: np.ndarray, yp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    m = init.model
    n_par = m.n_params
    if m.n_relations:
        with np.errstate(all="ignore"):
            z = np.asarray(m.function("ind")(t0, y, yp, p)).ravel()
        ab = np.asarray(m.function("tev")(p)).reshape(-1, 2)
        for k, rel in enumerate(m.relations):
            if rel.initial:
                continue
            if rel.time_event and z[k] == 0.0:
                p[n_par + k] = float(ab[k, 0] > 0)
            else:
                p[n_par + k] = float(rel.value(z[k]))
    failed: InitializationError | None = None
    for _ in range(20):
        try:
            y, yp = init.initial(t0, p, starts, steady)
            failed = None
        except InitializationError as err:
            failed = err
            # no solution with these relation values: re-evaluate the relations at the best point
            # found (the start guesses may lie on the wrong side of a limiter) and try again
            point = getattr(err, "point", None)
            if not m.n_relations or point is None or np.size(point[0]) != m.n or np.size(point[1]) != m.n:
                raise  # (a point of the full system, before explicit eliminations, is not this model's)
            with np.errstate(all="ignore"):
                z = np.asarray(m.function("ind")(t0, point[0], point[1], p)).ravel()
            flipped = False
            for k, rel in enumerate(m.relations):
                v = float(rel.value(z[k]))
                if not (rel.time_event or rel.initial) and v != p[n_par + k]:
                    p[n_par + k], flipped = v, True
            if not flipped:
                return start_by_flipping(init, t0, p, starts, steady, err)
            continue
        if not m.n_relations:
            break
        z = np.asarray(m.function("ind")(t0, y, yp, p)).ravel()
        changed = False
        for k, rel in enumerate(m.relations):
            if rel.time_event or rel.initial:
                continue
            v = float(rel.value(z[k]))
            if v != p[n_par + k]:
                p[n_par + k], changed = v, True
        if not changed:
            break
    if failed is not None:
        raise failed
    return y, yp

def start_by_flipping(init: Any, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]], steady: bool,
                      err: InitializationError, most: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Try the start with one state relation switched at a time (a start guess on the wrong side of a
    limiter gives a branch without solution); accept a switch whose solution agrees with it, else raise
    ``err`` (the failure of the unswitched problem, with its diagnosis)."""
    m = init.model
    n_par = m.n_params
    state_rel = [k for k, rel in enumerate(m.relations) if not (rel.time_event or rel.initial)][:most]
    for k in state_rel:
        trial = p.copy()
        trial[n_par + k] = 1.0 - trial[n_par + k]
        try:
            y, yp = init.initial(t0, trial, starts, steady, diagnose=False)
        except InitializationError:
            continue
        z = np.asarray(m.function("ind")(t0, y, yp, trial)).ravel()
        if all(float(m.relations[j].value(z[j])) == trial[n_par + j] for j in state_rel):
            p[:] = trial
            return y, yp
    raise err
