"""Slewing drive of a boom turret: compensated directional valve, two hose volumes, hydraulic motor, rotor, gear.

Diagram::

    port_P ─┐                 ┌─ line_a (Volume) ─┐
    port_T ─┴─ valve (4/3) ───┤                   ├── motor (HydraulicMotor) ── rotor (Inertia) ── gear ── flange
    u ───────> valve.u        └─ line_b (Volume) ─┘
                    (shock_a, makeup_a on line_a, shock_b, makeup_b on line_b, to and from port_T)
"""

from __future__ import annotations

import math
from typing import Any

import flexlib as fl
from flexlib import Input
from flexlib.components.hydraulics import DirectionalValve43, HydraulicMotor, Volume
from flexlib.components.hydraulics.fluid import HLP46
from flexlib.components.hydraulics.interfaces import Port
from flexlib.components.mechanics import rotational

from ._checks import positives
from .axis import V_HOSE, VALVE_DP, VALVE_HZ, VALVE_LEAK, port_cartridges  # a boom axis's valve block and hoses

__all__ = ["SlewDrive"]

# defaults: the slewing drive of models/pump_truck/model.py (SLEW_D, SLEW_RATIO, SLEW_Q, SLEW_ROTOR_J, V_HOSE,
# VALVE_DP, VALVE_HZ; spool damping 0.7, edge leakage area 1e-10 m2)
D_MOTOR = 50e-6 / (2 * math.pi)  # 50 cm3/rev [m3/rad]
RATIO = 300.0  # motor / turret speed (planetary gearbox and slewing ring)
Q_VALVE = 25.0 / 60000  # valve rating [m3/s]: 25 L/min
J_ROTOR = 0.02  # motor rotor and gearbox input [kg.m2]


class SlewDrive(fl.Model):
    """Hydraulic slewing drive: valve, hoses, motor, rotor inertia and reduction gear onto the slewing axis.

    Contains ``valve`` (:class:`~flexlib.components.hydraulics.DirectionalValve43`, closed centre, pressure-
    compensated meter-in edges at ``dp_nom``: the flow follows the command, ``Q_nom·u``, whatever the load, while
    the supply exceeds the load pressure by ``dp_nom``; spool second order ``f_spool``, damping 0.7), ``line_a`` and
    ``line_b`` (:class:`~flexlib.components.hydraulics.Volume`, the motor hoses), ``motor``
    (:class:`~flexlib.components.hydraulics.HydraulicMotor`, ``q = D·ω``), ``rotor``
    (:class:`~flexlib.components.mechanics.rotational.Inertia`, motor and gearbox input) and ``gear``
    (:class:`~flexlib.components.mechanics.rotational.IdealGear`, motor speed = ``ratio`` × turret speed).

    At full command the motor turns at ``Q_nom/D`` and the turret at ``Q_nom/(D·ratio)`` (default 52.4 rad/s,
    0.175 rad/s = 10°/s); with ``u = 0`` the closed centre holds the turret (leakage only). On each motor line the
    valve block's port cartridges (as a boom axis's, :func:`~flexlib.models.boom.axis.port_cartridges`): a shock
    relief valve to tank at ``1.1·p_system`` and a make-up check valve from tank; when the valve closes on a turning
    turret, its inertia drives the motor as a pump, and the make-up valve feeds the line it empties (without them
    that line reached −83 bar absolute in the pump truck's slew scenario) while the shock valve caps the other.

    Parameters
    ----------
    D : float
        Motor displacement [m3/rad] (default 50 cm3/rev).
    ratio : float
        Gear ratio, motor speed / turret speed [1] (default 300).
    Q_nom : float
        Valve rating [m3/s] at ``dp_nom`` per edge (default 25 L/min).
    J_rotor : float
        Rotor and gearbox input inertia [kg.m2] (default 0.02).
    V_hose : float
        Volume of each motor line [m3] (default 1 L).
    dp_nom : float
        Rated pressure drop per edge and compensator setting [Pa] (default 35 bar).
    f_spool : float
        Spool bandwidth [Hz] (default 20).
    p_system : float
        System pressure [Pa] (default 350 bar); the shock valves are set at ``1.1·p_system``.

    Connectors
    ----------
    flange : rotational Flange
        Output shaft (the slewing bearing's axis).
    port_P, port_T : Port
        Supply and tank.
    u : Input [1]
        Valve command, −1 … 1 (positive turns the turret positively).

    References
    ----------
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §6 (valve-controlled motor); Danfoss *PVG 32*
    (compensated valve sections); Rothe Erde slewing ring handbook (drive by pinion on the ring). Values:
    :mod:`models.pump_truck.model` (its slewing drive).
    """

    def __init__(self, D: float = D_MOTOR, ratio: float = RATIO, Q_nom: float = Q_VALVE, J_rotor: float = J_ROTOR,
                 V_hose: float = V_HOSE, dp_nom: float = VALVE_DP, f_spool: float = VALVE_HZ, p_system: float = 35e6,
                 **kw: Any) -> None:
        super().__init__(**kw)
        part = "SlewDrive"
        D, ratio, Q_nom, J_rotor, V_hose, dp_nom, f_spool, p_system = positives(
            part, D=(D, "m3/rad"), ratio=(ratio, "1"), Q_nom=(Q_nom, "m3/s"), J_rotor=(J_rotor, "kg.m2"),
            V_hose=(V_hose, "m3"), dp_nom=(dp_nom, "Pa"), f_spool=(f_spool, "Hz"), p_system=(p_system, "Pa"))
        self.flange = rotational.Flange(doc="Output shaft: the slewing axis")
        self.port_P, self.port_T = Port(doc="Supply"), Port(doc="Tank")
        self.u = Input(unit="1", doc="Valve command, -1 ... 1")
        self.valve = DirectionalValve43(Q_nom=Q_nom, dp_nom=dp_nom, omega=2 * math.pi * f_spool, zeta=0.7,
                                        A_leak=VALVE_LEAK, compensated=True, dp_comp=dp_nom)
        self.line_a, self.line_b = Volume(V=V_hose, p_start=HLP46.p_ref), Volume(V=V_hose, p_start=HLP46.p_ref)
        self.motor = HydraulicMotor(D=D)
        self.rotor = rotational.Inertia(J=J_rotor)
        self.gear = rotational.IdealGear(ratio=ratio)
        self.connect(self.u, self.valve.u)
        self.connect(self.port_P, self.valve.port_P)
        self.connect(self.port_T, self.valve.port_T)
        self.connect(self.valve.port_A, self.line_a.port, self.motor.port_a)
        self.connect(self.valve.port_B, self.line_b.port, self.motor.port_b)
        self.shock_a, self.makeup_a = port_cartridges(p_system)
        self.shock_b, self.makeup_b = port_cartridges(p_system)
        for line, shock, makeup in ((self.line_a, self.shock_a, self.makeup_a),
                                    (self.line_b, self.shock_b, self.makeup_b)):
            self.connect(line.port, shock.port_a, makeup.port_b)
            self.connect(self.port_T, shock.port_b, makeup.port_a)
        self.connect(self.motor.flange, self.rotor.flange_a)
        self.connect(self.rotor.flange_b, self.gear.flange_a)
        self.connect(self.gear.flange_b, self.flange)
