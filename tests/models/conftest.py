"""Shared pump-truck runs: each registered scenario runs once per test session, rigid or flexible."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from functools import cache

import pytest

import flexlib as fl
from flexlib.registry import get_model, run_scenario


def _pump_truck_run(scenario: str, flexible: bool = False) -> fl.Result:
    # one key per run: functools.cache keys f("a") and f("a", False) apart, which ran expand-fold twice
    return _cached_run(str(scenario), bool(flexible))


@cache
def _cached_run(scenario: str, flexible: bool) -> fl.Result:
    sc = get_model("pump-truck").scenario(scenario)
    if flexible:
        sc = replace(sc, options={**sc.options, "flexible": True})
    return run_scenario("pump-truck", sc, progress=False).result


@pytest.fixture(scope="session")
def pump_truck_run() -> Callable[..., fl.Result]:
    """``pump_truck_run(scenario, flexible=False)``: the registered scenario's result (cached for the session)."""
    return _pump_truck_run


@pytest.fixture(scope="session")
def polycrank_flexible() -> tuple:
    """``(model, sim)``: the POLYCRANK study's flexible fragment (``pulse_model(True)``: 30 Craig–Bampton pull rods,
    rigid shields, bearing friction built in, rods mounted for the study's preload) in the hanging pose, on CasADi's
    virtual machine (the runs here are short, and gcc would take minutes and 3 GB beside the suite); built once per
    session."""
    from flexlib.models.robots.polycrank_study import pulse_model

    model = pulse_model(True)
    return model, fl.Simulation(model, codegen=False)
