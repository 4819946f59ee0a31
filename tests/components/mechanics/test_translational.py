"""Tests of ``flexlib.components.mechanics.translational`` against analytic solutions.

Every test runs at rtol = 1e-8, atol = 1e-10; the reference and the tolerance are given in
each docstring.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Sine, Step
from flexlib.components.mechanics.translational import (
    Damper,
    Fixed,
    Force,
    ForceSensor,
    Mass,
    Position,
    PositionSensor,
    RelativePositionSensor,
    Speed,
    SpeedSensor,
    Spring,
    SpringDamper,
)

TOL = {"rtol": 1e-8, "atol": 1e-10}


def simulate(model: fl.Model, t_end: float, dt_out: float = 0.01, **kw) -> tuple[fl.Simulation, fl.Result]:
    sim = fl.Simulation(model, use_cache=False)
    return sim, sim.run(t_end, dt_out=dt_out, **TOL, **kw)


class MassSpringDamper(fl.Model):
    """Mass on a spring and a damper in parallel to the housing, released from s = s_start."""

    def __init__(self, m: float, c: float, d: float, s_start: float) -> None:
        super().__init__()
        self.fixed = Fixed()
        self.spring = Spring(c=c)
        self.damper = Damper(d=d)
        self.mass = Mass(m=m, init={"s": s_start, "v": 0.0})
        self.connect(self.fixed.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.mass.flange_a, self.spring.flange_b, self.damper.flange_b)


def damped_free_response(t: np.ndarray, m: float, c: float, d: float, x0: float) -> np.ndarray:
    """Under-damped free response from rest (Meirovitch, *Elements of Vibration Analysis*, §2.3)."""
    wn = np.sqrt(c / m)
    zeta = d / (2 * np.sqrt(c * m))
    wd = wn * np.sqrt(1 - zeta**2)
    return x0 * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))


def test_mass_spring_damper_free_response():
    """Mass–spring–damper released from rest.

    Reference: analytic under-damped oscillator x(t) = x0 e^(-ζωn t)(cos ωd t + ζωn/ωd sin ωd t);
    tolerance: error ≤ 1e-6 of the initial amplitude x0 at rtol 1e-8, atol 1e-10.
    """
    m, c, d, x0 = 1.5, 250.0, 3.0, 0.05
    _, res = simulate(MassSpringDamper(m, c, d, x0), 3.0)
    np.testing.assert_allclose(res["mass.s"], damped_free_response(res.t, m, c, d, x0), rtol=0, atol=1e-6 * x0)
    np.testing.assert_allclose(res["spring.f"] + res["damper.f"], -m * res["mass.a"], rtol=0, atol=1e-6 * c * x0)


class SpringDamperOnMass(fl.Model):
    """The same oscillator built with the combined SpringDamper."""

    def __init__(self, m: float, c: float, d: float, s_start: float) -> None:
        super().__init__()
        self.fixed = Fixed()
        self.spring_damper = SpringDamper(c=c, d=d)
        self.mass = Mass(m=m, init={"s": s_start, "v": 0.0})
        self.connect(self.fixed.flange, self.spring_damper.flange_a)
        self.connect(self.spring_damper.flange_b, self.mass.flange_a)


def test_spring_damper_matches_analytic():
    """SpringDamper = Spring ∥ Damper.

    Reference: the analytic damped oscillator of ``test_mass_spring_damper_free_response``;
    tolerance 1e-6 of x0.
    """
    m, c, d, x0 = 1.5, 250.0, 3.0, 0.05
    _, res = simulate(SpringDamperOnMass(m, c, d, x0), 3.0)
    np.testing.assert_allclose(res["mass.s"], damped_free_response(res.t, m, c, d, x0), rtol=0, atol=1e-6 * x0)
    # algebraic variables satisfy their equations to the integrator tolerance
    np.testing.assert_allclose(res["spring_damper.f"], res["spring_damper.f_c"] + res["spring_damper.f_d"],
                               rtol=0, atol=1e-7 * c * x0)


class SineShaker(fl.Model):
    """A mass moved by a Position source that follows a sine; a ForceSensor measures the drive."""

    def __init__(self, m: float, amplitude: float, f: float) -> None:
        super().__init__()
        self.sine = Sine(amplitude=amplitude, f=f)
        self.position = Position()
        self.force_sensor = ForceSensor()
        self.mass = Mass(m=m)
        self.connect(self.sine.y, self.position.s_ref)
        self.connect(self.position.flange, self.force_sensor.flange_a)
        self.connect(self.force_sensor.flange_b, self.mass.flange_a)


def test_position_source_differentiates_sine_twice():
    """Position source fed by a sine: the sine is differentiated twice (index 3).

    Reference: m·s'' with s = A sin(ωt), so the force on the mass is m(−Aω² sin ωt);
    tolerance 1e-6 relative to m A ω².
    """
    m, A, f = 3.0, 0.1, 2.0
    sim, res = simulate(SineShaker(m, A, f), 1.0)
    assert sim.report.index == 3
    times = {owner: n for owner, _, n in sim.report.differentiated}
    assert times.get("sine") == 2
    assert sim.states == []  # the motion is prescribed
    omega = 2 * np.pi * f
    scale = m * A * omega**2
    expected = m * (-A * omega**2 * np.sin(omega * res.t))
    np.testing.assert_allclose(res["mass.flange_a.f"], expected, rtol=0, atol=1e-6 * scale)
    np.testing.assert_allclose(res["force_sensor.f"], expected, rtol=0, atol=1e-6 * scale)
    np.testing.assert_allclose(res["mass.v"], A * omega * np.cos(omega * res.t), rtol=0, atol=1e-9 * A * omega)


class SineSpeed(fl.Model):
    """A mass moved by a Speed source that follows a sine."""

    def __init__(self, m: float, amplitude: float, f: float) -> None:
        super().__init__()
        self.sine = Sine(amplitude=amplitude, f=f)
        self.speed = Speed(init={"s": 0.0})
        self.mass = Mass(m=m)
        self.connect(self.sine.y, self.speed.v_ref)
        self.connect(self.speed.flange, self.mass.flange_a)


def test_speed_source():
    """Speed source: v = A sin(ωt), so s = A/ω (1 − cos ωt) and the force is m A ω cos(ωt).

    Reference: integral and derivative of the reference; tolerance 1e-7 relative to A/ω and
    to m A ω.
    """
    m, A, f = 2.0, 0.3, 1.5
    _, res = simulate(SineSpeed(m, A, f), 1.0)
    omega = 2 * np.pi * f
    np.testing.assert_allclose(res["mass.s"], A / omega * (1 - np.cos(omega * res.t)), rtol=0, atol=1e-7 * A / omega)
    np.testing.assert_allclose(res["mass.flange_a.f"], m * A * omega * np.cos(omega * res.t), rtol=0,
                               atol=1e-7 * m * A * omega)


class StepPush(fl.Model):
    """A step force on a free mass, with position/speed/relative-position sensors."""

    def __init__(self, m: float, F: float, t_step: float) -> None:
        super().__init__()
        self.step = Step(height=F, start_time=t_step)
        self.force = Force(use_support=True)
        self.fixed = Fixed(s0=0.0)
        self.mass = Mass(m=m, L=0.2, init={"s": 0.0, "v": 0.0})
        self.position_sensor = PositionSensor()
        self.speed_sensor = SpeedSensor()
        self.relative = RelativePositionSensor()
        self.connect(self.step.y, self.force.f)
        self.connect(self.fixed.flange, self.force.support, self.relative.flange_a)
        self.connect(self.force.flange, self.mass.flange_a, self.position_sensor.flange, self.speed_sensor.flange)
        self.connect(self.mass.flange_b, self.relative.flange_b)


def test_step_force_on_free_mass():
    """A force step at t_step accelerates a free mass: v = F/m (t − t_step)⁺.

    Reference: Newton's second law; the step is a time event hit exactly (listed in
    ``res.events`` at t_step). Tolerance 1e-8 relative to the final value.
    """
    m, F, t_step = 2.0, 4.0, 0.37
    _, res = simulate(StepPush(m, F, t_step), 1.0, dt_out=0.1)
    assert [t for t, _ in res.events] == [t_step]
    tt = np.clip(res.t - t_step, 0.0, None)
    v, s = F / m * tt, 0.5 * F / m * tt**2
    np.testing.assert_allclose(res["mass.v"], v, rtol=0, atol=1e-8 * v[-1])
    np.testing.assert_allclose(res["speed_sensor.v"], v, rtol=0, atol=1e-8 * v[-1])
    np.testing.assert_allclose(res["position_sensor.s"], s - 0.1, rtol=0, atol=1e-8 * s[-1])
    np.testing.assert_allclose(res["relative.s_rel"], s + 0.1, rtol=0, atol=1e-8 * s[-1])
    # actio = reactio: the housing takes -F through the support flange
    np.testing.assert_allclose(res["fixed.flange.f"], -res["mass.flange_a.f"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(res["mass.flange_a.f"], res["step.y"], rtol=0, atol=1e-12)


class SpringWithOffsets(fl.Model):
    """A constant force stretches a spring with offsets; the mass has a length L."""

    def __init__(self, m: float, c: float, d: float, F: float, s0: float, s_rel0: float, L: float) -> None:
        super().__init__()
        self.fixed = Fixed(s0=s0)
        self.spring = Spring(c=c, s_rel0=s_rel0)
        self.damper = Damper(d=d)
        self.mass = Mass(m=m, L=L)
        self.load = Constant(k=F)
        self.force = Force()
        self.connect(self.fixed.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.mass.flange_a)
        self.connect(self.load.y, self.force.f)
        self.connect(self.force.flange, self.mass.flange_b)


def test_static_equilibrium_with_offsets():
    """Steady-state initialisation: s = s0 + s_rel0 + F/c + L/2 and it stays there.

    Reference: static force balance c (s_rel − s_rel0) = F; tolerance 1e-9 absolute [m].
    """
    m, c, d, F, s0, s_rel0, L = 1.0, 400.0, 5.0, 20.0, 1.0, 0.5, 0.2
    _, res = simulate(SpringWithOffsets(m, c, d, F, s0, s_rel0, L), 0.5, dt_out=0.1, steady_state=True)
    np.testing.assert_allclose(res["mass.s"], s0 + s_rel0 + F / c + L / 2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["spring.f"], F, rtol=1e-9)


def test_negative_mass_is_rejected():
    """Bad input: m < 0 violates ``min=0`` (MSL ``m(min=0)``); the message names the path."""
    with pytest.raises(fl.ParameterError, match=r"m = -2"):
        Mass(m=-2.0)
    sim = fl.Simulation(MassSpringDamper(1.0, 1.0, 0.1, 0.1), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"mass\.m"):
        sim.run(1.0, params={"mass.m": -2.0})
    with pytest.raises(fl.ParameterError, match=r"damper\.d"):
        sim.run(1.0, params={"damper.d": -0.1})


def test_constant_force_accelerates_a_mass_and_loads_its_support():
    """``ConstantForce`` on a mass m from rest: ``v = F t / m``, ``s = F t²/(2 m)`` (analytic, 1e-9); with
    ``use_support`` on a ``Fixed`` the housing takes the same reaction as under a ``Force`` source fed by a
    ``Constant`` of the same value (1e-12)."""
    from flexlib.components.mechanics.translational import ConstantForce, Fixed, Force, Mass

    F, m = 40.0, 8.0

    class Driven(fl.Model):
        def __init__(self, constant: bool) -> None:
            super().__init__()
            if constant:
                self.source = ConstantForce(f_constant=F, use_support=True)
            else:
                self.source, self.value = Force(use_support=True), Constant(k=F)
                self.connect(self.value.y, self.source.f)
            self.housing = Fixed()
            self.mass = Mass(m=m, init={"s": 0.0, "v": 0.0})
            self.connect(self.source.flange, self.mass.flange_a)
            self.connect(self.source.support, self.housing.flange)

    _, res = simulate(Driven(True), 1.0)
    _, ref = simulate(Driven(False), 1.0)
    np.testing.assert_allclose(res["mass.v"], F * res.t / m, rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["mass.s"], F * res.t**2 / (2 * m), rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["housing.flange.f"], ref["housing.flange.f"], rtol=0, atol=1e-12)
    assert abs(res["housing.flange.f"][0]) == pytest.approx(F, rel=1e-12)
