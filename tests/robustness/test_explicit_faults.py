"""Robustness with explicit algebraics eliminated (``FLEXLIB_EXPLICIT``, ``flexlib/compile/explicit.py``): bad
input still gets a message that names the equations and variables as written, not the reduced DAE's rows.

Each case asserts the error class and that the message names the culprit.
"""

from __future__ import annotations

import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq
from flexlib.models.reference.orifice import SquareRootOrifice


@pytest.fixture
def stage(monkeypatch):
    """``FLEXLIB_EXPLICIT=all``: these small models' explicit unknowns are inside IDA's error test, which the
    default scope keeps."""
    monkeypatch.setenv("FLEXLIB_EXPLICIT", "all")


def sim(model, eliminated: str):
    s = fl.Simulation(model, use_cache=False)
    assert eliminated in s.compiled.report.explicit  # the case exercises the stage
    return s


class SingularPart(fl.Model):
    """u + w = 1 and 3u + 3w = 1: regular in structure, singular and inconsistent in value. Eliminating u
    through the first row would leave only ``3(1 − w) + 3w = 1`` to report."""

    u = Variable(unit="m")
    w = Variable(unit="m")
    s = Variable(unit="m")

    def equations(self):
        return [eq(der(self.s), -self.s), eq(self.u + self.w, 1.0, label="sum"),
                eq(3.0 * self.u + 3.0 * self.w, 1.0, label="scaled sum")]


class PartHolder(fl.Model):
    def __init__(self):
        super().__init__()
        self.bad = SingularPart(init={"s": 1.0})


def test_singular_initialisation_names_both_rows_and_both_variables(stage):
    """The failure is diagnosed again on the DAE that keeps the eliminated unknown: both equations and both
    variables of component ``bad`` are named."""
    with pytest.raises(fl.InitializationError) as err:
        sim(PartHolder(), "bad.u").run(0.1)
    msg = str(err.value)
    assert "dependent equations:\n  bad: sum; scaled sum" in msg
    assert "variables they leave undetermined:\n  bad: bad.u; bad.w" in msg


class ExplicitSpring(fl.Model):
    """f = −k·x given explicitly (eliminated with ``FLEXLIB_EXPLICIT=all``)."""

    k = Parameter(4.0, unit="N/m")
    m = Parameter(2.0, unit="kg")
    x = Variable(unit="m")
    v = Variable(unit="m/s")
    f = Variable(unit="N")

    def equations(self):
        return [eq(der(self.x), self.v), eq(self.m * der(self.v), self.f), eq(self.f, -self.k * self.x, label="hooke")]


def test_contradicting_fixed_starts_on_an_eliminated_variable_are_named(stage):
    """x(0) = 0.1 and f(0) = 1.2 fixed, f = −k·x eliminated: the contradiction is reported with both start
    values and the spring law named."""
    with pytest.raises(fl.InitializationError) as err:
        sim(ExplicitSpring(init={"x": 0.1, "f": 1.2, "v": 0.0}), "f").run(0.1)
    msg = str(err.value)
    assert "f = start value" in msg and "x = start value" in msg


class ReciprocalExplicit(fl.Model):
    """x' = −1 from 1, y = 1/x (division by a variable: not used to eliminate y), z = 2·y (explicit)."""

    x = Variable(unit="m")
    y = Variable(unit="1/m")
    z = Variable(unit="1/m")

    def equations(self):
        return [eq(der(self.x), -1.0), eq(self.y, 1.0 / self.x, label="reciprocal"), eq(self.z, 2.0 * self.y)]


def test_division_by_zero_still_names_the_equation(stage):
    """The row ``y = 1/x`` stays in the DAE (it can fail), so the integrator's failure at t = 1 names it."""
    with pytest.raises(fl.SolverError, match="reciprocal"):
        sim(ReciprocalExplicit(init={"x": 1.0}), "z").run(2.0, dt_out=0.1)


def test_non_finite_iteration_matrix_at_a_consistent_start_names_the_law(stage):
    """The catalogue's ``SquareRootOrifice``: with z eliminated the start is consistent without a Newton step, but
    d/d(dp) of sqrt(|dp|) at 0 is not finite: initialisation names the orifice equation and the variable
    instead of an integrator failure at t0."""
    with pytest.raises(fl.InitializationError) as err:
        sim(SquareRootOrifice(), "z").run(0.01)
    msg = str(err.value)
    assert "turbulent orifice: the derivative with respect to p_" in msg and "is not finite" in msg
