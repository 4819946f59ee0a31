"""The public option records: solver objects carry their options (the solver strings are their aliases),
``RunOptions`` holds a run's arguments, ``BuildOptions`` the build's with the environment switches as defaults."""

from __future__ import annotations

import os

import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq
from flexlib.solve.native import native_available


class Osc(fl.Model):
    """x'' = −k·x."""

    k = Parameter(4.0, unit="N/m")
    x = Variable(unit="m")
    v = Variable(unit="m/s")

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), -self.k * self.x)]


@pytest.fixture(scope="module")
def sim() -> fl.Simulation:
    return fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), use_cache=False)


def test_solver_object_carries_max_order(sim):
    by_object = sim.run(2.0, dt_out=0.1, solver=fl.IDA(max_order=2), progress=False)
    by_argument = sim.run(2.0, dt_out=0.1, max_order=2, progress=False)
    assert by_object.stats["max_order"] == 2 and by_object.stats["steps"] == by_argument.stats["steps"]
    np.testing.assert_array_equal(by_object["x"], by_argument["x"])


def test_solver_strings_are_aliases_of_objects(sim):
    alias = sim.run(1.0, dt_out=0.1, solver="ida-sksundae", progress=False)
    obj = sim.run(1.0, dt_out=0.1, solver=fl.IDA(native=False), progress=False)
    assert alias.stats["solver"] == obj.stats["solver"] == "ida-sksundae"
    np.testing.assert_array_equal(alias["x"], obj["x"])
    casadi = sim.run(1.0, dt_out=0.1, solver=fl.CasadiIDAS(max_order=3), progress=False)
    assert casadi.stats["solver"] == "casadi-idas" and casadi.stats["max_order"] == 3


@pytest.mark.skipif(not native_available(), reason="the C driver is not available")
def test_ida_linear_solver_option(sim):
    res = sim.run(1.0, dt_out=0.1, solver=fl.IDA(linear_solver="superlumt"), progress=False)
    assert res.stats["linear_solver"] == "superlumt" and res.stats["solver"] == "ida-native"


@pytest.mark.parametrize("make", [lambda: fl.IDA(max_order=7), lambda: fl.IDA(linear_solver="lu"),
                                  lambda: fl.IDA(native="yes"), lambda: fl.CasadiIDAS(max_order=0),
                                  lambda: fl.BuildOptions(tree_frames="cut"), lambda: fl.BuildOptions(explicit=2)])
def test_invalid_options_are_named(make):
    with pytest.raises(fl.RunArgumentError):
        make()


def test_run_options_record(sim):
    direct = sim.run(1.0, dt_out=0.1, rtol=1e-8, progress=False)
    record = sim.run(options=fl.RunOptions(t_end=1.0, dt_out=0.1, rtol=1e-8, progress=False))
    np.testing.assert_array_equal(direct.t, record.t)
    np.testing.assert_array_equal(direct["x"], record["x"])
    longer = sim.run(2.0, options=fl.RunOptions(t_end=1.0, dt_out=0.1, progress=False))  # the argument wins
    assert longer.t[-1] == 2.0
    with pytest.raises(fl.RunArgumentError, match="options"):
        sim.run(options={"t_end": 1.0})


def test_build_options_record():
    before = os.environ.get("FLEXLIB_EXPLICIT")
    sim = fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), build=fl.BuildOptions(codegen=False, use_cache=False,
                                                                              explicit=False, tree_frames="keep"))
    assert sim.build_options.explicit is False and os.environ.get("FLEXLIB_EXPLICIT") == before  # scoped to the build
    res = sim.run(1.0, dt_out=0.5, progress=False)
    np.testing.assert_allclose(res["x"], np.cos(2.0 * res.t), atol=1e-5)
    with pytest.raises(fl.RunArgumentError, match="not both"):
        fl.Simulation(Osc(), codegen=False, build=fl.BuildOptions())
    with pytest.raises(fl.RunArgumentError, match="BuildOptions"):
        fl.Simulation(Osc(), build={"codegen": False})
