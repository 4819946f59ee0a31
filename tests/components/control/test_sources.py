"""Tests of the signal sources (``Step``, ``Ramp``, ``Sine``, ``Constant``) against their formulas.

Reference: the defining equations of ``Modelica.Blocks.Sources`` (MSL 4.0). Block outputs are
algebraic unknowns of the DAE, which IDA interpolates between its steps, so they match their
formulas to the integration tolerance: 1e-7 absolute at rtol = 1e-8 (exactly, 1e-12, where
the signal is piecewise linear). Switching instants must be time events located exactly.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Ramp, Sine, Step
from flexlib.components.mechanics.translational import Force, Mass
from tests.components.control.signals import right_values

TOL = {"rtol": 1e-8, "atol": 1e-10}


class Sources(fl.Model):
    """All sources side by side (no states)."""

    def __init__(self) -> None:
        super().__init__()
        self.constant = Constant(k=-2.5)
        self.step = Step(height=2.0, offset=0.5, start_time=0.3)
        self.ramp = Ramp(height=3.0, duration=0.4, offset=-1.0, start_time=0.2)
        self.sine = Sine(amplitude=1.5, f=2.0, phase=0.3, offset=0.1, start_time=0.25)


@pytest.fixture(scope="module")
def sources() -> fl.Result:
    return fl.Simulation(Sources(), use_cache=False).run(1.0, dt_out=0.01, **TOL)


def test_events_at_switching_times(sources):
    """Step at 0.3, ramp corners at 0.2 and 0.6, sine start at 0.25: four exact time events."""
    times = sorted(t for t, _ in sources.events)
    assert times == pytest.approx([0.2, 0.25, 0.3, 0.6], abs=1e-14)


def test_constant(sources):
    """Constant: y = k."""
    np.testing.assert_allclose(sources["constant.y"], -2.5, rtol=0, atol=1e-12)


def test_step(sources):
    """Step: y = offset + (time < start_time ? 0 : height), left and right values at the event."""
    t, y = right_values(sources, "step.y")
    np.testing.assert_allclose(y, 0.5 + np.where(t >= 0.3, 2.0, 0.0), rtol=0, atol=1e-12)
    at = sources.t == 0.3
    assert sources["step.y"][at][0] == pytest.approx(0.5)  # left limit
    assert sources["step.y"][at][-1] == pytest.approx(2.5)  # right limit


def test_ramp(sources):
    """Ramp: offset, then linear rise by height over duration, then offset + height."""
    t, y = right_values(sources, "ramp.y")
    expected = -1.0 + 3.0 * np.clip((t - 0.2) / 0.4, 0.0, 1.0)
    np.testing.assert_allclose(y, expected, rtol=0, atol=1e-12)


def test_ramp_corners(sources):
    """At both corners the output is continuous and the slope changes at the event instant."""
    for t_corner, y_corner in ((0.2, -1.0), (0.6, 2.0)):
        at = np.isclose(sources.t, t_corner, rtol=0, atol=1e-14)
        assert at.sum() >= 2  # left and right values recorded at the event
        np.testing.assert_allclose(sources["ramp.y"][at], y_corner, rtol=0, atol=1e-12)
    eps = 1e-3
    for t_corner, slopes in ((0.2, [0.0, 7.5]), (0.6, [7.5, 0.0])):
        y = sources.value("ramp.y", [t_corner - eps, t_corner, t_corner + eps])
        np.testing.assert_allclose(np.diff(y) / eps, slopes, rtol=0, atol=1e-8)


def test_sine(sources):
    """Sine: y = offset + (time < start_time ? 0 : amplitude sin(2π f (time − start_time) + phase))."""
    t, y = right_values(sources, "sine.y")
    wave = 1.5 * np.sin(2 * np.pi * 2.0 * (t - 0.25) + 0.3)
    np.testing.assert_allclose(y, 0.1 + np.where(t >= 0.25, wave, 0.0), rtol=0, atol=1e-7)


class RampPush(fl.Model):
    """A ramp force on a free mass: the kinks of the input must be hit by events."""

    def __init__(self) -> None:
        super().__init__()
        self.ramp = Ramp(height=3.0, duration=0.4, start_time=0.2)
        self.force = Force()
        self.mass = Mass(m=1.5, init={"s": 0.0, "v": 0.0})
        self.connect(self.ramp.y, self.force.f)
        self.connect(self.force.flange, self.mass.flange_a)


def test_ramp_force_integrated_exactly():
    """Free mass pushed by a ramp force.

    Reference: integrating F/m twice gives a piecewise polynomial (cubic during the ramp,
    quadratic after it); tolerance 1e-8 relative to the final position.
    """
    h, T, t0, m = 3.0, 0.4, 0.2, 1.5
    res = fl.Simulation(RampPush(), use_cache=False).run(1.0, dt_out=0.05, **TOL)
    t = np.linspace(0.0, 1.0, 21)
    u = np.clip(t - t0, 0.0, T)
    after = np.clip(t - t0 - T, 0.0, None)
    v = (h / T * u**2 / 2 + h * after) / m
    s = (h / T * u**3 / 6 + (h / T * T**2 / 2) * after + h * after**2 / 2) / m
    np.testing.assert_allclose(res.value("mass.v", t), v, rtol=0, atol=1e-8 * v[-1])
    np.testing.assert_allclose(res.value("mass.s", t), s, rtol=0, atol=1e-8 * s[-1])


def test_negative_ramp_duration_is_rejected():
    """Bad input: a negative ramp duration (MSL ``duration(min=0)``); the message names the path."""
    with pytest.raises(fl.ParameterError, match=r"duration"):
        Ramp(duration=-1.0)
    sim = fl.Simulation(Sources(), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"ramp\.duration"):
        sim.run(1.0, params={"ramp.duration": -0.4})


class TwiceIntegrated(fl.Model):
    """A ``KinematicPTP`` integrated twice: speed ``qd`` and position ``q``."""

    def __init__(self, **ptp: float) -> None:
        super().__init__()
        from flexlib.components.control import Integrator, KinematicPTP

        self.ptp, self.qd, self.q = KinematicPTP(**ptp), Integrator(), Integrator()
        self.connect(self.ptp.y, self.qd.u)
        self.connect(self.qd.y, self.q.u)


@pytest.mark.parametrize(("delta_q", "qd_max", "t_e"), [(1.0, 1.0, 2.0), (-1.0, 0.5, 2.5)],
                         ids=["triangle", "trapezoid with cruise"])
def test_kinematic_ptp_moves_the_distance_as_fast_as_the_limits_allow(delta_q, qd_max, t_e):
    """Position and speed of the fastest move (qdd_max = 1, from t0 = 0.5 s): closed forms of the triangular
    (1 m at 1 m/s: T_e = 2 s) and trapezoidal (−1 m at 0.5 m/s: T_e = 2.5 s) profiles, 1e-9; the switching instants
    are time events, so the run steps on them."""
    t0, a = 0.5, 1.0
    res = fl.Simulation(TwiceIntegrated(delta_q=delta_q, qd_max=qd_max, qdd_max=a, start_time=t0),
                        use_cache=False).run(4.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    s = np.sign(delta_q)
    v_peak = min(qd_max, np.sqrt(a * abs(delta_q)))
    t_a = v_peak / a
    tau = np.clip(res.t - t0, 0.0, t_e)
    speed = np.minimum.reduce([a * tau, np.full_like(tau, v_peak), a * (t_e - tau)])
    # position: the integral of the speed profile
    up = np.minimum(tau, t_a)
    cruise = np.clip(tau - t_a, 0.0, t_e - 2 * t_a)
    down = np.clip(tau - (t_e - t_a), 0.0, t_a)
    position = 0.5 * a * up**2 + v_peak * cruise + v_peak * down - 0.5 * a * down**2
    np.testing.assert_allclose(res["qd.y"], s * speed, rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["q.y"], s * position, rtol=0, atol=1e-9)
    assert res["q.y"][-1] == pytest.approx(delta_q, abs=1e-9)
    assert any(abs(t - (t0 + t_e)) < 1e-12 for t, _ in res.events)
