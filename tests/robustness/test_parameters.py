"""Bad parameter values on every path: constructor, later assignment, flatten and ``run(params=...)``.

One validation hook (declared bounds ``min``/``max``/``gt``/``lt`` plus ``Component.check``) runs on each path, so a
run-time override gets the same check and message as the constructor, naming the instance path, the value and the
rule. Each test asserts the error class and that the message names the culprit.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Limiter, LimPID, TransferFunction
from flexlib.components.hydraulics import DirectionalValve43, PressureSource, Tank
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World
from flexlib.models.reference.signal_chain import LimitedSine


class Pid(fl.Model):
    def __init__(self, **pid) -> None:
        super().__init__()
        self.set_point, self.measured = Constant(k=1.0), Constant(k=0.0)
        self.pid = LimPID(controller_type="PI", y_max=1.0, y_min=-1.0, **pid)
        self.connect(self.set_point.y, self.pid.u_s)
        self.connect(self.measured.y, self.pid.u_m)


class Valve(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.supply, self.load_A, self.load_B = PressureSource(p=100e5), PressureSource(p=20e5), PressureSource(p=2e5)
        self.tank = Tank()
        self.command = Constant(k=0.5)
        self.valve = DirectionalValve43(Q_nom=40.0 / 60000.0, dp_nom=35e5)
        self.connect(self.command.y, self.valve.u)
        self.connect(self.supply.port, self.valve.port_P)
        self.connect(self.tank.port, self.valve.port_T)
        self.connect(self.load_A.port, self.valve.port_A)
        self.connect(self.load_B.port, self.valve.port_B)


class Pendulum(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.world = World()
        self.rev = Revolute(init={"phi": 0.3, "w": 0.0})
        self.rod = FixedTranslation(r=[0.5, 0, 0])
        self.body = Body(m=1.0, I=np.diag([1e-3, 2e-3, 2e-3]))
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.body.frame_a)


class Bounded(fl.Component):
    """Exclusive bounds on a scalar and on a vector, and a cross-parameter rule whose message names no path."""

    x = fl.Variable(unit="m")
    gap = fl.Parameter(1.0, unit="m", gt=0.0, doc="Gap, > 0")
    ratio = fl.Parameter(0.5, unit="1", gt=0.0, lt=1.0, doc="Ratio in (0, 1)")
    w = fl.Parameter([1.0, 2.0], unit="1", shape=2, gt=0.0, doc="Weights, > 0")

    def check(self, values: dict) -> None:
        if float(values["w"][0]) > float(values["w"][1]):
            raise fl.ParameterError(f"w must be increasing, got {values['w'].tolist()}")

    def equations(self):
        return [fl.eq(self.x, self.gap * self.ratio)]


class BoundedModel(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.part = Bounded()


@pytest.fixture(scope="module")
def limited() -> fl.Simulation:
    return fl.Simulation(LimitedSine(), use_cache=False)


@pytest.fixture(scope="module")
def pendulum() -> fl.Simulation:
    return fl.Simulation(Pendulum(), use_cache=False)


@pytest.fixture(scope="module")
def bounded() -> fl.Simulation:
    return fl.Simulation(BoundedModel(), use_cache=False)


# -- Limiter ----------------------------------------------------------------------------------------------------
def test_limiter_swapped_limits_at_run_time(limited):
    with pytest.raises(fl.ParameterError, match=r"^limiter: limits must be consistent \(u_max >= u_min\), but "
                                                r"u_max = -1 < u_min = -0\.5"):
        limited.run(0.1, params={"limiter.u_max": -1.0})


def test_limiter_lower_limit_above_upper_at_run_time(limited):
    with pytest.raises(fl.ParameterError, match=r"^limiter: .*u_max = 1 < u_min = 2"):
        limited.run(0.1, params={"limiter.u_min": 2.0})


def test_limiter_overrides_are_checked_together(limited):
    """Both limits moved at once: consistent together although each alone would be swapped; the output is clipped
    to the new limits (1e-6 at the output points; at rtol 1e-9, since a crossing is located on IDA's interpolant of
    the input, whose error is of order rtol·|u|)."""
    res = limited.run(1.0, dt_out=0.01, params={"limiter.u_max": -1.0, "limiter.u_min": -1.5}, progress=False,
                      rtol=1e-9, atol=1e-11)
    assert res["limiter.y"].max() <= -1.0 + 1e-6 and res["limiter.y"].min() >= -1.5 - 1e-6


def test_limiter_swapped_at_construction():
    with pytest.raises(fl.ParameterError, match=r"^Limiter: limits must be consistent .*u_max = 0 < u_min = 1"):
        Limiter(u_max=0.0, u_min=1.0)


def test_limiter_swapped_by_later_assignment_names_path():
    model = LimitedSine()
    with pytest.raises(fl.ParameterError, match=r"^limiter: .*u_max = -2 < u_min = -0\.5"):
        model.limiter.u_max = -2.0
    assert float(model.limiter.parameter_value("u_max")) == 1.0  # the refused value was not stored


# -- other control blocks ---------------------------------------------------------------------------------------
def test_rate_limiter_positive_falling_rate_at_run_time(limited):
    with pytest.raises(fl.ParameterError, match=r"^rate\.falling must be < 0, got 0\.5 \[1/s\]"):
        limited.run(0.1, params={"rate.falling": 0.5})


def test_first_order_zero_time_constant_at_run_time(limited):
    with pytest.raises(fl.ParameterError, match=r"^lag\.T = 0: time constant T must be != 0"):
        limited.run(0.1, params={"lag.T": 0.0})


def test_pid_zero_gain_at_run_time():
    sim = fl.Simulation(Pid(k=2.0, Ti=0.5), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"^pid: controller gain k must be non-zero, got 0"):
        sim.run(0.1, params={"pid.k": 0.0})


def test_pid_negative_integral_time_at_run_time():
    sim = fl.Simulation(Pid(k=2.0, Ti=0.5), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"^pid\.Ti must be > 0, got -1\.0 \[s\]"):
        sim.run(0.1, params={"pid.Ti": -1.0})


def test_pid_structural_option_changed_after_construction_checked_at_flatten():
    """``init_type`` changed after construction makes y_start outside the limits: caught when the model is built,
    with the instance path."""
    model = Pid(k=2.0, Ti=0.5, y_start=0.0)
    model.pid.y_start = 3.0  # fine while the output is not initialised from y_start
    model.pid.init_type = "initial_output"
    with pytest.raises(fl.ParameterError, match=r"^pid: y_start = 3 is outside the limits y_min = -1 and y_max = 1"):
        fl.Simulation(model, use_cache=False)


# -- hydraulic valve --------------------------------------------------------------------------------------------
def test_valve_zero_nominal_flow_at_run_time():
    sim = fl.Simulation(Valve(), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"^valve\.Q_nom must be > 0 \[m3/s\] \(got 0\.0\)"):
        sim.run(0.1, params={"valve.Q_nom": 0.0})
    with pytest.raises(fl.ParameterError, match=r"^valve\.lap_PA = 1\.0 \[1\] is above its maximum 0\.99"):
        sim.run(0.1, params={"valve.lap_PA": 1.0})


def test_valve_zero_nominal_flow_at_construction():
    with pytest.raises(fl.ParameterError, match=r"^DirectionalValve43: Q_nom must be > 0 \[m3/s\]"):
        DirectionalValve43(Q_nom=0.0)


# -- multibody body inertia and joint axis ----------------------------------------------------------------------
def test_body_inertia_not_positive_definite_at_run_time(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^body: inertia tensor I is not positive semi-definite"):
        pendulum.run(0.1, params={"body.I": np.diag([1e-3, -2e-3, 2e-3])})


def test_body_inertia_element_override_checked_with_whole_array(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^body: inertia tensor I is not positive semi-definite"):
        pendulum.run(0.1, params={"body.I[1,1]": -1e-3})


def test_body_inertia_element_override_breaks_symmetry(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^body: inertia tensor I is not symmetric"):
        pendulum.run(0.1, params={"body.I[0,1]": 1e-4})


def test_body_inertia_element_override_breaks_triangle_inequality(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^body: inertia tensor I violates the triangle inequality"):
        pendulum.run(0.1, params={"body.I[2,2]": 1.0})


def test_body_symmetric_pair_of_element_overrides_is_accepted(pendulum):
    """Products of inertia set on both symmetric elements pass the check and the run uses them."""
    res = pendulum.run(0.2, dt_out=0.1, params={"body.I[0,1]": 1e-4, "body.I[1,0]": 1e-4}, progress=False)
    assert res.parameters["body.I[0,1]"][0] == res.parameters["body.I[1,0]"][0] == 1e-4
    assert res.t[-1] == pytest.approx(0.2)


def test_body_negative_mass_element_is_named(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^body\.m = -1\.0 \[kg\] is below its minimum 0"):
        pendulum.run(0.1, params={"body.m": -1.0})


def test_body_inertia_element_not_a_number(pendulum):
    with pytest.raises(fl.ParameterError,
                       match=r"^body\.I\[0,0\]: parameter value 'abc' is a string, not a number; give a real number"):
        pendulum.run(0.1, params={"body.I[0,0]": "abc"})


def test_revolute_zero_axis_at_run_time(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^rev: joint axis n = \[0\.0, 0\.0, 0\.0\] has zero length"):
        pendulum.run(0.1, params={"rev.n": [0.0, 0.0, 0.0]})


def test_revolute_zero_axis_by_element_override(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^rev: joint axis n = \[0\.0, 0\.0, 0\.0\] has zero length"):
        pendulum.run(0.1, params={"rev.n[2]": 0.0})


def test_body_zero_start_quaternion_at_construction():
    with pytest.raises(fl.ParameterError, match=r"^Body: Q_start = \[0\.0, 0\.0, 0\.0, 0\.0\] has zero length"):
        Body(Q_start=[0.0, 0.0, 0.0, 0.0])


# -- exclusive bounds and the check hook on a user component ----------------------------------------------------
def test_exclusive_lower_bound_at_construction():
    with pytest.raises(fl.ParameterError, match=r"^Bounded: gap must be > 0, got 0\.0 \[m\]"):
        Bounded(gap=0.0)


def test_exclusive_upper_bound_at_run_time(bounded):
    with pytest.raises(fl.ParameterError, match=r"^part\.ratio must be < 1, got 1\.0 \[1\]"):
        bounded.run(0.1, params={"part.ratio": 1.0})


def test_exclusive_bound_on_vector_element_override(bounded):
    with pytest.raises(fl.ParameterError, match=r"^part\.w must be > 0, got \[-1\.0, 2\.0\] \[1\]"):
        bounded.run(0.1, params={"part.w[0]": -1.0})


def test_check_message_without_path_gets_instance_path(bounded):
    with pytest.raises(fl.ParameterError, match=r"^part: w must be increasing, got \[3\.0, 2\.0\]"):
        bounded.run(0.1, params={"part.w[0]": 3.0})


def test_check_message_unattached_gets_class_name():
    with pytest.raises(fl.ParameterError, match=r"^Bounded: w must be increasing, got \[2\.0, 1\.0\]"):
        Bounded(w=[2.0, 1.0])


def test_bounds_are_described():
    assert Bounded.ratio.rules() == "> 0, < 1"
    assert Limiter.u_max.rules() == ""


def test_valid_override_is_used(bounded):
    res = bounded.run(0.1, dt_out=0.1, params={"part.gap": 2.0, "part.ratio": 0.25}, progress=False)
    np.testing.assert_allclose(res["part.x"], 0.5, rtol=0, atol=1e-12)


class Filtered(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.step = Constant(k=1.0)
        self.tf = TransferFunction(b=[1.0], a=[0.1, 1.0])
        self.connect(self.step.y, self.tf.u)


def test_transfer_function_zero_leading_coefficient_at_construction():
    with pytest.raises(fl.ParameterError, match=r"^TransferFunction: leading denominator coefficient a\[0\] must be "
                                                r"!= 0, got a = \[0\.0, 1\.0\]"):
        TransferFunction(b=[1.0], a=[0.0, 1.0])


def test_transfer_function_zero_leading_coefficient_at_run_time():
    """Used to be a constructor-only check: a run-time ``a[0] = 0`` divided by zero in the model."""
    sim = fl.Simulation(Filtered(), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"^tf: leading denominator coefficient a\[0\] must be != 0, "
                                                r"got a = \[0\.0, 1\.0\]"):
        sim.run(0.1, params={"tf.a[0]": 0.0})
    with pytest.raises(fl.ParameterError, match=r"^tf: leading denominator coefficient"):
        sim.run(0.1, params={"tf.a": [0.0, 2.0]})
    res = sim.run(0.5, dt_out=0.5, params={"tf.a": [0.2, 1.0]}, rtol=1e-9, atol=1e-11, progress=False)
    np.testing.assert_allclose(res["tf.y"][-1], 1.0 - np.exp(-0.5 / 0.2), rtol=1e-6)  # first-order step response


def test_nan_override_is_named(limited):
    with pytest.raises(fl.ParameterError, match=r"^limiter\.u_max: parameter value nan is not finite"):
        limited.run(0.1, params={"limiter.u_max": float("nan")})


def test_nan_element_override_is_named(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^body\.I: parameter value \[\[nan, 0\.0, 0\.0\], .* is not finite"):
        pendulum.run(0.1, params={"body.I[0,0]": float("nan")})


def test_wrong_shape_override_is_named(pendulum):
    with pytest.raises(fl.ParameterError, match=r"^body\.I: parameter has shape \(3, 3\), got value of shape \(2,\)"):
        pendulum.run(0.1, params={"body.I": [1.0, 2.0]})


def test_element_index_out_of_range_suggests_names(pendulum):
    with pytest.raises(fl.ParameterError, match=r"unknown parameter 'body\.I\[3,3\]' in model Pendulum; did you mean "
                                                r"body\.I\["):
        pendulum.run(0.1, params={"body.I[3,3]": 1.0})
