"""MSL's multibody examples translated to flexlib, against the Modelica Association's reference results
(as ``test_msl_rotational_examples.py``: rtol 1e-6, every comparison signal within 1e-3 of its range). They use
MSL's defaults as MSL writes them: the World's standard gravity, a joint's support grounded in the joint."""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, BodyBox, Revolute, World
from flexlib.components.mechanics.rotational import Damper
from tests.msl.reference import reference, worst_deviation


class Pendulum(fl.Model):
    """``Modelica.Mechanics.MultiBody.Examples.Elementary.Pendulum``: a 1 kg body 0.5 m from a revolute, released
    horizontal, a damper of 0.1 N m s/rad between the joint's support and axis."""

    def __init__(self) -> None:
        super().__init__()
        self.world = World()
        self.rev = Revolute(n=[0, 0, 1], use_axis_flange=True, init={"phi": 0.0, "w": 0.0})
        self.damper = Damper(d=0.1)
        self.body = Body(m=1.0, r_CM=[0.5, 0.0, 0.0])
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.damper.flange_b, self.rev.axis)
        self.connect(self.rev.support, self.damper.flange_a)
        self.connect(self.body.frame_a, self.rev.frame_b)


def test_pendulum_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range over 5 s."""
    ref = reference("multibody_pendulum")
    res = fl.Simulation(Pendulum()).run(5.0, dt_out=0.001, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst


class DoublePendulum(fl.Model):
    """``Modelica.Mechanics.MultiBody.Examples.Elementary.DoublePendulum``: two steel boxes (0.5 m, 6 cm square) on
    two revolutes released horizontal; a damper of 0.1 N m s/rad between the first joint's support and axis."""

    def __init__(self) -> None:
        super().__init__()
        self.world = World()
        self.revolute1 = Revolute(use_axis_flange=True, init={"phi": 0.0, "w": 0.0})
        self.damper = Damper(d=0.1)
        self.boxBody1 = BodyBox(r=[0.5, 0.0, 0.0], width=0.06)
        self.revolute2 = Revolute(init={"phi": 0.0, "w": 0.0})
        self.boxBody2 = BodyBox(r=[0.5, 0.0, 0.0], width=0.06)
        self.connect(self.damper.flange_b, self.revolute1.axis)
        self.connect(self.revolute1.support, self.damper.flange_a)
        self.connect(self.revolute1.frame_b, self.boxBody1.frame_a)
        self.connect(self.revolute2.frame_b, self.boxBody2.frame_a)
        self.connect(self.boxBody1.frame_b, self.revolute2.frame_a)
        self.connect(self.world.frame_b, self.revolute1.frame_a)


def test_double_pendulum_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range over the 3 s of chaotic-looking swing."""
    ref = reference("multibody_double_pendulum")
    res = fl.Simulation(DoublePendulum()).run(3.0, dt_out=0.0006, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst


class Fourbar1(fl.Model):
    """``Modelica.Mechanics.MultiBody.Examples.Loops.Fourbar1``: a spatial loop of six revolutes and a prismatic
    joint and three steel cylinders, driven by its crank's start speed of 300°/s; the crank's ``stateSelect`` is
    MSL's single modifier."""

    def __init__(self) -> None:
        super().__init__()
        from flexlib.components.mechanics.multibody import BodyCylinder, FixedTranslation, Prismatic

        self.world = World()
        self.j1 = Revolute(n=[1, 0, 0], state_select="always", init={"phi": 0.0, "w": 5.235987755982989})
        self.j2 = Prismatic(n=[1, 0, 0], guess={"s": -0.2})
        self.b1 = BodyCylinder(r=[0.0, 0.5, 0.1], diameter=0.05)
        self.b2 = BodyCylinder(r=[0.0, 0.2, 0.0], diameter=0.05)
        self.b3 = BodyCylinder(r=[-1.0, 0.3, 0.1], diameter=0.05)
        self.rev = Revolute(n=[0, 1, 0])
        self.rev1 = Revolute(n=[0, 0, 1])
        self.j3, self.j4, self.j5 = Revolute(n=[1, 0, 0]), Revolute(n=[0, 1, 0]), Revolute(n=[0, 0, 1])
        self.b0 = FixedTranslation(r=[1.2, 0.0, 0.0])
        self.connect(self.j2.frame_b, self.b2.frame_a)
        self.connect(self.j1.frame_b, self.b1.frame_a)
        self.connect(self.rev.frame_a, self.b2.frame_b)
        self.connect(self.rev.frame_b, self.rev1.frame_a)
        self.connect(self.rev1.frame_b, self.b3.frame_a)
        self.connect(self.world.frame_b, self.j1.frame_a, self.b0.frame_a)
        self.connect(self.b1.frame_b, self.j3.frame_a)
        self.connect(self.j3.frame_b, self.j4.frame_a)
        self.connect(self.j4.frame_b, self.j5.frame_a)
        self.connect(self.j5.frame_b, self.b3.frame_b)
        self.connect(self.b0.frame_b, self.j2.frame_a)


def test_fourbar1_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range over 5 s of the loop's motion."""
    ref = reference("multibody_fourbar1")
    res = fl.Simulation(Fourbar1()).run(5.0, dt_out=0.001, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst


class Fourbar2(fl.Model):
    """``Modelica.Mechanics.MultiBody.Examples.Loops.Fourbar2``: Fourbar1's loop with the three revolutes and the
    third cylinder replaced by a ``UniversalSpherical`` joint whose rod length is found at the start."""

    def __init__(self) -> None:
        super().__init__()
        from flexlib.components.mechanics.multibody import (
            BodyCylinder,
            FixedTranslation,
            Prismatic,
            UniversalSpherical,
        )

        self.world = World()
        self.j1 = Revolute(n=[1, 0, 0], state_select="always", init={"phi": 0.0, "w": 5.235987755983})
        self.j2 = Prismatic(n=[1, 0, 0], init={"s": -0.2})
        self.b1 = BodyCylinder(r=[0.0, 0.5, 0.1], diameter=0.05)
        self.b2 = BodyCylinder(r=[0.0, 0.2, 0.0], diameter=0.05)
        self.universalSpherical = UniversalSpherical(n1_a=[0, 1, 0], compute_rod_length=True, rRod_ia=[-1, 0.3, 0.1])
        self.b3 = FixedTranslation(r=[1.2, 0.0, 0.0])
        self.connect(self.j2.frame_b, self.b2.frame_a)
        self.connect(self.j1.frame_b, self.b1.frame_a)
        self.connect(self.world.frame_b, self.j1.frame_a, self.b3.frame_a)
        self.connect(self.b1.frame_b, self.universalSpherical.frame_b)
        self.connect(self.universalSpherical.frame_a, self.b2.frame_b)
        self.connect(self.b3.frame_b, self.j2.frame_a)


def test_fourbar2_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range over 5 s; the rod length found at the start is the frames'
    distance there (1e-12 relative) and stays it."""
    ref = reference("multibody_fourbar2")
    res = fl.Simulation(Fourbar2()).run(5.0, dt_out=0.001, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst
    gap = res["universalSpherical.frame_b.r_0"] - res["universalSpherical.frame_a.r_0"]
    np.testing.assert_allclose(np.linalg.norm(gap, axis=-1), res["universalSpherical.rodLength"][0], rtol=1e-6)
