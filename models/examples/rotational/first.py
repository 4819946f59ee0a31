"""Motor, gear, elastic shaft and load (after MSL ``Rotational.Examples.First``)."""

from __future__ import annotations

import flexlib as fl
from flexlib.components.control import Sine
from flexlib.components.mechanics.rotational import Damper, Fixed, IdealGear, Inertia, Spring, Torque

__all__ = ["FirstDriveTrain"]


class FirstDriveTrain(fl.Model):
    """Motor, gear, elastic shaft and load (after MSL ``Rotational.Examples.First``).

    A sinusoidal motor torque drives the motor inertia ``inertia1``; an ideal gear reduces
    the speed by ``ratio``; an elastic, damped shaft (``spring`` and ``damper`` in parallel)
    connects the gear to the load inertia ``inertia2``. The torque source and the gear
    housing are fixed to the ground. The drive train starts at rest with an untwisted shaft.

    Parameters
    ----------
    J_motor : float
        Motor inertia [kg.m2].
    J_load : float
        Load inertia [kg.m2].
    ratio : float
        Gear ratio, motor angle / gear output angle [1].
    c : float
        Shaft stiffness [N.m/rad].
    d : float
        Shaft damping [N.m.s/rad].
    amplitude : float
        Amplitude of the motor torque [N.m].
    f : float
        Frequency of the motor torque [Hz].

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Examples.First``.
    """

    experiment = fl.Experiment(t_end=1.0, dt_out=1e-3)

    def __init__(self, J_motor: float = 0.1, J_load: float = 2.0, ratio: float = 10.0, c: float = 1e4,
                 d: float = 10.0, amplitude: float = 10.0, f: float = 5.0) -> None:
        super().__init__()
        self.fixed = Fixed()
        self.sine = Sine(amplitude=amplitude, f=f)
        self.torque = Torque(use_support=True)
        self.inertia1 = Inertia(J=J_motor, init={"w": 0.0})
        self.gear = IdealGear(ratio=ratio, use_support=True)
        self.spring = Spring(c=c, init={"phi_rel": 0.0})
        self.damper = Damper(d=d)
        self.inertia2 = Inertia(J=J_load, init={"phi": 0.0, "w": 0.0})
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia1.flange_a)
        self.connect(self.inertia1.flange_b, self.gear.flange_a)
        self.connect(self.gear.flange_b, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.inertia2.flange_a)
        self.connect(self.fixed.flange, self.torque.support, self.gear.support)


if __name__ == "__main__":
    result = fl.Simulation(FirstDriveTrain()).run()
    print(result)
