"""The default ``solver="ida"`` on the C driver: the choice and its fallback, the state-selection monitor's
schedule honoured in C, the switch to C compiled in the background during a run, and the event restart that the
scikit-sundae route got right by luck."""

import time
from pathlib import Path

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.reference.mass_spring_damper import Oscillator
from flexlib.solve import native, simulation
from flexlib.solve.backends.base import DENSE_MAX

HERE = Path(__file__).resolve().parent
needs_driver = pytest.mark.skipif(not native.native_available(),
                                  reason="C driver unavailable (no gcc, or FLEXLIB_NATIVE=0)")


@pytest.fixture(scope="module")
def osc():
    return fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


def count_advances(monkeypatch: pytest.MonkeyPatch) -> dict[str, int]:
    """``{"n": calls}``: the calls of the C driver's ``advance`` (one per block of C steps) from now on."""
    calls = {"n": 0}
    advance = native.Driver.advance

    def counted(self, *args):
        calls["n"] += 1
        return advance(self, *args)

    monkeypatch.setattr(native.Driver, "advance", counted)
    return calls


@needs_driver
def test_default_runs_on_the_c_driver(osc):
    """The C driver reports its wall-time split; the scikit-sundae route does not. Same IDA: the same steps,
    x = cos t to 1e-6 and the two routes to 1e-10 (rtol 1e-8)."""
    res = osc.run(5.0, dt_out=0.1, rtol=1e-8, atol=1e-10)
    ref = osc.run(5.0, dt_out=0.1, rtol=1e-8, atol=1e-10, solver="ida-sksundae")
    assert "wall_model" in res.stats and "wall_model" not in ref.stats
    assert res.stats["steps"] == ref.stats["steps"]
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-6)
    np.testing.assert_allclose(res["x"], ref["x"], atol=1e-10)


@needs_driver
def test_monitor_schedule_runs_in_c(monkeypatch):
    """The four-bar with the state-selection monitor: the C loop runs the steps the monitor's schedule skips, so
    the monitor makes exactly the checks it makes when it sees every step (scikit-sundae route: same steps, same
    indicator checks and full tests), while Python sees a small fraction of the steps."""
    from flexlib.models.planar_mechanisms import FourBarLinkage

    sim = fl.Simulation(FourBarLinkage(), use_cache=False)
    # the scikit-sundae route's linear solver (dense LU up to DENSE_MAX unknowns, SuperLU_MT above): the same IDA
    monkeypatch.setenv("FLEXLIB_LINSOL", "dense" if sim.compiled.n <= DENSE_MAX else "superlumt")
    mon = sim._monitor()
    ref = sim.run(3.0, dt_out=0.01, solver="ida-sksundae", progress=False)
    counts_ref = dict(mon.counts)
    calls = count_advances(monkeypatch)
    res = sim.run(3.0, dt_out=0.01, progress=False)
    counts = {k: v - counts_ref[k] for k, v in mon.counts.items()}
    assert counts == counts_ref and counts["indicator"] > 0
    assert res.stats["steps"] == ref.stats["steps"]
    assert calls["n"] < res.stats["steps"] / 10
    np.testing.assert_allclose(res.values, ref.values, atol=1e-9 * max(1.0, np.abs(ref.values).max()))


@needs_driver
def test_monitor_still_switches_in_c():
    """The Cartesian pendulum over the top switches its states on the C driver as on the scikit-sundae route."""
    from flexlib.models.reference.cartesian_pendulum import CartesianPendulum

    sim = fl.Simulation(CartesianPendulum(init={"x": 0.0, "u": 8.0}, guess={"y": -1.0}), use_cache=False)
    res = sim.run(3.0, rtol=1e-8, atol=1e-10, dt_out=0.01, progress=False)
    ref = sim.run(3.0, rtol=1e-8, atol=1e-10, dt_out=0.01, progress=False, solver="ida-sksundae")
    assert res.stats["state_switches"] >= 2 and res.stats["state_switches"] == ref.stats["state_switches"]
    np.testing.assert_allclose(res["x"] ** 2 + res["y"] ** 2, 1.0, atol=1e-6)  # the constraint (length 1 m)


@needs_driver
def test_background_c_is_adopted_during_the_run(tmp_path, monkeypatch):
    """Chain of 100 masses (301 unknowns, gcc in the background): the run starts on the SX virtual machine and
    switches to the compiled library between two steps once gcc has finished, without a restart. Reference: the
    same run on the library from its start (same operations, same order): equal to 1e-12 relative."""
    from flexlib.models.n_mass_chain import NMassChain

    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    sim = fl.Simulation(NMassChain(100))
    m = sim.compiled
    if m.library_pending is None:
        pytest.skip("gcc finished before the run started")
    real, adopt = m.c_ready, m._adopt_pending
    seen = {"n": 0, "allowed": False}

    def ready_after_a_while() -> bool:  # let a few blocks run on the VM, then wait for gcc
        seen["n"] += 1
        if seen["n"] < 3:
            return False
        deadline = time.monotonic() + 600.0
        while not real() and time.monotonic() < deadline:
            time.sleep(0.1)
        seen["allowed"] = real()
        return seen["allowed"]

    def adopt_when_allowed() -> None:  # gcc finishing during the run's start would otherwise be adopted there
        if seen["allowed"]:
            adopt()

    monkeypatch.setattr(m, "c_ready", ready_after_a_while)
    monkeypatch.setattr(m, "_adopt_pending", adopt_when_allowed)
    mixed = sim.run(10.0, dt_out=0.1, progress=False)
    assert 0.0 < mixed.stats["compiled_at"] < 10.0
    assert m.library is not None
    c = sim.run(10.0, dt_out=0.1, progress=False)
    assert "compiled_at" not in c.stats
    np.testing.assert_allclose(mixed.values, c.values, rtol=1e-12, atol=1e-12 * np.abs(c.values).max())


@needs_driver
def test_limiter_restart_at_a_root_located_early():
    """A limiter at rtol 1e-9 whose input re-enters the band: IDA locates the crossing within its interpolation
    error, a few 1e-11 before the true one. The relation switched there must not be switched back by the sign
    of its indicator after the restart (Newton noise): the run completes, the output stays clipped to the limits
    to 1e-6, and the events agree with the scikit-sundae route to 1e-9 s."""
    from flexlib.models.reference.signal_chain import LimitedSine

    sim = fl.Simulation(LimitedSine(), use_cache=False)
    kw = dict(dt_out=0.01, params={"limiter.u_max": -1.0, "limiter.u_min": -1.5}, progress=False, rtol=1e-9,
              atol=1e-11)
    res = sim.run(1.0, **kw)
    ref = sim.run(1.0, solver="ida-sksundae", **kw)
    assert res["limiter.y"].max() <= -1.0 + 1e-6 and res["limiter.y"].min() >= -1.5 - 1e-6
    assert [e[1] for e in res.events] == [e[1] for e in ref.events]
    np.testing.assert_allclose([e[0] for e in res.events], [e[0] for e in ref.events], atol=1e-9)


def test_solver_names_include_the_fallback():
    assert "ida-sksundae" in simulation.check_run_arguments.__globals__["SOLVERS"]


@needs_driver
def test_blocks_of_c_steps_are_bounded_in_wall_time(osc, monkeypatch):
    """Ctrl-C, SIGTERM and the progress bar reach Python when a block of C steps returns: a block ends after
    ``CHUNK_WALL`` seconds even within its 256 steps. With the bound at 1e-12 s every block is one step."""
    from flexlib.solve.backends import ida_c

    calls = count_advances(monkeypatch)
    free = osc.run(5.0, progress=False)
    n_free = calls["n"]
    monkeypatch.setattr(ida_c, "CHUNK_WALL", 1e-12)
    calls["n"] = 0
    bounded = osc.run(5.0, progress=False)
    assert n_free < free.stats["steps"] / 10
    assert calls["n"] >= bounded.stats["steps"] == free.stats["steps"]
    np.testing.assert_array_equal(bounded.values, free.values)


def test_a_compile_an_earlier_process_left_is_adopted(tmp_path, monkeypatch):
    """A background gcc outlives the process that started it; a process that ends first (a short CLI run) leaves the
    library unadopted in gcc's private directory. The next process of the same build takes that library (hashed,
    recorded in the cache) instead of compiling the same C again, and joins a compile still under way; a finished
    library of other C is not taken. Chain of 100 masses (301 unknowns: C in the background)."""
    from flexlib.compile import gcc, pipeline
    from flexlib.models.n_mass_chain import NMassChain

    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    first = fl.Simulation(NMassChain(100)).compiled
    if first.library is not None:
        pytest.skip("gcc finished before the build was stored")
    pending = Path(first.library_pending)
    deadline = time.monotonic() + 600.0
    while not pending.exists() and time.monotonic() < deadline:  # the earlier process's gcc finishes ...
        time.sleep(0.1)
    assert pending.exists()
    pipeline._COMPILING.clear()  # ... and that process is gone: this one knows of no compile
    dirs = set((tmp_path / "lib").glob(".flexlib-gcc-*.tmp"))
    second = fl.Simulation(NMassChain(100)).compiled
    assert second is not first  # read from the cache entry, stored before gcc finished
    assert set((tmp_path / "lib").glob(".flexlib-gcc-*.tmp")) == dirs  # no second gcc
    assert second.library_pending == str(pending) and second.wait_for_library(0.0)
    assert Path(second.library).parent == tmp_path / "lib" and second.library_problem() is None
    texts = (second.serialized["res"], second.serialized["jac"])
    assert gcc.earlier_compile(tmp_path / "lib", texts) is None  # adopted: nothing left to take
    assert gcc.earlier_compile(tmp_path / "lib", (texts[0] + " ", texts[1])) is None  # other C: never


def test_a_compile_under_way_is_joined_and_a_stale_or_failed_one_is_not(tmp_path):
    """:func:`flexlib.compile.gcc.earlier_compile` on gcc's private directories as :func:`generate_c` makes them (mode
    0700, ``flexlib_<digest>.c``): one still compiling (no library yet) is joined while younger than ``JOIN_AGE``;
    an older one (a killed gcc), one whose gcc failed (a log and no output) or one another user could write is not."""
    import os

    from flexlib.compile import gcc

    texts = ("res-text", "jac-text")
    digest = gcc._source_digest(texts)

    def work(name: str, mode: int = 0o700) -> Path:
        d = tmp_path / f".flexlib-gcc-{name}.tmp"
        d.mkdir()
        (d / f"flexlib_{digest}.c").write_text("/* C */")
        d.chmod(mode)
        return d

    running = work("running")
    assert gcc.earlier_compile(tmp_path, texts) == str(running / "flexlib.so")
    old = time.time() - gcc.JOIN_AGE - 10
    os.utime(running, (old, old))
    assert gcc.earlier_compile(tmp_path, texts) is None
    failed = work("failed")
    (failed / "gcc.log").write_text("error: ...")
    assert gcc.earlier_compile(tmp_path, texts) is None
    shared = work("shared", 0o777)
    (shared / "flexlib.so").write_bytes(b"\x7fELF")
    assert gcc.earlier_compile(tmp_path, texts) is None
