"""Mass–spring–damper systems: the catalogue's linear oscillators, as raw equations and of components.

- :class:`Oscillator`: x'' = −x in raw equations (unit mass on a unit spring); from x(0) = x0, v(0) = 0 the exact
  solution is x = x0 cos t, and the energy ½ (v² + x²) is conserved.
- :class:`DampedOscillator`: m x'' + d x' + k x = 0 in raw equations, with its closed-form underdamped response.
- :class:`MassSpringDamper`: a wall, a :class:`~flexlib.components.mechanics.translational.SpringDamper` and a
  :class:`~flexlib.components.mechanics.translational.Mass` (translational library); from s(0) = s0 at rest the
  underdamped response is s = s0 e^(−ζω t) (cos ω_d t + ζω/ω_d sin ω_d t) with ω = √(c/m), ζ = d/(2√(c m)),
  ω_d = ω √(1 − ζ²) (:meth:`MassSpringDamper.exact`).
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib import Parameter, Variable, der, eq
from flexlib.components.mechanics.translational import Fixed, Mass, SpringDamper

__all__ = ["DampedOscillator", "MassSpringDamper", "Oscillator"]


class Oscillator(fl.Model):
    """x'' = −x (unit mass on a unit spring, raw equations); with ``init={"x": 1.0, "v": 0.0}``: x = cos t."""

    x = Variable(unit="m", doc="Position")
    v = Variable(unit="m/s", doc="Velocity")

    experiment = fl.Experiment(t_end=1.0)

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), -self.x)]

    @staticmethod
    def exact(t: np.ndarray, x0: float = 1.0) -> np.ndarray:
        """Exact position [m] at times ``t`` [s] from x(0) = ``x0``, v(0) = 0."""
        return x0 * np.cos(np.asarray(t, dtype=float))

    @staticmethod
    def energy(res: fl.Result) -> np.ndarray:
        """Energy [J] along a run: ½ (v² + x²) (unit mass and stiffness)."""
        return 0.5 * (res["v"] ** 2 + res["x"] ** 2)


class MassSpringDamper(fl.Model):
    """Wall – spring-damper – mass, released at rest from ``s0``.

    Parameters
    ----------
    m : float
        Mass [kg].
    c : float
        Spring stiffness [N/m].
    d : float
        Damping coefficient [N.s/m].
    s0 : float
        Start position of the mass [m] (the spring is relaxed at 0).
    """

    experiment = fl.Experiment(t_end=2.0, dt_out=0.01)

    def __init__(self, m: float = 1.0, c: float = 400.0, d: float = 2.0, s0: float = 0.1) -> None:
        super().__init__()
        self.wall = Fixed()
        self.spring = SpringDamper(c=c, d=d)
        self.mass = Mass(m=m, init={"s": s0, "v": 0.0})
        self.connect(self.wall.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.mass.flange_a)
        self.m_value, self.c_value, self.d_value, self.s0_value = m, c, d, s0

    def exact(self, t: np.ndarray) -> np.ndarray:
        """Exact (underdamped) position [m] of the mass at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        m, c, d, s0 = self.m_value, self.c_value, self.d_value, self.s0_value
        w = np.sqrt(c / m)
        zeta = d / (2.0 * np.sqrt(c * m))
        wd = w * np.sqrt(1.0 - zeta**2)
        return s0 * np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))

    def energy(self, res: fl.Result) -> np.ndarray:
        """Kinetic plus spring energy [J] along a run (decreasing: the damper dissipates it)."""
        return 0.5 * self.m_value * res["mass.v"] ** 2 + 0.5 * self.c_value * res["mass.s"] ** 2


class DampedOscillator(fl.Model):
    """m·x'' + d·x' + k·x = 0 (raw equations); from x(0) = 1, v(0) = 0 the underdamped response
    :meth:`exact`."""

    m = Parameter(1.0, unit="kg")
    k = Parameter(4.0, unit="N/m")
    d = Parameter(0.4, unit="N.s/m")
    x = Variable(unit="m")
    v = Variable(unit="m/s")

    def equations(self):
        return [eq(der(self.x), self.v), eq(self.m * der(self.v), -self.k * self.x - self.d * self.v)]

    @staticmethod
    def exact(t: np.ndarray, m: float = 1.0, k: float = 4.0, d: float = 0.4, x0: float = 1.0) -> np.ndarray:
        """Exact position [m] at times ``t`` [s] from x(0) = ``x0``, v(0) = 0 (underdamped: d² < 4 k m)."""
        delta = d / (2 * m)
        wd = np.sqrt(k / m - delta**2)
        return x0 * np.exp(-delta * t) * (np.cos(wd * t) + delta / wd * np.sin(wd * t))
