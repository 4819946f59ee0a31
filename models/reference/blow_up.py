"""Finite-time blow-up x' = x² (a Riccati equation): the catalogue's failing run with a closed form.

From x(0) = 1 the solution x = 1/(1 − t) grows without bound as t → 1 s, so every integrator must stop just before
t = 1 s with a step-size failure; a run that ends before t = 0.9 s matches the closed form (:meth:`BlowUp.exact`).
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib import Variable, der, eq

__all__ = ["BlowUp", "Decay"]


class BlowUp(fl.Model):
    """x' = x², x(0) = 1: x = 1/(1 − t) blows up at t = 1 s (give ``init={"x": 1.0}``)."""

    x = Variable()

    experiment = fl.Experiment(t_end=1.0)

    def equations(self):
        return [eq(der(self.x), self.x**2)]

    @staticmethod
    def exact(t: np.ndarray, x0: float = 1.0) -> np.ndarray:
        """x(t) = x0 / (1 − x0 t), finite for t < 1/x0."""
        return x0 / (1.0 - x0 * np.asarray(t, dtype=float))


class Decay(fl.Model):
    """x' = −x: x = x0 e^(−t)."""

    x = Variable()

    experiment = fl.Experiment(t_end=1.0)

    def equations(self):
        return [eq(der(self.x), -self.x)]
