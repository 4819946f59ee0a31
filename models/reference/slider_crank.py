"""Slider-crank of 3D components: crank about world z, connecting rod, piston sliding on world x.

Reference: the closed-form kinematics (Heywood §2.2) and the crank torque balancing a piston force by virtual work
in :mod:`flexlib.models.reference.closed_form`. Invariant: the piston position ``slide.s`` equals
:func:`~flexlib.models.reference.closed_form.slider_position` of the crank angle ``crank_joint.phi``.
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.mechanics import rotational, translational
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Prismatic, Revolute, World
from flexlib.models.reference.closed_form import slider_position

__all__ = ["SliderCrank"]


class SliderCrank(fl.Model):
    """Crank (radius r) about the world z axis, connecting rod (rod_length), slider on the world x axis.

    ``lock_crank``: the crank's axis flange is held by a rotational Fixed (static balance; the joint
    torque is the holding torque) and a force ``F`` pushes the piston toward the crank axis.

    Parameters
    ----------
    theta : float
        Start crank angle [rad] (from world x).
    r, rod_length : float
        Crank radius and connecting-rod length [m].
    w0 : float
        Start crank speed [rad/s] (free crank only).
    lock_crank : bool
        Hold the crank at ``theta`` (static balance).
    F : float
        Force on the piston toward the crank axis [N] (locked crank only).
    """

    experiment = fl.Experiment(t_end=1.0)

    def __init__(self, theta: float, r: float = 0.1, rod_length: float = 0.35, w0: float = 0.0,
                 lock_crank: bool = False,
                 F: float = 0.0) -> None:
        super().__init__()
        x0 = float(slider_position(theta, r, rod_length))
        phi_rod = float(np.arctan2(-r * np.sin(theta), x0 - r * np.cos(theta)))
        self.world = World(g=0.0)
        self.crank_joint = Revolute(use_axis_flange=lock_crank,
                                    **({"guess": {"phi": theta}} if lock_crank else {"init": {"phi": theta, "w": w0}}))
        self.crank = FixedTranslation(r=[r, 0, 0])
        self.crank_mass = Body(m=1.0, r_CM=[-r / 2, 0, 0], I=np.diag([1e-5, 1e-3, 1e-3]))
        self.wrist = Revolute(guess={"phi": phi_rod - theta})
        self.rod = FixedTranslation(r=[rod_length, 0, 0])
        self.rod_mass = Body(m=0.5, r_CM=[-rod_length / 2, 0, 0], I=np.diag([1e-5, 5e-3, 5e-3]))
        self.pin = Revolute(guess={"phi": -phi_rod})
        self.slide = Prismatic(n=[1, 0, 0], use_axis_flange=lock_crank, guess={"s": x0})
        self.piston = Body(m=0.8, I=np.diag([1e-4, 1e-4, 1e-4]))
        self.connect(self.world.frame_b, self.crank_joint.frame_a, self.slide.frame_a)
        self.connect(self.crank_joint.frame_b, self.crank.frame_a)
        self.connect(self.crank.frame_b, self.crank_mass.frame_a, self.wrist.frame_a)
        self.connect(self.wrist.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.rod_mass.frame_a, self.pin.frame_a)
        self.connect(self.pin.frame_b, self.slide.frame_b, self.piston.frame_a)
        if lock_crank:
            self.lock = rotational.Fixed(phi0=theta)
            self.housing = rotational.Fixed()
            self.ground = translational.Fixed()
            self.gas = translational.Force(use_support=True)
            self.pressure = Constant(k=-F)  # toward the crank axis: −x
            self.connect(self.lock.flange, self.crank_joint.axis)
            self.connect(self.housing.flange, self.crank_joint.support)
            self.connect(self.pressure.y, self.gas.f)
            self.connect(self.gas.flange, self.slide.axis)
            self.connect(self.ground.flange, self.gas.support, self.slide.support)
