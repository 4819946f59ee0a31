"""Robustness: initialisation failures name their source (issue 8, "Messages that do not say where").

Each case asserts the error class and that the message names the culprit: the parameter or start value,
the equation (component path and label) and the variable. References and tolerances are stated per test.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq, if_else
from flexlib.models.reference.hydraulic_boom import A_P, A_R, BORE, ROD, CylinderBoom
from flexlib.models.reference.orifice import SquareRootOrifice
from flexlib.units import g_n


class Lag(fl.Model):
    """x' = -k·x."""

    k = Parameter(1.0, unit="1/s")
    x = Variable(unit="m", start=1.0, fixed=True)

    def equations(self):
        return [eq(der(self.x), -self.k * self.x, label="lag")]


class LagHolder(fl.Model):
    def __init__(self, **init):
        super().__init__()
        self.lag = Lag(init=init)


def sim(model):
    return fl.Simulation(model, use_cache=False)


# -- 1. non-finite parameters and start values, named up front -----------------------------------------------
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_non_finite_fixed_start_value_is_named(value):
    with pytest.raises(fl.InitializationError,
                       match=r"start values must be finite; not finite: lag\.x = (nan|inf|-inf) \(fixed\)"):
        sim(LagHolder(x=value)).run(0.1)


def test_non_finite_guess_is_named():
    """A start value that is only a guess (not fixed) is checked as well: it seeds Newton's iteration."""

    class Guess(fl.Model):
        x = Variable(unit="m")
        y = Variable(unit="m", start=math.nan)

        def equations(self):
            return [eq(der(self.x), -self.x), eq(self.y**2, 4.0 + self.x)]

    with pytest.raises(fl.InitializationError, match=r"not finite: y = nan\b"):
        sim(Guess(init={"x": 0.0})).run(0.1)


def test_non_finite_parameter_override_is_named():
    with pytest.raises(fl.ParameterError, match=r"lag\.k.*not finite"):
        sim(LagHolder(x=1.0)).run(0.1, params={"lag.k": math.nan})


# -- 2. non-finite residuals and Jacobian entries at the start point ---------------------------------------------
class ReciprocalAtZero(fl.Model):
    """y = 1/x with x fixed at 0: the residual is infinite at the start."""

    x = Variable(unit="m", start=0.0, fixed=True)
    y = Variable(unit="1/m")

    def equations(self):
        return [eq(der(self.x), 1.0), eq(self.y * 1.0, 1.0 / self.x, label="reciprocal")]


def test_division_by_zero_at_start_names_equation_and_variable():
    with pytest.raises(fl.InitializationError, match=r"non-finite values:[\s\S]*reciprocal[\s\S]*x = 0"):
        sim(ReciprocalAtZero()).run(0.1)


class LogChamber(fl.Model):
    """Chamber with p = p_ref + beta·ln(m/(rho·V)) (isothermal liquid, constant bulk modulus); der(m) = q·rho."""

    V = Parameter(1e-3, unit="m3")
    beta = Parameter(1.6e9, unit="Pa")
    rho = Parameter(870.0, unit="kg/m3")
    p_ref = Parameter(1e5, unit="Pa")
    q = Parameter(0.0, unit="m3/s")
    m = Variable(unit="kg", nominal=1.0, start=0.9)
    p = Variable(unit="Pa", nominal=1e7)

    def equations(self):
        return [eq(der(self.m), self.q * self.rho),
                eq(self.p, self.p_ref + self.beta * ca.log(self.m / (self.rho * self.V)), label="pressure from mass")]


def test_log_of_zero_at_the_guess_names_equation_and_variable():
    """Start guess m = 0 makes ln(m) = -inf: the message names the equation and m = 0, not an empty list."""
    with pytest.raises(fl.InitializationError,
                       match=r"non-finite values:[\s\S]*pressure from mass evaluates to -?inf[\s\S]*m = 0") as err:
        model = LogChamber(init={"p": 1e7})
        model.set_start("m", 0.0, fixed=False)
        sim(model).run(0.1)
    assert "largest residuals:\n\n" not in str(err.value)


def test_zero_times_infinity_jacobian_names_the_flow_law():
    """sign(dp)·sqrt(|dp|) at dp = 0: its derivative 0·inf is NaN. The message names the orifice equation, the
    variable and the remedy instead of large residuals in unrelated equations."""
    with pytest.raises(fl.InitializationError) as err:
        sim(SquareRootOrifice()).run(0.01)
    msg = str(err.value)
    assert "turbulent orifice: the derivative with respect to p_" in msg
    assert "is not finite" in msg and "regularise" in msg and "laminar" in msg


# -- 3. scaled consistency test ---------------------------------------------------------------------------------
@pytest.mark.parametrize("p0", [1e7, 1.35e7, 2e7])
@pytest.mark.parametrize("V", [1e-3, 3.3e-4])
def test_round_off_on_a_1e7_pa_equation_initialises(p0, V):
    """p = p_ref + beta·ln(m/(rho·V)) with p fixed: the residual cannot go below ~beta·eps ≈ 2e-8 Pa (the ulp of
    m moves ln by 1e-16), which the former absolute 1e-10 (1e-8 on retry) refused; the per-equation scale
    (|dF/dp|·nominal(p) = 1e7) accepts it. Reference: m = rho·V·exp((p0 − p_ref)/beta), 1e-12 relative."""
    res = sim(LogChamber(V=V, init={"p": p0})).run(0.01, dt_out=0.01)
    np.testing.assert_allclose(res["m"][0], 870.0 * V * math.exp((p0 - 1e5) / 1.6e9), rtol=1e-12)
    np.testing.assert_allclose(res["p"], p0, rtol=1e-12)


class QuadraticChamber(LogChamber):
    """p = p_ref + beta·(m/(rho·V))²: no solution for p < p_ref."""

    def equations(self):
        return [eq(der(self.m), self.q * self.rho),
                eq(self.p, self.p_ref + self.beta * (self.m / (self.rho * self.V)) ** 2, label="pressure from mass")]


def test_genuinely_inconsistent_start_is_still_refused():
    """p fixed 0.5 bar below p_ref has no solution: the residual stays >= 5e4 Pa, far above tol·scale."""
    with pytest.raises(fl.InitializationError,
                       match=r"largest residuals:\n  \|residual\| = 5e\+04 .*pressure from mass"):
        sim(QuadraticChamber(init={"p": 0.5e5})).run(0.01)


# -- 4. numerically singular systems name the dependent equations -------------------------------------------------
class Dependent(fl.Model):
    """x + y = 1 and 2x + 2y = 3: structurally regular, numerically singular and inconsistent."""

    x = Variable(unit="m")
    y = Variable(unit="m")
    s = Variable(unit="m")

    def equations(self):
        return [eq(der(self.s), -self.s), eq(self.x + self.y, 1.0, label="sum"),
                eq(2.0 * self.x + 2.0 * self.y, 3.0, label="double sum")]


def test_singular_initialisation_names_dependent_equations_and_variables():
    with pytest.raises(fl.InitializationError) as err:
        sim(Dependent(init={"s": 1.0})).run(0.1)
    msg = str(err.value)
    assert "numerically singular" in msg
    dep = msg.split("dependent equations:")[1]
    assert "sum" in dep and "double sum" in dep
    free = msg.split("variables they leave undetermined:")[1]
    assert "x" in free and "y" in free and " s" not in free


class Part(fl.Model):
    """A component whose two unknowns are fixed by a singular, inconsistent pair of equations."""

    u = Variable(unit="m")
    w = Variable(unit="m")

    def equations(self):
        return [eq(self.u + self.w, 1.0, label="sum"), eq(3.0 * self.u + 3.0 * self.w, 1.0, label="scaled sum")]


class Coupled(fl.Model):
    def __init__(self):
        super().__init__()
        self.good = LagHolder(x=1.0)
        self.bad = Part()


def test_singular_initialisation_groups_by_component():
    with pytest.raises(fl.InitializationError) as err:
        sim(Coupled()).run(0.1)
    msg = str(err.value)
    assert "dependent equations:\n  bad: sum; scaled sum" in msg
    assert "variables they leave undetermined:\n  bad: bad.u; bad.w" in msg
    assert "good" not in msg.split("numerically singular")[1]


# -- 5. steady state of a boom held by a cylinder -----------------------------------------------------------------


def test_steady_state_holds_the_boom():
    """steady_state=True with the boom angle fixed gives the static equilibrium: the cylinder force balances the
    weight's moment about the hinge (1e-6 relative), the boom does not accelerate (|a| < 1e-6 rad/s²), the
    supply sits on its relief valve (der(m) = 0) and the chamber pressures hold the load.

    Reference: moment balance about the hinge, F·|r_mid × e| = m·g·cos(phi)·1 m with e the cylinder's unit
    vector; formerly the hydraulic rows won and the boom started at 10.8 rad/s²."""
    model = CylinderBoom()
    res = fl.Simulation(model).run(0.01, dt_out=0.005, steady_state=True, rtol=1e-8, atol=1e-10, progress=False)
    phi = 0.3
    mid = 0.5 * np.array([math.cos(phi), math.sin(phi)])
    base = np.array([0.3, -0.8])
    e = (mid - base) / np.linalg.norm(mid - base)
    F = res["cyl.cylinder.F"][0]
    lever = mid[0] * e[1] - mid[1] * e[0]
    np.testing.assert_allclose(F * lever, 200.0 * g_n * math.cos(phi) * 1.0, rtol=1e-6)
    p_A, p_B = res["cyl.cylinder.p_A"][0], res["cyl.cylinder.p_B"][0]
    F_hyd = p_A * A_P - p_B * A_R - 1.01325e5 * (A_P - A_R)
    np.testing.assert_allclose(F_hyd, F, rtol=1e-6)  # no friction at rest: the pressures carry the load
    assert abs(res["hinge.a"][0]) < 1e-6
    assert abs(res["hinge.w"][-1]) < 1e-5 and abs(res["hinge.phi"][-1] - phi) < 1e-8
    assert res["supply.p"][0] > 160e5  # on the relief valve
    assert abs(res["supply.p"][-1] / res["supply.p"][0] - 1.0) < 1e-6  # and stays there: der(supply.m) ≈ 0
    for name in ("cyl.cylinder.m_A", "cyl.cylinder.m_B", "supply.m"):  # stored masses (~0.3–1 kg) at rest:
        assert abs(res[name][-1] - res[name][0]) < 1e-9, name  # only the closed valve's 1e-12 m² leakage moves them


def test_steady_state_with_fixed_pressures_names_the_conflict():
    """With the chamber pressures fixed (p_fixed=True: 50 and 20 bar) and the angle fixed, no equilibrium exists:
    the error names the state that would not be at rest and the fixed start value in the way."""
    with pytest.raises(fl.InitializationError) as err:
        fl.Simulation(CylinderBoom(p_fixed=True)).run(0.01, steady_state=True, progress=False)
    msg = str(err.value)
    assert "no equilibrium with the fixed start values" in msg
    assert "der(hinge.w)" in msg and "component hinge" in msg
    assert "hinge.phi = 0.3 (fixed start value)" in msg
    assert "cyl.cylinder: start pressure A (initial equation)" in msg


def _lift():
    from flexlib.components.control import Constant
    from flexlib.components.hydraulics import (
        DirectionalValve43,
        DoubleActingCylinder,
        FixedDisplacementPump,
        PressureReliefValve,
        Tank,
        Volume,
    )
    from flexlib.components.mechanics.translational import Fixed, Force, Mass

    class Lift(fl.Model):
        """A 500 kg load under gravity (constant force −m·g) on a vertical 63/36 cylinder started at x = 0.2 m
        (the cylinder's own initial equation, x_fixed), closed-centre valve, pump with 160 bar relief."""

        def __init__(self):
            super().__init__()
            self.tank, self.supply = Tank(), Volume(V=5e-4)
            self.pump = FixedDisplacementPump(D=20e-6 / (2 * math.pi))
            self.speed = Constant(k=1500 * 2 * math.pi / 60)
            self.relief = PressureReliefValve(p_crack=160e5, p_grad=4e9)
            self.valve = DirectionalValve43(Q_nom=40 / 60000, dp_nom=35e5)
            self.cmd = Constant(k=0.0)
            self.cylinder = DoubleActingCylinder(d_bore=BORE, d_rod=ROD, stroke=0.4, m=8.0, d=3000.0, p_fixed=False,
                                                 x_start=0.2)
            self.ground, self.load = Fixed(), Mass(m=500.0)
            self.weight, self.g = Force(), Constant(k=-500.0 * 9.81)
            self.connect(self.speed.y, self.pump.w)
            self.connect(self.cmd.y, self.valve.u)
            self.connect(self.g.y, self.weight.f)
            self.connect(self.weight.flange, self.load.flange_b)
            self.connect(self.tank.port, self.pump.port_a, self.relief.port_b, self.valve.port_T)
            self.connect(self.pump.port_b, self.supply.port, self.relief.port_a, self.valve.port_P)
            self.connect(self.valve.port_A, self.cylinder.port_A)
            self.connect(self.valve.port_B, self.cylinder.port_B)
            self.connect(self.ground.flange, self.cylinder.flange_a)
            self.connect(self.cylinder.flange_b, self.load.flange_a)

    return Lift()


def test_steady_state_holds_a_load_on_a_1d_cylinder():
    """1D DoubleActingCylinder with x fixed by its initial equation: steady_state=True gives the holding
    pressures, p_A·A_P − p_B·A_R − p_ref·(A_P − A_R) = m·g (no friction at rest), 1e-6 relative; the load does
    not accelerate (|a| < 1e-6 m/s²). Formerly the hydraulic rows won: p_A = p_B and a = 8.4 m/s²."""
    res = fl.Simulation(_lift()).run(0.02, dt_out=0.01, steady_state=True, rtol=1e-8, atol=1e-10, progress=False)
    p_A, p_B = res["cylinder.p_A"][0], res["cylinder.p_B"][0]
    np.testing.assert_allclose(p_A * A_P - p_B * A_R - 1.01325e5 * (A_P - A_R), 500.0 * 9.81, rtol=1e-6)
    assert abs(res["cylinder.a"][0]) < 1e-6 and abs(res["cylinder.x"][-1] - 0.2) < 1e-8


class AnglePendulum(fl.Model):
    """Simple pendulum phi'' = -g/L·sin(phi)."""

    phi = Variable(unit="rad")
    w = Variable(unit="rad/s")

    def equations(self):
        return [eq(der(self.phi), self.w), eq(der(self.w), -9.81 * ca.sin(self.phi))]


def test_steady_state_pendulum_off_its_equilibrium_is_refused():
    with pytest.raises(fl.InitializationError,
                       match=r"der\(w\) = -2\.89[\s\S]*conflicting conditions.*: phi = 0\.3 \(fixed start value\)\."):
        sim(AnglePendulum(init={"phi": 0.3, "w": 0.0})).run(0.1, steady_state=True)


def test_steady_state_pendulum_at_its_equilibrium_runs():
    """phi = 0 fixed is an equilibrium: it stays there exactly (1e-12)."""
    res = sim(AnglePendulum(init={"phi": 0.0, "w": 0.0})).run(0.1, dt_out=0.05, steady_state=True)
    np.testing.assert_allclose(res["phi"], 0.0, atol=1e-12)


def test_steady_state_leaves_free_states_to_make_the_equilibrium():
    """Pendulum with only w fixed: steady_state=True chooses phi = 0 (the equilibrium), 1e-10."""
    res = sim(AnglePendulum(init={"w": 0.0})).run(0.1, dt_out=0.05, steady_state=True)
    np.testing.assert_allclose(res["phi"], 0.0, atol=1e-10)


# -- 6. event re-initialisation ------------------------------------------------------------------------------------
class Switched(fl.Model):
    """s·z = x − 2 with s switching from 1 to 0 at t = 0.5: after the event z is undetermined and x ≠ 2."""

    x = Variable(unit="m")
    z = Variable(unit="m")

    def equations(self):
        s = if_else(fl.time >= 0.5, 0.0, 1.0)
        return [eq(der(self.x), 1.0), eq(s * self.z, self.x - 2.0, label="switched gain")]


def test_singular_reinit_at_an_event_names_the_equation():
    with pytest.raises(fl.SolverError) as err:
        sim(Switched(init={"x": 0.0})).run(1.0)
    msg = str(err.value)
    assert "t = 0.5" in msg and "switched gain" in msg
    assert "variables they leave undetermined:\n  (model): z" in msg
    assert err.value.result is not None and err.value.result.t[-1] == pytest.approx(0.5)


def test_steady_state_with_a_spool_fixed_off_its_command_names_the_valve():
    """The valve's spool starts fixed at 0 (component default) while the command is 0.5: no equilibrium; the
    error names the spool state of the valve and its fixed start value."""
    model = CylinderBoom()
    model.cmd.k = 0.5
    with pytest.raises(fl.InitializationError, match=r"der\(valve\.vs\) = [\s\S]*valve\.xs = 0 \(fixed start value\)"):
        fl.Simulation(model).run(0.01, steady_state=True, progress=False)


def test_non_finite_start_of_a_vector_variable_is_named():
    """A NaN in one entry of a 3D body's start position names that entry (0-based, as the result names it)."""
    from flexlib.components.mechanics.multibody import Body, World

    class FreeBody(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World()
            self.body = Body(m=1.0, I=np.eye(3), init={"r_0": [0.0, math.nan, 0.0], "v_0": [0.0, 0.0, 0.0]})

    with pytest.raises(fl.InitializationError, match=r"not finite: body\.r_0\[1\] = nan \(fixed\)"):
        sim(FreeBody()).run(0.1)
