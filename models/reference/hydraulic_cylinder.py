"""Double-acting cylinder driven into both end stops by switched supply pressures: the catalogue's hydraulic
cylinder with state events.

A 63/36 mm × 400 mm cylinder (:data:`CYL`, a common ISO 6020 size) carrying 20 kg, its chambers fed through
meter-in/out orifices from two pressure sources that swap supply and atmospheric pressure at ``t_switch``.
Reference: at rest in a stop the penetration is the net pressure force over the stop stiffness (1e9 N/m),
``(p_s A_P − p_atm A_R − p_atm (A_P − A_R)) / 1e9`` at the rod end; pressures are absolute.
"""

from __future__ import annotations

import math

import flexlib as fl
from flexlib.components.control import Step
from flexlib.components.hydraulics import HLP46, DoubleActingCylinder, Orifice, PressureSource
from flexlib.components.mechanics.translational import Fixed, Mass

__all__ = ["A_P", "A_R", "BAR", "BORE", "CYL", "P_ATM", "ROD", "STROKE", "G", "PressureDriven"]

#: Pressure unit [Pa] and atmospheric (tank) pressure [Pa]; gravity [m/s2].
BAR = 1e5
P_ATM = HLP46.p_ref
G = 9.81
#: A 63/36 mm cylinder with 400 mm stroke (a common ISO 6020 size).
BORE, ROD, STROKE = 0.063, 0.036, 0.4
A_P = math.pi / 4 * BORE**2
A_R = math.pi / 4 * (BORE**2 - ROD**2)
CYL = {"d_bore": BORE, "d_rod": ROD, "stroke": STROKE, "m": 8.0, "F_c": 200.0, "stribeck": 1.5, "d": 2000.0,
       "V_dead_A": 5e-5, "V_dead_B": 5e-5}


class PressureDriven(fl.Model):
    """Supply pressure switched from chamber A to chamber B at t_switch, through meter-in/out orifices.

    Parameters
    ----------
    p_s : float
        Supply pressure [Pa] (absolute).
    t_switch : float
        Time [s] at which the supply moves from chamber A to chamber B.
    """

    experiment = fl.Experiment(t_end=4.0)

    def __init__(self, p_s: float, t_switch: float) -> None:
        super().__init__()
        self.fixed = Fixed()
        self.p_A = PressureSource(use_input=True)
        self.p_B = PressureSource(use_input=True)
        self.step_A = Step(offset=p_s, height=P_ATM - p_s, start_time=t_switch)
        self.step_B = Step(offset=P_ATM, height=p_s - P_ATM, start_time=t_switch)
        self.orifice_A = Orifice(A=2e-5)
        self.orifice_B = Orifice(A=2e-5)
        self.cylinder = DoubleActingCylinder(x_start=0.3, **CYL)
        self.load = Mass(m=20.0)
        self.connect(self.step_A.y, self.p_A.p_in)
        self.connect(self.step_B.y, self.p_B.p_in)
        self.connect(self.p_A.port, self.orifice_A.port_a)
        self.connect(self.orifice_A.port_b, self.cylinder.port_A)
        self.connect(self.p_B.port, self.orifice_B.port_a)
        self.connect(self.orifice_B.port_b, self.cylinder.port_B)
        self.connect(self.fixed.flange, self.cylinder.flange_a)
        self.connect(self.cylinder.flange_b, self.load.flange_a)
