"""Signals during a run: SIGTERM (timeouts, batch schedulers, containers) takes the Ctrl-C path, so the result
up to that point is kept and written; Ctrl-C during a save leaves no partial file (issue 8: before, SIGTERM
wrote nothing)."""

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.reference.blow_up import BlowUp
from flexlib.models.reference.mass_spring_damper import Oscillator
from flexlib.results import hdf5
from flexlib.solve import native, signals, sundae_callbacks, trajectory


@pytest.fixture(scope="module")
def sim():
    return fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


@pytest.fixture
def recorder():
    """A Python SIGTERM handler in place before the run (records calls); restored after the test."""
    calls = []
    previous = signal.signal(signal.SIGTERM, lambda signum, frame: calls.append(signum))
    yield calls
    signal.signal(signal.SIGTERM, previous)


@pytest.fixture
def ctrl_c():
    """Python's own SIGINT handler (KeyboardInterrupt) for the test, restored after it: a suite started as a
    background job (``pytest &``) inherits SIGINT ignored, and a raised SIGINT would then do nothing."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def signal_at_call(monkeypatch, n, signum=signal.SIGTERM):
    """Deliver ``signum`` to this process during the steps of the default backend: from inside the ``n``-th
    residual evaluation of IDA stepped from Python, or, on the C driver (whose residual is not Python), when its
    second block of steps returns (the first point where a signal that arrived during C steps reaches Python)."""
    calls = {"n": 0, "blocks": 0}
    original = sundae_callbacks.Callbacks.resfn

    def resfn(self, t, y, yp, r):
        calls["n"] += 1
        if calls["n"] == n:
            signal.raise_signal(signum)
        original(self, t, y, yp, r)

    advance = native.Driver.advance

    def blocks(self, *args):
        out = advance(self, *args)
        calls["blocks"] += 1
        if calls["blocks"] == 2:
            signal.raise_signal(signum)
        return out

    monkeypatch.setattr(sundae_callbacks.Callbacks, "resfn", resfn)
    monkeypatch.setattr(native.Driver, "advance", blocks)


CHILD = textwrap.dedent("""
    import sys
    import flexlib as fl
    from flexlib import Variable, der, eq
    from flexlib.solve import native, simulation

    from flexlib.models.reference.mass_spring_damper import Oscillator

    sim = fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    if native.native_available():  # the default backend: announce once the C loop has returned rows
        real = native.Driver.advance

        def advance(self, *args):
            out = real(self, *args)
            if out[1] > 10 and not getattr(advance, "said", False):
                advance.said = True
                print("integrating", flush=True)
            return out

        native.Driver.advance = advance
    else:
        real = simulation.run_loop

        def announce(*args, **kwargs):
            print("integrating", flush=True)
            return real(*args, **kwargs)

        simulation.run_loop = announce
    try:
        sim.run(1e5, dt_out=0.1, result_file=sys.argv[1], progress=False)
    except fl.SimulationInterrupted as err:
        print("interrupted", err.result.status, len(err.result.t), flush=True)
        sys.exit(3)
    print("finished", flush=True)
""")


def test_sigterm_from_outside_writes_the_result(tmp_path):
    """A separate process starts a long run (1e5 s) with result_file and gets SIGTERM while integrating: it
    raises SimulationInterrupted and leaves a readable file with status interrupted and rows x = cos t.

    On the C driver the child says "integrating" only once the C loop has returned rows (under a load average of
    10 the first rows could take longer than the 0.5 s the parent waits, and the signal then came before them)."""
    path = tmp_path / "long.h5"
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    child = subprocess.Popen([sys.executable, str(script), str(path)], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        line = child.stdout.readline()
        assert line.strip() == "integrating", child.stderr.read()
        time.sleep(0.5)
        child.send_signal(signal.SIGTERM)
        out, err = child.communicate(timeout=120)
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode == 3, err
    assert out.startswith("interrupted interrupted ")
    res = fl.load_result(path)
    assert res.status == "interrupted" and "interrupted by SIGTERM at t = " in res.message
    assert len(res.t) > 10 and 0 < res.t[-1] < 1e5
    early = res.t <= 1000.0  # the phase error grows with t (rtol 1e-6): the C driver reaches t ~ 3e4 s in 0.5 s
    np.testing.assert_allclose(res["x"][early], np.cos(res.t[early]), atol=1e-3)
    assert [p.name for p in tmp_path.iterdir() if p.suffix == ".tmp"] == []


def test_sigterm_during_the_steps(sim, monkeypatch, tmp_path, recorder):
    signal_at_call(monkeypatch, 300)
    path = tmp_path / "run.h5"
    with pytest.raises(fl.SimulationInterrupted, match=r"interrupted by SIGTERM at t = ") as err:
        sim.run(100.0, dt_out=0.01, result_file=path)
    res = err.value.result
    assert res.status == "interrupted" and 0 < res.t[-1] < 100
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-4)
    assert fl.load_result(path).status == "interrupted"
    assert recorder == []  # the run's handler took it; the previous one is back
    assert signal.getsignal(signal.SIGTERM) is not signals._StopState.handler


def test_sigterm_with_the_casadi_backend(sim, monkeypatch, tmp_path, recorder):

    calls = {"n": 0}
    original = trajectory.Progress.update

    def update(self, t):
        calls["n"] += 1
        if calls["n"] == 3:
            signal.raise_signal(signal.SIGTERM)
        original(self, t)

    monkeypatch.setattr(trajectory.Progress, "update", update)
    with pytest.raises(fl.SimulationInterrupted, match=r"interrupted by SIGTERM at t = ") as err:
        sim.run(100.0, dt_out=0.01, solver="casadi-idas", result_file=tmp_path / "run.h5")
    assert err.value.result.status == "interrupted" and len(err.value.result.t) > 1
    assert fl.load_result(tmp_path / "run.h5").status == "interrupted"


def test_sigterm_during_initialisation(sim, monkeypatch, tmp_path, recorder):
    real = sim._initialize

    def initialize(*args):
        signal.raise_signal(signal.SIGTERM)
        return real(*args)

    monkeypatch.setattr(sim, "_initialize", initialize)
    with pytest.raises(fl.SimulationInterrupted, match=r"interrupted by SIGTERM during initialisation") as err:
        sim.run(1.0, result_file=tmp_path / "init.h5")
    assert err.value.result.status == "interrupted" and len(err.value.result.t) == 0
    back = fl.load_result(tmp_path / "init.h5")
    assert back.status == "interrupted" and back.values.shape[0] == 0


def test_ctrl_c_signal_during_the_steps(sim, monkeypatch, tmp_path, ctrl_c):
    signal_at_call(monkeypatch, 300, signal.SIGINT)
    with pytest.raises(fl.SimulationInterrupted, match=r"interrupted by the user at t = "):
        sim.run(100.0, dt_out=0.01, result_file=tmp_path / "run.h5")
    assert fl.load_result(tmp_path / "run.h5").status == "interrupted"


@pytest.mark.parametrize("outcome", ["success", "solver error", "argument error", "interrupt"])
def test_previous_handler_is_restored(monkeypatch, recorder, outcome):
    model = BlowUp(init={"x": 1.0}) if outcome == "solver error" else Oscillator(init={"x": 1.0, "v": 0.0})
    run = fl.Simulation(model, use_cache=False).run
    mine = signal.getsignal(signal.SIGTERM)
    if outcome == "success":
        run(1.0)
    elif outcome == "solver error":
        with pytest.raises(fl.SolverError, match=r"at t = 0\.9"):
            run(2.0)
    elif outcome == "argument error":
        with pytest.raises(fl.RunArgumentError, match="dt_out"):
            run(1.0, dt_out=0.0)
    else:
        signal_at_call(monkeypatch, 50)
        with pytest.raises(fl.SimulationInterrupted, match="SIGTERM"):
            run(100.0)
    assert signal.getsignal(signal.SIGTERM) is mine
    signal.raise_signal(signal.SIGTERM)
    assert recorder == [signal.SIGTERM]


def test_sigterm_while_writing_is_delivered_after_the_file_is_complete(sim, monkeypatch, tmp_path, recorder):
    """The run has ended and its file is being written when SIGTERM arrives: the write completes, the run
    returns, and the signal then reaches the handler that was there before the run."""
    real = hdf5._write

    def write(result, tmp, *args):
        signal.raise_signal(signal.SIGTERM)
        assert recorder == []  # not yet
        real(result, tmp, *args)

    monkeypatch.setattr(hdf5, "_write", write)
    res = sim.run(1.0, dt_out=0.1, result_file=tmp_path / "run.h5")
    assert res.success and recorder == [signal.SIGTERM]
    assert len(fl.load_result(tmp_path / "run.h5").t) == 11


def test_ctrl_c_during_a_save_leaves_no_partial_file(sim, saved_file, monkeypatch, ctrl_c):
    """SIGINT when the temporary file is written but not yet renamed: the previous file is intact and no
    temporary file remains."""
    before = saved_file.read_bytes()
    real = hdf5._write

    def write(result, tmp, *args):
        real(result, tmp, *args)
        signal.raise_signal(signal.SIGINT)

    monkeypatch.setattr(hdf5, "_write", write)
    with pytest.raises(KeyboardInterrupt):
        sim.run(0.5).save(saved_file)
    assert saved_file.read_bytes() == before
    assert [p.name for p in saved_file.parent.iterdir()] == [saved_file.name]


def test_ctrl_c_during_the_save_of_a_run_keeps_the_result(sim, monkeypatch, tmp_path, ctrl_c):
    def write(result, tmp, *args):
        signal.raise_signal(signal.SIGINT)

    monkeypatch.setattr(hdf5, "_write", write)
    path = tmp_path / "run.h5"
    with pytest.raises(fl.SimulationInterrupted, match=r"interrupted while writing the result file .*run\.h5 "
                                                       r"\(not written") as err:
        sim.run(1.0, dt_out=0.1, result_file=path)
    assert err.value.result.success and len(err.value.result.t) == 11
    assert list(tmp_path.iterdir()) == []


def test_run_in_a_thread_installs_no_handler(sim, recorder):
    """signal.signal works in the main thread only: a run in another thread leaves SIGTERM alone and works."""
    mine = signal.getsignal(signal.SIGTERM)
    out = {}

    def work():
        try:
            out["res"] = sim.run(1.0, dt_out=0.5)
        except BaseException as err:  # reported below
            out["err"] = err

    thread = threading.Thread(target=work)
    thread.start()
    thread.join(60)
    assert "err" not in out and out["res"].success
    assert signal.getsignal(signal.SIGTERM) is mine


@pytest.fixture
def saved_file(sim, tmp_path):
    path = tmp_path / "keep.h5"
    sim.run(0.2).save(path)
    return path


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("solver", ["ida", "ida-sksundae", "casadi-idas"])
def test_every_backend_stops_mid_run_with_the_rows_so_far(sim, solver, signum, ctrl_c):
    """A signal from another thread while a long run integrates (an undamped oscillator over 1e6 s, minutes of
    work): every backend stops with SimulationInterrupted and the rows so far (issue 26: CasADi's IDAS turned
    the KeyboardInterrupt raised in its residual into a failed step, its halve-and-retry went on, and the run
    ended 7 s later with "maximum number of steps reached"). The signal is sent once the run is past t = 100 s."""
    started = threading.Event()
    real = trajectory.Progress.update

    def update(self, t):  # every backend reports its progress here as the run advances
        if t > 100.0:
            started.set()
        real(self, t)

    def send():
        if started.wait(120.0):
            os.kill(os.getpid(), signum)

    trajectory.Progress.update = update
    sender = threading.Thread(target=send, daemon=True)
    sender.start()
    try:
        with pytest.raises(fl.SimulationInterrupted, match="SIGTERM" if signum == signal.SIGTERM else "by the user") \
                as err:
            sim.run(1e6, dt_out=1.0, solver=solver, max_steps=10**9, progress=False)
    finally:
        trajectory.Progress.update = real
        started.set()
        sender.join()
    res = err.value.result
    assert res.status == "interrupted"
    assert 100.0 < res.t[-1] < 1e6 and np.array_equal(res.t[:101], np.arange(101.0))
    assert res["x"][50] == pytest.approx(np.cos(50.0), abs=1e-3)  # the rows kept are the solution
