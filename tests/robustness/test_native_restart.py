"""The C driver restarts once from the last accepted point when IDA gives up (``ida_c.RECOVERABLE``).

IDA's failure is injected: the driver's ``advance`` takes its steps as usual but reports ``IDA_CONV_FAIL`` at
the point it reached, as IDA does when its corrector fails ten times in a row there."""

import numpy as np
import pytest

import flexlib as fl
from flexlib import Variable, der, eq
from flexlib.solve import loop, native
from flexlib.solve.backends import ida_c

IDA_CONV_FAIL = -4


@pytest.fixture(autouse=True)
def short_chunks(monkeypatch):
    """The C loop returns every 4 steps, so the injected failure falls inside the run."""
    monkeypatch.setattr(ida_c, "CHUNK_STEPS", 4)


class FastOscillator(fl.Model):
    """x'' = −ω² x with ω = 2π rad/s, x(0) = 1: x = cos(ωt)."""

    x = Variable(unit="m")
    v = Variable(unit="m/s")

    def equations(self):
        w = 2 * np.pi
        return [eq(der(self.x), self.v), eq(der(self.v), -w**2 * self.x)]


def _failing_advance(monkeypatch, fail_after: float, times: int):
    """Make ``Driver.advance`` report IDA_CONV_FAIL ``times`` times once the run has passed ``fail_after`` s."""
    real = native.Driver.advance
    left = [times]

    def advance(self, t_stop, max_chunk, T, Y, YP):
        code, k, t, nsteps = real(self, t_stop, max_chunk, T, Y, YP)
        if t > fail_after and left[0] > 0 and code >= 0:
            left[0] -= 1
            return IDA_CONV_FAIL, k, t, nsteps
        return code, k, t, nsteps

    monkeypatch.setattr(native.Driver, "advance", advance)


def test_a_corrector_failure_restarts_from_the_last_accepted_point(monkeypatch):
    """One failure at ~0.5 s: the run completes, records the restart, and still follows cos(2πt) to 1e-5 m."""
    _failing_advance(monkeypatch, 0.5, 1)
    sim = fl.Simulation(FastOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    res = sim.run(2.0, dt_out=0.01, rtol=1e-8, atol=1e-10, solver="ida-native", progress=False)
    assert res.status == "success"
    assert res.stats["recoveries"] == 1
    assert next(t for t, text in res.events if "restart after IDA_CONV_FAIL" in text) > 0.5
    np.testing.assert_allclose(res["x"], np.cos(2 * np.pi * res.t), atol=1e-5)


def test_a_second_failure_at_the_same_point_stops_with_the_result(monkeypatch):
    """Failing again where it restarted, without a step in between: SolverError naming IDA_CONV_FAIL, with the
    rows up to there attached."""
    real = native.Driver.advance
    stuck = []

    def advance(self, t_stop, max_chunk, T, Y, YP):
        if stuck:
            return IDA_CONV_FAIL, 0, stuck[0], 0
        code, k, t, nsteps = real(self, t_stop, max_chunk, T, Y, YP)
        if t > 0.5:
            stuck.append(t)
            return IDA_CONV_FAIL, k, t, nsteps
        return code, k, t, nsteps

    monkeypatch.setattr(native.Driver, "advance", advance)
    sim = fl.Simulation(FastOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match="IDA_CONV_FAIL") as info:
        sim.run(2.0, dt_out=0.01, solver="ida-native", progress=False)
    res = info.value.result
    assert res is not None and 0.5 < res.t[-1] < 2.0
    assert res.stats["recoveries"] == 1


def test_restarts_are_limited_per_run(monkeypatch):
    """A run that fails at every chunk it reaches is stopped after MAX_RECOVERIES restarts, not carried along."""
    _failing_advance(monkeypatch, 0.0, 10**6)
    sim = fl.Simulation(FastOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match="IDA_CONV_FAIL") as info:
        sim.run(2.0, dt_out=0.01, solver="ida-native", progress=False)
    assert info.value.result.stats["recoveries"] == loop.MAX_RECOVERIES
