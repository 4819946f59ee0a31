"""Ideal flow rate sensor."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialFluidComponent, Port

__all__ = ["FlowSensor"]


class FlowSensor(PartialFluidComponent):
    """Ideal flow sensor in series: no pressure drop, measures the flow from a to b.

    ``port_a.p = port_b.p``, ``port_a.m_flow + port_b.m_flow = 0``,
    ``m_flow = port_a.m_flow`` and ``q = m_flow / rho(p)`` (volume flow at the line pressure).

    References
    ----------
    MathWorks Simscape Fluids, *Flow Rate Sensor (IL)* block documentation.
    Hopsan component library, *Flow Sensor* (``HydraulicFlowSensor``).
    """

    port_a = Port(doc="Inlet")
    port_b = Port(doc="Outlet")
    m_flow = Output(unit="kg/s", doc="Mass flow rate from a to b")
    q = Output(unit="m3/s", nominal=1e-3, doc="Volume flow rate from a to b at the line pressure")

    def equations(self) -> list:
        a, b = self.port_a, self.port_b
        return [eq(a.p, b.p), eq(a.m_flow + b.m_flow, 0.0), eq(self.m_flow, a.m_flow),
                eq(self.q * self.fluid.density(a.p), self.m_flow)]
