"""What a run produces before it becomes a :class:`~flexlib.results.result.Result`, and the run's progress bar.

:class:`Trajectory` holds the rows (``y``, ``y'`` and relation values per row, the model of each row when state
selection changes it), the events, the statistics and the outcome of one run of :func:`flexlib.solve.loop.run_loop`.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexlib.compile.codegen import CompiledModel

__all__ = ["Progress", "Trajectory"]


@dataclass
class Trajectory:
    """Raw solver output (``y``, ``y'`` and relation values per row) before it becomes a Result."""

    t: list[float] = field(default_factory=list)
    y: list[np.ndarray] = field(default_factory=list)
    yp: list[np.ndarray] = field(default_factory=list)
    rel: list[np.ndarray] = field(default_factory=list)
    events: list[tuple[float, str]] = field(default_factory=list)
    stats: dict[str, Any] = field(default_factory=dict)
    status: str = "success"
    message: str = ""
    models: list[CompiledModel] = field(default_factory=list)
    seg: list[int] = field(default_factory=list)

    def add(self, t: float, y: np.ndarray, yp: np.ndarray, rel: np.ndarray) -> None:
        """Append one output row (copies); rows belong to the last model in ``models``."""
        self.seg.append(len(self.models) - 1)
        self.t.append(float(t))
        self.y.append(np.array(y, dtype=float))
        self.yp.append(np.array(yp, dtype=float))
        self.rel.append(np.array(rel, dtype=float))

    def close(self, t: float, y: Any, yp: Any, rel: np.ndarray) -> None:
        """End the rows of a failed or interrupted run at its last accepted point ``(t, y, yp)`` when that is after
        the last row: a run recorded on an output grid kept only the grid times before the failure (``dt_out=0.1``
        and a failure at 0.99998 s ended at 0.9 s). Nothing is added without rows, at or before the last row's
        time (every step recorded, or an event's rows at ``t``) or for non-finite values."""
        if y is None or not self.t or not t > self.t[-1]:
            return
        y, yp = np.array(y, dtype=float), np.array(yp, dtype=float)
        if y.shape == yp.shape == self.y[-1].shape and np.all(np.isfinite(y)) and np.all(np.isfinite(yp)):
            self.add(t, y, yp, rel)

    def add_owned(self, t: float, y: np.ndarray, yp: np.ndarray, rel: np.ndarray) -> None:
        """Append one row without copying: ``y`` and ``yp`` are fresh arrays nobody else writes to (a
        solver's step result), ``rel`` is shared between rows until the next event changes it."""
        self.seg.append(len(self.models) - 1)
        self.t.append(t)
        self.y.append(y)
        self.yp.append(yp)
        self.rel.append(rel)

    def extend(self, t: list[float], y: list[np.ndarray], yp: list[np.ndarray], rel: np.ndarray) -> None:
        """Append rows without copying (as :meth:`add_owned`), all with the relation values ``rel``."""
        self.t.extend(t)
        self.y.extend(y)
        self.yp.extend(yp)
        self.rel.extend([rel] * len(t))
        self.seg.extend([len(self.models) - 1] * len(t))

    def trim(self) -> None:
        """Cut the row lists to their common length (an interrupt in the middle of :meth:`extend`)."""
        n = min(len(self.t), len(self.y), len(self.yp), len(self.rel), len(self.seg))
        for rows in (self.t, self.y, self.yp, self.rel, self.seg):
            del rows[n:]


class Progress:
    """A tqdm progress bar over simulated time that appears once a run has taken ``delay`` seconds.

    Parameters
    ----------
    name : str
        Label (the model name).
    t0, t_end : float
        Simulated time span [s].
    show : bool or None
        True: from the start; False: never; None: after ``delay`` seconds of wall time.
    """

    def __init__(self, name: str, t0: float, t_end: float, show: bool | None, delay: float = 2.0) -> None:
        self.name, self.t0, self.t_end, self.show = name, t0, t_end, show
        self.deadline = _time.perf_counter() + (0.0 if show else delay)
        self.bar: Any = None

    def update(self, t: float) -> None:
        """Show simulated time ``t`` [s] (creates the bar when due)."""
        if self.bar is None:
            if self.show is False or _time.perf_counter() < self.deadline:
                return
            from tqdm.auto import tqdm

            self.bar = tqdm(total=float(self.t_end - self.t0), unit="s", desc=self.name, leave=False,
                            bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s [{elapsed}<{remaining}]")
        self.bar.n = float(t - self.t0)
        self.bar.refresh()

    def close(self) -> None:
        """Remove the bar."""
        if self.bar is not None:
            self.bar.close()
