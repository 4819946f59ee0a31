"""The integrator interface the run loop drives, and what every backend shares (tolerances, Newton iterations).

A backend is an adapter: it steps a DAE solver and reports where it stopped (:class:`Stop`); the run loop
(:func:`flexlib.solve.loop.run_loop`) owns everything else — the output rows' relation values, time and state
events and their iteration, the relation watch after restarts, the chattering guard, the state-selection schedule,
progress, Ctrl-C/SIGTERM, failure diagnostics and the common statistics. A new integrator is one new file with a
class that has the methods of :class:`Integrator`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.environment import env_default

__all__ = ["DENSE_MAX", "NEWTON_ITERS", "Integrator", "Limits", "Stop", "absolute_tolerances"]

#: Systems up to this many unknowns use IDA's dense LU (faster than sparse LU there, measured in
#: benchmarks/ida_overhead.py); larger ones a sparse LU.
DENSE_MAX = 40

#: Newton iterations IDA may take per step before it declares a convergence failure (IDA's default 4; both IDA
#: backends; see docs/engine.md, "Newton iterations").
NEWTON_ITERS = 6

#: The kinds of :class:`Stop`.
KINDS = ("step", "full", "tstop", "root", "failed", "recover")


@dataclass
class Stop:
    """Where :meth:`Integrator.advance` stopped.

    Attributes
    ----------
    kind : str
        ``"step"``: steps taken, nothing to report (the step budget is used up, or one call's worth);
        ``"full"``: the row buffer is full (rows only: the step and any event it ended on come with the next call);
        ``"tstop"``: ``t_stop`` reached; ``"root"``: a state relation crosses at ``t`` (``roots``);
        ``"failed"``: the solver gave up (``message`` says how; :meth:`Integrator.state` is the point to diagnose);
        ``"recover"``: the solver gave up in a way that a restart from the last accepted point may cure.
    t : float
        Time reached [s].
    steps : int
        Internal steps taken by this call.
    rows : tuple of lists
        Output rows ``(t, y, yp)`` produced by this call (fresh arrays; the loop adds the relation values).
    roots : list of (int, bool)
        For ``"root"``: the relations that cross and their new values.
    message : str
        For ``"failed"``/``"recover"``: the solver's failure.
    flag : str
        For ``"recover"``: the solver's name of the failure (``"IDA_ERR_FAIL"``).
    """

    kind: str
    t: float
    steps: int = 0
    rows: tuple[list[float], list[np.ndarray], list[np.ndarray]] | None = None
    roots: list[tuple[int, bool]] = field(default_factory=list)
    message: str = ""
    flag: str = ""


@dataclass
class Limits:
    """How far one :meth:`Integrator.advance` may go besides ``t_stop``: at most ``steps`` internal steps, and
    (state selection's schedule) stop after the first step that ends at or after ``t_check`` [s] or is shorter
    than ``h_min`` [s]. A backend that cannot stop on these returns after each step instead."""

    steps: int
    t_check: float = np.inf
    h_min: float = 0.0


class Integrator(Protocol):
    """What the run loop needs from a DAE integrator ``F(t, y, y', p) = 0``.

    The options (tolerances, step limits, linear solver) are given to the adapter's constructor. ``p`` is the run's
    parameter vector followed by the relation values; the loop changes it in place at events, so an adapter keeps
    the array, not a copy.
    """

    #: Name in the statistics (``stats["solver"]``)
    name: ClassVar[str]
    #: Steps after a restart in which the loop checks the state relations' signs (:func:`flexlib.solve.events.watch`)
    watch_steps: ClassVar[int]
    #: Relations switched at a root that are heading across are left to the backend's root finding
    #: (:func:`flexlib.solve.events.settled`)
    settles_roots: ClassVar[bool]
    #: The state-selection monitor may run with this backend
    monitors: ClassVar[bool]
    #: Steps between progress-bar updates
    progress_every: ClassVar[int]
    rtol: float
    atol: float
    #: Every unknown in the local error test (:func:`absolute_tolerances`); set by the solver object
    #: (:meth:`flexlib.solve.solvers.Solver.integrator`), None: the environment default
    error_test_all: bool | None
    #: The state relations the backend locates (indices into ``model.relations``)
    state_rel: np.ndarray

    def start(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
              grid: np.ndarray | None, t_end: float) -> None:
        """Begin at the consistent point ``(t, y, yp)`` of a run to ``t_end`` [s]; ``grid`` are the output times after
        ``t`` (None: every step). Called again with another model after a state-selection switch (``grid`` None):
        the output grid goes on where it was."""

    def advance(self, t_stop: float, limits: Limits) -> Stop:
        """Integrate towards ``t_stop`` [s] (never past it)."""

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        """Restart at ``(t, y, yp)`` after an event (the solver's history is discarded)."""

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        """``(y, yp)`` at the time of the last :class:`Stop`."""

    def accepted(self) -> tuple[float, Any, Any] | None:
        """The last accepted point ``(t, y, yp)`` (after a failure or interrupt), or None."""

    def unsaved_rows(self) -> tuple[list[float], list[np.ndarray], list[np.ndarray]]:
        """Rows computed but not yet returned (an interrupt between the solver's return and the copy)."""

    def last_step(self) -> float | None:
        """Size of the last internal step [s] (None: the state-selection monitor takes the time between checks)."""

    def stats(self, wall: float) -> dict[str, Any]:
        """Counters of the whole run (``nfev``, ``njev``, ``max_order``, ``solver`` and backend-specific ones);
        ``wall``: the run's integration time so far [s] by the backend's ``clock``."""


def absolute_tolerances(model: CompiledModel, atol: float, error_test_all: bool | None = None) -> np.ndarray:
    """Per-unknown absolute tolerances: ``atol`` scaled by each nominal value, infinite for the
    derivative-level unknowns kept out of the error test (``structure.derivative_level``; every
    backend) unless ``error_test_all`` (the solver object's option; None: its environment default,
    ``FLEXLIB_ERROR_TEST_ALL=1``)."""
    atol_vec = atol * np.asarray(model.nominal, dtype=float)
    if error_test_all is None:
        error_test_all = env_default("error_test_all")
    if not error_test_all:
        atol_vec = np.where(model.derivative_level, 1e20, atol_vec)
    return atol_vec
