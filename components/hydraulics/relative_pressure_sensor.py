"""Ideal differential pressure sensor."""

from __future__ import annotations

from flexlib import Component, Output, eq

from .interfaces import Port

__all__ = ["RelativePressureSensor"]


class RelativePressureSensor(Component):
    """Ideal differential pressure sensor: ``dp = port_a.p - port_b.p``, no flow at either port.

    Connectors
    ----------
    port_a, port_b : Port
        Measured nodes.

    References
    ----------
    MathWorks Simscape Fluids, *Pressure Sensor (IL)* block documentation (pressure difference
    between ports A and B).
    Hopsan component library, *Differential Pressure Sensor* (``HydraulicDifferentialPressureSensor``).
    """

    port_a = Port(doc="First measured node")
    port_b = Port(doc="Second measured node")
    dp = Output(unit="Pa", nominal=1e6, doc="Pressure difference port_a.p - port_b.p")

    def equations(self) -> list:
        return [eq(self.port_a.m_flow, 0.0), eq(self.port_b.m_flow, 0.0),
                eq(self.dp, self.port_a.p - self.port_b.p)]
