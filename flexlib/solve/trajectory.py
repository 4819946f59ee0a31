"""What a run produces before it becomes a :class:`~flexlib.results.result.Result`, and the run's progress bar.

:class:`Trajectory` holds the rows (``y``, ``y'`` and relation values per row, the model of each row when state
selection changes it), the events, the statistics and the outcome of one run of :func:`flexlib.solve.loop.run_loop`.
"""

from __future__ import annotations

import sys
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
    _stacked: Any = field(default=None, repr=False, compare=False)

    def stacked(self) -> tuple[np.ndarray, np.ndarray]:
        """Every row's ``y`` and ``y'`` as row-major ``(rows, n)`` arrays (one model throughout), stacked once and
        kept until rows are added: they become the result's rows (:func:`~flexlib.solve.assemble.assemble_result`
        settles them in place), which the run's later checks read."""
        n = len(self.t)
        if self._stacked is None or self._stacked[0] != n:
            self._stacked = (n, np.vstack(self.y[:n], dtype=float), np.vstack(self.yp[:n], dtype=float), {})
        return self._stacked[1], self._stacked[2]

    def stacked_parameters(self, pvec: np.ndarray) -> np.ndarray:
        """Per row the parameter vector ``pvec`` followed by the row's relation values, ``(rows, n_p + n_rel)``, made
        once per ``pvec`` and kept with :meth:`stacked` (callers do not write to it)."""
        self.stacked()
        kept = self._stacked[3]
        key = np.asarray(pvec, dtype=float).tobytes()
        if key not in kept:
            n = len(self.t)
            rel = np.array(self.rel[:n], dtype=float).reshape(n, -1)
            P = np.empty((n, len(pvec) + rel.shape[1]))
            P[:, :len(pvec)] = pvec
            P[:, len(pvec):] = rel
            kept.clear()
            kept[key] = P
        return kept[key]

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
    """Progress of a run over simulated time, shown once the run has taken ``delay`` seconds: a tqdm bar on a
    terminal; where standard error is not a terminal (a log file, a CI job) a plain line at every tenth of the span
    instead (``pump-truck: 30 % (168 s of 560 s simulated, 2.1 s)``), not hundreds of kilobytes of bar redraws.

    Parameters
    ----------
    name : str
        Label (the model name).
    t0, t_end : float
        Simulated time span [s].
    show : bool or None
        True: from the start; False: never; None: after ``delay`` seconds of wall time.
    stream : file, optional
        Where it is written (default ``sys.stderr``).
    """

    def __init__(self, name: str, t0: float, t_end: float, show: bool | None, delay: float = 2.0,
                 stream: Any = None) -> None:
        self.name, self.t0, self.t_end, self.show = name, t0, t_end, show
        self.start = _time.perf_counter()
        self.deadline = self.start + (0.0 if show else delay)
        self.bar: Any = None
        self.stream = stream
        self.tenths = -1  # the last tenth written as a line (no terminal)

    def _terminal(self) -> bool:
        stream = self.stream if self.stream is not None else sys.stderr
        isatty = getattr(stream, "isatty", None)
        try:
            return bool(isatty and isatty())
        except ValueError:  # a closed stream
            return False

    def update(self, t: float) -> None:
        """Show simulated time ``t`` [s] (creates the bar when due)."""
        if self.bar is None:
            if self.show is False or _time.perf_counter() < self.deadline:
                return
            if not self._terminal():
                self._line(t)
                return
            from tqdm.auto import tqdm

            self.bar = tqdm(total=float(self.t_end - self.t0), unit="s", desc=self.name, leave=False,
                            file=self.stream, bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s [{elapsed}<{remaining}]")
        self.bar.n = float(t - self.t0)
        self.bar.refresh()

    def _line(self, t: float) -> None:
        span = float(self.t_end - self.t0)
        done = min(max(float(t - self.t0) / span, 0.0), 1.0) if span > 0 else 1.0
        tenths = int(done * 10 + 1e-9)
        if tenths <= self.tenths:
            return
        self.tenths = tenths
        stream = self.stream if self.stream is not None else sys.stderr
        print(f"{self.name}: {10 * tenths} % ({t - self.t0:.4g} s of {span:.4g} s simulated, "
              f"{_time.perf_counter() - self.start:.1f} s)", file=stream, flush=True)

    def close(self, t: float | None = None) -> None:
        """Remove the bar; without a terminal, the line of the run's end ``t`` [s] (when progress is due)."""
        if self.bar is not None:
            self.bar.close()
        elif t is not None and self.show is not False and _time.perf_counter() >= self.deadline \
                and not self._terminal():
            self._line(t)
