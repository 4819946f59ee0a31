"""Integration of a model without unknowns.

When every variable is fixed by an equation to an expression of time and parameters (``x = 2``,
``y = k·time``, a set-point table), simplification leaves no unknowns, and IDA cannot be created for an
empty system. The result is then evaluated directly: rows at the output grid (or at the start, every
time event and the end), with the relation values switched at time events exactly as the integrators do.
"""

from __future__ import annotations

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.solve.events import next_time_event
from flexlib.solve.trajectory import Trajectory

__all__ = ["integrate_static"]


def integrate_static(model: CompiledModel, p: np.ndarray, t0: float, t_end: float,
                     t_out: np.ndarray | None) -> Trajectory:
    """Rows of a model with ``model.n == 0`` from ``t0`` to ``t_end`` (relation values in ``p`` updated in place).

    Parameters
    ----------
    model : CompiledModel
        A compiled model without unknowns.
    p : ndarray
        Parameters followed by relation values.
    t0, t_end : float
        Start and end time [s].
    t_out : ndarray or None
        Output times [s]; None gives rows at the start, at every time event and at the end.
    """
    traj = Trajectory(models=[model])
    traj.stats = {"steps": 0, "nfev": 0, "njev": 0, "state_events": 0, "time_events": 0, "restarts": 0,
                  "state_switches": 0}
    n_par = model.n_params
    empty = np.zeros(0)
    traj.add(t0, empty, empty, p[n_par:])
    grid = list(np.asarray(t_out, dtype=float)) if t_out is not None else []
    grid = [tq for tq in grid if t0 < tq <= t_end]
    t = t0
    while t < t_end:
        t_event, which = next_time_event(model, p, t, t_end)
        while grid and grid[0] < t_event:
            traj.add(grid.pop(0), empty, empty, p[n_par:])
        if not which:
            break
        traj.add(t_event, empty, empty, p[n_par:])
        ab = np.asarray(model.function("tev")(p)).reshape(-1, 2)
        for k in which:
            p[n_par + k] = float(ab[k, 0] > 0)
        t = t_event
        traj.stats["time_events"] += 1
        traj.events.append((t, "time event: " + ", ".join(model.relations[k].text for k in which)))
        traj.add(t, empty, empty, p[n_par:])
        if grid and grid[0] == t:
            grid.pop(0)
    while grid:
        traj.add(grid.pop(0), empty, empty, p[n_par:])
    if t_out is None and traj.t[-1] < t_end:
        traj.add(t_end, empty, empty, p[n_par:])
    return traj
