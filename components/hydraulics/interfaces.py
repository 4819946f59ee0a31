"""Connector and partial models of the hydraulics library.

The port carries the absolute pressure ``p`` (Pa, potential) and the **mass** flow rate
``m_flow`` (kg/s, flow, positive into the component). Mass flow is what a connection
node conserves exactly (Σ m_flow = 0) even when density depends on pressure, as in
Simscape Fluids' isothermal-liquid domain and Modelica.Fluid. Volume flow is derived
inside components, ``q = m_flow / rho(p)``, and reported in L/min by results helpers.

References
----------
MathWorks Simscape Fluids, *Isothermal Liquid* domain (mass flow rate through variable).
Modelica Standard Library 4.0, ``Modelica.Fluid.Interfaces.FluidPort``.
"""

from __future__ import annotations

from typing import Any

from flexlib import Component, Connector, Flow, Potential, Variable, der, eq

from .fluid import HLP46, Fluid

__all__ = ["PartialTwoPort", "Port", "chamber_equations"]


class Port(Connector):
    """Hydraulic port: absolute pressure and mass flow rate (positive into the component)."""

    p = Potential(unit="Pa", nominal=1e7, doc="Absolute pressure at the port")
    m_flow = Flow(unit="kg/s", doc="Mass flow rate through the port, positive into the component")


class PartialTwoPort(Component):
    """Component with ports ``port_a`` and ``port_b`` that stores no mass.

    ``port_a.m_flow + port_b.m_flow = 0``; ``m_flow`` is the mass flow from ``a`` to ``b``,
    ``dp = port_a.p - port_b.p`` the pressure drop, and ``q`` the volume flow from a to b at
    the upstream density (``rho`` of the higher-pressure port, smooth through dp = 0 by using
    the mean pressure). A subclass adds one equation relating ``m_flow`` (or ``q``) and ``dp``.

    Parameters
    ----------
    fluid : Fluid
        Fluid property record (structural; default HLP46).

    References
    ----------
    MathWorks Simscape Fluids, isothermal-liquid two-port restrictions (``Local Restriction (IL)``).
    """

    port_a = Port(doc="Port a (flow from a to b is positive)")
    port_b = Port(doc="Port b")
    m_flow = Variable(unit="kg/s", doc="Mass flow rate from port_a to port_b")
    q = Variable(unit="m3/s", doc="Volume flow rate from port_a to port_b at the mean-pressure density")
    dp = Variable(unit="Pa", nominal=1e6, doc="Pressure drop port_a.p - port_b.p")

    def __init__(self, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(**kw)
        self.__dict__["fluid"] = fluid

    def equations(self) -> list:
        a, b = self.port_a, self.port_b
        rho = self.fluid.density(0.5 * (a.p + b.p))
        return [eq(a.m_flow, self.m_flow), eq(a.m_flow + b.m_flow, 0.0),
                eq(self.dp, a.p - b.p), eq(self.m_flow, rho * self.q)]


def chamber_equations(fluid: Fluid, m: Any, p: Any, V: Any, m_flow_in: Any) -> list:
    """Mass balance of a lumped compressible chamber (volume, cylinder chamber, hose).

    The stored mass ``m`` is the differential state and the pressure follows from it:

        der(m) = Σ m_flow_in,     m = rho(p) * V

    which is ``dp/dt = beta_eff / V * (Σ q_in - dV/dt)`` written in conserved form. BDF
    methods preserve linear invariants, so the total mass of a circuit is conserved to the
    Newton tolerance whatever the step size (the mass-balance test relies on it).

    Parameters
    ----------
    fluid : Fluid
        Fluid property record.
    m : casadi.SX
        Stored mass variable [kg].
    p : casadi.SX
        Chamber pressure variable [Pa].
    V : casadi.SX or float
        Chamber volume [m3], > 0 (may depend on a piston position).
    m_flow_in : casadi.SX
        Net mass flow into the chamber [kg/s].

    References
    ----------
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §2.3 (continuity equation).
    """
    return [eq(m, fluid.density(p) * V), eq(der(m), m_flow_in)]
