"""A boom held by a hydraulic cylinder: the catalogue's hydraulic-mechanical coupling with a static equilibrium.

A 200 kg mass on a 1 m arm hinged to the world (Revolute about z) is held by a 63/36 mm line cylinder pinned
0.3/−0.8 m from the hinge and 0.5 m along the arm, fed through a closed-centre 4/3 valve (command 0) from a
fixed-displacement pump with a 160 bar relief valve. Reference: at steady state the cylinder force balances the
weight's moment about the hinge, F·|r_mid × e| = m·g·cos φ·1 m (e the cylinder's unit vector).
"""

from __future__ import annotations

import math

import numpy as np

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.hydraulics import (
    DirectionalValve43,
    FixedDisplacementPump,
    LineCylinder,
    PressureReliefValve,
    Tank,
    Volume,
)
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World

__all__ = ["A_P", "A_R", "BORE", "ROD", "CylinderBoom"]

#: Cylinder bore and rod diameters [m]; piston and annulus areas [m2].
BORE, ROD = 0.063, 0.036
A_P, A_R = math.pi / 4 * BORE**2, math.pi / 4 * (BORE**2 - ROD**2)


class CylinderBoom(fl.Model):
    """A 200 kg mass on a 1 m arm (revolute, z axis) held by a 63/36 cylinder pinned 0.3/-0.8 m from the hinge
    and 0.5 m along the arm, fed through a closed-centre 4/3 valve (command 0) from a pump with a 160 bar
    relief valve.

    Parameters
    ----------
    p_fixed : bool
        The cylinder's chamber pressures are fixed start values (else the initialisation finds them).
    init : dict, optional
        Start values of the hinge (default ``{"phi": 0.3, "w": 0.0}``: 0.3 rad above horizontal, at rest).
    """

    experiment = fl.Experiment(t_end=0.01)

    def __init__(self, p_fixed: bool = False, init: dict[str, float] | None = None) -> None:
        super().__init__()
        self.world = World()
        self.hinge = Revolute(n=[0, 0, 1], init=init if init is not None else {"phi": 0.3, "w": 0.0})
        self.arm = FixedTranslation(r=[1.0, 0, 0])
        self.body = Body(m=200.0, I=np.diag([1.0, 1.0, 1.0]))
        self.base = FixedTranslation(r=[0.3, -0.8, 0])
        self.mid = FixedTranslation(r=[0.5, 0, 0])
        self.cyl = LineCylinder(L0=0.6, d_bore=BORE, d_rod=ROD, stroke=0.5, m=0.0, d=3000.0, p_fixed=p_fixed,
                                p_A_start=50e5, p_B_start=20e5)
        self.tank, self.supply = Tank(), Volume(V=5e-4)
        self.pump = FixedDisplacementPump(D=20e-6 / (2 * math.pi))
        self.speed = Constant(k=1500 * 2 * math.pi / 60)
        self.relief = PressureReliefValve(p_crack=160e5, p_grad=4e9)
        self.valve = DirectionalValve43(Q_nom=40 / 60000, dp_nom=35e5)
        self.cmd = Constant(k=0.0)
        self.connect(self.world.frame_b, self.hinge.frame_a, self.base.frame_a)
        self.connect(self.hinge.frame_b, self.arm.frame_a, self.mid.frame_a)
        self.connect(self.arm.frame_b, self.body.frame_a)
        self.connect(self.base.frame_b, self.cyl.frame_a)
        self.connect(self.mid.frame_b, self.cyl.frame_b)
        self.connect(self.speed.y, self.pump.w)
        self.connect(self.cmd.y, self.valve.u)
        self.connect(self.tank.port, self.pump.port_a, self.relief.port_b, self.valve.port_T)
        self.connect(self.pump.port_b, self.supply.port, self.relief.port_a, self.valve.port_P)
        self.connect(self.valve.port_A, self.cyl.port_A)
        self.connect(self.valve.port_B, self.cyl.port_B)

