"""Progress of a run where standard error is not a terminal (a log file, a CI job): a line per tenth of the span."""

from __future__ import annotations

import io

import flexlib as fl
from flexlib.solve import trajectory
from tests.test_results import Oscillator


def test_progress_in_a_log_is_a_line_per_tenth(capsys):
    """Without a terminal: one plain line per tenth of the span however often it is updated (eleven for 0 … 100 %,
    in order), and a run with ``progress=True`` and standard error captured writes its end line and no
    carriage-return redraws (a tqdm bar wrote 86–322 KB of them into a redirected log, issue 29)."""
    log = io.StringIO()
    bar = trajectory.Progress("m", 0.0, 10.0, True, stream=log)
    for t in [0.0, *[k * 0.01 for k in range(1, 1001)]]:
        bar.update(t)
    bar.close(10.0)
    lines = log.getvalue().splitlines()
    assert [int(line.split(": ")[1].split(" %")[0]) for line in lines] == list(range(0, 101, 10))
    assert lines[-1].startswith("m: 100 % (10 s of 10 s simulated, ")
    fl.Simulation(Oscillator(), use_cache=False).run(2.0, dt_out=0.001, progress=True)
    err = capsys.readouterr().err
    assert "\r" not in err
    assert [line for line in err.splitlines() if line.startswith("Oscillator: ")][-1].startswith(
        "Oscillator: 100 % (2 s of 2 s simulated, ")


def test_progress_on_a_terminal_is_a_bar():
    """On a terminal the bar is tqdm's (drawn in place)."""

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    out = Terminal()
    bar = trajectory.Progress("m", 0.0, 10.0, True, stream=out)
    bar.update(5.0)
    bar.close()
    assert "\r" in out.getvalue() and "5/10 s" in out.getvalue()
