"""Tests of ``Trapezoid`` (MSL ``Modelica.Blocks.Sources.Trapezoid``).

Reference: MSL's defining equations, written here with numpy (phase ``(time − start_time) mod
period``, zero before start_time and after nperiod periods). The signal is piecewise linear and
every corner is a time event, so the output matches exactly (1e-12) on the output grid; the times
are dyadic so that the corners are exact in floating point. Integrated by a mass, the impulse of
one period A (rising/2 + width + falling/2) gives the velocity at the period ends (1e-9 relative
at rtol = 1e-10).
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Trapezoid
from flexlib.components.mechanics.translational import Force, Mass
from tests.components.control.signals import right_values

TOL = {"rtol": 1e-8, "atol": 1e-10}
DT = 1.0 / 64.0


def reference(t: np.ndarray, A: float, rising: float, width: float, falling: float, period: float, nperiod: int,
              offset: float, start_time: float) -> np.ndarray:
    """MSL Trapezoid: y = offset + (rise | plateau | fall | 0) by the phase in the current period."""
    s = t - start_time
    count = np.floor(s / period)
    ph = s - count * period
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.where(ph < rising, A * ph / rising,
                     np.where(ph < rising + width, A,
                              np.where(ph < rising + width + falling, A * (rising + width + falling - ph) / falling,
                                       0.0)))
    return offset + np.where((s < 0) | (count >= nperiod), 0.0, y)


CASES = {
    "ramps": {"amplitude": 2.0, "rising": 0.125, "width": 0.25, "falling": 0.1875, "period": 0.75, "nperiod": 3,
              "offset": 0.5, "start_time": 0.25},
    "rectangle": {"amplitude": -1.5, "rising": 0.0, "width": 0.25, "falling": 0.0, "period": 0.5, "nperiod": 2,
                  "offset": 0.0, "start_time": 0.0},
    "cut": {"amplitude": 1.0, "rising": 0.25, "width": 0.25, "falling": 0.25, "period": 0.625, "nperiod": 2,
            "offset": 0.0, "start_time": 0.125},  # the fall is cut at the period end, as in MSL
}


class Trapezoids(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        for name, kw in CASES.items():
            setattr(self, name, Trapezoid(**kw))


@pytest.fixture(scope="module")
def result() -> fl.Result:
    return fl.Simulation(Trapezoids(), use_cache=False).run(3.0, dt_out=DT, **TOL)


@pytest.mark.parametrize("name", list(CASES))
def test_trapezoid_matches_msl_formula(result, name):
    """Output equals the MSL formula at every output point (right values at events), 1e-12."""
    kw = CASES[name]
    t, y = right_values(result, f"{name}.y")
    expected = reference(t, kw["amplitude"], kw["rising"], kw["width"], kw["falling"], kw["period"],
                         kw["nperiod"], kw["offset"], kw["start_time"])
    np.testing.assert_allclose(y, expected, rtol=0, atol=1e-12)
    assert y[-1] == pytest.approx(kw["offset"])  # after nperiod periods: offset


def test_corners_are_time_events(result):
    """Every corner of ``ramps`` is a time event at its exact time (start, 4 corners per period)."""
    kw = CASES["ramps"]
    P, t0 = kw["period"], kw["start_time"]
    corners = {t0}
    for k in range(kw["nperiod"]):
        Ts = t0 + k * P
        corners |= {Ts + 0.125, Ts + 0.375, Ts + 0.5625, Ts + P}
    event_times = {t for t, text in result.events if "ramps:" in text}
    assert event_times == corners
    assert result.stats["time_events"] >= len(corners) and result.stats["state_events"] == 0


class TrapezoidPush(fl.Model):
    """A trapezoidal force accelerates a free mass."""

    def __init__(self, m: float) -> None:
        super().__init__()
        self.trapezoid = Trapezoid(**CASES["ramps"])
        self.force = Force()
        self.mass = Mass(m=m, init={"s": 0.0, "v": 0.0})
        self.connect(self.trapezoid.y, self.force.f)
        self.connect(self.force.flange, self.mass.flange_a)


def test_trapezoid_force_impulse():
    """Velocity of a mass pushed by the trapezoid: v(t) = (offset t + n A (rising/2 + width + falling/2))/m
    at the end of period n. Reference: the impulse of each trapezoid; tolerance 1e-9 relative at
    rtol = 1e-10 (measured 2.3e-10; 2.8e-8 at rtol = 1e-8)."""
    kw, m = CASES["ramps"], 1.5
    res = fl.Simulation(TrapezoidPush(m), use_cache=False).run(3.0, dt_out=DT, rtol=1e-10, atol=1e-12)
    impulse = kw["amplitude"] * (kw["rising"] / 2 + kw["width"] + kw["falling"] / 2)
    ends = kw["start_time"] + kw["period"] * np.arange(kw["nperiod"] + 1)
    expected = (kw["offset"] * ends + impulse * np.arange(kw["nperiod"] + 1)) / m
    np.testing.assert_allclose(res.value("mass.v", ends), expected, rtol=1e-9)


def test_bad_trapezoid_inputs():
    """Bad input: infinitely many periods (nperiod < 0) cannot be time events; period must be > 0."""
    with pytest.raises(fl.ModelError, match=r"nperiod must be an integer >= 0"):
        Trapezoid(nperiod=-1, period=1.0)
    with pytest.raises(fl.ParameterError, match=r"period must be > 0"):
        Trapezoid(nperiod=1, period=0.0)
    with pytest.raises(fl.ParameterError, match=r"rising"):
        Trapezoid(nperiod=1, period=1.0, rising=-0.1)
