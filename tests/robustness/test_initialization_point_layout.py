"""A failed initialisation whose best point belongs to another layout of the unknowns (the model diagnosed again
without its explicit eliminations, as ``Initializer.initial`` does) ends in the InitializationError, not in a
CasADi shape error from re-evaluating the relations at that point (found on the flexible pump-truck boom)."""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Gain, Limiter
from flexlib.errors import InitializationError
from flexlib.solve.init import initializer


class WithRelation(fl.Model):
    """A state driven through a limiter (a relation), so the start re-evaluates relations after a failure."""

    x = fl.Variable(unit="1", start=1.0)

    def __init__(self) -> None:
        super().__init__()
        self.src, self.gain, self.lim = Constant(k=2.0), Gain(k=3.0), Limiter(u_max=1.0, u_min=-1.0)
        self.connect(self.src.y, self.gain.u)
        self.connect(self.gain.y, self.lim.u)
        self.set_start("x", 1.0, fixed=True)

    def equations(self):
        return [fl.eq(fl.der(self.x), -self.x + self.lim.y)]


def test_a_point_of_another_layout_is_not_used(monkeypatch):
    sim = fl.Simulation(WithRelation(), use_cache=False)
    n = sim.compiled.n

    def failing(self, *args, **kwargs):
        err = InitializationError("could not find consistent initial values (forced)")
        err.point = (np.zeros(n + 7), np.zeros(n + 7))  # the full system's layout: more unknowns
        raise err

    monkeypatch.setattr(initializer.Initializer, "initial", failing)
    with pytest.raises(InitializationError, match="forced"):
        sim.run(0.1, progress=False)
