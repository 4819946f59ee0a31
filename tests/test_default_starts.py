"""Start values with ``fixed="default"`` (``Component.set_start``): initial conditions only where the initial system
needs them, taken in the model's order and only when independent of the equations and of the conditions already
given. References: the analytic solutions of the small models below."""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib import InitializationError, ModelError


class Pair(fl.Component):
    """Two points on a line, rigidly 1 m apart (x2 = x1 + 1), with a spring to the origin on x1 (k = 4, m = 1)."""

    x1 = fl.Variable(unit="m")
    x2 = fl.Variable(unit="m")
    v1 = fl.Variable(unit="m/s")

    def equations(self):
        return [fl.eq(fl.der(self.x1), self.v1), fl.eq(fl.der(self.v1), -4.0 * self.x1),
                fl.eq(self.x2, self.x1 + 1.0)]


def test_defaults_fill_only_what_is_missing():
    """Default starts x1 = 0.5, x2 = 5, v1 = 0: x1 and v1 are taken, x2's default (inconsistent with x2 = x1 + 1) is
    not, so no over-specified start: x1(t) = 0.5 cos 2t (1e-6), x2 = x1 + 1."""
    pair = Pair()
    pair.set_start("x1", 0.5, fixed="default")
    pair.set_start("x2", 5.0, fixed="default")
    pair.set_start("v1", 0.0, fixed="default")
    res = fl.Simulation(pair, use_cache=False).run(1.0, dt_out=0.1, rtol=1e-10, atol=1e-12, progress=False)
    np.testing.assert_allclose(res["x1"], 0.5 * np.cos(2 * res.t), atol=1e-6)
    np.testing.assert_allclose(res["x2"], res["x1"] + 1.0, atol=1e-12)


def test_given_conditions_win_over_defaults():
    """A fixed start on x2 (x2 = 1.25, so x1 = 0.25) takes precedence: x1's default 0.5 is not used."""
    pair = Pair(init={"x2": 1.25, "v1": 0.0})
    pair.set_start("x1", 0.5, fixed="default")
    res = fl.Simulation(pair, use_cache=False).run(0.5, dt_out=0.1, progress=False)
    assert res["x1"][0] == pytest.approx(0.25, abs=1e-9)


def test_fixed_true_still_over_specifies():
    """The same starts given as initial conditions over-specify the start, as before."""
    pair = Pair(init={"x1": 0.5, "x2": 5.0, "v1": 0.0})
    with pytest.raises(InitializationError, match="over-specified"):
        fl.Simulation(pair, use_cache=False).run(0.1, progress=False)


def test_bad_fixed_value_is_named():
    with pytest.raises(ModelError, match=r"x1: fixed must be True, False or 'default'"):
        Pair().set_start("x1", 0.0, fixed="sometimes")
