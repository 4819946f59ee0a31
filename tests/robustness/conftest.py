"""Fixtures shared by the robustness tests."""

from __future__ import annotations

import pytest

import flexlib as fl


@pytest.fixture
def no_work(sim: fl.Simulation, monkeypatch: pytest.MonkeyPatch) -> fl.Simulation:
    """The module's ``sim``, failing the test if a run gets as far as initialisation (arguments come first)."""

    def forbidden(*args, **kwargs):
        raise AssertionError("run() started work before checking its arguments")

    monkeypatch.setattr(sim, "_initialize", forbidden)
    return sim
