"""Power unit of a boom: pressure-compensated pump at constant speed, supply volume, relief valve, tank.

Diagram::

    pump_speed (Constant w) ──> pump (PressureCompensatedPump) ──┬── supply (Volume) ──── port_P
                                  ^ suction                      └── relief (PressureReliefValve) ─┐
    port_T ──── tank (Tank) ──────┴────────────────────────────────────────────────────────────────┘

Equations (the components'): pump ``q = eta_v·eps·D·w`` with the compensator
``eps = clamp(1 − (Δp − p_comp)/dp_reg, 0, 1)`` (corners rounded over 5 % of ``dp_reg``); relief
``q = G_leak·Δp + max(Δp − p_relief, 0)/p_grad``; the supply volume's pressure from its mass balance.
"""

from __future__ import annotations

import math
from typing import Any

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.hydraulics import PressureCompensatedPump, PressureReliefValve, Tank, Volume
from flexlib.components.hydraulics.fluid import HLP46
from flexlib.components.hydraulics.interfaces import Port
from flexlib.errors import ParameterError

from ._checks import positive, positives

__all__ = ["PowerUnit"]

# defaults: the hydraulic supply of models/pump_truck/model.py (PUMP_D, PUMP_SPEED, P_COMP, DP_REG, V_SUPPLY) and
# the relief at PumpTruckParameters.p_system (350 bar) with model.py's gradient (1e10 Pa.s/m3)
D_PUMP = 140e-6 / (2 * math.pi)  # 140 cm3/rev [m3/rad]: 210 L/min at 1500 rpm
SPEED = 1500 * 2 * math.pi / 60  # [rad/s]
P_COMP = 32e6  # compensator setting [Pa]
DP_REG = 1e6  # compensator regulation band [Pa]
V_SUPPLY = 5e-3  # supply line and accumulator-free manifold [m3]
P_RELIEF = 35e6  # relief valve setting [Pa]
P_GRAD = 1e10  # relief valve pressure gradient [Pa.s/m3]: 10 bar per 6 L/min


class PowerUnit(fl.Model):
    """Hydraulic power unit: pressure-compensated pump at constant speed into a supply volume, relief valve, tank.

    Contains ``pump_speed`` (:class:`~flexlib.components.control.Constant`, the drive speed), ``pump``
    (:class:`~flexlib.components.hydraulics.PressureCompensatedPump`: full displacement below ``p_comp``, de-stroked
    linearly to zero over ``dp_reg`` above it), ``supply`` (:class:`~flexlib.components.hydraulics.Volume`: supply
    line and manifold), ``relief`` (:class:`~flexlib.components.hydraulics.PressureReliefValve` from supply to tank)
    and ``tank`` (:class:`~flexlib.components.hydraulics.Tank`, atmospheric).

    Steady states: into a consumer taking less than the pump's full flow ``eta_v·D·w`` the supply pressure sits in
    the compensator band, ``p = p_T + p_comp + dp_reg·(1 − q/(eta_v·D·w))``, dead-headed at ``p_comp + dp_reg``
    (the relief valve set above); below ``p_comp`` the pump delivers ``eta_v·D·w``. With ``p_relief`` below the
    compensator band the relief valve passes the surplus: ``Δp = p_relief + p_grad·q_relief``.

    Parameters
    ----------
    D : float
        Pump displacement [m3/rad] (default 140 cm3/rev).
    speed : float
        Pump drive speed [rad/s] (default 1500 rpm).
    p_comp : float
        Compensator setting [Pa] (default 320 bar): the pressure rise at which the pump starts to de-stroke.
    dp_reg : float
        Compensator regulation band [Pa] (default 10 bar): from full to zero displacement.
    V_supply : float
        Supply volume [m3] (default 5 L).
    p_relief : float
        Relief valve cracking pressure difference [Pa] (default 350 bar, the system pressure).
    p_grad : float
        Relief valve pressure gradient [Pa.s/m3] (default 1e10).
    eta_v : float
        Pump volumetric efficiency [1], 0 < eta_v <= 1 (default 1).
    p_start : float, optional
        Supply pressure at the start [Pa] (default: tank + ``p_comp + dp_reg``, the dead-headed pressure).

    Connectors
    ----------
    port_P : Port
        Supply (the supply volume).
    port_T : Port
        Tank.

    References
    ----------
    MathWorks Simscape Fluids, *Pressure-Compensated Pump (IL)* (pressure setting, regulation range); Siemens
    Simcenter Amesim *RV00* relief valve; H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §6.2. Values:
    :mod:`models.pump_truck.model` (its hydraulic supply).
    """

    def __init__(self, D: float = D_PUMP, speed: float = SPEED, p_comp: float = P_COMP, dp_reg: float = DP_REG,
                 V_supply: float = V_SUPPLY, p_relief: float = P_RELIEF, p_grad: float = P_GRAD, eta_v: float = 1.0,
                 p_start: float | None = None, **kw: Any) -> None:
        super().__init__(**kw)
        part = "PowerUnit"
        D, speed, p_comp, dp_reg, V_supply, p_relief, p_grad, eta_v = positives(
            part, D=(D, "m3/rad"), speed=(speed, "rad/s"), p_comp=(p_comp, "Pa"), dp_reg=(dp_reg, "Pa"),
            V_supply=(V_supply, "m3"), p_relief=(p_relief, "Pa"), p_grad=(p_grad, "Pa.s/m3"), eta_v=(eta_v, "1"))
        if eta_v > 1.0:
            raise ParameterError(f"{part}: eta_v must be <= 1 [1] (volumetric efficiency), got {eta_v!r}")
        p_tank = HLP46.p_ref
        p_start = p_tank + p_comp + dp_reg if p_start is None else positive(part, "p_start", p_start, "Pa")
        self.port_P = Port(doc="Supply")
        self.port_T = Port(doc="Tank")
        self.tank = Tank()
        self.pump_speed = Constant(k=speed)
        self.pump = PressureCompensatedPump(D_max=D, p_set=p_comp, dp_reg=dp_reg, eta_v=eta_v)
        self.supply = Volume(V=V_supply, p_start=p_start)
        self.relief = PressureReliefValve(p_crack=p_relief, p_grad=p_grad)
        self.connect(self.pump_speed.y, self.pump.w)
        self.connect(self.port_T, self.tank.port, self.pump.port_a, self.relief.port_b)
        self.connect(self.port_P, self.pump.port_b, self.supply.port, self.relief.port_a)
