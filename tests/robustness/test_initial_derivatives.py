"""Initial equations with ``der()`` of a variable that is not a state (issue 26).

MSL's ``Blocks.Examples.PID_Controller`` writes ``der(spring.w_rel) = 0``; MSL makes ``w_rel`` a state, flexlib may
keep it as a dummy derivative, so CasADi stopped the build with "variables [der(w_rel)] are free". The derivative
is now taken from the index-reduced system (as Modelica tools do); a variable the equations do not express in
the states is refused, naming the initial equation, the variable and what to write instead.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib import ModelError, Variable, der, eq, time
from flexlib.components.mechanics.rotational import Inertia, SpringDamper

C, D, J1, J2, PHI0 = 1e4, 100.0, 1.0, 2.0, 0.01  # N.m/rad, N.m.s/rad, kg.m2, kg.m2, rad


class StretchedTwoInertias(fl.Model):
    """inertia1 (held at rest by its start values) — spring/damper — inertia2; the spring starts stretched."""

    def __init__(self, on_w_rel: bool = True):
        super().__init__()
        self.on_w_rel = on_w_rel
        self.i1 = Inertia(J=J1, init={"phi": 0.0, "w": 0.0})
        self.spring = SpringDamper(c=C, d=D)
        self.i2 = Inertia(J=J2)
        self.connect(self.i1.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.i2.flange_a)

    def initial_equations(self):
        steady = (eq(der(self.spring.w_rel), 0.0) if self.on_w_rel  # as MSL writes it
                  else eq(der(self.i2.w), der(self.i1.w)))          # the same condition on the states
        return [steady, eq(self.spring.phi_rel, PHI0)]


def test_der_of_a_dummy_derivative_is_taken_from_the_reduced_system():
    res = fl.Simulation(StretchedTwoInertias(), use_cache=False).run(0.05, dt_out=0.01)
    # der(w_rel) = a2 - a1 = -tau (1/J2 + 1/J1) = 0 -> tau = c phi_rel + d w_rel = 0 -> w_rel = -c phi0 / d
    assert res["spring.w_rel"][0] == pytest.approx(-C * PHI0 / D, rel=1e-9)
    assert res["spring.phi_rel"][0] == pytest.approx(PHI0, rel=1e-12)
    assert abs(res["i2.a"][0]) < 1e-9 and abs(res["i1.a"][0]) < 1e-9


def test_same_run_as_the_condition_written_on_states():
    a = fl.Simulation(StretchedTwoInertias(), use_cache=False).run(0.05, dt_out=0.01, rtol=1e-9, atol=1e-12)
    b = fl.Simulation(StretchedTwoInertias(on_w_rel=False), use_cache=False).run(0.05, dt_out=0.01, rtol=1e-9,
                                                                                 atol=1e-12)
    for name in ("spring.w_rel", "i2.w", "i2.phi", "spring.tau"):
        assert np.allclose(a[name], b[name], rtol=1e-7, atol=1e-9), name


class LagWithRamp(fl.Model):
    """x' = u - x with v = x + 2 t (an expression of a state and time): der(v) = 0 at the start gives x'(0) = -2."""

    x = Variable()
    v = Variable()

    def equations(self):
        return [eq(der(self.x), 1.0 - self.x), eq(self.v, self.x + 2.0 * time)]

    def initial_equations(self):
        return [eq(der(self.v), 0.0)]


def test_der_of_an_expression_of_a_state_and_time():
    res = fl.Simulation(LagWithRamp(), use_cache=False).run(0.1, dt_out=0.05)
    assert res["x"][0] == pytest.approx(3.0, rel=1e-9)  # x' = 1 - x = -2


class Implicit(fl.Model):
    """v defined implicitly (v^3 + v = x): no row gives it explicitly in the states."""

    x = Variable()
    v = Variable(start=0.5)

    def equations(self):
        return [eq(der(self.x), 1.0 - self.x), eq(self.v**3 + self.v, self.x)]

    def initial_equations(self):
        return [eq(der(self.v), 0.0)]


def test_der_of_an_implicit_algebraic_variable_is_refused_naming_it():
    with pytest.raises(ModelError, match=r"initial equation of \(model\): der\(v\) = 0: der\(v\) is not known at the "
                                         r"start: v is not a state.*state_select='prefer'.*steady_state=True"):
        fl.Simulation(Implicit(), use_cache=False)


class Twice(fl.Model):
    x = Variable()
    v = Variable()

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), -self.x)]

    def initial_equations(self):
        return [eq(der(der(self.x)), 0.0), eq(self.x, 1.0)]


def test_second_derivative_in_an_initial_equation_is_refused_naming_it():
    with pytest.raises(ModelError, match=r"der\(der\(x\)\) = 0: der\(der\(x\)\) cannot be evaluated at the start"):
        fl.Simulation(Twice(), use_cache=False)
