"""Ideal volume flow source."""

from __future__ import annotations

from flexlib import Parameter, Variable, eq

from .interfaces import PartialSource, Port

__all__ = ["FlowSource"]


class FlowSource(PartialSource):
    """Ideal volume flow source: delivers ``q`` out of ``port`` into the network, any pressure.

    The volume flow is counted at the port pressure, so the mass flow is
    ``port.m_flow = -rho(port.p) * q`` (negative: out of the source). The source draws its
    fluid from an implicit reservoir; ``q < 0`` sucks fluid out of the network.

    Parameters
    ----------
    use_input : bool
        True if the flow comes from the signal input ``q_in`` (structural).

    Connectors
    ----------
    port : Port
        Delivery port.
    q_in : Input [m3/s]
        Delivered volume flow rate (only if ``use_input``).

    References
    ----------
    MathWorks Simscape Fluids, *Flow Rate Source (IL)* block documentation.
    Hopsan component library, *Flow Source* (``HydraulicFlowSourceQ``).
    """

    q = Parameter(0.0, unit="m3/s", doc="Delivered volume flow rate (used if not ``use_input``)")
    m_flow = Variable(unit="kg/s", doc="Delivered mass flow rate (= ``-port.m_flow``)")
    port = Port(doc="Delivery port")

    source_parameter = "q"

    def equations(self) -> list:
        q = self.source_value()
        return [eq(self.m_flow, self.fluid.density(self.port.p) * q), eq(self.port.m_flow, -self.m_flow)]
