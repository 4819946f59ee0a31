"""Tests of the basic hydraulic components against analytic references.

Every test states its reference and tolerance in the docstring. Simulations run at
rtol = 1e-8, atol = 1e-10 (scaled by each variable's nominal) unless stated otherwise.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import flexlib as fl
from flexlib.components.control import Constant, Ramp
from flexlib.components.hydraulics import (
    HLP46,
    CheckValve,
    FixedDisplacementPump,
    FlowSensor,
    FlowSource,
    Fluid,
    HydraulicMotor,
    Line,
    Orifice,
    PressureCompensatedPump,
    PressureReliefValve,
    PressureSensor,
    PressureSource,
    RelativePressureSensor,
    Tank,
    VariableOrifice,
    Volume,
    critical_pressure,
)
from flexlib.components.mechanics import rotational as rot

TOL = {"rtol": 1e-8, "atol": 1e-10}
P_ATM = 1.01325e5
REV = 2.0 * math.pi


def simulate(model: fl.Model, t_end: float, dt_out: float = 0.01, **kw) -> tuple[fl.Simulation, fl.Result]:
    sim = fl.Simulation(model, use_cache=False)
    return sim, sim.run(t_end, dt_out=dt_out, **{**TOL, **kw})


def rel_err(x, ref) -> float:
    return float(np.max(np.abs(np.asarray(x) - ref) / np.abs(ref)))


# ------------------------------------------------------------------------------------------------
# (a) pressure build-up in a closed volume
# ------------------------------------------------------------------------------------------------
class FilledVolume(fl.Model):
    """A flow source delivering q into a closed volume, with pressure and flow sensors."""

    def __init__(self, q: float, V: float, p_start: float, fluid: Fluid = HLP46) -> None:
        super().__init__()
        self.source = FlowSource(q=q, fluid=fluid)
        self.flow_sensor = FlowSensor(fluid=fluid)
        self.volume = Volume(V=V, p_start=p_start, fluid=fluid)
        self.pressure = PressureSensor()
        self.connect(self.source.port, self.flow_sensor.port_a)
        self.connect(self.flow_sensor.port_b, self.volume.port, self.pressure.port)


def test_pressure_build_up_pure_liquid():
    """Closed volume fed by a flow source (pure liquid).

    Reference: mass balance ``d(rho V)/dt = rho(p) q`` with ``rho = rho_ref exp((p - p_ref)/beta)``
    gives ``dp/dt = beta q / V`` — constant, so ``p(t) = p0 + beta q t / V`` exactly (Merritt §2.3).
    Tolerances: initial slope within 0.5 %; whole p(t) within 2e-5 of the pressure rise (measured
    7.4e-6: the state is the stored mass, and a relative mass error e is a pressure error beta*e);
    the flow sensor reads q (volume flow at the node pressure) to 1e-9.
    """
    q, V, p0, T = 1e-4, 1e-3, 1e6, 0.1  # 6 L/min into 1 L from 10 bar, 160 bar rise
    _, res = simulate(FilledVolume(q, V, p0), T, dt_out=1e-3)
    beta = HLP46.beta
    slope = (res["pressure.p"][1] - res["pressure.p"][0]) / (res.t[1] - res.t[0])
    assert abs(slope / (beta * q / V) - 1) < 5e-3
    exact = p0 + beta * q * res.t / V
    assert np.max(np.abs(res["volume.p"] - exact)) < 2e-5 * (exact[-1] - p0)
    np.testing.assert_allclose(res["flow_sensor.q"], q, rtol=1e-9)


def test_pressure_build_up_with_entrained_air():
    """Closed volume, oil with 1 % entrained air (strongly pressure-dependent stiffness).

    Reference: with the specific volume ``v(p)`` of the mixture (Fluid docstring), the mass balance
    ``d(V/v)/dt = q/v`` integrates to ``t(p) = V/q * ln(v(p0)/v(p))``; we compare the simulated p(t)
    with the root of that relation. Tolerance 1e-6 relative to the pressure rise; initial slope
    ``beta_eff(p0) q / V`` within 0.5 %.
    """
    oil = Fluid(name="HLP46 + 1 % air", x_air=0.01)
    q, V, p0, T = 1e-4, 1e-3, 2e5, 0.2
    _, res = simulate(FilledVolume(q, V, p0, fluid=oil), T, dt_out=1e-3)
    _, start = simulate(FilledVolume(q, V, p0, fluid=oil), 1e-5, dt_out=1e-6)
    slope = (start["volume.p"][1] - start["volume.p"][0]) / (start.t[1] - start.t[0])
    beta0 = float(oil.bulk_modulus(p0))
    assert abs(slope / (beta0 * q / V) - 1) < 5e-3
    v = lambda p: float(oil.specific_volume(p))  # noqa: E731
    exact = [p0] + [brentq(lambda p, t=t: V / q * math.log(v(p0) / v(p)) - t, p0, 1e9, xtol=1e-6)
                    for t in res.t[1:]]
    p = res["volume.p"]
    assert np.max(np.abs(p - exact)) < 1e-6 * (p[-1] - p0)


# ------------------------------------------------------------------------------------------------
# (b) orifice characteristic
# ------------------------------------------------------------------------------------------------
class OrificeSweep(fl.Model):
    """An orifice between two ramped pressure sources: dp from -dp_max to +dp_max at a fixed mean."""

    def __init__(self, orifice: fl.Component, p_mean: float, dp_max: float) -> None:
        super().__init__()
        self.ramp_a = Ramp(height=dp_max, duration=1.0, offset=p_mean - dp_max / 2)
        self.ramp_b = Ramp(height=-dp_max, duration=1.0, offset=p_mean + dp_max / 2)
        self.source_a = PressureSource(use_input=True)
        self.source_b = PressureSource(use_input=True)
        self.orifice = orifice
        self.connect(self.ramp_a.y, self.source_a.p_in)
        self.connect(self.ramp_b.y, self.source_b.p_in)
        self.connect(self.source_a.port, self.orifice.port_a)
        self.connect(self.orifice.port_b, self.source_b.port)


def test_orifice_turbulent_law_symmetry_and_laminar_transition():
    """Orifice A = 10 mm2, Cd = 0.64 swept over ±20 bar and over ±2 p_cr at 100 bar mean pressure.

    Reference: turbulent orifice ``m_flow = Cd A sqrt(2 rho |dp|) sign(dp)`` (Merritt §3.2; Simscape
    *Orifice (IL)*), rho at the mean pressure. Tolerances: 1e-3 relative for |dp| >= 1 bar
    (>> p_cr ≈ 25 Pa); odd symmetry ``m(-dp) = -m(dp)`` to 1e-8 of the flow scale (output values
    are the integrator's interpolants, accurate to its tolerance); through zero the
    slope is finite and continuous: the centred and one-sided difference quotients at dp = 0 agree with
    the laminar slope ``Cd A sqrt(2 rho / p_cr)`` within 1e-3.
    """
    A, Cd, p_mean = 1e-5, 0.64, 1e7
    model = OrificeSweep(Orifice(A=A, Cd=Cd), p_mean, 2e6)
    sim, res = simulate(model, 1.0, dt_out=0.005)
    rho = float(HLP46.density(p_mean))
    _, first = np.unique(res.t, return_index=True)  # drop the right values stored at the time events
    dp, m = res["orifice.dp"][first], res["orifice.m_flow"][first]
    turbulent = np.abs(dp) >= 1e5
    ref = Cd * A * np.sqrt(2 * rho * np.abs(dp[turbulent])) * np.sign(dp[turbulent])
    assert rel_err(m[turbulent], ref) < 1e-3
    np.testing.assert_allclose(m + m[::-1], 0.0, atol=1e-8 * np.max(np.abs(m)))
    np.testing.assert_allclose(res["orifice.q"][first], m / rho, rtol=1e-12, atol=1e-18)

    p_cr = float(critical_pressure(A, Cd, rho, HLP46.nu))
    res = sim.run(1.0, dt_out=0.005, params={"ramp_a.height": 2 * p_cr, "ramp_a.offset": p_mean - p_cr,
                                             "ramp_b.height": -2 * p_cr, "ramp_b.offset": p_mean + p_cr}, **TOL)
    _, first = np.unique(res.t, return_index=True)
    dp, m = res["orifice.dp"][first], res["orifice.m_flow"][first]
    k0 = int(np.argmin(np.abs(dp)))
    assert abs(dp[k0]) < 1e-6 * p_cr and abs(m[k0]) < 1e-9
    h = dp[k0 + 1] - dp[k0]
    slope_lam = Cd * A * math.sqrt(2 * rho / p_cr)
    centred = (m[k0 + 1] - m[k0 - 1]) / (2 * h)
    right, left = (m[k0 + 1] - m[k0]) / h, (m[k0] - m[k0 - 1]) / h
    for s in (centred, right, left):
        assert abs(s / slope_lam - 1) < 1e-3
    assert np.all(np.diff(m) > 0)  # monotone through the transition


def test_variable_orifice_follows_area_signal():
    """Variable orifice commanded to A = 5 mm2 at 10 bar drop.

    Reference: ``m_flow = Cd (A + A_leak) sqrt(2 rho dp)``; a negative command closes to the leakage
    area. Tolerance 1e-3 relative (p_cr << dp).
    """

    class Throttle(fl.Model):
        def __init__(self, area: float) -> None:
            super().__init__()
            self.command = Constant(k=area)
            self.high = PressureSource(p=1.1e6)
            self.low = PressureSource(p=1e5)
            self.orifice = VariableOrifice(Cd=0.7)
            self.connect(self.command.y, self.orifice.A)
            self.connect(self.high.port, self.orifice.port_a)
            self.connect(self.orifice.port_b, self.low.port)

    sim, res = simulate(Throttle(5e-6), 0.01)
    rho = float(HLP46.density(6e5))
    assert rel_err(res["orifice.m_flow"], 0.7 * (5e-6 + 1e-12) * math.sqrt(2 * rho * 1e6)) < 1e-3
    res = sim.run(0.01, dt_out=0.01, params={"command.k": -1e-6}, **TOL)
    p_cr = float(critical_pressure(1e-12, 0.7, rho, HLP46.nu))
    leak = 0.7 * 1e-12 * math.sqrt(2 * rho) * 1e6 / (1e12 + p_cr**2) ** 0.25
    np.testing.assert_allclose(res["orifice.m_flow"], leak, rtol=1e-6, atol=1e-12)


# ------------------------------------------------------------------------------------------------
# (c) relief valve on a blocked pump line
# ------------------------------------------------------------------------------------------------
class BlockedPumpLine(fl.Model):
    """Pump (speed signal) from the tank into a volume; relief valve from the volume to the tank."""

    def __init__(self, D: float, w: float, eta_v: float, use_dynamics: bool = False, **valve) -> None:
        super().__init__()
        self.speed = Constant(k=w)
        self.tank = Tank()
        self.pump = FixedDisplacementPump(D=D, eta_v=eta_v)
        self.volume = Volume(V=1e-3, p_start=P_ATM)
        self.valve = PressureReliefValve(use_dynamics=use_dynamics, **valve)
        self.connect(self.speed.y, self.pump.w)
        self.connect(self.tank.port, self.pump.port_a, self.valve.port_b)
        self.connect(self.pump.port_b, self.volume.port, self.valve.port_a)


@pytest.mark.parametrize("use_dynamics", [False, True], ids=["static", "poppet-dynamics"])
def test_relief_valve_limits_pressure(use_dynamics):
    """Fixed pump, 60 L/min, blocked except for a relief valve cracking at 150 bar, 10 bar per 100 L/min.

    Reference (steady state, exact): the pump delivers ``rho(p_t) eta_v D w`` (suction density); the
    valve passes ``rho((p + p_t)/2) (G_leak dp + (dp - p_crack) / p_grad)``; equating the two gives
    dp by a scalar root. Without the density ratio this is the closed form
    ``dp = (p_crack + p_grad q) / (1 + G_leak p_grad)``. Tolerance: steady pressure within 1e-6
    relative of the exact root after 0.2 s; closed form within 0.1 % (density ratio).
    """
    D, w, eta_v = 20e-6 / REV, 52.36, 0.955  # 20 cm3/rev at 500 rpm: ≈ 60 L/min geometric
    p_crack, p_grad, G_leak = 1.5e7, 10e5 / (100 / 60000), 1e-12
    model = BlockedPumpLine(D, w, eta_v, use_dynamics, p_crack=p_crack, p_grad=p_grad, G_leak=G_leak, T=2e-3)
    _, res = simulate(model, 0.2, dt_out=1e-3)
    q = eta_v * D * w
    rho = lambda p: float(HLP46.density(p))  # noqa: E731

    def residual(dp):
        return rho(P_ATM) * q - rho(P_ATM + dp / 2) * (G_leak * dp + (dp - p_crack) / p_grad)

    dp_exact = brentq(residual, p_crack, 2 * p_crack, xtol=1e-6)
    dp_sim = res["valve.dp"][-1]
    assert abs(dp_sim / dp_exact - 1) < 1e-6
    assert abs(dp_sim / ((p_crack + p_grad * q) / (1 + G_leak * p_grad)) - 1) < 1e-3
    assert abs(res["pump.q"][-1] / q - 1) < 1e-12
    assert np.max(res["valve.dp"]) < dp_exact * 1.05  # no large overshoot with the small volume


# ------------------------------------------------------------------------------------------------
# (d) motor driving an inertia with a viscous and a constant load
# ------------------------------------------------------------------------------------------------
class MotorDrive(fl.Model):
    """Flow source → volume → motor → tank; motor shaft: inertia, damper to ground, load torque."""

    def __init__(self, q: float, D: float, eta_v: float, eta_m: float, d: float, tau_load: float) -> None:
        super().__init__()
        self.source = FlowSource(q=q)
        self.volume = Volume(V=1e-4, p_start=P_ATM)
        self.motor = HydraulicMotor(D=D, eta_v=eta_v, eta_m=eta_m)
        self.tank = Tank()
        self.inertia = rot.Inertia(J=1e-3, init={"phi": 0.0, "w": 0.0})
        self.damper = rot.Damper(d=d)
        self.ground = rot.Fixed()
        self.load = rot.Torque()
        self.load_torque = Constant(k=-tau_load)
        self.connect(self.source.port, self.volume.port, self.motor.port_a)
        self.connect(self.motor.port_b, self.tank.port)
        self.connect(self.motor.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.damper.flange_b, self.load.flange)
        self.connect(self.damper.flange_a, self.ground.flange)
        self.connect(self.load_torque.y, self.load.tau)


def test_motor_speed_and_load_pressure():
    """Motor 10 cm3/rev, eta_v 0.95, eta_m 0.9, fed with 20 L/min; viscous 0.02 N.m.s/rad + 5 N.m load.

    Reference (steady state, exact): ``w = eta_v q / D`` (the source's q is counted at the node
    pressure, as the motor's) and ``eta_m D (p - p_t) = d w + tau_load`` (Merritt §6.2). The start-up
    transient decays as exp(-d t / 2J) = exp(-10 t). Tolerance 1e-6 relative after 3 s.
    """
    q, D, eta_v, eta_m, d, tau_load = 20 / 60000, 10e-6 / REV, 0.95, 0.9, 0.02, 5.0
    _, res = simulate(MotorDrive(q, D, eta_v, eta_m, d, tau_load), 3.0, dt_out=0.01)
    w = eta_v * q / D
    assert abs(res["motor.w"][-1] / w - 1) < 1e-6
    assert abs(res["inertia.w"][-1] / w - 1) < 1e-6
    dp = (d * w + tau_load) / (eta_m * D)
    assert abs(res["motor.dp"][-1] / dp - 1) < 1e-6
    assert abs(res["motor.tau"][-1] / (d * w + tau_load) - 1) < 1e-6


# ------------------------------------------------------------------------------------------------
# (e) pumps
# ------------------------------------------------------------------------------------------------
class PumpRig(fl.Model):
    """Pump driven through its flange by a speed source, from the tank into a pressure source."""

    def __init__(self, pump: fl.Component, w: float, p_out: float) -> None:
        super().__init__()
        self.speed_ref = Constant(k=w)
        self.drive = rot.Speed(init={"phi": 0.0})
        self.pump = pump
        self.tank = Tank()
        self.load = PressureSource(p=p_out)
        self.flow_sensor = FlowSensor()
        self.dp_sensor = RelativePressureSensor()
        self.connect(self.speed_ref.y, self.drive.w_ref)
        self.connect(self.drive.flange, self.pump.flange)
        self.connect(self.tank.port, self.pump.port_a, self.dp_sensor.port_b)
        self.connect(self.pump.port_b, self.flow_sensor.port_a, self.dp_sensor.port_a)
        self.connect(self.flow_sensor.port_b, self.load.port)


def test_fixed_displacement_pump_flow_and_torque():
    """Pump 20 cm3/rev at 1500 rpm against 100 bar, eta_v 0.93, eta_m 0.88, then with laminar leakage.

    Reference: ``q = eta_v D w - C_leak dp`` at suction density, i.e. mass flow ``rho(p_t) q``;
    the measured volume flow at 100 bar is ``q rho(p_t)/rho(p)``; shaft torque ``D dp / eta_m``
    (Merritt §6.2; Simscape *Fixed-Displacement Pump (IL)*). Tolerance 1e-9 relative.
    """
    D, w, eta_v, eta_m, p_out = 20e-6 / REV, 1500 * REV / 60, 0.93, 0.88, 1e7
    sim, res = simulate(PumpRig(FixedDisplacementPump(D=D, eta_v=eta_v, eta_m=eta_m, use_flange=True), w, p_out),
                        0.1)
    q = eta_v * D * w
    rho_t, rho_p = float(HLP46.density(P_ATM)), float(HLP46.density(p_out))
    assert rel_err(res["pump.q"], q) < 1e-9
    assert rel_err(res["flow_sensor.m_flow"], rho_t * q) < 1e-9
    assert rel_err(res["flow_sensor.q"], q * rho_t / rho_p) < 1e-9
    dp = p_out - P_ATM
    assert rel_err(res["dp_sensor.dp"], dp) < 1e-12
    assert rel_err(res["pump.flange.tau"], D * dp / eta_m) < 1e-9  # torque driven into the pump
    assert rel_err(-res["drive.flange.tau"], D * dp / eta_m) < 1e-9
    C_leak = 1e-12
    res = sim.run(0.1, dt_out=0.01, params={"pump.C_leak": C_leak}, **TOL)
    assert rel_err(res["pump.q"], q - C_leak * dp) < 1e-9


class CompensatedPumpRig(fl.Model):
    """Pressure-compensated pump (speed signal) from the tank into a volume with an optional outlet."""

    def __init__(self, pump: PressureCompensatedPump, w: float, p_load: float | None) -> None:
        super().__init__()
        self.speed = Constant(k=w)
        self.tank = Tank()
        self.pump = pump
        self.volume = Volume(V=1e-3, p_start=P_ATM)
        self.connect(self.speed.y, self.pump.w)
        self.connect(self.tank.port, self.pump.port_a)
        self.connect(self.pump.port_b, self.volume.port)
        if p_load is not None:
            self.load = PressureSource(p=p_load)
            self.connect(self.load.port, self.pump.port_ls)


def test_pressure_compensated_pump_limits_pressure():
    """Compensated pump D_max 20 cm3/rev, 1500 rpm, p_set 200 bar, regulation range 10 bar, blocked
    except for its laminar leakage C_leak.

    Reference (steady state, exact): zero net delivery ``eta_v eps D_max w = C_leak dp`` with
    ``eps = 1 - (dp - p_set)/dp_reg`` (linear part of the compensator) gives
    ``dp = (1 + p_set/dp_reg) / (1/dp_reg + C_leak/(eta_v D_max w))`` (Simscape *Pressure-Compensated
    Pump (IL)*). Tolerance 1e-6 relative after 0.5 s (with and without displacement dynamics).
    Below p_set the pump delivers its full flow ``eta_v D_max w`` (checked into 100 bar, 1e-9).
    """
    D, w, eta_v, p_set, dp_reg, C = 20e-6 / REV, 1500 * REV / 60, 0.95, 2e7, 1e6, 2e-12
    exact = (1 + p_set / dp_reg) / (1 / dp_reg + C / (eta_v * D * w))
    for dynamics in (False, True):
        pump = PressureCompensatedPump(D_max=D, p_set=p_set, dp_reg=dp_reg, eta_v=eta_v, C_leak=C,
                                       use_dynamics=dynamics, T=0.01)
        _, res = simulate(CompensatedPumpRig(pump, w, None), 0.5, dt_out=0.01)
        assert abs(res["pump.dp"][-1] / exact - 1) < 1e-6, dynamics
        if not dynamics:  # (a lagging swash plate overshoots, by ≈ 5 bar here)
            assert np.max(res["pump.dp"]) < p_set + 1.0001 * dp_reg
    rig = PumpRig(PressureCompensatedPump(D_max=D, p_set=p_set, dp_reg=dp_reg, eta_v=eta_v, use_flange=True),
                  w, 1e7)
    _, res = simulate(rig, 0.01)
    assert rel_err(res["pump.q"], eta_v * D * w) < 1e-9


def test_load_sensing_pump_holds_margin():
    """Load-sensing pump, margin 15 bar over a 80 bar load signal, blocked except for leakage.

    Reference (steady state, exact): ``eps = 1 - (p_b - p_ls - dp_margin)/dp_reg`` and
    ``eta_v eps D_max w = C_leak (p_b - p_t)``, linear in p_b. Tolerance 1e-6 relative.
    """
    D, w, eta_v, p_set, dp_reg, C, margin, p_ls = 20e-6 / REV, 157.08, 1.0, 2.5e7, 1e6, 2e-12, 1.5e6, 8e6
    pump = PressureCompensatedPump(D_max=D, p_set=p_set, dp_reg=dp_reg, eta_v=eta_v, C_leak=C, dp_margin=margin,
                                   use_load_sensing=True)
    _, res = simulate(CompensatedPumpRig(pump, w, p_ls), 0.5, dt_out=0.01)
    k = eta_v * D * w
    # k (1 - (p_b - p_ls - margin)/dp_reg) = C (p_b - P_ATM)
    p_b = (k * (1 + (p_ls + margin) / dp_reg) + C * P_ATM) / (k / dp_reg + C)
    assert abs(res["volume.p"][-1] / p_b - 1) < 1e-6


# ------------------------------------------------------------------------------------------------
# (f) check valve
# ------------------------------------------------------------------------------------------------
def test_check_valve_blocks_reverse_flow_and_opens_at_cracking_pressure():
    """Check valve, cracking 2 bar, fully open at 5 bar, A_max 20 mm2, swept over ±10 bar at 50 bar.

    Reference: orifice law (Merritt §3.2) through ``A = A_leak + x (A_max - A_leak)``, with
    ``x = clamp((dp - p_crack)/(p_open - p_crack))`` outside the corner fillets (Simscape *Check Valve
    (IL)*). Tolerances: reverse flow and flow below cracking equal the leakage-area flow (< 1e-6 of
    the full-open flow), open region within 1e-3 of the formula, the flow rises from leakage only
    above ``p_crack - smoothing/2 (p_open - p_crack)``.
    """
    A_max, A_leak, Cd, p_crack, p_open, s = 2e-5, 1e-11, 0.64, 2e5, 5e5, 0.05
    valve = CheckValve(A_max=A_max, A_leak=A_leak, Cd=Cd, p_crack=p_crack, p_open=p_open, smoothing=s)
    _, res = simulate(OrificeSweep(valve, 5e6, 2e6), 1.0, dt_out=0.0025)
    dp, m, x = res["orifice.dp"], res["orifice.m_flow"], res["orifice.x"]
    rho = float(HLP46.density(5e6))

    def orifice(area, dp):
        p_cr = float(critical_pressure(area, Cd, rho, HLP46.nu))
        return Cd * area * math.sqrt(2 * rho) * dp / (dp**2 + p_cr**2) ** 0.25

    m_full = orifice(A_max, 1e6)
    h = s / 2 * (p_open - p_crack)
    closed = dp < p_crack - h
    assert np.all(x[closed] == 0.0)
    assert np.max(np.abs(m[closed])) < 1e-6 * m_full
    # leakage flows are ~1e-8 kg/s: compared at the integrator's absolute tolerance on m_flow
    np.testing.assert_allclose(m[closed], [orifice(A_leak, v) for v in dp[closed]], rtol=1e-6, atol=1e-10)
    linear = (dp > p_crack + h) & (dp < p_open - h)
    open_ = dp > p_open + h
    assert linear.sum() > 10 and open_.sum() > 10
    x_ref = (dp[linear] - p_crack) / (p_open - p_crack)
    np.testing.assert_allclose(x[linear], x_ref, rtol=1e-9)
    assert rel_err(m[linear], [orifice(A_leak + xi * (A_max - A_leak), v) for xi, v in zip(x_ref, dp[linear],
                                                                                         strict=True)]) < 1e-3
    assert rel_err(m[open_], [orifice(A_max, v) for v in dp[open_]]) < 1e-3


# ------------------------------------------------------------------------------------------------
# (g) exact mass conservation
# ------------------------------------------------------------------------------------------------
class TwoVolumes(fl.Model):
    """Flow source → volume 1 → orifice → volume 2, with the delivered mass integrated."""

    delivered = fl.Variable(unit="kg", doc="Mass delivered by the source since t = 0")

    def __init__(self) -> None:
        super().__init__(init={"delivered": 0.0})
        self.source = FlowSource(q=2e-4)
        self.volume1 = Volume(V=5e-4, p_start=P_ATM)
        self.orifice = Orifice(A=2e-6)
        self.volume2 = Volume(V=2e-3, p_start=P_ATM)
        self.connect(self.source.port, self.volume1.port, self.orifice.port_a)
        self.connect(self.orifice.port_b, self.volume2.port)

    def equations(self) -> list:
        return [fl.eq(fl.der(self.delivered), self.source.m_flow)]


def test_mass_conservation_two_volumes():
    """Two volumes filled through an orifice: delivered mass equals the stored mass change.

    Reference: conservation of mass, ``∫ m_flow_source dt = Δ(m1 + m2)``. BDF preserves this linear
    invariant, so it holds to the Newton tolerance: 1e-9 relative to the stored mass change, over a
    run where the pressures rise by ≈ 200 bar and the orifice flow changes regime, at the default
    (loose) tolerances rtol = 1e-6.
    """
    sim = fl.Simulation(TwoVolumes(), use_cache=False)
    res = sim.run(0.5, dt_out=0.01)
    stored = res["volume1.m"] + res["volume2.m"]
    change = stored - stored[0]
    assert res["volume2.p"][-1] > 1e7
    np.testing.assert_allclose(res["delivered"], change, rtol=0, atol=1e-9 * change[-1])


# ------------------------------------------------------------------------------------------------
# line
# ------------------------------------------------------------------------------------------------
def test_line_friction_laminar_and_turbulent():
    """Line 2 m, bore 10 mm, between two pressure sources, in steady flow.

    Reference: Hagen–Poiseuille ``dp = 128 mu L q / (pi d^4)`` at Re ≈ 20 (White §6.4) and Blasius
    ``dp = 0.3164 Re^-1/4 (L/d) rho v^2 / 2`` at Re ≈ 1e4 (White §6.6), mu = nu rho at the mean
    pressure. Tolerances 1e-3 (the blend of the two laws contributes < 1e-4 there).
    """

    class Pipe(fl.Model):
        def __init__(self, dp: float) -> None:
            super().__init__()
            self.high = PressureSource(p=1e6 + dp)
            self.low = PressureSource(p=1e6)
            self.line = Line(L=2.0, d=0.01)
            self.connect(self.high.port, self.line.port_a)
            self.connect(self.line.port_b, self.low.port)

    L, d, nu = 2.0, 0.01, HLP46.nu
    area = math.pi * d**2 / 4
    for dp in (1e3, 3e6):
        _, res = simulate(Pipe(dp), 0.01)
        rho = float(HLP46.density(1e6 + dp / 2))
        q = res["line.q"][-1]
        Re = abs(q) * d / (area * nu)
        if dp < 1e4:
            assert Re < 50
            ref = 128 * nu * rho * L * q / (math.pi * d**4)
        else:
            assert Re > 5e3
            v = q / area
            ref = 0.3164 * Re**-0.25 * L / d * rho * v**2 / 2
        assert abs(ref / dp - 1) < 1e-3, (dp, Re)


def test_line_capacitance_with_wall_compliance():
    """Line (hose) closed at b, filled with q at a: initial pressure rise rate.

    Reference: ``dp/dt = q / (V (1/beta + k_wall))`` with ``V = pi d^2 L / 4`` (series compliance of
    oil and wall; Merritt §2.3). Tolerance 0.5 %.
    """

    class Hose(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.source = FlowSource(q=1e-5)
            self.hose = Line(L=1.0, d=0.012, k_wall=1 / 2e9, p_start=P_ATM)
            self.connect(self.source.port, self.hose.port_a)

    _, res = simulate(Hose(), 0.05, dt_out=1e-3)
    V = math.pi * 0.012**2 / 4
    slope = (res["hose.p_b"][-1] - res["hose.p_b"][0]) / res.t[-1]
    ref = 1e-5 / (V * (1 / HLP46.beta + 1 / 2e9))
    assert abs(slope / ref - 1) < 5e-3


# ------------------------------------------------------------------------------------------------
# (h) bad input
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("make", "match"), [
    (lambda: Volume(V=-1e-3), r"Volume: V .*below its minimum"),
    (lambda: Volume(V=0.0), r"Volume: V must be > 0"),
    (lambda: Fluid(beta=0.0), r"Fluid 'HLP46': beta must be > 0"),
    (lambda: Fluid(beta=-1e9), r"Fluid 'HLP46': beta must be > 0"),
    (lambda: FixedDisplacementPump(D=-1e-6), r"FixedDisplacementPump: D .*below its minimum"),
    (lambda: FixedDisplacementPump(D=1e-6, eta_v=1.2), r"FixedDisplacementPump: eta_v .*above its maximum"),
    (lambda: HydraulicMotor(D=0.0), r"HydraulicMotor: D must be > 0"),
    (lambda: HydraulicMotor(D=1e-6, eta_m=0.0), r"HydraulicMotor: eta_m must be > 0"),
    (lambda: Orifice(A=-1e-6), r"Orifice: A .*below its minimum"),
    (lambda: Line(L=1.0, d=0.0), r"Line: d must be > 0"),
    (lambda: CheckValve(A_max=1e-5, p_crack=3e5, p_open=2e5), r"CheckValve: p_open .* must be > p_crack"),
    (lambda: PressureReliefValve(p_crack=1e7, p_grad=0.0), r"PressureReliefValve: p_grad must be > 0"),
    (lambda: PressureCompensatedPump(D_max=1e-6, p_set=1e7, dp_reg=0.0),
     r"PressureCompensatedPump: dp_reg must be > 0"),
    (lambda: Volume(V=1e-3, fluid="oil"), r"Volume: fluid must be a Fluid record"),
])
def test_bad_parameters_raise_clear_errors(make, match):
    """Invalid values are rejected when set, naming the component class and the parameter."""
    with pytest.raises(fl.ModelError, match=match):
        make()


def test_bad_run_time_parameter_names_the_path():
    """A run-time override below the bound names the full path of the parameter."""
    sim = fl.Simulation(FilledVolume(1e-4, 1e-3, 1e6), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"volume\.V"):
        sim.run(0.01, params={"volume.V": -1.0})


# ------------------------------------------------------------------------------------------------
# sources and structure
# ------------------------------------------------------------------------------------------------
def test_flow_source_signal_into_tank():
    """Flow source driven by a signal, delivering into a tank at 5 bar.

    Reference: ``port.m_flow = -rho(port.p) q`` (Simscape *Flow Rate Source (IL)*); the tank takes it.
    Tolerance 1e-12 relative.
    """

    class Fill(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.command = Constant(k=3e-4)
            self.source = FlowSource(use_input=True)
            self.tank = Tank(p=5e5)
            self.connect(self.command.y, self.source.q_in)
            self.connect(self.source.port, self.tank.port)

    _, res = simulate(Fill(), 0.01)
    m = float(HLP46.density(5e5)) * 3e-4
    assert rel_err(res["tank.port.m_flow"], m) < 1e-12
    assert rel_err(res["source.m_flow"], m) < 1e-12


def test_fluid_record_is_part_of_the_cache_key():
    """Two circuits that differ only in their fluid must not share a compiled model.

    The fluid's numbers are constants in the equations; the engine's cache key hashes plain-data
    attributes only, so the components store a tuple copy of the record (``fluid_record``).
    """
    from flexlib.compile.cache_key import model_key

    a = model_key(FilledVolume(1e-4, 1e-3, 1e6), {})
    b = model_key(FilledVolume(1e-4, 1e-3, 1e6, fluid=Fluid(beta=1.2e9)), {})
    assert a is not None and b is not None and a != b
    assert a == model_key(FilledVolume(2e-4, 1e-3, 2e6), {})  # parameters and starts are not structure
