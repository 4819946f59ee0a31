"""Tests of ``LimPID`` (MSL ``Modelica.Blocks.Continuous.LimPID``) in closed and open loop.

Closed loop: the controller drives a mass with a viscous damper to ground, m v' = F − d v, i.e.
the plant K/(T s + 1) with K = 1/d, T = m/d, built from the translational library and measured by
a SpeedSensor. The references are the closed-loop transfer functions, evaluated by
``scipy.signal.step`` (matrix exponential, independent of flexlib), and closed-form solutions of
the anti-windup dynamics. All runs use rtol = 1e-8, atol = 1e-10; tolerances are in each docstring.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

import flexlib as fl
from flexlib.components.control import Constant, LimPID, Ramp, Step
from flexlib.components.mechanics.translational import Damper, Fixed, Force, Mass, SpeedSensor

TOL = {"rtol": 1e-8, "atol": 1e-10}
M, D = 2.0, 4.0  # plant: mass [kg], damping [N.s/m] -> K = 0.25 m/(N.s), T = 0.5 s
K, T = 1.0 / D, M / D
T_STEP = 0.1  # set-point step time [s]


class SpeedLoop(fl.Model):
    """Set-point step -> LimPID -> force on a damped mass; the speed sensor closes the loop."""

    def __init__(self, height: float = 1.0, **pid: object) -> None:
        super().__init__()
        self.set_point = Step(height=height, start_time=T_STEP)
        self.pid = LimPID(**pid)
        self.force = Force()
        self.mass = Mass(m=M, init={"s": 0.0, "v": 0.0})
        self.damper = Damper(d=D)
        self.fixed = Fixed()
        self.speed = SpeedSensor()
        self.connect(self.set_point.y, self.pid.u_s)
        self.connect(self.speed.v, self.pid.u_m)
        self.connect(self.pid.y, self.force.f)
        self.connect(self.force.flange, self.mass.flange_a, self.speed.flange, self.damper.flange_b)
        self.connect(self.fixed.flange, self.damper.flange_a)


def run(model: fl.Model, t_end: float, **kw) -> fl.Result:
    return fl.Simulation(model, use_cache=False).run(t_end, dt_out=0.01, **TOL, **kw)


def closed_loop(k: float, Ti: float, Td: float, Nd: float, wp: float, wd: float) -> tuple[tuple, tuple]:
    """Transfer functions set point -> speed and set point -> force of the PID loop, as (num, den).

    Controller (MSL LimPID without limits): U = k [wp R - Y + Td s/(Tf s + 1) (wd R - Y) + (R - Y)/(Ti s)],
    Tf = Td/Nd; plant Y = K/(T s + 1) U.
    """
    Tf = Td / Nd
    common = np.polymul([Ti, 0.0], [Tf, 1.0])  # Ti s (Tf s + 1)
    n_r = np.polyadd(np.polyadd(wp * common, [wd * Td * Ti, 0.0, 0.0]), [Tf, 1.0])  # k Cr = k n_r / common
    n_y = np.polyadd(np.polyadd(common, [Td * Ti, 0.0, 0.0]), [Tf, 1.0])  # k Cy = k n_y / common
    den = np.polyadd(np.polymul([T, 1.0], common), k * K * n_y)
    return (k * K * n_r, den), (k * np.polymul(n_r, [T, 1.0]), den)


def test_pi_closed_loop_step_matches_transfer_function():
    """PI speed loop, limits far away: the speed follows kK(Ti s+1)/(Ti T s² + Ti(1+kK)s + kK).

    Reference: scipy.signal.step of that closed-loop transfer function (second order, derived
    from U = k(e + e/(Ti s)), Y = K/(Ts+1) U); tolerance 1e-7 absolute on a unit step (speed [m/s])
    and 1e-7 relative to the force scale k for the controller output.
    """
    k, Ti = 8.0, 0.3
    res = run(SpeedLoop(controller_type="PI", k=k, Ti=Ti, y_max=1e3, y_min=-1e3), 2.0)
    t = T_STEP + np.linspace(0.0, 1.9, 191)
    _, v_ref = signal.step(([k * K * Ti, k * K], [Ti * T, Ti * (1 + k * K), k * K]), T=t - T_STEP)
    np.testing.assert_allclose(res.value("mass.v", t), v_ref, rtol=0, atol=1e-7)
    assert np.all(res.value("mass.v", [0.0, 0.05, 0.099]) == 0.0)  # nothing moves before the step
    (_, _), (num_u, den_u) = closed_loop(k, Ti, 0.0, 1.0, 1.0, 0.0)
    _, u_ref = signal.step((num_u, den_u), T=t - T_STEP)  # from the right value at the step on
    np.testing.assert_allclose(res.value("pid.y", t[1:]), u_ref[1:], rtol=0, atol=1e-7 * k)


def test_pid_with_filter_and_set_point_weights_matches_transfer_function():
    """PID with derivative filter (Nd) and set-point weights wp, wd on the same plant.

    Reference: scipy.signal.step of the closed-loop transfer functions of ``closed_loop`` (third
    order); tolerance 1e-7 on the speed [m/s] and 1e-6 on the force [N] (scale k = 5 N; the
    derivative kick of wd makes the force jump at the step).
    """
    pid = {"k": 5.0, "Ti": 0.4, "Td": 0.08, "Nd": 6.0, "wp": 0.6, "wd": 0.5}
    res = run(SpeedLoop(controller_type="PID", y_max=1e3, y_min=-1e3, **pid), 2.0)
    (num_y, den_y), (num_u, den_u) = closed_loop(pid["k"], pid["Ti"], pid["Td"], pid["Nd"], pid["wp"], pid["wd"])
    t = T_STEP + np.linspace(0.0, 1.9, 191)
    _, v_ref = signal.step((num_y, den_y), T=t - T_STEP)
    _, u_ref = signal.step((num_u, den_u), T=t - T_STEP)
    np.testing.assert_allclose(res.value("mass.v", t), v_ref, rtol=0, atol=1e-7)
    np.testing.assert_allclose(res.value("pid.y", t[1:]), u_ref[1:], rtol=0, atol=1e-6)
    # the weights matter: with wp = 1, wd = 0 the response differs by far more than the tolerance
    (num_y1, den_y1), _ = closed_loop(pid["k"], pid["Ti"], pid["Td"], pid["Nd"], 1.0, 0.0)
    _, v_other = signal.step((num_y1, den_y1), T=t - T_STEP)
    assert np.abs(v_other - v_ref).max() > 1e-2


def overshoot_run(Ni: float) -> fl.Result:
    """Saturating PI loop: the steady force 4 N is close to the limit 4.4 N, so the output saturates."""
    return run(SpeedLoop(controller_type="PI", k=4.0, Ti=0.05, y_max=4.4, y_min=-4.4, Ni=Ni), 4.0)


def test_anti_windup_reduces_overshoot_and_output_stays_in_limits():
    """Anti-windup by back-calculation (Ni = 0.1) against none (Ni = 1e6, ``Ni → ∞`` in MSL).

    Reference: the saturated loop of Åström & Hägglund (ch. 3): without back-calculation the
    integrator winds up during saturation, so the speed overshoots much more. Measured overshoots
    0.020 m/s (Ni = 0.1) and 0.0995 m/s (Ni = 1e6): asserted ratio < 0.3. The limiter keeps
    ``y`` in [y_min, y_max] (to 1e-6 N: IDA interpolates between steps and the output reaches the
    limit at a state event) and equals y_max while ``y_unlimited`` is above it.
    """
    with_aw, without = overshoot_run(0.1), overshoot_run(1e6)
    over_aw = with_aw["mass.v"].max() - 1.0
    over_none = without["mass.v"].max() - 1.0
    assert 0.0 < over_aw < 0.3 * over_none
    for res in (with_aw, without):
        y, v = res["pid.y"], res["pid.y_unlimited"]
        assert np.all(y <= 4.4 + 1e-6) and np.all(y >= -4.4 - 1e-6)
        above = v > 4.4 + 1e-6
        assert above.sum() > 10  # the output saturates
        np.testing.assert_allclose(y[above], 4.4, rtol=0, atol=1e-6)
        np.testing.assert_allclose(y[~above], np.minimum(v[~above], 4.4), rtol=0, atol=1e-6)
        assert any("pid" in text for _, text in res.events)  # the limit is a state event of the PID
    # wind-up: without back-calculation the unlimited output grows far beyond the limit
    assert without["pid.y_unlimited"].max() - 4.4 > 10 * (with_aw["pid.y_unlimited"].max() - 4.4)


class OpenLoop(fl.Model):
    """Controller with constant set point and measurement (no plant)."""

    def __init__(self, u_s: float, u_m: float, **pid: object) -> None:
        super().__init__()
        self.set_point = Constant(k=u_s)
        self.measurement = Constant(k=u_m)
        self.pid = LimPID(**pid)
        self.connect(self.set_point.y, self.pid.u_s)
        self.connect(self.measurement.y, self.pid.u_m)


def test_back_calculation_follows_msl_formula():
    """Saturated PI with a constant error e: Ti xi' = e + (y_max − k(e + xi))/(k Ni).

    Reference: that linear ODE (MSL's integrator input u_s − u_m + (y − v)/(k Ni)) solved in
    closed form: xi = xi∞ + (xi0 − xi∞) exp(−t/(Ni Ti)), xi∞ = y_max/k + e (Ni − 1), so the
    unlimited output settles at y_max + k Ni e; tolerance 1e-7 relative to xi∞ (measured 3e-8).
    """
    k, Ti, Ni, y_max, e = 2.0, 0.5, 0.3, 1.0, 1.5
    res = run(OpenLoop(2.0, 0.5, controller_type="PI", k=k, Ti=Ti, Ni=Ni, y_max=y_max, y_min=-y_max), 1.0)
    xi_inf = y_max / k + e * (Ni - 1.0)
    xi = xi_inf * (1.0 - np.exp(-res.t / (Ni * Ti)))
    np.testing.assert_allclose(res["pid.xi"], xi, rtol=0, atol=1e-7 * abs(xi_inf))
    np.testing.assert_allclose(res["pid.y_unlimited"], k * (e + xi), rtol=0, atol=1e-7 * k * abs(xi_inf))
    np.testing.assert_allclose(res["pid.y"], y_max, rtol=0, atol=1e-12)
    # within the limits the integrator is the plain e/Ti and the gain k applies to e + xi
    free = run(OpenLoop(2.0, 0.5, controller_type="PI", k=k, Ti=Ti, Ni=Ni, y_max=1e3, y_min=-1e3), 1.0)
    np.testing.assert_allclose(free["pid.xi"], e * free.t / Ti, rtol=0, atol=1e-9)
    np.testing.assert_allclose(free["pid.y"], k * (e + e * free.t / Ti), rtol=0, atol=1e-8)


def test_steady_state_initialisation_in_saturation():
    """``init_type="steady_state"``: der(xi) = der(xd) = 0 at the start, so nothing moves.

    Reference: the steady state of the back-calculation ODE above, xi = y_max/k + e (Ni − 1)
    (saturated, e = 1.5), and xd = wd u_s − u_m (filter at rest); tolerance 1e-10.
    """
    k, Ni, y_max, wd = 2.0, 0.3, 1.0, 0.4
    # the guess puts the limiter relation on the saturated side: flexlib takes relation values for the
    # initialisation from the start guesses, and the unsaturated branch has no steady state (e != 0)
    res = run(OpenLoop(2.0, 0.5, controller_type="PID", k=k, Ti=0.5, Td=0.1, Ni=Ni, wd=wd, y_max=y_max,
                       y_min=-y_max, init_type="steady_state", guess={"y_unlimited": 2.0}), 0.5)
    np.testing.assert_allclose(res["pid.xi"], y_max / k + 1.5 * (Ni - 1.0), rtol=0, atol=1e-10)
    np.testing.assert_allclose(res["pid.xd"], wd * 2.0 - 0.5, rtol=0, atol=1e-10)
    np.testing.assert_allclose(res["pid.y"], y_max, rtol=0, atol=1e-12)


def test_initial_output_and_initial_state():
    """``"initial_output"``: k (wp u_s − u_m + d + xi) = y_start at t0 (xi follows, filter at rest);
    ``"initial_state"``: xi = xi_start, xd = xd_start. Reference: the defining equations; 1e-10."""
    res = run(OpenLoop(1.0, 0.2, controller_type="PID", k=2.0, Ti=0.5, Td=0.1, wp=0.5, y_max=5.0, y_min=-5.0,
                       init_type="initial_output", y_start=0.3), 0.1)
    assert res["pid.y"][0] == pytest.approx(0.3, abs=1e-10)
    assert res["pid.xi"][0] == pytest.approx(0.3 / 2.0 - (0.5 * 1.0 - 0.2), abs=1e-10)
    assert res["pid.xd"][0] == pytest.approx(-0.2, abs=1e-10)  # wd = 0: ud = -u_m
    res = run(OpenLoop(1.0, 0.2, controller_type="PID", k=2.0, Ti=0.5, Td=0.1, y_max=5.0, y_min=-5.0,
                       xi_start=0.7, xd_start=-0.4), 0.1)
    assert (res["pid.xi"][0], res["pid.xd"][0]) == pytest.approx((0.7, -0.4), abs=1e-12)


def test_no_init_needs_conditions_from_the_model():
    """``"no_init"`` writes no initial equation: without one the initialisation is under-specified
    (error naming the PID states); ``init={...}`` on the states supplies it."""
    kw = {"controller_type": "PID", "y_max": 5.0, "y_min": -5.0, "init_type": "no_init"}
    with pytest.raises(fl.InitializationError, match=r"pid\.x[id]"):
        run(OpenLoop(1.0, 0.2, **kw), 0.1)
    res = run(OpenLoop(1.0, 0.2, init={"xi": 0.25, "xd": 0.0}, **kw), 0.1)
    assert res["pid.xi"][0] == pytest.approx(0.25, abs=1e-12)


class RampMeasurement(fl.Model):
    """P or PD controller with a ramp measurement and a feed-forward input."""

    def __init__(self, **pid: object) -> None:
        super().__init__()
        self.set_point = Constant(k=0.4)
        self.measurement = Ramp(height=3.0, duration=1.0)
        self.feed_forward = Constant(k=0.25)
        self.pid = LimPID(use_feed_forward=True, y_max=100.0, y_min=-100.0, **pid)
        self.connect(self.set_point.y, self.pid.u_s)
        self.connect(self.measurement.y, self.pid.u_m)
        self.connect(self.feed_forward.y, self.pid.u_ff)


def test_p_and_pd_with_feed_forward():
    """P: y = k (wp u_s − u_m) + k_ff u_ff. PD on a ramp u_m = c t (wd = 0): the filter
    Td s/(Tf s + 1), Tf = Td/Nd, gives d = −c Td (1 − exp(−t/Tf)). Reference: these closed forms;
    tolerance 1e-7 [1] (measured 4e-8)."""
    k, wp, k_ff, c = 3.0, 0.7, 2.0, 3.0
    res = run(RampMeasurement(controller_type="P", k=k, wp=wp, k_ff=k_ff), 1.0)
    np.testing.assert_allclose(res["pid.y"], k * (wp * 0.4 - c * res.t) + k_ff * 0.25, rtol=0, atol=1e-8)
    Td, Nd = 0.2, 4.0
    res = run(RampMeasurement(controller_type="PD", k=k, wp=wp, k_ff=k_ff, Td=Td, Nd=Nd), 1.0)
    d = -c * Td * (1.0 - np.exp(-res.t / (Td / Nd)))
    np.testing.assert_allclose(res["pid.y"], k * (wp * 0.4 - c * res.t + d) + k_ff * 0.25, rtol=0, atol=1e-7)
    np.testing.assert_allclose(res["pid.xi"], 0.0, atol=0)  # no integrator


def test_bad_parameters_are_rejected():
    """Bad input: Ti <= 0, Td < 0, y_max < y_min, k = 0, unknown types, y_start outside the limits
    and an output initialisation without integrator are errors naming the culprit."""
    limits = {"y_max": 1.0, "y_min": -1.0}
    with pytest.raises(fl.ParameterError, match=r"Ti must be > 0"):
        LimPID(Ti=0.0, **limits)
    with pytest.raises(fl.ParameterError, match=r"Ti must be > 0, got -1"):
        LimPID(Ti=-1.0, **limits)
    with pytest.raises(fl.ParameterError, match=r"Td = -0\.1 \[s\] is below its minimum 0"):
        LimPID(Td=-0.1, **limits)
    with pytest.raises(fl.ParameterError, match=r"y_max = -1 < y_min = 1"):
        LimPID(y_max=-1.0, y_min=1.0)
    with pytest.raises(fl.ParameterError, match=r"gain k must be non-zero"):
        LimPID(k=0.0, **limits)
    with pytest.raises(fl.ModelError, match=r"controller_type='PIDD'"):
        LimPID(controller_type="PIDD", **limits)
    with pytest.raises(fl.ModelError, match=r"init_type='steady'"):
        LimPID(init_type="steady", **limits)
    with pytest.raises(fl.ModelError, match=r"needs an integrator"):
        LimPID(controller_type="PD", init_type="initial_output", **limits)
    with pytest.raises(fl.ParameterError, match=r"y_start = 2 is outside"):
        LimPID(init_type="initial_output", y_start=2.0, **limits)
    model = OpenLoop(1.0, 0.0, **limits)
    with pytest.raises(fl.ParameterError, match=r"pid: limits must be consistent"):
        model.pid.y_min = 3.0  # later assignments are checked too
    sim = fl.Simulation(OpenLoop(1.0, 0.0, **limits), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"pid\.Ti"):
        sim.run(0.1, params={"pid.Ti": 0.0})


def test_limits_overridden_at_run_time_are_checked():
    """Limits swapped by a run-time override (y_max < y_min) are refused before the run by the same check as
    at construction, naming the block."""
    sim = fl.Simulation(SpeedLoop(controller_type="PI", k=8.0, Ti=0.3, y_max=100.0, y_min=-100.0), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"^pid: limits must be consistent .*y_max = -200 < y_min = -100"):
        sim.run(0.1, params={"pid.y_max": -200.0}, progress=False)


def test_y_min_defaults_to_minus_y_max_as_msl():
    """MSL's ``yMin = -yMax``: without ``y_min`` the block saturates at ``-y_max`` (a negative error drives it to
    the lower limit, 1e-12); a run-time ``y_max`` alone would leave the built ``y_min`` behind and is refused naming
    both; both together run; an explicit ``y_min`` is kept."""
    model = OpenLoop(0.0, 2.0, controller_type="P", k=1.0, y_max=0.5)
    assert model.pid.parameter_value("y_min") == -0.5
    sim = fl.Simulation(model, use_cache=False)
    res = sim.run(0.1, dt_out=0.05, **TOL)
    np.testing.assert_allclose(res["pid.y"], -0.5, rtol=0, atol=1e-12)
    with pytest.raises(fl.ParameterError, match=r"pid: y_min was not given, so it is -y_max .* y_max = 0\.8 and "
                                                r"y_min = -0\.5"):
        sim.run(0.1, params={"pid.y_max": 0.8})
    res = sim.run(0.1, dt_out=0.05, params={"pid.y_max": 0.8, "pid.y_min": -0.8}, **TOL)
    np.testing.assert_allclose(res["pid.y"], -0.8, rtol=0, atol=1e-12)
    assert LimPID(controller_type="P", y_max=0.5, y_min=-0.1).parameter_value("y_min") == -0.1
