"""Bad multibody input gets a clear error naming the component."""

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Fixed, FixedTranslation, Revolute, World


def test_negative_mass_and_bad_inertia():
    with pytest.raises(fl.ParameterError, match=r"Body: m = -1"):
        Body(m=-1.0)
    with pytest.raises(fl.ParameterError, match=r"not positive semi-definite"):
        Body(I=np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(fl.ParameterError, match=r"not symmetric"):
        Body(I=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(fl.ParameterError, match=r"triangle inequality"):
        Body(I=np.diag([1.0, 1.0, 5.0]))

    class BodyModel(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World()
            self.body = Body()
            self.connect(self.world.frame_b, self.body.frame_a)
            self.body.I = np.diag([1.0, -2.0, 1.0])

    with pytest.raises(fl.ParameterError, match=r"body: inertia tensor I is not positive semi-definite"):
        BodyModel()


def test_zero_joint_axis():
    with pytest.raises(fl.ParameterError, match=r"Revolute: joint axis n = \[0.0, 0.0, 0.0\] has zero length"):
        Revolute(n=[0, 0, 0])

    class BodyModel(fl.Model):
        def __init__(self):
            super().__init__()
            self.joint = Revolute()
            self.joint.n = [0.0, 0.0, 0.0]

    with pytest.raises(fl.ParameterError, match=r"joint: joint axis n"):
        BodyModel()


class TooShort(fl.Model):
    """Two links of 0.3 m each cannot reach a pivot 1 m away: the loop cannot close."""

    def __init__(self):
        super().__init__()
        self.world = World(g=0.0)
        self.far = Fixed(r=[1.0, 0, 0])
        self.j1 = Revolute(guess={"phi": 0.3})
        self.l1 = FixedTranslation(r=[0.3, 0, 0])
        self.m1 = Body(m=1.0)
        self.j2 = Revolute(guess={"phi": 0.0})
        self.l2 = FixedTranslation(r=[0.3, 0, 0])
        self.m2 = Body(m=1.0)
        self.j3 = Revolute(guess={"phi": 0.0})
        self.connect(self.world.frame_b, self.j1.frame_a)
        self.connect(self.j1.frame_b, self.l1.frame_a)
        self.connect(self.l1.frame_b, self.m1.frame_a, self.j2.frame_a)
        self.connect(self.j2.frame_b, self.l2.frame_a)
        self.connect(self.l2.frame_b, self.m2.frame_a, self.j3.frame_a)
        self.connect(self.j3.frame_b, self.far.frame_b)


def test_loop_that_cannot_close():
    """Assembly fails with an initialisation error naming the loop-closure equations."""
    with pytest.raises((fl.InitializationError, fl.StructuralSingularityError), match=r"loop closure|r_0"):
        fl.Simulation(TooShort(), use_cache=False).run(0.1)
