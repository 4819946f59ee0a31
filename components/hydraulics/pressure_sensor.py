"""Ideal absolute pressure sensor."""

from __future__ import annotations

from flexlib import Component, Output, eq

from .interfaces import Port

__all__ = ["PressureSensor"]


class PressureSensor(Component):
    """Ideal absolute pressure sensor: ``p = port.p``, no flow (``port.m_flow = 0``).

    Connectors
    ----------
    port : Port
        Measured node.

    References
    ----------
    MathWorks Simscape Fluids, *Pressure Sensor (IL)* block documentation.
    Hopsan component library, *Pressure Sensor* (``HydraulicPressureSensor``).
    """

    port = Port(doc="Measured node")
    p = Output(unit="Pa", nominal=1e7, doc="Absolute pressure at the port")

    def equations(self) -> list:
        return [eq(self.port.m_flow, 0.0), eq(self.p, self.port.p)]
