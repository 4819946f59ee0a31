"""A chain of small signal blocks with events: the catalogue's control-library system; and a constant 3-vector
signal source (:class:`VectorConstant`) for vector inputs such as world forces and torques.

A 2-amplitude, 1 Hz sine through a limiter (−0.5 … 1), a rate limiter (±10 /s) and a first-order lag (T = 0.1 s).
The limiter switches its relations at state events; invariant: the limiter output stays within its limits and
the rate limiter's slope within ±10 /s.
"""

from __future__ import annotations

import flexlib as fl
from flexlib.components.control import FirstOrder, Limiter, RateLimiter, Sine

__all__ = ["LimitedSine", "VectorConstant"]


class LimitedSine(fl.Model):
    """A sine through a limiter, a rate limiter and a first-order lag (all small signal blocks)."""

    experiment = fl.Experiment(t_end=2.0)

    def __init__(self) -> None:
        super().__init__()
        self.sine = Sine(amplitude=2.0, f=1.0)
        self.limiter = Limiter(u_max=1.0, u_min=-0.5)
        self.rate = RateLimiter(rising=10.0, falling=-10.0)
        self.lag = FirstOrder(k=1.0, T=0.1)
        self.connect(self.sine.y, self.limiter.u)
        self.connect(self.limiter.y, self.rate.u)
        self.connect(self.rate.y, self.lag.u)


class VectorConstant(fl.Component):
    """Constant 3-vector signal ``y = k`` (the unit is the receiving input's: N for a force, N.m for a torque)."""

    k = fl.Parameter([0.0, 0.0, 0.0], unit="1", shape=3, doc="Value")
    y = fl.Output(unit="1", shape=3, doc="Output")

    def equations(self):
        return [fl.eq(self.y, self.k)]
