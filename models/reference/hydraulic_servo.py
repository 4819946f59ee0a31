"""Hydraulic position servo driven into its end stops: the catalogue's hydraulic circuit with events.

Fixed-displacement pump (20 cm3/rev at 1500 rpm = 30 L/min) with a relief valve (160 bar) and a 0.5 L supply
volume → proportional 4/3 valve (40 L/min at 35 bar per edge, 30 Hz spool) → 63/36 × 400 mm cylinder lifting 300 kg
(vertical, gravity on the load) → position measured at the rod end and fed back through a LimPID (PID, output limited
to ±1 = the valve command). The set-point ramps at 0.12 m/s between −30 mm and +430 mm over 20 s: the piston is
driven into the rod-end and the cap-end stops twice each, the controller saturates there and the pump flow goes over
the relief valve. Invariant: the piston stays within the stroke (penetration into the stops below a few µm) and the
valve command within [−1, 1].
"""

from __future__ import annotations

import math

import flexlib as fl
from flexlib.components.control import Constant, LimPID, TimeTable
from flexlib.components.hydraulics import (
    DirectionalValve43,
    DoubleActingCylinder,
    FixedDisplacementPump,
    PressureReliefValve,
    Tank,
    Volume,
)
from flexlib.components.mechanics.translational import Fixed, Force, Mass, PositionSensor

__all__ = ["ATOL", "MASS", "RTOL", "SET_POINT", "STROKE", "T_END", "G", "HydraulicServo"]

#: End time [s] and tolerances of the reference run.
T_END, RTOL, ATOL = 20.0, 1e-6, 1e-8
STROKE, MASS, G = 0.4, 300.0, 9.81
#: Set-point [m] vs time [s]: ramps at 0.12 m/s to 30 mm beyond the rod-end and the cap-end stops, held 1.5 s.
SET_POINT = ([0.0, 1.0, 3.75, 5.25, 9.08, 10.58, 14.42, 15.92, 19.75, 20.0],
             [0.1, 0.1, 0.43, 0.43, -0.03, -0.03, 0.43, 0.43, -0.03, -0.03])


class HydraulicServo(fl.Model):
    """Pump, relief valve, 4/3 proportional valve, cylinder lifting a mass, PID position loop."""

    def __init__(self) -> None:
        super().__init__()
        self.tank = Tank()
        self.pump = FixedDisplacementPump(D=20e-6 / (2 * math.pi))
        self.speed = Constant(k=1500 * 2 * math.pi / 60)
        self.supply = Volume(V=5e-4, p_start=1e5)
        self.relief = PressureReliefValve(p_crack=160e5, p_grad=4e9)
        self.valve = DirectionalValve43(Q_nom=40 / 60000, dp_nom=35e5, omega=2 * math.pi * 30, zeta=0.7,
                                        A_leak=1e-10)
        self.cylinder = DoubleActingCylinder(d_bore=0.063, d_rod=0.036, stroke=STROKE, m=8.0, F_c=300.0,
                                             stribeck=1.5, d=3000.0, x_start=0.1, G_int=1e-13,
                                             p_A_start=MASS * G / (math.pi / 4 * 0.063**2) + 1e5)
        self.fixed, self.load = Fixed(), Mass(m=MASS)
        self.weight, self.gravity = Force(), Constant(k=-MASS * G)
        self.sensor = PositionSensor()
        self.set_point = TimeTable(t=SET_POINT[0], y=SET_POINT[1])
        self.controller = LimPID(controller_type="PID", k=25.0, Ti=0.5, Td=0.02, Nd=10.0, y_max=1.0, y_min=-1.0)
        self.connect(self.speed.y, self.pump.w)
        self.connect(self.tank.port, self.pump.port_a, self.relief.port_b, self.valve.port_T)
        self.connect(self.pump.port_b, self.supply.port, self.relief.port_a, self.valve.port_P)
        self.connect(self.valve.port_A, self.cylinder.port_A)
        self.connect(self.valve.port_B, self.cylinder.port_B)
        self.connect(self.fixed.flange, self.cylinder.flange_a)
        self.connect(self.cylinder.flange_b, self.load.flange_a, self.weight.flange, self.sensor.flange)
        self.connect(self.gravity.y, self.weight.f)
        self.connect(self.set_point.y, self.controller.u_s)
        self.connect(self.sensor.s, self.controller.u_m)
        self.connect(self.controller.y, self.valve.u)
