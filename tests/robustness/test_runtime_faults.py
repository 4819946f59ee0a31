"""Robustness: run-time failures say what failed (issue 8), and relations exactly zero at t0 start quietly.

Each case asserts the error class, that the message names the culprit (component path, equation, variable) and
that ``err.result`` keeps the result up to the failure.
"""

from __future__ import annotations

import casadi as ca
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, assert_, der, eq, if_else
from flexlib.models.reference.blow_up import BlowUp


def sim(model):
    return fl.Simulation(model, use_cache=False)


class Reciprocal(fl.Model):
    """x' = −1 from 1, y = 1/x: division by zero at t = 1."""

    x = Variable(unit="m")
    y = Variable(unit="1/m")

    def equations(self):
        return [eq(der(self.x), -1.0), eq(self.y, 1.0 / self.x, label="reciprocal")]


class Root(fl.Model):
    """x' = −1 from 1, y = sqrt(x): square root of a negative number after t = 1."""

    x = Variable(unit="m")
    y = Variable(unit="m0.5")

    def equations(self):
        return [eq(der(self.x), -1.0), eq(self.y, ca.sqrt(self.x), label="square root")]


class Logarithm(fl.Model):
    """x' = −1 from 1, y = ln(x): logarithm of zero at t = 1."""

    x = Variable(unit="m")
    y = Variable(unit="1")

    def equations(self):
        return [eq(der(self.x), -1.0), eq(self.y, ca.log(self.x), label="logarithm")]


class Plant(fl.Model):
    def __init__(self, inner):
        super().__init__()
        self.inner = inner


def quiet_run(model: fl.Model, capfd: pytest.CaptureFixture, *args, **kw) -> fl.Result:
    """``sim(model).run(*args, **kw)``, asserting that nothing on the terminal says "identically 0" (the SUNDIALS
    warning about a root function that is zero at the start)."""
    res = sim(model).run(*args, progress=False, **kw)
    out, errout = capfd.readouterr()
    assert "identically 0" not in out + errout
    return res


def _fail(model, **kw):
    with pytest.raises(fl.SolverError) as err:
        sim(model).run(2.0, progress=False, **kw)
    res = err.value.result
    assert res is not None and res.status == "failed" and len(res.t) > 1
    return str(err.value), res


def test_blow_up_names_the_growing_variable():
    msg, res = _fail(BlowUp(init={"x": 1.0}))
    assert "at t = 0.99" in msg and "fastest-changing unknowns" in msg
    assert "\n  (model): x = " in msg
    assert 0.99 < res.t[-1] < 1.0


def test_blow_up_in_a_sub_component_names_its_path():
    msg, _ = _fail(Plant(BlowUp(init={"x": 1.0})), dt_out=0.01)
    assert "\n  inner: inner.x = " in msg


def test_division_by_zero_names_the_variables():
    msg, res = _fail(Reciprocal(init={"x": 1.0}))
    ranked = msg.split("fastest-changing unknowns")[1]
    assert "y = " in ranked and "x = " in ranked
    assert ranked.index("y = ") < ranked.index("x = ")  # y = 1/x dominates
    assert res.t[-1] == pytest.approx(1.0, abs=1e-6)


def test_sqrt_of_negative_names_the_equation():
    msg, _ = _fail(Root(init={"x": 1.0}))
    assert "equation (model): square root" in msg
    assert "is not finite" in msg or "evaluates to nan" in msg
    assert "x = -" in msg  # the variable and its (negative) value at the predicted point


def test_sqrt_of_negative_in_a_sub_component():
    msg, _ = _fail(Plant(Root(init={"x": 1.0})), dt_out=0.05)
    assert "equation inner: square root" in msg and "inner.x = " in msg


def test_log_of_zero_names_the_equation():
    msg, _ = _fail(Logarithm(init={"x": 1.0}))
    assert "logarithm" in msg and ("not finite" in msg or "evaluates to" in msg)


def test_step_failure_keeps_result_with_output_grid():
    """The partial result on an output grid: every grid point before the failure (t = 0 … 0.99, 100 rows)."""
    _, res = _fail(BlowUp(init={"x": 1.0}), dt_out=0.01)
    assert len(res.t) >= 100 and res.t[99] == pytest.approx(0.99)


class SignSqrtFlow(fl.Model):
    """p' = −q with q = k·sign(p)·sqrt(|p|) from p = 0: the Jacobian at t0 holds 0·inf."""

    k = Parameter(1.0, unit="1")
    p = Variable(unit="Pa")
    q = Variable(unit="Pa/s")

    def equations(self):
        return [eq(der(self.p), 1.0 - self.q), eq(self.q, self.k * ca.sign(self.p) * ca.sqrt(ca.fabs(self.p)),
                                                   label="turbulent law")]


def test_zero_times_infinity_at_the_start_names_the_law():
    """At p = 0 the Jacobian of the law holds 0·inf = NaN, and Newton needs it (der(p) starts unknown): the
    error names the law, the variable and the remedy."""
    with pytest.raises(fl.InitializationError, match=r"turbulent law: the derivative with respect to p \(= 0\) is "
                                                     r"nan[\s\S]*regularise"):
        sim(SignSqrtFlow(init={"p": 0.0})).run(1.0, progress=False)


def test_regularised_law_runs():
    """The same law with a laminar region (|p| < 1e-3: linear) initialises and settles at q = 1, p = 1 (1e-4)."""

    class Regularised(SignSqrtFlow):
        def equations(self):
            p = self.p
            law = if_else(ca.fabs(p) < 1e-3, p / ca.sqrt(1e-3), ca.sign(p) * ca.sqrt(ca.fabs(p)))
            return [eq(der(self.p), 1.0 - self.q), eq(self.q, self.k * law, label="regularised law")]

    res = sim(Regularised(init={"p": 0.0})).run(20.0, progress=False)
    assert res["p"][-1] == pytest.approx(1.0, rel=1e-4)


# -- quiet start for relations exactly zero at t0 --------------------------------------------------------------
class Asserted(fl.Model):
    """An assertion of parameters only, exactly zero at the default (like a cylinder's x_start >= 0)."""

    x0 = Parameter(0.0, unit="m")
    x = Variable(unit="m")

    def equations(self):
        assert_(self.x0 >= 0.0, "x0 must not be negative")
        return [eq(der(self.x), -self.x)]


def test_parameter_assertion_exactly_zero_is_quiet(capfd):
    res = quiet_run(Asserted(init={"x": 1.0}), capfd, 1.0, dt_out=0.5)
    assert res["x"][-1] == pytest.approx(0.36787944, rel=1e-4)


def test_parameter_assertion_still_fires(capfd):
    with pytest.raises(fl.SolverError,
                       match=r"assertion failed at t = 0 s:\n  Asserted: 0 <= x0: x0 must not be negative"):
        sim(Asserted(init={"x": 1.0})).run(1.0, params={"x0": -1.0}, progress=False)


class Contact(fl.Model):
    """A state relation exactly zero at t0 that leaves zero at once (x = t, event at x >= 0 stays true)."""

    x = Variable(unit="m")
    y = Variable(unit="m")

    def equations(self):
        return [eq(der(self.x), 1.0), eq(self.y, if_else(self.x >= 0.0, self.x, 0.0))]


def test_state_relation_zero_at_start_is_quiet_and_correct(capfd):
    res = quiet_run(Contact(init={"x": 0.0}), capfd, 1.0, dt_out=0.5)
    assert res["y"][-1] == pytest.approx(1.0, abs=1e-9)


def test_cylinder_with_default_x_start_is_quiet(capfd):
    """The README's lift (cylinder x_start = 0 asserted >= 0): no SUNDIALS warning on the terminal."""
    from flexlib.components.hydraulics import DoubleActingCylinder, PressureSource, Tank
    from flexlib.components.mechanics.translational import Fixed, Mass

    class PressureLift(fl.Model):
        def __init__(self):
            super().__init__()
            self.tank, self.source = Tank(), PressureSource(p=50e5)
            self.cylinder = DoubleActingCylinder(d_bore=0.063, d_rod=0.036, stroke=0.4, m=8.0, d=3000.0,
                                                 p_fixed=False)
            self.ground, self.load = Fixed(), Mass(m=500.0)
            self.connect(self.source.port, self.cylinder.port_A)
            self.connect(self.tank.port, self.cylinder.port_B)
            self.connect(self.ground.flange, self.cylinder.flange_a)
            self.connect(self.cylinder.flange_b, self.load.flange_a)

    res = fl.Simulation(PressureLift()).run(0.05, dt_out=0.01, progress=False)
    out, errout = capfd.readouterr()
    assert "identically 0" not in out + errout
    assert res["cylinder.x"][-1] > 0.0


class Fading(fl.Model):
    """(1 − t)·z = x − 2: the equation stops determining z at t = 1 (the iteration matrix becomes singular)."""

    x = Variable(unit="m")
    z = Variable(unit="m")

    def equations(self):
        return [eq(der(self.x), 1.0), eq((1.0 - fl.time) * self.z, self.x - 2.0, label="fading gain")]


def test_singular_iteration_matrix_names_equation_and_variable():
    msg, res = _fail(Fading(init={"x": 0.0}))
    assert "numerically singular" in msg
    assert "fading gain" in msg.split("dependent equations:")[1]
    assert "variables they leave undetermined:\n  (model): z" in msg
    assert res.t[-1] == pytest.approx(1.0, abs=1e-6)


def test_arc_cosine_out_of_range_names_the_equation():
    """y = acos(x) with x = t reaching 1 at t = 1: NaN beyond; named with x's value."""

    class Angle(fl.Model):
        x = Variable(unit="1")
        y = Variable(unit="rad")

        def equations(self):
            return [eq(der(self.x), 1.0), eq(self.y, ca.acos(self.x), label="angle from cosine")]

    msg, res = _fail(Angle(init={"x": 0.0}))
    assert "equation (model): angle from cosine" in msg and "x = 1" in msg
    assert res.t[-1] == pytest.approx(1.0, abs=1e-6)


def test_blow_up_with_casadi_idas_keeps_result():
    """The CasADi-IDAS backend keeps its own message; the partial result is still attached."""
    with pytest.raises(fl.SolverError) as err:
        sim(BlowUp(init={"x": 1.0})).run(2.0, dt_out=0.05, solver="casadi-idas", progress=False)
    assert err.value.result is not None and err.value.result.t[-1] < 1.0


class Resting(fl.Model):
    """A mass resting exactly on a one-sided contact at x = 0 (no force): the indicator stays exactly zero."""

    x = Variable(unit="m")
    v = Variable(unit="m/s")
    push = Parameter(0.0, unit="m/s2")

    def equations(self):
        return [eq(der(self.x), self.v),
                eq(der(self.v), self.push + if_else(self.x < 0.0, -1e4 * self.x - 50.0 * self.v, 0.0))]


def test_relation_identically_zero_over_the_first_step_is_quiet(capfd):
    res = quiet_run(Resting(init={"x": 0.0, "v": 0.0}), capfd, 1.0, dt_out=0.5)
    assert res["x"][-1] == 0.0 and res.stats["state_events"] == 0


def test_relation_zero_at_start_still_switches_when_it_moves(capfd):
    """The same contact pushed into the wall (push = −1 m/s²): the contact event at t = 0⁺ is kept, and the
    mass settles at the static penetration x = push/c = −1e-4 m (1e-9 m)."""
    res = quiet_run(Resting(init={"x": 0.0, "v": 0.0}), capfd, 2.0, dt_out=0.5, params={"push": -1.0})
    assert res.stats["state_events"] >= 1
    assert res["x"][-1] == pytest.approx(-1e-4, abs=1e-9)
