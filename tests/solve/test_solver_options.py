"""Run switches as solver options: ``IDA(error_test_all=..., linear_solver=..., native=...)`` and
``CasadiIDAS(error_test_all=...)`` give what the environment variables behind them (their defaults) give, and a value
given wins over the environment."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_integrator_protocol import PushedOscillator

import flexlib as fl
from flexlib.solve.backends import base
from flexlib.solve.native import native_available
from flexlib.solve.solvers import as_solver

SWITCHES = ("FLEXLIB_ERROR_TEST_ALL", "FLEXLIB_LINSOL", "FLEXLIB_NATIVE")


@pytest.fixture
def sim(monkeypatch) -> fl.Simulation:
    for name in SWITCHES:
        monkeypatch.delenv(name, raising=False)
    return fl.Simulation(PushedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


class Model:
    nominal = np.ones(2)
    derivative_level = np.array([False, True])


def test_error_test_all_option_and_its_environment_default(monkeypatch):
    monkeypatch.delenv("FLEXLIB_ERROR_TEST_ALL", raising=False)
    assert base.absolute_tolerances(Model, 1e-8).tolist() == [1e-8, 1e20]
    assert base.absolute_tolerances(Model, 1e-8, True).tolist() == [1e-8, 1e-8]
    monkeypatch.setenv("FLEXLIB_ERROR_TEST_ALL", "1")
    assert base.absolute_tolerances(Model, 1e-8).tolist() == [1e-8, 1e-8]
    assert base.absolute_tolerances(Model, 1e-8, False).tolist() == [1e-8, 1e20]  # the value given wins
    integ = fl.IDA(native=False).integrator(rtol=1e-6, atol=1e-8, max_step=0.0, max_order=5, max_steps=10)
    assert integ.error_test_all is True  # resolved from the environment when the run starts
    integ = fl.CasadiIDAS(error_test_all=False).integrator(rtol=1e-6, atol=1e-8, max_step=0.0, max_order=5,
                                                          max_steps=10)
    assert integ.error_test_all is False


@pytest.mark.parametrize("solver", ["ida-sksundae", "casadi-idas"] + (["ida-native"] if native_available() else []))
def test_error_test_all_option_runs_as_the_environment_switch(sim, monkeypatch, solver):
    """The run with ``error_test_all=True`` is the run with ``FLEXLIB_ERROR_TEST_ALL=1``, step for step."""
    obj = as_solver(solver)
    by_option = sim.run(2.0, dt_out=0.1, solver=dataclasses.replace(obj, error_test_all=True), progress=False)
    monkeypatch.setenv("FLEXLIB_ERROR_TEST_ALL", "1")
    by_environment = sim.run(2.0, dt_out=0.1, solver=solver, progress=False)
    assert by_option.stats["steps"] == by_environment.stats["steps"]
    np.testing.assert_array_equal(by_option["x"], by_environment["x"])


@pytest.mark.skipif(not native_available(), reason="the C driver is not available")
def test_linear_solver_option_wins_over_the_environment(sim, monkeypatch):
    monkeypatch.setenv("FLEXLIB_LINSOL", "superlumt")
    assert sim.run(0.5, progress=False).stats["linear_solver"] == "superlumt"  # the default: the environment's
    res = sim.run(0.5, solver=fl.IDA(linear_solver="dense"), progress=False)
    assert res.stats["linear_solver"] == "dense"


@pytest.mark.skipif(not native_available(), reason="the C driver is not available")
def test_native_option_wins_over_the_environment(sim, monkeypatch):
    monkeypatch.setenv("FLEXLIB_NATIVE", "0")
    assert sim.run(0.5, progress=False).stats["solver"] == "ida-sksundae"  # the default: the environment's
    assert sim.run(0.5, solver=fl.IDA(native=True), progress=False).stats["solver"] == "ida-native"


@pytest.mark.parametrize("make", [lambda: fl.IDA(error_test_all="yes"), lambda: fl.CasadiIDAS(error_test_all=2)])
def test_invalid_switch_values_are_named(make):
    with pytest.raises(fl.RunArgumentError, match="error_test_all"):
        make()
