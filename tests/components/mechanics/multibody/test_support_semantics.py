"""A joint's drive support is its housing, grounded in the joint as in MSL (issue 31).

MSL's ``Joints.Revolute``/``Prismatic`` connect ``support`` to an internal ``Fixed``: a spring, damper or source
between ``support`` and ``axis`` acts between the housing and the axis. The references are independent: the
same model with a ``Fixed`` on the support (the support then placed by it), and hand statics of a pendulum and a
slider held by a spring.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import flexlib as fl
from flexlib.components.mechanics import rotational, translational
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Prismatic, Revolute, World
from flexlib.units import g_n

M, L = 2.0, 0.8  # bob [kg] on a massless rod [m]


class Pendulum(fl.Model):
    """A pendulum on a revolute with a 1D element between ``support`` and ``axis`` (and a ``Fixed`` on the support
    if ``grounded_by_fixed``)."""

    def __init__(self, element: fl.Component, grounded_by_fixed: bool = False, phi0: float = -0.3,
                 free: bool = False) -> None:
        super().__init__()
        self.world = World()
        self.hinge = Revolute(n=[0, 0, 1], use_axis_flange=True, init={"phi": phi0, "w": 0.0})
        if free:  # a guess: the equilibrium chooses the angle
            self.hinge.set_start("phi", phi0, fixed=False)
        self.rod = FixedTranslation(r=[L, 0, 0])
        self.bob = Body(m=M, I=np.diag([1e-4, 1e-4, 1e-4]))
        self.element = element
        self.connect(self.world.frame_b, self.hinge.frame_a)
        self.connect(self.hinge.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.bob.frame_a)
        self.connect(self.hinge.support, element.flange_a)
        self.connect(element.flange_b, self.hinge.axis)
        if grounded_by_fixed:
            self.housing = rotational.Fixed()
            self.connect(self.housing.flange, self.hinge.support)


def test_damper_between_support_and_axis_acts_on_the_housing():
    """MSL's pattern (a damper between support and axis, nothing else on the support) runs, and equals the same
    pendulum with its support held by a ``Fixed`` (1e-9 of the swing): the support is the grounded housing."""
    runs = [fl.Simulation(Pendulum(rotational.Damper(d=0.5), fixed)).run(2.0, dt_out=0.01, rtol=1e-10, atol=1e-12,
                                                                         progress=False) for fixed in (False, True)]
    phi = [r["hinge.phi"] for r in runs]
    assert np.ptp(phi[0]) > 0.3  # it swings
    np.testing.assert_allclose(phi[0], phi[1], rtol=0, atol=1e-9 * np.ptp(phi[1]))
    assert np.all(runs[0]["hinge.support.phi"] == 0.0)
    # the damper's torque reaches the world through frame_a: the axis torque is the damper's
    np.testing.assert_allclose(runs[0]["element.tau"], 0.5 * runs[0]["hinge.w"], rtol=1e-9, atol=1e-12)


def test_spring_between_support_and_axis_holds_the_pendulum_at_the_static_angle():
    """A torsion spring c between support and axis: at rest ``c·φ = −m g L cos φ`` (hand statics, the root by
    Brent's method), 1e-9 relative."""
    c = 40.0
    sim = fl.Simulation(Pendulum(rotational.Spring(c=c), free=True))
    res = sim.run(0.1, dt_out=0.05, steady_state=True, rtol=1e-10, atol=1e-12, progress=False)
    phi = brentq(lambda p: c * p + M * g_n * L * math.cos(p), -math.pi / 2, 0.0, xtol=1e-15)
    assert res["hinge.phi"][0] == pytest.approx(phi, rel=1e-9)
    assert res["hinge.w"][-1] == pytest.approx(0.0, abs=1e-9)


class Slider(fl.Model):
    """A mass on a vertical prismatic joint held by a spring between the joint's support and axis."""

    def __init__(self, c: float) -> None:
        super().__init__()
        self.world = World()
        self.slide = Prismatic(n=[0, 1, 0], use_axis_flange=True, init={"v": 0.0})
        self.slide.set_start("s", 0.0, fixed=False)  # a guess: the equilibrium chooses the position
        self.mass = Body(m=M, I=np.diag([1e-4, 1e-4, 1e-4]))
        self.spring = translational.Spring(c=c)
        self.connect(self.world.frame_b, self.slide.frame_a)
        self.connect(self.slide.frame_b, self.mass.frame_a)
        self.connect(self.slide.support, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.slide.axis)


def test_spring_between_prismatic_support_and_axis_gives_the_static_sag():
    """Static sag of the slider on its spring, ``s = −m g / c`` (1e-9 relative), the support at rest."""
    c = 5e3
    res = fl.Simulation(Slider(c)).run(0.1, dt_out=0.05, steady_state=True, rtol=1e-10, atol=1e-12, progress=False)
    assert res["slide.s"][0] == pytest.approx(-M * g_n / c, rel=1e-9)
    assert np.all(res["slide.support.s"] == 0.0)


def test_a_single_state_select_applies_to_the_joint_coordinates_as_msl():
    """MSL's joints take one ``stateSelect`` for their coordinates and speeds: ``Revolute(state_select="always")``
    sets ``phi`` and ``w``; the dict form still sets one variable; a component without joint coordinates refuses
    a single value, naming the dict form; a bad value names the choices."""
    j = Revolute(n=[0, 0, 1], state_select="always")
    assert j.state_select_of("phi") is fl.StateSelect.always and j.state_select_of("w") is fl.StateSelect.always
    p = Prismatic(n=[1, 0, 0], state_select=fl.StateSelect.avoid)
    assert p.state_select_of("s") is fl.StateSelect.avoid and p.state_select_of("v") is fl.StateSelect.avoid
    j = Revolute(n=[0, 0, 1], state_select={"phi": "never"})
    assert j.state_select_of("phi") is fl.StateSelect.never and j.state_select_of("w") is fl.StateSelect.prefer
    with pytest.raises(fl.ModelError, match=r"Body: state_select must be a dict"):
        Body(m=1.0, state_select="always")
    with pytest.raises(fl.ModelError, match=r"Revolute: state_select must be a dict .* or one value for phi, w"):
        Revolute(n=[0, 0, 1], state_select=3)
    with pytest.raises(fl.ModelError, match=r"'sometimes' is not one of"):
        Revolute(n=[0, 0, 1], state_select="sometimes")
