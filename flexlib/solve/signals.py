"""SIGTERM handled like Ctrl-C during a run (timeouts, batch schedulers and containers send SIGTERM).

While a run integrates, SIGTERM raises the same ``KeyboardInterrupt`` path as Ctrl-C, so the run stops,
keeps and writes its result and raises :class:`~flexlib.errors.SimulationInterrupted`. Once the run is
ending (its result being assembled and written) a SIGTERM is held back and delivered afterwards to the
handler that was there before the run.

Both signals are also recorded (:func:`interrupted`): a ``KeyboardInterrupt`` raised while C code runs a Python
signal check can be swallowed there (CasADi's IDAS turns it into a failed residual and returns an ordinary
error), and the backend then asks whether the run was interrupted instead of treating the error as a solver
failure.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["interrupted", "sigterm_as_interrupt"]


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
        self.received = False  # SIGINT or SIGTERM seen during the run (see interrupted())

    @property
    def by(self) -> str:
        return "SIGTERM" if self.signalled else "the user"

    def handler(self, signum: int, frame: Any) -> None:
        if self.stopping:
            self.pending = True
            return
        self.signalled = self.stopping = self.received = True
        raise _Terminated("SIGTERM")

    def int_handler(self, signum: int, frame: Any) -> None:
        """Python's own SIGINT behaviour (``KeyboardInterrupt``), recorded."""
        if not self.stopping:
            self.received = True
        raise KeyboardInterrupt


#: the runs in progress in this process (innermost last)
_ACTIVE: list[_StopState] = []


def interrupted() -> bool:
    """True if the run in progress has received SIGINT or SIGTERM (also when the ``KeyboardInterrupt`` raised for it
    was swallowed by C code, as CasADi's IDAS does inside its residual)."""
    return bool(_ACTIVE) and _ACTIVE[-1].received


@contextmanager
def sigterm_as_interrupt() -> Iterator[_StopState]:
    """During a run (main thread only), SIGTERM takes the Ctrl-C path: the run stops, keeps and writes its
    result, and raises SimulationInterrupted. The previous handler is restored afterwards, also on error."""
    state = _StopState()
    previous: Any = None
    previous_int: Any = None
    if threading.current_thread() is threading.main_thread() and hasattr(signal, "SIGTERM"):
        previous = signal.getsignal(signal.SIGTERM)
        if previous is None or previous is signal.SIG_IGN:
            previous = None  # set outside Python (cannot be restored) or ignored on purpose: leave it alone
        else:
            signal.signal(signal.SIGTERM, state.handler)
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:  # Python's Ctrl-C, not a user's handler
            previous_int = signal.signal(signal.SIGINT, state.int_handler)
    _ACTIVE.append(state)
    try:
        yield state
    finally:
        _ACTIVE.remove(state)
        if previous_int is not None:
            signal.signal(signal.SIGINT, previous_int)
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
            if state.pending:  # a SIGTERM that arrived while the result was written: deliver it now
                signal.raise_signal(signal.SIGTERM)
