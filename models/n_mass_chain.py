"""A chain of ``n`` masses and nonlinear spring-dampers, fixed to a wall, driven by a sine force.

Benchmark model (``benchmarks/chain.py``). It is self-contained — its own 1-D translational
``Flange`` connector (potential ``s`` [m], flow ``f`` [N], Modelica sign convention: a flow is
positive into the component) and four small raw components — so that it does not depend on
the ``components`` library::

    wall ─ spring[0] ─ mass[0] ─ spring[1] ─ mass[1] ─ … ─ mass[n-1] ─ force (F = F0·sin(ω·t))

Every spring-damper has a cubic stiffening term, ``f = c·(s_rel − L) + c3·(s_rel − L)³ + d·v_rel``.
The masses start at rest at ``s = (i+1)·L`` (every spring unstretched; fixed initial conditions),
which is the equilibrium for ``F(0) = 0``.

Examples
--------
>>> import flexlib as fl
>>> from flexlib.models.n_mass_chain import NMassChain
>>> res = fl.Simulation(NMassChain(10)).run(10.0, dt_out=0.1)   # doctest: +SKIP
"""

from __future__ import annotations

import casadi as ca

import flexlib as fl
from flexlib.errors import ParameterError
from flexlib.registry import ModelOption, Scenario, register_model

__all__ = ["N_OPTION", "ChainFixed", "ChainForce", "ChainMass", "ChainSpring", "Flange", "NMassChain"]

#: The model option ``n`` (declared once: the registry and :class:`NMassChain` check it with this).
N_OPTION = ModelOption("n", int, 10, "number of masses (structural)", low=1)


class Flange(fl.Connector):
    """1-D translational flange: position ``s`` and cut force ``f`` (positive into the component)."""

    s = fl.Potential(unit="m", doc="Absolute position")
    f = fl.Flow(unit="N", doc="Cut force, positive into the component")


class ChainMass(fl.Component):
    """Sliding mass with two flanges (rigidly attached to its centre)."""

    m = fl.Parameter(1.0, unit="kg", min=0.0, doc="Mass")
    s = fl.Variable(unit="m", state_select="prefer", doc="Position")
    v = fl.Variable(unit="m/s", state_select="prefer", doc="Velocity")

    flange_a = Flange()
    flange_b = Flange()

    def equations(self) -> list:
        return [
            fl.eq(self.flange_a.s, self.s),
            fl.eq(self.flange_b.s, self.s),
            fl.eq(fl.der(self.s), self.v),
            fl.eq(self.m * fl.der(self.v), self.flange_a.f + self.flange_b.f),
        ]


class ChainSpring(fl.Component):
    """Nonlinear (cubic-stiffening) spring in parallel with a linear damper."""

    c = fl.Parameter(100.0, unit="N/m", min=0.0, doc="Linear stiffness")
    c3 = fl.Parameter(1000.0, unit="N/m3", min=0.0, doc="Cubic stiffness")
    d = fl.Parameter(0.5, unit="N.s/m", min=0.0, doc="Damping")
    L = fl.Parameter(1.0, unit="m", doc="Unstretched length")
    f = fl.Variable(unit="N", doc="Force transmitted (tension > 0)")

    flange_a = Flange()
    flange_b = Flange()

    def equations(self) -> list:
        s_rel = self.flange_b.s - self.flange_a.s
        e = s_rel - self.L
        return [
            fl.eq(self.f, self.c * e + self.c3 * e**3 + self.d * fl.der(s_rel)),
            fl.eq(self.flange_b.f, self.f),
            fl.eq(self.flange_a.f, -self.f),
        ]


class ChainFixed(fl.Component):
    """Wall: the flange is held at ``s0``."""

    s0 = fl.Parameter(0.0, unit="m", doc="Position of the wall")

    flange = Flange()

    def equations(self) -> list:
        return [fl.eq(self.flange.s, self.s0)]


class ChainForce(fl.Component):
    """Prescribed force ``F0·sin(ω·t)`` pulling on the connected flange (positive along +s)."""

    F0 = fl.Parameter(10.0, unit="N", doc="Amplitude")
    w = fl.Parameter(3.0, unit="rad/s", doc="Angular frequency")

    flange = Flange()

    def equations(self) -> list:
        return [fl.eq(self.flange.f, -self.F0 * ca.sin(self.w * fl.time))]


class NMassChain(fl.Model):
    """``n`` masses in series between a wall and a sine force.

    Parameters
    ----------
    n : int
        Number of masses, at least 1 (structural: changes the equations, hence a cache key entry).

    Raises
    ------
    ParameterError
        ``n`` is not an integer >= 1 (:data:`N_OPTION`).
    """

    experiment = fl.Experiment(t_end=10.0, dt_out=0.1)

    def __init__(self, n: int = 10, **kwargs: object) -> None:
        n = N_OPTION.validate(n, "NMassChain: ", error=ParameterError)
        super().__init__(**kwargs)
        self.n = n
        self.wall = ChainFixed()
        self.force = ChainForce()
        L = ChainSpring.L.default
        masses, springs = [], []
        for i in range(self.n):
            spring = ChainSpring()
            mass = ChainMass(init={"s": (i + 1) * L, "v": 0.0})
            setattr(self, f"spring{i}", spring)
            setattr(self, f"mass{i}", mass)
            springs.append(spring)
            masses.append(mass)
        self.connect(self.wall.flange, springs[0].flange_a)
        for i in range(self.n):
            self.connect(springs[i].flange_b, masses[i].flange_a)
            if i + 1 < self.n:
                self.connect(masses[i].flange_b, springs[i + 1].flange_a)
        self.connect(masses[-1].flange_b, self.force.flange)


# -- registration (flexlib list / flexlib run) ------------------------------------------------------------------
def _chain_factory(scenario: Scenario) -> NMassChain:
    """``options``: ``n`` (number of masses)."""
    return NMassChain(**scenario.options)


register_model(
    "n-mass-chain", _chain_factory,
    doc="n masses and cubic spring-dampers between a wall and a sine force (benchmark model)",
    scenarios=[
        Scenario("sine", "10 masses, 10 s of the sine force F0 = 10 N at 3 rad/s", t_end=10.0,
                 options={"n": 10}, run={"dt_out": 0.1}),
        Scenario("short", "3 masses, 1 s (a quick check)", t_end=1.0, options={"n": 3}, run={"dt_out": 0.05}),
    ],
    summary_signals=lambda model: [f"mass{model.n - 1}.s", f"mass{model.n - 1}.v", "spring0.f"],
    options=[N_OPTION], data=(),
)
