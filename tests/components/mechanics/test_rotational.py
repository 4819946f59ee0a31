"""Tests of ``flexlib.components.mechanics.rotational`` against analytic solutions.

Every test runs at rtol = 1e-8, atol = 1e-10 unless stated; the reference and the
tolerance are given in each docstring.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Ramp, Sine
from flexlib.components.mechanics.rotational import (
    AngleSensor,
    Damper,
    ElastoBacklash2,
    Fixed,
    IdealGear,
    IdealPlanetary,
    Inertia,
    Position,
    QuadraticSpeedDependentTorque,
    RelativeAngleSensor,
    Speed,
    SpeedSensor,
    Spring,
    SpringDamper,
    Torque,
    TorqueSensor,
    TorqueStep,
)

TOL = {"rtol": 1e-8, "atol": 1e-10}


def simulate(model: fl.Model, t_end: float, dt_out: float = 0.01) -> tuple[fl.Simulation, fl.Result]:
    sim = fl.Simulation(model, use_cache=False)
    return sim, sim.run(t_end, dt_out=dt_out, **TOL)


class RigidPair(fl.Model):
    """Constant torque on two inertias connected flange to flange (index 2)."""

    def __init__(self, tau: float = 3.0, J1: float = 1.0, J2: float = 2.0) -> None:
        super().__init__()
        self.const = Constant(k=tau)
        self.torque = Torque()
        self.inertia1 = Inertia(J=J1, init={"phi": 0.0, "w": 0.0})
        self.inertia2 = Inertia(J=J2)
        self.connect(self.const.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia1.flange_a)
        self.connect(self.inertia1.flange_b, self.inertia2.flange_a)


def test_rigidly_connected_inertias_index2():
    """Two rigidly connected inertias under a constant torque (index 2).

    Reference: Newton's second law for the combined body, w = tau t/(J1 + J2) and
    phi = tau t²/(2 (J1 + J2)); tolerance 1e-8 relative to the final value. The states are
    chosen by the dummy-derivative method, not by the model.
    """
    tau, J1, J2 = 3.0, 1.0, 2.0
    sim, res = simulate(RigidPair(tau, J1, J2), 2.0, dt_out=0.1)
    assert sim.report.index >= 2
    assert sim.report.differentiated
    assert len(sim.states) == 2
    assert set(sim.states) <= {"inertia1.phi", "inertia1.w", "inertia2.phi", "inertia2.w"}
    assert sim.report.dummy_derivatives
    t = res.t
    w_ref = tau * t / (J1 + J2)
    for name in ("inertia1.w", "inertia2.w"):
        np.testing.assert_allclose(res[name], w_ref, rtol=0, atol=1e-8 * w_ref[-1])
    np.testing.assert_allclose(res["inertia2.phi"], 0.5 * tau * t**2 / (J1 + J2), rtol=0, atol=1e-8 * 3.0)
    # the connection torque accelerates inertia2 alone
    np.testing.assert_allclose(res["inertia2.flange_a.tau"], J2 * tau / (J1 + J2), rtol=1e-8)


class InertiaOnSpring(fl.Model):
    """One inertia on a spring to the housing, released from phi = phi_start."""

    def __init__(self, J: float, c: float, phi0: float, phi_rel0: float, phi_start: float) -> None:
        super().__init__()
        self.fixed = Fixed(phi0=phi0)
        self.spring = Spring(c=c, phi_rel0=phi_rel0)
        self.inertia = Inertia(J=J, init={"phi": phi_start, "w": 0.0})
        self.connect(self.fixed.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.inertia.flange_a)


def test_spring_inertia_oscillation():
    """Inertia on a spring with offsets ``phi0``/``phi_rel0`` oscillates about their sum.

    Reference: undamped oscillator, phi(t) = phi_eq + (phi_start - phi_eq) cos(sqrt(c/J) t) with
    phi_eq = phi0 + phi_rel0; tolerance 1e-6 of the amplitude.
    """
    J, c, phi0, phi_rel0, phi_start = 0.5, 200.0, 0.3, -0.1, 0.5
    _, res = simulate(InertiaOnSpring(J, c, phi0, phi_rel0, phi_start), 1.0)
    phi_eq, amp = phi0 + phi_rel0, phi_start - (phi0 + phi_rel0)
    expected = phi_eq + amp * np.cos(np.sqrt(c / J) * res.t)
    np.testing.assert_allclose(res["inertia.phi"], expected, rtol=0, atol=1e-6 * amp)
    # algebraic variables satisfy their equations to the integrator tolerance
    np.testing.assert_allclose(res["spring.tau"], c * (res["inertia.phi"] - phi_eq), rtol=0, atol=1e-7 * c * amp)


class TwoInertiasCoupled(fl.Model):
    """Two free inertias coupled by a spring, released at rest with a twist ``phi_rel``."""

    def __init__(self, J1: float, J2: float, c: float, twist: float) -> None:
        super().__init__()
        self.inertia1 = Inertia(J=J1, init={"phi": 0.0, "w": 0.0})
        self.spring = Spring(c=c, init={"phi_rel": twist})
        self.inertia2 = Inertia(J=J2, init={"w": 0.0})
        self.connect(self.inertia1.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.inertia2.flange_a)


def test_two_inertia_natural_frequency():
    """Free–free two-inertia oscillator.

    Reference: omega = sqrt(c (J1 + J2)/(J1 J2)) (e.g. Den Hartog, *Mechanical Vibrations*,
    §4.1), so phi_rel(t) = twist cos(omega t); angular momentum J1 w1 + J2 w2 = 0 is
    conserved. Tolerance 1e-6 of the twist (1e-6 of J1·|w1|max for the momentum).
    """
    J1, J2, c, twist = 1.0, 3.0, 100.0, 0.1
    _, res = simulate(TwoInertiasCoupled(J1, J2, c, twist), 1.0, dt_out=0.005)
    omega = np.sqrt(c * (J1 + J2) / (J1 * J2))
    np.testing.assert_allclose(res["spring.phi_rel"], twist * np.cos(omega * res.t), rtol=0, atol=1e-6 * twist)
    momentum = J1 * res["inertia1.w"] + J2 * res["inertia2.w"]
    np.testing.assert_allclose(momentum, 0.0, atol=1e-6 * J1 * np.max(np.abs(res["inertia1.w"])))


class FreeSpringDamper(fl.Model):
    """Two free inertias coupled by a SpringDamper, released at rest with a twist."""

    def __init__(self, J1: float, J2: float, c: float, d: float, twist: float) -> None:
        super().__init__()
        self.inertia1 = Inertia(J=J1, init={"phi": 0.0, "w": 0.0})
        self.coupling = SpringDamper(c=c, d=d, init={"phi_rel": twist, "w_rel": 0.0})
        self.inertia2 = Inertia(J=J2)
        self.connect(self.inertia1.flange_b, self.coupling.flange_a)
        self.connect(self.coupling.flange_b, self.inertia2.flange_a)


def test_spring_damper_two_inertias():
    """SpringDamper between free inertias: damped oscillator in the reduced inertia.

    Reference: J_red phi_rel'' + d phi_rel' + c phi_rel = 0 with J_red = J1 J2/(J1 + J2),
    from rest: phi_rel = twist e^(-ζωn t)(cos ωd t + ζωn/ωd sin ωd t). Tolerance 1e-6 of twist.
    """
    J1, J2, c, d, twist = 1.0, 3.0, 100.0, 1.5, 0.1
    _, res = simulate(FreeSpringDamper(J1, J2, c, d, twist), 1.0, dt_out=0.005)
    J_red = J1 * J2 / (J1 + J2)
    wn, zeta = np.sqrt(c / J_red), d / (2 * np.sqrt(c * J_red))
    wd = wn * np.sqrt(1 - zeta**2)
    t = res.t
    expected = twist * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))
    np.testing.assert_allclose(res["coupling.phi_rel"], expected, rtol=0, atol=1e-6 * twist)


class DampedInertia(fl.Model):
    """Inertia spinning down on a damper to the housing; speed measured by a SpeedSensor."""

    def __init__(self, J: float, d: float, w_start: float) -> None:
        super().__init__()
        self.fixed = Fixed()
        self.damper = Damper(d=d)
        self.inertia = Inertia(J=J, init={"phi": 0.0, "w": w_start})
        self.speed_sensor = SpeedSensor()
        self.angle_sensor = AngleSensor()
        self.connect(self.fixed.flange, self.damper.flange_a)
        self.connect(self.damper.flange_b, self.inertia.flange_a, self.speed_sensor.flange)
        self.connect(self.inertia.flange_b, self.angle_sensor.flange)


def test_damper_spin_down_and_sensors():
    """Inertia on a viscous damper: w(t) = w0 exp(-d t/J), phi(t) = w0 J/d (1 - exp(-d t/J)).

    Reference: first-order linear ODE J w' = -d w; tolerance 1e-7 relative to w0 (and to
    the final angle). The sensors read the same values without loading the shaft.
    """
    J, d, w0 = 2.0, 3.0, 5.0
    _, res = simulate(DampedInertia(J, d, w0), 2.0)
    decay = np.exp(-d * res.t / J)
    np.testing.assert_allclose(res["inertia.w"], w0 * decay, rtol=0, atol=1e-7 * w0)
    np.testing.assert_allclose(res["speed_sensor.w"], w0 * decay, rtol=0, atol=1e-7 * w0)
    phi = w0 * J / d * (1 - decay)
    np.testing.assert_allclose(res["angle_sensor.phi"], phi, rtol=0, atol=1e-7 * phi[-1])
    np.testing.assert_allclose(res["damper.tau"], d * res["inertia.w"], rtol=0, atol=1e-7 * d * w0)


class GearTrain(fl.Model):
    """Constant torque → inertia1 → ideal gear (housing fixed) → torque sensor → inertia2."""

    def __init__(self, tau: float, J1: float, J2: float, ratio: float, use_support: bool) -> None:
        super().__init__()
        self.const = Constant(k=tau)
        self.torque = Torque(use_support=use_support)
        self.inertia1 = Inertia(J=J1, init={"phi": 0.0, "w": 0.0})
        self.gear = IdealGear(ratio=ratio, use_support=use_support)
        self.torque_sensor = TorqueSensor()
        self.inertia2 = Inertia(J=J2)
        self.relative_angle = RelativeAngleSensor()
        self.connect(self.const.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia1.flange_a, self.relative_angle.flange_a)
        self.connect(self.inertia1.flange_b, self.gear.flange_a)
        self.connect(self.gear.flange_b, self.torque_sensor.flange_a)
        self.connect(self.torque_sensor.flange_b, self.inertia2.flange_a, self.relative_angle.flange_b)
        if use_support:
            self.fixed = Fixed()
            self.connect(self.fixed.flange, self.torque.support, self.gear.support)


@pytest.mark.parametrize("use_support", [True, False])
def test_ideal_gear_kinematics_and_torques(use_support):
    """Ideal gear: w_b = w_a/ratio, flange_b.tau = -ratio·flange_a.tau.

    Reference: rigid reduction to the motor shaft, J_eff = J1 + J2/ratio², so
    w1 = tau t/J_eff; the torque sensor reads J2·a2 = J2·tau/(J_eff·ratio); the housing
    reacts -(flange_a.tau + flange_b.tau). Tolerance 1e-8 relative.
    """
    tau, J1, J2, ratio = 2.0, 0.5, 4.0, 4.0
    sim, res = simulate(GearTrain(tau, J1, J2, ratio, use_support), 1.0, dt_out=0.1)
    assert sim.report.index >= 2  # the gear makes the two inertias rigidly coupled
    J_eff = J1 + J2 / ratio**2
    t = res.t
    np.testing.assert_allclose(res["inertia1.w"], tau * t / J_eff, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(res["inertia2.w"], res["inertia1.w"] / ratio, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(res["gear.flange_b.tau"], -ratio * res["gear.flange_a.tau"], rtol=1e-10)
    np.testing.assert_allclose(res["torque_sensor.tau"], J2 * tau / (J_eff * ratio), rtol=1e-8)
    if use_support:
        np.testing.assert_allclose(res["gear.support.tau"], -(res["gear.flange_a.tau"] + res["gear.flange_b.tau"]),
                                   rtol=1e-10, atol=1e-12)
        # the housing takes the motor reaction and the gear reaction
        np.testing.assert_allclose(res["fixed.flange.tau"], -(res["gear.support.tau"] + res["torque.support.tau"]),
                                   rtol=1e-10, atol=1e-12)
    phi1 = 0.5 * tau * t**2 / J_eff
    np.testing.assert_allclose(res["relative_angle.phi_rel"], phi1 / ratio - phi1, rtol=0, atol=1e-8 * phi1[-1])


class PositionDriven(fl.Model):
    """Inertia whose angle follows a sine through a Position source (index 3)."""

    def __init__(self, J: float, amplitude: float, f: float) -> None:
        super().__init__()
        self.sine = Sine(amplitude=amplitude, f=f)
        self.position = Position(use_support=True)
        self.fixed = Fixed()
        self.inertia = Inertia(J=J)
        self.connect(self.sine.y, self.position.phi_ref)
        self.connect(self.fixed.flange, self.position.support)
        self.connect(self.position.flange, self.inertia.flange_a)


def test_position_source_drives_inertia():
    """Position source: the torque needed is J·phi_ref'' = -J A omega² sin(omega t).

    Reference: second derivative of the sine reference; the support takes the reaction.
    Tolerance 1e-6 of J A omega².
    """
    J, A, f = 0.2, 0.5, 3.0
    sim, res = simulate(PositionDriven(J, A, f), 1.0)
    assert sim.report.index == 3
    omega = 2 * np.pi * f
    scale = J * A * omega**2
    np.testing.assert_allclose(res["inertia.flange_a.tau"], -scale * np.sin(omega * res.t), rtol=0, atol=1e-6 * scale)
    np.testing.assert_allclose(res["position.support.tau"], res["inertia.flange_a.tau"], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(res["inertia.phi"], A * np.sin(omega * res.t), rtol=0, atol=1e-9)


class SpeedDriven(fl.Model):
    """Inertia whose speed follows a ramp through a Speed source."""

    def __init__(self, J: float, height: float, duration: float, start_time: float) -> None:
        super().__init__()
        self.ramp = Ramp(height=height, duration=duration, start_time=start_time)
        self.speed = Speed(init={"phi": 0.0})
        self.inertia = Inertia(J=J)
        self.connect(self.ramp.y, self.speed.w_ref)
        self.connect(self.speed.flange, self.inertia.flange_a)


def test_speed_source_ramp():
    """Speed source fed by a ramp: torque J·h/T during the ramp, 0 outside.

    Reference: w = ramp, phi = integral of the ramp (piecewise quadratic); both ramp corners
    are events. Tolerance 1e-8 relative (torque) and 1e-7 of the final angle.
    """
    J, h, T, t0 = 2.0, 3.0, 0.4, 0.2
    _, res = simulate(SpeedDriven(J, h, T, t0), 1.0, dt_out=0.05)
    times = [t for t, _ in res.events]
    assert times == pytest.approx([t0, t0 + T], abs=1e-12)
    t = np.array([0.1, 0.3, 0.5, 0.7, 0.9])
    tau = res.value("inertia.flange_a.tau", t)
    np.testing.assert_allclose(tau, [0.0, J * h / T, J * h / T, 0.0, 0.0], rtol=1e-8, atol=1e-8)
    tau_phi = np.clip(t - t0, 0, T)
    phi = h / T * tau_phi**2 / 2 + h * np.clip(t - t0 - T, 0, None)
    np.testing.assert_allclose(res.value("inertia.phi", t), phi, rtol=0, atol=1e-7 * phi[-1])


def test_negative_inertia_is_rejected():
    """Bad input: J < 0 violates ``min=0`` (MSL ``J(min=0)``); the message names the path."""
    with pytest.raises(fl.ParameterError, match=r"J = -1"):
        Inertia(J=-1.0)
    sim = fl.Simulation(RigidPair(), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"inertia1\.J"):
        sim.run(1.0, params={"inertia1.J": -1.0})


def test_missing_spring_constant_names_instance():
    """Bad input: a required parameter without a value is reported with its instance path."""

    class Unset(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.fixed = Fixed()
            self.spring = Spring()
            self.inertia = Inertia(J=1.0, init={"phi": 0.0, "w": 0.0})
            self.connect(self.fixed.flange, self.spring.flange_a)
            self.connect(self.spring.flange_b, self.inertia.flange_a)

    with pytest.raises(fl.ModelError, match=r"spring\.c"):
        fl.Simulation(Unset(), use_cache=False)


def test_constant_torque_accelerates_an_inertia_and_loads_its_support():
    """``ConstantTorque`` on an inertia J from rest: ``w = τ t / J``, ``φ = τ t²/(2 J)`` (analytic, 1e-9); with
    ``use_support`` on a ``Fixed`` the housing takes the same reaction as under a ``Torque`` source fed by a
    ``Constant`` of the same value (1e-12)."""
    from flexlib.components.mechanics.rotational import ConstantTorque

    tau, J = -2.5, 0.5

    class Driven(fl.Model):
        def __init__(self, constant: bool) -> None:
            super().__init__()
            if constant:
                self.source = ConstantTorque(tau_constant=tau, use_support=True)
            else:
                self.source, self.value = Torque(use_support=True), Constant(k=tau)
                self.connect(self.value.y, self.source.tau)
            self.housing = Fixed()
            self.inertia = Inertia(J=J, init={"phi": 0.0, "w": 0.0})
            self.connect(self.source.flange, self.inertia.flange_a)
            self.connect(self.source.support, self.housing.flange)

    _, res = simulate(Driven(True), 1.0)
    _, ref = simulate(Driven(False), 1.0)
    np.testing.assert_allclose(res["inertia.w"], tau * res.t / J, rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["inertia.phi"], tau * res.t**2 / (2 * J), rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["source.tau"], tau, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res["housing.flange.tau"], ref["housing.flange.tau"], rtol=0, atol=1e-12)
    assert abs(res["housing.flange.tau"][0]) == pytest.approx(abs(tau), rel=1e-12)


def test_torque_step_accelerates_from_its_start_time():
    """``TorqueStep``: 4 N m from 1 s (0.5 N m before) on 2 kg m²: ``w = 0.25 t`` until 1 s, then
    ``0.25 + 2 (t − 1)`` (1e-9)."""

    class Stepped(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.step = TorqueStep(step_torque=3.5, offset_torque=0.5, start_time=1.0)
            self.disc = Inertia(J=2.0, init={"phi": 0.0, "w": 0.0})
            self.connect(self.step.flange, self.disc.flange_a)

    _, res = simulate(Stepped(), 2.0, 0.125)
    t = res.t
    np.testing.assert_allclose(res["disc.w"], np.where(t < 1.0, 0.25 * t, 0.25 + 2.0 * (t - 1.0)), atol=1e-9)


@pytest.mark.parametrize("direction", [True, False])
def test_quadratic_speed_dependent_torque_brakes_as_closed_form(direction):
    """A load ``tau = −20 N m (w / 10 rad/s)²`` on 1 kg m² spinning at ±5 rad/s: ``w = w0 / (1 + c |w0| t)`` with
    ``c = 0.2`` (rtol 1e-7). With ``torque_direction=True`` the torque keeps its sign: it speeds a backward spin
    up, ``w = w0 / (1 − c w0 t)`` for ``w0 < 0`` until 0.5 s (checked to 0.5 s)."""

    class Fan(fl.Model):
        def __init__(self, w0: float) -> None:
            super().__init__()
            self.load = QuadraticSpeedDependentTorque(tau_nominal=-20.0, w_nominal=10.0, torque_direction=direction)
            self.disc = Inertia(J=1.0, init={"phi": 0.0, "w": w0})
            self.connect(self.load.flange, self.disc.flange_a)

    for w0 in (5.0, -5.0):
        _, res = simulate(Fan(w0), 0.5, 0.05)
        t = res.t[res.t < 0.45]
        if direction and w0 < 0:
            expected = w0 / (1.0 + 0.2 * w0 * t)
        else:
            expected = w0 / (1.0 + 0.2 * abs(w0) * t)
        np.testing.assert_allclose(res["disc.w"][res.t < 0.45], expected, rtol=1e-7)


def test_ideal_planetary_kinematics_and_torques():
    """``IdealPlanetary`` (ring/sun 2): carrier held, sun driven at 3 rad/s → ring at −1.5 rad/s (Willis:
    ``(1 + r) w_c = w_s + r w_r``); a 1 N m load on the ring takes ``ring.tau = r sun.tau`` = −1 N m, so the sun's
    flange torque is −0.5 N m and the carrier's ``−(1 + r) sun.tau`` = +1.5 N m (1e-9)."""

    class Gearset(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.gear = IdealPlanetary(ratio=2.0)
            self.drive = Speed(init={"phi": 0.0})
            self.w = Constant(k=3.0)
            self.hold = Fixed()
            self.load = Torque()
            self.tau = Constant(k=-1.0)
            self.ring = Inertia(J=0.0)
            self.sensor = TorqueSensor()
            self.connect(self.w.y, self.drive.w_ref)
            self.connect(self.drive.flange, self.sensor.flange_a)
            self.connect(self.sensor.flange_b, self.gear.sun)
            self.connect(self.gear.carrier, self.hold.flange)
            self.connect(self.gear.ring, self.ring.flange_a)
            self.connect(self.ring.flange_b, self.load.flange)
            self.connect(self.tau.y, self.load.tau)

    _, res = simulate(Gearset(), 1.0, 0.25)
    np.testing.assert_allclose(res["ring.w"], -1.5, atol=1e-9)
    np.testing.assert_allclose(res["sensor.tau"], -0.5, atol=1e-9)
    np.testing.assert_allclose(res["gear.ring.tau"], -1.0, atol=1e-9)
    np.testing.assert_allclose(res["gear.carrier.tau"], 1.5, atol=1e-9)


def test_elasto_backlash2_jumps_at_contact_and_never_pulls():
    """``ElastoBacklash2`` (MSL Backlash example's third part: 5 kg m² released at 90° on a 45° backlash, 20 kN m/rad,
    50 N m s/rad): in the gap the torque is exactly 0 and the speed constant; entering contact the torque jumps from
    0 to ``d·w_rel`` (the left and right values at the event, 1e-9 relative); in contact it never pulls
    (``tau ≥ 0`` above the gap, ``≤ 0`` below, to the round-off of the no-pulling event's root, 1e-9 of ``c b``)."""

    class Swing(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.fixed = Fixed()
            self.backlash = ElastoBacklash2(c=20e3, d=50.0, b=np.pi / 4)
            self.disc = Inertia(J=5.0, init={"phi": np.pi / 2, "w": 0.0})
            self.connect(self.fixed.flange, self.backlash.flange_a)
            self.connect(self.backlash.flange_b, self.disc.flange_a)

    _, res = simulate(Swing(), 1.0, 0.0005)
    phi, tau = res["backlash.phi_rel"], res["backlash.tau"]
    gap = np.abs(phi) < np.pi / 8 - 1e-9
    assert gap.sum() > 10 and np.all(tau[gap] == 0.0)
    entries = [t for t, text in res.events if "backlash" in text][:4]
    assert entries
    jumps = 0
    for t in entries:
        before, after = (float(res.value("backlash.tau", [t], side=s)[0]) for s in ("left", "right"))
        speed = float(res.value("backlash.w_rel", [t], side="right")[0])
        if before == 0.0 and after != 0.0:  # entering contact
            np.testing.assert_allclose(after, 50.0 * speed, rtol=1e-9)
            jumps += 1
    assert jumps >= 1
    above, below = phi > np.pi / 8 + 1e-9, phi < -np.pi / 8 - 1e-9
    scale = 1e-9 * 20e3 * np.pi / 4
    assert np.all(tau[above] >= -scale) and np.all(tau[below] <= scale)
