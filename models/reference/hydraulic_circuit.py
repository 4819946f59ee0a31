"""A pump–valve–cylinder circuit with mass counters: the catalogue's hydraulic chambers and their mass balance.

A fixed-displacement pump (10 cm3/rev at 1500 rpm) with a relief valve (150 bar) and a 0.5 L supply volume feeds a
4/3 valve driven by a sine (0.8, 0.7 Hz) to a 63/36 × 400 mm cylinder with internal leakage and a drained rod seal,
carrying 50 kg; mass counters sit on the pump delivery and on the return to the tank. Invariant: conservation of
mass, pumped − returned = Δ(stored in the chambers and the supply volume) (:func:`mass_balance_error`); it holds
to the Newton tolerance when the chambers carry their stored mass as the state (``chamber_form="mass"``).
"""

from __future__ import annotations

import math

import numpy as np

import flexlib as fl
from flexlib.components.control import Constant, Sine
from flexlib.components.hydraulics import (
    DirectionalValve43,
    DoubleActingCylinder,
    FixedDisplacementPump,
    Port,
    PressureReliefValve,
    Tank,
    Volume,
)
from flexlib.components.mechanics.translational import Fixed, Mass
from flexlib.models.reference.hydraulic_cylinder import BAR, CYL, P_ATM

__all__ = ["DP_NOM", "Q_NOM", "MassCounter", "PumpValveCylinder", "mass_balance_error"]

#: Nominal flow [m3/s] at the nominal pressure drop [Pa] per edge of the 4/3 valve (40 L/min at 35 bar).
Q_NOM, DP_NOM = 40.0 / 60000.0, 35 * BAR


class MassCounter(fl.Component):
    """Ideal flow meter in series that integrates the mass passed from port_a to port_b."""

    M = fl.Variable(unit="kg", start=0.0, fixed=True, doc="Mass passed from a to b since the start")
    port_a = Port(doc="Inlet")
    port_b = Port(doc="Outlet")

    def equations(self) -> list:
        a, b = self.port_a, self.port_b
        return [fl.eq(a.p, b.p), fl.eq(a.m_flow + b.m_flow, 0.0), fl.eq(fl.der(self.M), a.m_flow)]


class PumpValveCylinder(fl.Model):
    """Fixed-displacement pump with relief valve and accumulator volume, 4/3 valve driven by a sine,
    cylinder with internal leakage and a drained rod seal, load mass; counters on the pump delivery and
    on the return to the tank. ``chamber_form`` of the supply volume and the cylinder (default ``"mass"``)."""

    def __init__(self, chamber_form: str = "mass") -> None:
        super().__init__()
        self.tank = Tank()
        self.pump = FixedDisplacementPump(D=10e-6 / (2 * math.pi), C_leak=1e-12)
        self.speed = Constant(k=1500 * 2 * math.pi / 60)
        self.pumped, self.returned = MassCounter(), MassCounter()
        self.supply = Volume(V=5e-4, p_start=P_ATM, chamber_form=chamber_form)
        self.relief = PressureReliefValve(p_crack=150 * BAR, p_grad=5e10)
        self.command = Sine(amplitude=0.8, f=0.7)
        self.valve = DirectionalValve43(Q_nom=Q_NOM, dp_nom=DP_NOM, A_leak=1e-9)
        self.cylinder = DoubleActingCylinder(x_start=0.2, G_int=1e-13, G_ext=5e-14, use_drain=True,
                                             chamber_form=chamber_form, **CYL)
        self.fixed, self.load = Fixed(), Mass(m=50.0)
        self.connect(self.speed.y, self.pump.w)
        self.connect(self.tank.port, self.pump.port_a, self.returned.port_b)
        self.connect(self.pump.port_b, self.pumped.port_a)
        self.connect(self.pumped.port_b, self.supply.port, self.relief.port_a, self.valve.port_P)
        self.connect(self.returned.port_a, self.relief.port_b, self.valve.port_T, self.cylinder.port_D)
        self.connect(self.command.y, self.valve.u)
        self.connect(self.valve.port_A, self.cylinder.port_A)
        self.connect(self.valve.port_B, self.cylinder.port_B)
        self.connect(self.fixed.flange, self.cylinder.flange_a)
        self.connect(self.cylinder.flange_b, self.load.flange_a)



def mass_balance_error(res: fl.Result) -> float:
    """max |pumped − returned − Δstored| / pumped mass at the end (dimensionless)."""
    stored = res["cylinder.m_A"] + res["cylinder.m_B"] + res["supply.m"]
    balance = res["pumped.M"] - res["returned.M"] - (stored - stored[0])
    return float(np.abs(balance).max() / res["pumped.M"][-1])
