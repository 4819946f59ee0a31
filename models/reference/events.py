"""Systems with events: the catalogue's time events, state events and their coincidences.

- :class:`BangBang`: an inertia J driven by +T, −T, +T switched at t1 and t2 (time events); ω is piecewise linear.
- :class:`StepForce`: x'' = f − x' with f stepping from 0 to 1 at t_on (a time event); closed form after t_on.
- :class:`Thermostat`: a heater switched by a relation on the temperature (a state event).
- :class:`SaturatedRamp`: a lag driven by min(u, 1) where the ramp u reaches 1 exactly when its time event ends
  the ramp (a state event on a time event).
- :class:`BouncingContact` and :class:`FallingBall`: a ball falling onto a stiff contact spring that acts while
  h < 0 (state events); free fall h = h0 − g t²/2 until the first contact.
"""

from __future__ import annotations

import flexlib as fl
from flexlib import Parameter, Variable, der, eq, if_else, time

__all__ = ["BangBang", "BouncingContact", "FallingBall", "SaturatedRamp", "StepForce", "Thermostat"]


class BangBang(fl.Model):
    """An inertia driven by +T until t1, −T until t2, then +T again (time events)."""

    J = Parameter(2.0, unit="kg.m2")
    T = Parameter(1.0, unit="N.m")
    t1 = Parameter(1.0, unit="s")
    t2 = Parameter(2.5, unit="s")
    w = Variable(unit="rad/s")
    tau = Variable(unit="N.m")

    def equations(self):
        return [
            eq(self.tau, if_else(time < self.t1, self.T, if_else(time < self.t2, -self.T, self.T))),
            eq(self.J * der(self.w), self.tau),
        ]


class Thermostat(fl.Model):
    """Heater switched by a relation on the state with hysteresis written as nested relations."""

    T = Variable(unit="K")
    q = Variable(unit="W")

    def equations(self):
        return [eq(der(self.T), self.q - 0.5 * (self.T - 280.0)),
                eq(self.q, if_else(self.T < 295.0, 10.0, 0.0))]


class SaturatedRamp(fl.Model):
    """A first-order lag driven by min(u, 1), where u ramps from 0 to exactly 1 on [0.5, 0.55] and then holds:
    the state event of ``u > 1`` falls exactly on the time event ending the ramp."""

    x = Variable(start=0.0, fixed=True)
    u = Variable()

    def equations(self):
        ramp = if_else(time < 0.5, 0.0, if_else(time < 0.55, (time - 0.5) / 0.05, 1.0))
        return [eq(self.u, ramp), eq(der(self.x), if_else(self.u > 1.0, 1.0, self.u) - self.x)]


class BouncingContact(fl.Model):
    """A ball falling onto a stiff contact spring: the contact force switches on when h < 0."""

    g = Parameter(9.81, unit="m/s2")
    m = Parameter(1.0, unit="kg")
    k = Parameter(1e5, unit="N/m")
    d = Parameter(10.0, unit="N.s/m")
    h = Variable(unit="m")
    v = Variable(unit="m/s")
    fc = Variable(unit="N", doc="Contact force")

    def equations(self):
        return [
            eq(der(self.h), self.v),
            eq(self.m * der(self.v), -self.m * self.g + self.fc),
            eq(self.fc, if_else(self.h < 0, -self.k * self.h - self.d * self.v, 0.0)),
        ]



class StepForce(fl.Model):
    """x'' = f − x', with the force f switching from 0 to 1 at t = t_on (a time event)."""

    t_on = Parameter(0.5, unit="s")
    x = Variable(unit="m")
    v = Variable(unit="m/s")
    f = Variable(unit="N")

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), self.f - self.v),
                eq(self.f, if_else(time >= self.t_on, 1.0, 0.0))]



class FallingBall(fl.Model):
    """A ball falling under gravity onto a stiff contact spring that acts while h < 0."""

    g = Parameter(9.81, unit="m/s2")
    k = Parameter(1e4, unit="N/m")
    d = Parameter(20.0, unit="N.s/m")
    h = Variable(unit="m")
    v = Variable(unit="m/s")
    fc = Variable(unit="N")

    def equations(self):
        return [
            eq(der(self.h), self.v),
            eq(der(self.v), -self.g + self.fc),
            eq(self.fc, if_else(self.h < 0, -self.k * self.h - self.d * self.v, 0.0)),
        ]

