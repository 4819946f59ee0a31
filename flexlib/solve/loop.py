"""The run loop: one integration from a consistent start to the end time, for every backend.

:func:`run_loop` drives an :class:`~flexlib.solve.backends.base.Integrator` (the backend only steps and reports where
it stopped) and does the rest once: the output rows and their relation values, time events (the integrator stops
exactly at them), state events found by the backend, the event iteration (:mod:`flexlib.solve.events`), the sign
check of the state relations in the first steps after a restart, the chattering guard, the restart from the last
accepted point that a backend may ask for, the state-selection monitor's schedule, the progress bar, Ctrl-C/SIGTERM
(the rows up to the interrupt are kept), failure diagnostics (the rows up to the failure are kept, the last at the
last accepted point) and the statistics common to every backend.
"""

from __future__ import annotations

import time as _time
import warnings
from typing import Any

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import AccuracyWarning, SimulationInterrupted, SolverError
from flexlib.solve.backends.base import Integrator, Limits, Stop
from flexlib.solve.diagnose import failure_message
from flexlib.solve.events import event_iteration, indeterminate_split, next_time_event, settled, time_triggers, watch
from flexlib.solve.sampling import Samplers
from flexlib.solve.signals import interrupted
from flexlib.solve.trajectory import Progress, Trajectory

__all__ = ["CHATTER_EVENTS", "MAX_RECOVERIES", "STATS_KEYS", "run_loop"]

#: Restarts from the last accepted point a backend may ask for (``Stop.kind == "recover"``) per run
MAX_RECOVERIES = 10
#: Events at one instant after which the run stops with "event chattering"
CHATTER_EVENTS = 100
#: Statistics every backend's run reports (backends add their own)
STATS_KEYS = ("steps", "nfev", "njev", "state_events", "time_events", "restarts", "state_switches", "recoveries",
              "max_order", "solver", "wall_integrate")


def run_loop(integ: Integrator, model: CompiledModel, init: Any, p: np.ndarray, y0: np.ndarray, yp0: np.ndarray,
             t0: float, t_end: float, t_out: np.ndarray | None, *, max_steps: int = 5_000_000,
             progress: bool | None = None, monitor: Any = None, sampled: list[Any] | None = None) -> Trajectory:
    """Integrate from the consistent ``y0, yp0`` at ``t0`` to ``t_end`` [s] with ``integ``.

    Parameters
    ----------
    integ : Integrator
        The backend, with its options (tolerances, step limits) set.
    model : CompiledModel
        The compiled model.
    init : Initializer
        Re-initialisation at events.
    p : ndarray
        Parameters followed by relation values (updated in place at events).
    t_out : ndarray or None
        Output times [s]; None records every internal step (or what the backend gives instead).
    max_steps : int
        Maximum number of internal steps for the whole run.
    progress : bool or None
        Show a progress bar; None shows one when the run takes longer than 2 s.
    monitor : StateSelectionMonitor, optional
        Dynamic state selection, checked on the monitor's schedule (backends with ``monitors``).
    sampled : list, optional
        Sampled blocks of the model (:mod:`flexlib.solve.sampling`): the run stops at their instants.

    Returns
    -------
    Trajectory
        With ``status`` ``"success"``.

    Raises
    ------
    SolverError
        The integration failed; ``err.result`` is the trajectory up to the failure.
    SimulationInterrupted
        Ctrl-C or SIGTERM; ``err.result`` is the trajectory up to the interrupt.
    """
    loop = _Loop(integ, model, init, p, t0, t_end, max_steps, progress, monitor)
    if not sampled:
        return loop.run(y0, yp0, t_out)
    loop.samplers = Samplers(sampled, model, t0)
    loop.samplers.start()
    try:
        return loop.run(y0, yp0, t_out)
    finally:
        loop.samplers.stop()


class _Loop:
    """The state of one run of :func:`run_loop`."""

    def __init__(self, integ: Integrator, model: CompiledModel, init: Any, p: np.ndarray, t0: float, t_end: float,
                 max_steps: int, progress: bool | None, monitor: Any) -> None:
        self.integ, self.model, self.init, self.p = integ, model, init, p
        self.n_par = model.n_params
        self.t, self.t_end, self.max_steps = t0, t_end, max_steps
        self.traj = Trajectory(models=[model])
        self.stats: dict[str, Any] = {"steps": 0, "nfev": 0, "njev": 0, "state_events": 0, "time_events": 0,
                                      "restarts": 0, "state_switches": 0, "recoveries": 0}
        self.traj.stats = self.stats
        self.bar = Progress(model.name, t0, t_end, progress)
        self.monitor = monitor if integ.monitors else None
        self.use_monitor = self.monitor is not None and model.has_state_choice
        self.watch, self.rooted = 0, set()
        self.last_event_t, self.burst, self.last_recovery_t, self.last_split_t = -np.inf, 0, -np.inf, -np.inf
        self.ties: set[int] = set()  # relations a split put on their limit: held while their indicator is exactly 0
        self.unseen = 0  # steps taken since the monitor last saw one
        self.now: tuple[np.ndarray, np.ndarray] | None = None  # (y, yp) at t, once fetched in this round
        self.rel = p[self.n_par:].copy()  # the relation values of the rows until the next event
        self.samplers: Samplers | None = None

    def run(self, y0: np.ndarray, yp0: np.ndarray, t_out: np.ndarray | None) -> Trajectory:
        integ, traj, stats = self.integ, self.traj, self.stats
        grid = None
        if t_out is not None:
            grid = np.asarray(t_out, dtype=float)
            grid = np.ascontiguousarray(grid[grid > self.t])
        if self.monitor is not None:
            self.monitor.reset()
        integ.start(self.model, self.t, y0, yp0, self.p, grid, self.t_end)
        traj.add(self.t, y0, yp0, self.rel)
        self.restarted()
        if self.samplers is not None:
            self.now = (y0, yp0)
            self.sample()  # the blocks' outputs after their initialisation, their first step
        clock = getattr(integ, "clock", _time.perf_counter)
        wall0 = clock()
        self.t_event, self.which = next_time_event(self.model, self.p, self.t, self.t_end)
        try:
            while self.t < self.t_end:
                self.round()
        except KeyboardInterrupt:
            self.interrupted()
        except SolverError as err:
            if interrupted():  # (a failure caused by Ctrl-C / SIGTERM swallowed in C is the interrupt)
                self.interrupted()
            self.close()
            traj.status, traj.message = "failed", str(err)
            err.result = traj
            raise
        except Exception as err:  # e.g. an event iteration that raises
            if interrupted():
                self.interrupted()
            self.close()
            traj.status, traj.message = "failed", f"error at t = {self.t:.10g} s: {err}"
            raise SolverError(traj.message, traj) from err
        finally:
            stats.update(integ.stats(clock() - wall0))
            stats["wall_integrate"] = clock() - wall0
            self.bar.close(self.t)
        if stats.get("unconverged_steps"):
            warnings.warn(AccuracyWarning(
                f"{stats['solver']}: {stats['unconverged_steps']} step solutions (in {stats['steps']} steps, "
                f"{stats.get('halved_steps', 0)} of them halved) were taken with Newton corrections that had not "
                f"converged, the first ending at t = {stats['first_unconverged_t']:.10g} s: the result may be "
                "inaccurate there; a smaller step h, or more newton_iters or max_halvings, converge"),
                stacklevel=4)
        return traj

    def round(self) -> None:
        """One call of the integrator and what follows from where it stopped."""
        integ, stats = self.integ, self.stats
        t_sample = self.samplers.next_time() if self.samplers is not None else np.inf
        stop = integ.advance(min(self.t_end, self.t_event, t_sample), self.limits())
        stats["steps"] += stop.steps
        self.unseen += stop.steps
        self.t, self.now = stop.t, None
        if stop.rows is not None:
            self.traj.extend(*stop.rows, self.rel)
        if stop.kind in ("recover", "failed"):
            if self.t == self.last_event_t and self.t > self.last_split_t and self.split():
                return
            if stop.kind == "recover" and self.t > self.last_recovery_t and stats["recoveries"] < MAX_RECOVERIES:
                self.recover(stop)
                return
            raise SolverError(self.failure(stop))
        if stop.kind == "step" or stats["steps"] % integ.progress_every < stop.steps or integ.progress_every <= 1:
            self.bar.update(self.t)
        if stop.kind == "full":
            return  # rows copied; the step (and any event it ended on) is reported by the next call
        self.events(stop)
        if self.use_monitor and self.unseen:
            self.check_states()
        if stats["steps"] >= self.max_steps and self.t < self.t_end:
            raise SolverError(f"maximum number of steps ({self.max_steps}) reached at t = {self.t:.10g} s")

    def limits(self) -> Limits:
        """The step budget of the next call: one step while the relations are watched, the monitor's schedule."""
        n = 1 if self.watch > 0 else self.max_steps
        t_check, h_min = np.inf, 0.0
        if self.use_monitor:  # as many steps as the monitor's schedule lets pass unchecked
            allowed, t_check, h_min = self.monitor.steps_allowed()
            n = min(n, allowed - self.unseen) if allowed > self.unseen else 1
        return Limits(max(1, min(n, self.max_steps - self.stats["steps"])), t_check, h_min)

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        """``(y, yp)`` at the current time (fetched once per round)."""
        if self.now is None:
            self.now = self.integ.state()
        return self.now

    def events(self, stop: Stop) -> None:
        """Time and state events at the stop, and the relation watch after a restart."""
        model, p, t = self.model, self.p, self.t
        kind = None
        triggered: list[tuple[int, bool]] = []
        time_hit = bool(self.which) and stop.kind in ("tstop", "root") and t >= self.t_event
        if stop.kind == "root":
            triggered, kind = list(stop.roots), "state"
        if time_hit:  # also when a state event is found exactly at the time event
            triggered += time_triggers(model, p, self.which)
            kind = kind or "time"
        elif stop.kind != "root" and self.watch > 0:
            # a relation that re-crosses at once after a restart (sliding) is caught by checking its sign, except
            # those the backend's root finding switched and that start on their new side (events.settled)
            self.watch -= 1
            y, yp = self.state()
            triggered = watch(model, p, t, y, yp, self.integ.state_rel, self.rooted | self.ties)
            kind = "state" if triggered else None
        if kind and any(p[self.n_par + k] != float(v) for k, v in triggered):
            self.event(kind, triggered, stop.kind == "root")
        if time_hit:
            self.t_event, self.which = next_time_event(model, p, t, self.t_end)
        if self.samplers is not None and stop.kind in ("tstop", "root"):
            self.sample()

    def sample(self) -> None:
        """The sampled blocks due now: their states set, the point made consistent, the integrator restarted."""
        y, yp = self.state()
        found = self.samplers.due(self.t, y, yp, self.p)
        if found is None:
            return
        y1, blocks = found
        self.traj.events.append((self.t, f"sample: {', '.join(blocks)}"))
        self.traj.add(self.t, y, yp, self.rel)
        y2, yp2 = event_iteration(self.model, self.init, self.p, self.t, y1, yp, [], ties=self.ties)
        self.stats["samples"] = self.samplers.samples
        self.integ.reinit(self.t, y2, yp2)
        self.now = (y2, yp2)
        self.rel = self.p[self.n_par:].copy()
        self.traj.add(self.t, y2, yp2, self.rel)
        self.restarted()

    def event(self, kind: str, triggered: list[tuple[int, bool]], root: bool) -> None:
        """Switch the relations, iterate, restart the integrator; rows before and after at the event time."""
        model, p, t, traj = self.model, self.p, self.t, self.traj
        y, yp = self.state()
        traj.add(t, y, yp, self.rel)
        before = p[self.n_par:].copy()
        y1, yp1 = event_iteration(model, self.init, p, t, y, yp, triggered, ties=self.ties)
        self.ties = {k for k in self.ties if p[self.n_par + k] == before[k]}  # a tie ends when its relation switches
        self.stats["state_events" if kind == "state" else "time_events"] += 1
        self.stats["restarts"] += 1
        texts = ", ".join(model.relations[k].text for k, _ in triggered)
        traj.events.append((t, f"{kind} event: {texts}"))
        self.integ.reinit(t, y1, yp1)
        self.now = (y1, yp1)
        self.rel = p[self.n_par:].copy()
        traj.add(t, y1, yp1, self.rel)
        self.restarted()
        if root and self.integ.settles_roots:
            self.rooted = settled(model, p, t, y1, yp1, triggered)
        self.burst = self.burst + 1 if t - self.last_event_t <= 1e-10 * max(1.0, abs(t)) else 0
        self.last_event_t = t
        if self.burst > CHATTER_EVENTS:
            raise SolverError(f"event chattering at t = {t:.10g} s: {texts} switches without time advancing")

    def split(self) -> bool:
        """After an event, the integrator cannot step from a point that leaves unknowns undetermined (stuck elements
        sharing a holding force): one relation switched to make it regular (:func:`events.indeterminate_split`, once
        per event time), the integrator restarted; False if it is not that."""
        self.last_split_t = self.t
        y, yp = self.state()
        found = indeterminate_split(self.model, self.init, self.p, self.t, y, yp)
        if found is None:
            return False
        y1, yp1 = found
        changed = [int(k) for k in np.flatnonzero(self.p[self.n_par:] != self.rel)]
        texts = ", ".join(self.model.relations[k].text for k in changed)
        self.traj.events.append((self.t, f"indeterminate split of a holding force: {texts}"))
        self.integ.reinit(self.t, y1, yp1)
        self.now = (y1, yp1)
        self.rel = self.p[self.n_par:].copy()
        self.traj.add(self.t, y1, yp1, self.rel)
        self.restarted()
        self.ties.update(changed)
        return True

    def restarted(self) -> None:
        """Watch the state relations' signs for the next steps (the backend's root finding is blind to a relation
        that is zero at the restart)."""
        self.watch = self.integ.watch_steps if len(self.integ.state_rel) else 0
        self.rooted = set()

    def recover(self, stop: Stop) -> None:
        """Restart from the last accepted point, made consistent, with the integrator's history reset (once per
        point reached, at most :data:`MAX_RECOVERIES` times in a run): the corrector or error test failed repeatedly
        with the step shrinking (a valve snapping open at the limit of the iteration matrix's reuse)."""
        y, yp = self.state()
        try:
            y, yp = event_iteration(self.model, self.init, self.p, self.t, y, yp, [], ties=self.ties)
        except SolverError:
            raise SolverError(self.failure(stop)) from None
        self.last_recovery_t = self.t
        self.stats["recoveries"] += 1
        self.traj.events.append((self.t, f"restart after {stop.flag} "
                                         "(IDA re-initialised at the last accepted point)"))
        self.integ.reinit(self.t, y, yp)
        self.rel = self.p[self.n_par:].copy()
        self.traj.add(self.t, y, yp, self.rel)
        self.watch = self.integ.watch_steps if len(self.integ.state_rel) else 0
        self.rooted = set()

    def check_states(self) -> None:
        """The state-selection monitor's check (when due), and the switch to a better-conditioned selection."""
        from flexlib.solve.init.initializer import Initializer

        y, yp = self.state()
        skipped, self.unseen = self.unseen - 1, 0
        model, t = self.model, self.t
        if not self.monitor.needs_switch(model, t, y, yp, self.p, skipped=skipped, h=self.integ.last_step()):
            return
        switched = self.monitor.switch(model, t, y, yp, self.p)
        if switched is None:
            return
        self.model, y1, yp1 = switched
        self.init = Initializer(self.model)
        y1, yp1 = self.init.reinit(t, y1, yp1, self.p)
        self.integ.start(self.model, t, y1, yp1, self.p, None, self.t_end)
        self.now = (y1, yp1)
        self.traj.models.append(self.model)
        self.rel = self.p[self.n_par:].copy()
        self.traj.add(t, y1, yp1, self.rel)
        self.stats["state_switches"] += 1
        m = self.model
        states = ", ".join(n for n, d in zip(m.y_names, m.differential, strict=True) if d)
        self.traj.events.append((t, f"state selection: states are now {states}"))
        self.watch = self.integ.watch_steps if len(self.integ.state_rel) else 0
        self.use_monitor = m.has_state_choice

    def failure(self, stop: Stop) -> str:
        """The backend's failure with what :func:`~flexlib.solve.diagnose.failure_message` finds at its point."""
        y, yp = self.integ.state()
        return failure_message(stop.message, self.model, self.p, stop.t, y, yp, self.traj, self.integ.rtol,
                               self.integ.atol, getattr(self.integ, "error_test_all", None))

    def close(self, unsaved: bool = False) -> None:
        """End the rows of a failed or interrupted run at the backend's last accepted point (never raises)."""
        traj, rel = self.traj, self.p[self.n_par:].copy()
        try:
            if unsaved and traj.t:  # rows an interrupt kept from being copied
                for t, y, yp in zip(*self.integ.unsaved_rows(), strict=True):
                    if t > traj.t[-1] and y.shape == traj.y[-1].shape:
                        traj.add(t, y, yp, rel)
            point = self.integ.accepted()
            if point is not None:
                traj.close(*point, rel)
        except Exception:  # never let the extra rows hide the failure itself
            pass

    def interrupted(self) -> None:
        """Keep the rows up to the interrupt and raise :class:`SimulationInterrupted`."""
        traj = self.traj
        traj.trim()  # the interrupt may have come in the middle of a block copy
        self.close(unsaved=True)
        t = max(self.t, traj.t[-1]) if traj.t else self.t
        traj.status, traj.message = "interrupted", f"interrupted by the user at t = {t:.10g} s"
        raise SimulationInterrupted(traj.message, traj) from None
