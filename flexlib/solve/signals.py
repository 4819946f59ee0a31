"""SIGTERM handled like Ctrl-C during a run (timeouts, batch schedulers and containers send SIGTERM).

While a run integrates, SIGTERM raises the same ``KeyboardInterrupt`` path as Ctrl-C, so the run stops,
keeps and writes its result and raises :class:`~flexlib.errors.SimulationInterrupted`. Once the run is
ending (its result being assembled and written) a SIGTERM is held back and delivered afterwards to the
handler that was there before the run.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["sigterm_as_interrupt"]


class _Terminated(KeyboardInterrupt):
    """SIGTERM, turned into the Ctrl-C path of a run."""


class _StopState:
    """What the SIGTERM handler of one run has seen.

    ``stopping`` is set once the run is ending (interrupted, failed or done): a SIGTERM then no longer
    interrupts (the result is being assembled and written) but is delivered again, to the handler that was
    there before the run, once the run has ended."""

    def __init__(self) -> None:
        self.signalled = False
        self.stopping = False
        self.pending = False

    @property
    def by(self) -> str:
        return "SIGTERM" if self.signalled else "the user"

    def handler(self, signum: int, frame: Any) -> None:
        if self.stopping:
            self.pending = True
            return
        self.signalled = self.stopping = True
        raise _Terminated("SIGTERM")


@contextmanager
def sigterm_as_interrupt() -> Iterator[_StopState]:
    """During a run (main thread only), SIGTERM takes the Ctrl-C path: the run stops, keeps and writes its
    result, and raises SimulationInterrupted. The previous handler is restored afterwards, also on error."""
    state = _StopState()
    previous: Any = None
    if threading.current_thread() is threading.main_thread() and hasattr(signal, "SIGTERM"):
        previous = signal.getsignal(signal.SIGTERM)
        if previous is None or previous is signal.SIG_IGN:
            previous = None  # set outside Python (cannot be restored) or ignored on purpose: leave it alone
        else:
            signal.signal(signal.SIGTERM, state.handler)
    try:
        yield state
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
            if state.pending:  # a SIGTERM that arrived while the result was written: deliver it now
                signal.raise_signal(signal.SIGTERM)
