"""The disk cache's key covers the data a model class's code reads that its source file does not hold (issue 26).

A class made by a factory function has the same source for every argument, and a module constant computed at import
is not in the source either: a model built with ``k = 5`` found the cached build of ``k = 1`` and ran it, giving
exp(-1) instead of exp(-5) (found from outside). Reference: the closed form x = exp(-k t).
"""

from __future__ import annotations

import importlib
import textwrap

import numpy as np
import pytest

import flexlib as fl
from flexlib import Variable, der, eq


def make(k):
    class RateDecay(fl.Model):
        x = Variable()

        def equations(self):
            return [eq(der(self.x), -k * self.x)]

    return RateDecay


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path / "cache"))


def test_a_class_from_a_factory_is_keyed_by_its_closure(cache):
    for k in (1.0, 5.0, 1.0):
        sim = fl.Simulation(make(k)(init={"x": 1.0}))
        res = sim.run(1.0, rtol=1e-10, atol=1e-12)
        assert res["x"][-1] == pytest.approx(np.exp(-k), rel=1e-6), k
    assert sim.build_info.get("cached")  # the third build (k = 1 again) is the first one's entry


def test_a_module_constant_read_at_import_is_part_of_the_key(cache, tmp_path, monkeypatch):
    """The module's source stays the same; the constant comes from a data file read at import."""
    (tmp_path / "decay_model_k.py").write_text(textwrap.dedent("""
        from pathlib import Path

        import flexlib as fl
        from flexlib import Variable, der, eq

        K = float((Path(__file__).parent / "k.txt").read_text())

        class Decay(fl.Model):
            x = Variable()

            def equations(self):
                return [eq(der(self.x), -K * self.x)]
    """))
    monkeypatch.syspath_prepend(str(tmp_path))
    mod = None
    for k in (1.0, 3.0):
        (tmp_path / "k.txt").write_text(repr(k))
        mod = importlib.import_module("decay_model_k") if mod is None else importlib.reload(mod)
        res = fl.Simulation(mod.Decay(init={"x": 1.0})).run(1.0, rtol=1e-10, atol=1e-12)
        assert res["x"][-1] == pytest.approx(np.exp(-k), rel=1e-6), k
