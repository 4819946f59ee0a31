"""The public option records: solver objects carry their options (the solver strings are their aliases),
``RunOptions`` holds a run's arguments, ``BuildOptions`` the build's with the environment switches as defaults."""

from __future__ import annotations

import os

import numpy as np
import pytest
from test_integrator_protocol import PushedOscillator, exact_x

import flexlib as fl
from flexlib.solve.native import native_available


@pytest.fixture(scope="module")
def sim() -> fl.Simulation:
    return fl.Simulation(PushedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


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
    options = fl.BuildOptions(codegen=False, use_cache=False, explicit=False, tree_frames="keep")
    sim = fl.Simulation(PushedOscillator(init={"x": 1.0, "v": 0.0}), build=options)
    assert sim.build_options.explicit is False and os.environ.get("FLEXLIB_EXPLICIT") == before  # scoped to the build
    res = sim.run(1.0, dt_out=0.5, progress=False)
    np.testing.assert_allclose(res["x"], exact_x(res.t), atol=1e-5)
    with pytest.raises(fl.RunArgumentError, match="not both"):
        fl.Simulation(PushedOscillator(), codegen=False, build=fl.BuildOptions())
    with pytest.raises(fl.RunArgumentError, match="BuildOptions"):
        fl.Simulation(PushedOscillator(), build={"codegen": False})
