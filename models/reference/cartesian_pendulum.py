"""Planar pendulum in Cartesian coordinates: the catalogue's index-3 DAE (Hairer & Wanner, *Solving Ordinary
Differential Equations II*, §VII.1).

A point mass ``m`` on a massless rod of length ``L`` in gravity ``g`` along −y, written with the constraint force
λ·(x, y)::

    x' = u,  y' = v,  m u' = −λ x,  m v' = −λ y − m g,  x² + y² = L²

Invariants: the energy ½ m (u² + v²) + m g y and the constraint residuals at position (x² + y² − L²) and velocity
level (x u + y v). Reference: the period of the libration with amplitude θ0,
4 √(L/g) K(sin²(θ0/2)) (:func:`~flexlib.models.reference.closed_form.pendulum_period`).
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib import Parameter, Variable, der, eq
from flexlib.models.reference.closed_form import pendulum_period

__all__ = ["CartesianPendulum"]


class CartesianPendulum(fl.Model):
    """Planar pendulum in Cartesian coordinates: index 3 (Hairer & Wanner, Solving ODEs II, §VII.1)."""

    m = Parameter(1.0, unit="kg", doc="Mass")
    L = Parameter(1.0, unit="m", doc="Length")
    g = Parameter(9.81, unit="m/s2", doc="Gravity")
    x = Variable(unit="m", doc="Horizontal position")
    y = Variable(unit="m", doc="Vertical position")
    u = Variable(unit="m/s", doc="Horizontal velocity")
    v = Variable(unit="m/s", doc="Vertical velocity")
    lam = Variable(unit="N/m", doc="Constraint force per length")

    experiment = fl.Experiment(t_end=1.0)

    def equations(self):
        return [
            eq(der(self.x), self.u),
            eq(der(self.y), self.v),
            eq(self.m * der(self.u), -self.lam * self.x),
            eq(self.m * der(self.v), -self.lam * self.y - self.m * self.g),
            eq(self.x**2 + self.y**2, self.L**2),
        ]

    @classmethod
    def released_at(cls, theta0: float) -> CartesianPendulum:
        """The unit pendulum (m = L = 1) released at rest at ``theta0`` [rad] from the downward vertical."""
        return cls(init={"x": np.sin(theta0), "u": 0.0}, guess={"y": -np.cos(theta0)})

    @staticmethod
    def energy(res: fl.Result, m: float = 1.0, g: float = 9.81) -> np.ndarray:
        """Mechanical energy [J] along a run: ½ m (u² + v²) + m g y."""
        return 0.5 * m * (res["u"] ** 2 + res["v"] ** 2) + m * g * res["y"]

    @staticmethod
    def constraint_residuals(res: fl.Result, L: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """Position-level [m²] and velocity-level [m²/s] constraint residuals: x² + y² − L², x u + y v."""
        x, y = res["x"], res["y"]
        return x**2 + y**2 - L**2, x * res["u"] + y * res["v"]

    @staticmethod
    def period(theta0: float, L: float = 1.0, g: float = 9.81) -> float:
        """Exact period [s] of the libration with amplitude ``theta0`` [rad]."""
        return pendulum_period(L, g, theta0)
