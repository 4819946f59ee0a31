"""Flow laws shared by the hydraulic restrictions (orifices, valve edges, lines).

Turbulent orifice with a smooth laminar transition (Simscape Fluids, *Orifice (IL)*):

    m_flow = Cd * A * sqrt(2 * rho) * dp / (dp**2 + p_cr**2)**(1/4)

For ``|dp| >> p_cr`` this is the orifice equation ``m_flow = Cd*A*sqrt(2*rho*|dp|)*sign(dp)``;
near ``dp = 0`` it is linear (laminar) with the finite slope ``Cd*A*sqrt(2*rho/p_cr)``, so the
Jacobian stays finite and the flow is smooth through zero. The transition pressure follows
from a critical Reynolds number of the opening, ``Re = q * D_h / (A * nu)``:

    p_cr = rho / 2 * (Re_cr * nu / (Cd * D_h))**2,   D_h = sqrt(4 A / pi)

References
----------
MathWorks Simscape Fluids, *Orifice (IL)* and *Local Restriction (IL)* block documentation.
H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §3.2 (orifice flow).
"""

from __future__ import annotations

import math
from typing import Any

import casadi as ca

__all__ = ["critical_pressure", "orifice_mass_flow", "to_lpm"]


def critical_pressure(area: Any, Cd: Any, rho: Any, nu: Any, Re_cr: Any = 12.0) -> Any:
    """Laminar–turbulent transition pressure of an opening [Pa].

    Parameters
    ----------
    area : float or casadi.SX
        Opening area [m2], > 0 (a tiny floor is applied so that a closed opening keeps a
        finite transition pressure).
    Cd : float or casadi.SX
        Discharge coefficient [1].
    rho : float or casadi.SX
        Density [kg/m3].
    nu : float or casadi.SX
        Kinematic viscosity [m2/s].
    Re_cr : float or casadi.SX
        Critical Reynolds number of the opening [1] (Simscape default 12 for orifices).
    """
    d_h = ca.sqrt(4.0 * ca.fmax(area, 1e-12) / math.pi)
    return rho / 2.0 * (Re_cr * nu / (Cd * d_h)) ** 2


def orifice_mass_flow(dp: Any, area: Any, Cd: Any, rho: Any, p_cr: Any) -> Any:
    """Mass flow through an orifice [kg/s], turbulent with a smooth laminar transition.

    Parameters
    ----------
    dp : float or casadi.SX
        Pressure drop across the orifice, upstream minus downstream [Pa].
    area : float or casadi.SX
        Opening area [m2], >= 0.
    Cd : float or casadi.SX
        Discharge coefficient [1].
    rho : float or casadi.SX
        Density [kg/m3].
    p_cr : float or casadi.SX
        Transition pressure [Pa], > 0 (see :func:`critical_pressure`).
    """
    return Cd * area * ca.sqrt(2.0 * rho) * dp / (dp**2 + p_cr**2) ** 0.25


def to_lpm(q: Any) -> Any:
    """Volume flow in L/min from m3/s (what hydraulics engineers read)."""
    return q * 60000.0
