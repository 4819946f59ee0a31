"""Reference-model catalogue: the canonical small systems, each defined once with its experiment, its invariants
and a reference where one exists; tests, benchmarks and the README import them from here.

============================  ==================================================================================
module                        systems
============================  ==================================================================================
:mod:`.cartesian_pendulum`    planar pendulum in Cartesian coordinates (index 3)
:mod:`.rigid_pendulum`        3D body on a Revolute; conical pendulum on a Universal joint
:mod:`.four_bar`              four-bar of four Revolutes (crank-rocker, triple rocker)
:mod:`.slider_crank`          slider-crank (free, or held against a piston force)
:mod:`.mass_spring_damper`    x'' = −x and m x'' + d x' + k x = 0 in raw equations; wall, spring-damper, mass
:mod:`.hydraulic_cylinder`    cylinder driven into its end stops by switched pressures
:mod:`.hydraulic_circuit`     pump, relief valve, supply volume, 4/3 valve, leaking cylinder; mass counters
:mod:`.hydraulic_boom`        boom held by a line cylinder, pump and valve (static equilibrium)
:mod:`.hydraulic_servo`       position servo: pump, relief valve, 4/3 valve, cylinder, PID
:mod:`.orifice`               turbulent orifice at zero pressure difference (singular start)
:mod:`.events`                time and state events: bang-bang torque, step force, thermostat, bouncing ball
:mod:`.drive_trains`          MSL's CoupledClutches: three stick/slip clutches in series (reference in tests/msl)
:mod:`.blow_up`               x' = x² (finite-time blow-up) and x' = −x
:mod:`.signal_chain`          sine through limiter, rate limiter and lag
:mod:`.planar_minimal`        hand-written minimal DAE / ODE of the planar mechanisms (references)
:mod:`.closed_form`           closed-form references (numpy/scipy only)
============================  ==================================================================================

The N-mass chain and the N-link pendulum are :mod:`flexlib.models.n_mass_chain` and
:mod:`flexlib.models.n_link_pendulum`. :data:`flexlib.models.reference.catalogue.CASES` lists every system with a
short run and the bounds of its invariants and references; each case is registered (``flexlib run NAME``) under
``reference-`` + its name.
"""

from flexlib.models.reference.catalogue import CASES, ReferenceCase
from flexlib.registry import Scenario, register_model

__all__ = ["CASES", "ReferenceCase"]


def _register(case: ReferenceCase) -> None:
    run = {k: v for k, v in case.run.items() if k != "t_end"}
    register_model(f"reference-{case.name}", lambda scenario: case.build(), doc=case.doc,
                   scenarios=[Scenario("check", "the catalogue's short run", t_end=case.run["t_end"], run=run)],
                   options=(), data=())


for _case in CASES.values():
    _register(_case)
