"""Ideal volume flow source."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Input, Parameter, Variable, eq

from ._checks import flag, store_fluid
from .fluid import HLP46, Fluid
from .interfaces import Port

__all__ = ["FlowSource"]


class FlowSource(Component):
    """Ideal volume flow source: delivers ``q`` out of ``port`` into the network, any pressure.

    The volume flow is counted at the port pressure, so the mass flow is
    ``port.m_flow = -rho(port.p) * q`` (negative: out of the source). The source draws its
    fluid from an implicit reservoir; ``q < 0`` sucks fluid out of the network.

    Parameters
    ----------
    q : float
        Delivered volume flow rate [m3/s] (used if not ``use_input``).
    use_input : bool
        True if the flow comes from the signal input ``q_in`` (structural).
    fluid : Fluid
        Fluid property record (structural; default HLP46).

    Connectors
    ----------
    port : Port
        Delivery port.
    q_in : Input [m3/s]
        Delivered volume flow rate (only if ``use_input``).

    Variables
    ---------
    m_flow : kg/s
        Delivered mass flow rate (= ``-port.m_flow``).

    References
    ----------
    MathWorks Simscape Fluids, *Flow Rate Source (IL)* block documentation.
    Hopsan component library, *Flow Source* (``HydraulicFlowSourceQ``).
    """

    q = Parameter(0.0, unit="m3/s", doc="Delivered volume flow rate")
    m_flow = Variable(unit="kg/s", doc="Delivered mass flow rate")
    port = Port(doc="Delivery port")

    def __init__(self, use_input: bool = False, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.use_input = flag(self, "use_input", use_input, structural=True)
        if self.use_input:
            self.q_in = Input(unit="m3/s", doc="Delivered volume flow rate")

    def equations(self) -> list:
        q = self.q_in if self.use_input else self.q
        return [eq(self.m_flow, self.fluid.density(self.port.p) * q), eq(self.port.m_flow, -self.m_flow)]
