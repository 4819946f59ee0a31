"""Tests of ``Product``, ``Limiter``, ``DeadZone``, ``Switch`` and ``RateLimiter`` against their MSL
definitions (``Modelica.Blocks.Math.Product``, ``Nonlinear.Limiter``, ``Nonlinear.DeadZone``,
``Logical.Switch``, ``Nonlinear.SlewRateLimiter``).

The static blocks are fed by a sine (amplitude 2, 1 Hz) and compared with numpy formulas
(``np.clip`` etc.) on the output grid: algebraic outputs match to 1e-7 at rtol 1e-8 (the sine is
interpolated by IDA between its steps). Limit crossings are state events, located at the analytic
crossing times asin(level/2)/(2π) to 1e-9 s. The rate limiter follows a closed-form solution.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import (
    Constant,
    DeadZone,
    Limiter,
    Product,
    Ramp,
    RateLimiter,
    Sine,
    Step,
    Switch,
)
from tests.components.control.signals import right_values

TOL = {"rtol": 1e-8, "atol": 1e-10}


class Static(fl.Model):
    """A sine through each static block."""

    def __init__(self) -> None:
        super().__init__()
        self.sine = Sine(amplitude=2.0, f=1.0)
        self.ramp = Ramp(height=3.0, duration=1.0)
        self.on = Step(height=1.0, start_time=0.375)
        self.level = Constant(k=-0.25)
        self.limiter = Limiter(u_max=1.2, u_min=-0.7)
        self.strict_limiter = Limiter(u_max=1.2, u_min=-0.7, strict=True)
        self.dead_zone = DeadZone(u_max=0.5, u_min=-0.3)
        self.product = Product()
        self.switch_time = Switch()  # switched by a step at 0.375 s
        self.switch_state = Switch()  # switched where the sine crosses 0.5
        self.connect(self.sine.y, self.limiter.u, self.strict_limiter.u, self.dead_zone.u, self.product.u1,
                     self.switch_time.u1, self.switch_state.u2, self.switch_state.u1)
        self.connect(self.ramp.y, self.product.u2)
        self.connect(self.on.y, self.switch_time.u2)
        self.connect(self.level.y, self.switch_time.u3, self.switch_state.u3)


@pytest.fixture(scope="module")
def static() -> fl.Result:
    return fl.Simulation(Static(), use_cache=False).run(1.0, dt_out=0.01, **TOL)


def crossings(level: float) -> list[float]:
    """Times in (0, 1) where 2 sin(2π t) = level."""
    a = np.arcsin(level / 2.0) / (2 * np.pi)
    return sorted(x % 1.0 for x in (a, 0.5 - a))


def test_product(static):
    """Product: y = u1 u2 (sine × ramp), 1e-7."""
    t, y = right_values(static, "product.y")
    np.testing.assert_allclose(y, 2.0 * np.sin(2 * np.pi * t) * 3.0 * np.clip(t, 0.0, 1.0), rtol=0, atol=1e-7)


def test_limiter(static):
    """Limiter: y = clip(u, u_min, u_max), both versions (events and strict); crossings are state
    events of the event version at the analytic times (1e-9 s), none for the strict one."""
    for name in ("limiter", "strict_limiter"):
        t, y = right_values(static, f"{name}.y")
        np.testing.assert_allclose(y, np.clip(2.0 * np.sin(2 * np.pi * t), -0.7, 1.2), rtol=0, atol=1e-7)
    found = sorted(t for t, text in static.events if "limiter:" in text and "strict" not in text)
    np.testing.assert_allclose(found, sorted(crossings(1.2) + crossings(-0.7)), rtol=0, atol=1e-9)
    assert not any("strict_limiter" in text for _, text in static.events)


def test_dead_zone(static):
    """DeadZone: u − u_max above, u − u_min below, 0 in between; edges are state events (1e-9 s)."""
    t, y = right_values(static, "dead_zone.y")
    u = 2.0 * np.sin(2 * np.pi * t)
    np.testing.assert_allclose(y, np.where(u > 0.5, u - 0.5, np.where(u < -0.3, u + 0.3, 0.0)), rtol=0, atol=1e-7)
    found = sorted(t for t, text in static.events if "dead_zone:" in text)
    np.testing.assert_allclose(found, sorted(crossings(0.5) + crossings(-0.3)), rtol=0, atol=1e-9)


def test_switch(static):
    """Switch: y = u1 if u2 > 0.5 else u3 — after a step at 0.375 s (switches at that time event)
    and where the sine crosses 0.5 (state events at the analytic times, 1e-9 s)."""
    t, y = right_values(static, "switch_time.y")
    u = 2.0 * np.sin(2 * np.pi * t)
    np.testing.assert_allclose(y, np.where(t >= 0.375, u, -0.25), rtol=0, atol=1e-7)
    found = sorted(t for t, text in static.events if "switch_state:" in text)
    np.testing.assert_allclose(found, crossings(0.5), rtol=0, atol=1e-9)
    t, y = right_values(static, "switch_state.y")
    away = np.min(np.abs(t[:, None] - np.array(found)[None, :]), axis=1) > 1e-9  # u2 = 0.5 at the events
    u = 2.0 * np.sin(2 * np.pi * t)
    np.testing.assert_allclose(y[away], np.where(u > 0.5, u, -0.25)[away], rtol=0, atol=1e-7)
    at = static["switch_time.y"][static.t == 0.375]  # switched in the event iteration of the step's time event
    assert at[0] == -0.25 and at[-1] == pytest.approx(2.0 * np.sin(2 * np.pi * 0.375), abs=1e-9)


class RateLimited(fl.Model):
    """Steps up and down through a slew-rate limiter."""

    def __init__(self, **kw: object) -> None:
        super().__init__()
        self.up = Step(height=1.0, start_time=0.25)
        self.down = Step(height=-1.5, start_time=1.5)
        self.input = Constant(k=0.0)
        self.limiter = RateLimiter(**kw)
        self.sum = _Sum3()
        self.connect(self.up.y, self.sum.u1)
        self.connect(self.down.y, self.sum.u2)
        self.connect(self.input.y, self.sum.u3)
        self.connect(self.sum.y, self.limiter.u)


class _Sum3(fl.Component):
    """u1 + u2 + u3 (test helper)."""

    u1, u2, u3 = fl.Input(), fl.Input(), fl.Input()
    y = fl.Output()

    def equations(self) -> list:
        return [fl.eq(self.y, self.u1 + self.u2 + self.u3)]


def slew_reference(t: np.ndarray, t0: float, y0: float, h: float, rate: float, Td: float) -> np.ndarray:
    """Slew-rate limiter after a step from steady y0 to y0 + h at t0 (|h| > |rate| Td).

    der(y) = rate while |u − y|/Td > |rate|, i.e. until t1 = t0 + (|h| − |rate| Td)/|rate|; then
    der(y) = (u − y)/Td, so y = u − rate Td exp(−(t − t1)/Td).
    """
    t1 = t0 + (abs(h) - abs(rate) * Td) / abs(rate)
    return np.where(t < t0, y0, np.where(t < t1, y0 + rate * (t - t0), y0 + h - rate * Td * np.exp(-(t - t1) / Td)))


def test_rate_limiter_follows_steps_at_the_limiting_rates():
    """Step +1 at 0.25 s (rising 2/s), step −1.5 at 1.5 s (falling −3/s), Td = 0.01 s.

    Reference: the closed form of ``slew_reference`` (linear at the rate, then exponential with Td);
    tolerance 1e-7 [1]; the regime changes are state events at t1 (1e-9 s)."""
    rising, falling, Td = 2.0, -3.0, 0.01
    res = fl.Simulation(RateLimited(rising=rising, falling=falling, Td=Td), use_cache=False).run(
        3.0, dt_out=1.0 / 128, **TOL)
    t, y = right_values(res, "limiter.y")
    up = slew_reference(t, 0.25, 0.0, 1.0, rising, Td)
    expected = np.where(t < 1.5, up, slew_reference(t, 1.5, 1.0, -1.5, falling, Td))
    np.testing.assert_allclose(y, expected, rtol=0, atol=1e-7)
    found = sorted(t for t, text in res.events if "limiter:" in text)
    t1_up, t1_down = 0.25 + (1.0 - rising * Td) / rising, 1.5 + (1.5 + falling * Td) / -falling
    for t_switch in (t1_up, t1_down):
        assert min(abs(np.array(found) - t_switch)) < 1e-9


def test_rate_limiter_initialisation_and_bad_input():
    """``steady_state`` (default): y = u at the start; ``initial_state``: y = y_start. Bad input:
    rising <= 0, falling >= 0, Td = 0."""
    res = fl.Simulation(RateLimited(), use_cache=False).run(0.1, dt_out=0.05, **TOL)
    assert res["limiter.y"][0] == pytest.approx(0.0, abs=1e-12)
    res = fl.Simulation(RateLimited(init_type="initial_state", y_start=0.5, rising=1.0, falling=-1.0),
                        use_cache=False).run(0.2, dt_out=0.05, **TOL)
    np.testing.assert_allclose(res["limiter.y"], 0.5 - res.t, rtol=0, atol=1e-9)  # falls at the limit -1/s
    with pytest.raises(fl.ParameterError, match=r"rising must be > 0"):
        RateLimiter(rising=0.0)
    with pytest.raises(fl.ParameterError, match=r"falling must be < 0"):
        RateLimiter(falling=0.5)
    with pytest.raises(fl.ParameterError, match=r"Td must be > 0"):
        RateLimiter(Td=0.0)


def test_inconsistent_limits_are_rejected():
    """Bad input: u_max < u_min for Limiter and DeadZone (MSL asserts the same)."""
    with pytest.raises(fl.ParameterError, match=r"u_max = -1 < u_min = 1"):
        Limiter(u_max=-1.0, u_min=1.0)
    with pytest.raises(fl.ParameterError, match=r"u_max = 0 < u_min = 0\.5"):
        DeadZone(u_max=0.0, u_min=0.5)


def test_lower_limits_default_to_minus_the_upper_as_msl():
    """MSL's ``uMin = -uMax``: a ``Limiter`` and a ``DeadZone`` built with ``u_max`` alone act symmetrically (a sine
    of amplitude 2 limited to ±0.8, a dead zone of ±0.5: closed forms, 1e-9); a run-time ``u_max`` alone is refused
    naming both limits, both together run."""

    class Blocks(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.sine = Sine(amplitude=2.0, f=1.0)
            self.limiter, self.dead_zone = Limiter(u_max=0.8), DeadZone(u_max=0.5)
            self.connect(self.sine.y, self.limiter.u, self.dead_zone.u)

    sim = fl.Simulation(Blocks(), use_cache=False)
    res = sim.run(1.0, dt_out=0.01, **TOL)
    u = 2.0 * np.sin(2 * np.pi * res.t)
    np.testing.assert_allclose(res["limiter.y"], np.clip(u, -0.8, 0.8), rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["dead_zone.y"], u - np.clip(u, -0.5, 0.5), rtol=0, atol=1e-9)
    with pytest.raises(fl.ParameterError, match=r"limiter: u_min was not given, so it is -u_max .* u_max = 1 and "
                                                r"u_min = -0\.8"):
        sim.run(1.0, params={"limiter.u_max": 1.0})
    res = sim.run(1.0, dt_out=0.01, params={"dead_zone.u_max": 1.0, "dead_zone.u_min": -1.0}, **TOL)
    np.testing.assert_allclose(res["dead_zone.y"], u - np.clip(u, -1.0, 1.0), rtol=0, atol=1e-9)


def test_hysteresis_switches_on_above_u_high_and_off_below_u_low():
    """A sine of amplitude 1 through a hysteresis of ±0.5: on where the sine rises through 0.5 (t = 1/12 + k),
    off where it falls through −0.5 (t = 7/12 + k); between, the value held whatever the sine does (so it is on at
    the sine's zero going down and off at its zero going up). Reference: the sine's crossings in closed form; the
    switchings are state events (1e-9 s)."""
    from flexlib.components.control import Hysteresis

    class Relay(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.sine = Sine(amplitude=1.0, f=1.0)
            self.relay = Hysteresis(u_low=-0.5, u_high=0.5)
            self.connect(self.sine.y, self.relay.u)

    res = fl.Simulation(Relay(), use_cache=False).run(2.5, dt_out=0.01, **TOL)
    on = np.array([1 / 12 + k for k in range(3)])
    off = np.array([7 / 12 + k for k in range(2)])
    times = np.array(sorted(t for t, _ in res.events))
    np.testing.assert_allclose(times, np.sort(np.r_[on, off]), rtol=0, atol=1e-9)
    phase = res.t % 1.0
    expected = np.where(res.t < 1 / 12, 0.0, ((phase >= 1 / 12) & (phase < 7 / 12)).astype(float))
    away = np.min(np.abs(res.t[:, None] - np.r_[on, off][None, :]), axis=1) > 1e-6
    np.testing.assert_array_equal(res["relay.y"][away], expected[away])
    with pytest.raises(fl.ParameterError, match=r"relay: u_high = 0\.1 must be > u_low = 0\.2"):
        fl.Simulation(Relay(), use_cache=False).run(1.0, params={"relay.u_low": 0.2, "relay.u_high": 0.1})


def test_hysteresis_thermostat_cycles_at_the_closed_form_instants():
    """A thermostat: a first-order plant ``τ x' = 2 y − x`` heated while the relay is on, the relay on below 0.8 and
    off above 1.2 (``u = −x``). From x = 0 it heats to 1.2 at ``τ ln 2.5``, cools to 0.8 after ``τ ln 1.5`` and
    cycles with the period ``2 τ ln 1.5``: the switchings are state events of the loop itself, held between by the
    relay's memory. Reference: the exponentials in closed form; 1e-6 s (each instant is the state's error at rtol
    1e-8 over the crossing slope, ~1e-8 s, accumulated over thirteen cycles of the loop: 2.2e-7 s measured)."""
    from flexlib.components.control import FirstOrder, Gain, Hysteresis

    tau = 0.5

    class Thermostat(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.plant = FirstOrder(k=2.0, T=tau)
            self.invert = Gain(k=-1.0)
            self.relay = Hysteresis(u_low=-1.2, u_high=-0.8)
            self.connect(self.relay.y, self.plant.u)
            self.connect(self.plant.y, self.invert.u)
            self.connect(self.invert.y, self.relay.u)

    res = fl.Simulation(Thermostat(), use_cache=False).run(3.0, dt_out=0.01, **TOL)
    first, half = tau * np.log(2.5), tau * np.log(1.5)
    expected = first + half * np.arange(20)
    times = np.array(sorted(t for t, _ in res.events))
    np.testing.assert_allclose(times, expected[expected < 3.0], rtol=0, atol=1e-6)
    assert res["plant.y"].max() == pytest.approx(1.2, abs=1e-7) and res["plant.y"][res.t > first].min() >= 0.8 - 1e-7
