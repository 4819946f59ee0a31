"""Ideal pressure source."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialSource, Port

__all__ = ["PressureSource"]


class PressureSource(PartialSource):
    """Ideal pressure source: ``port.p = p`` (or ``p_in``), any flow.

    Parameters
    ----------
    use_input : bool
        True if the pressure comes from the signal input ``p_in`` (structural).

    Connectors
    ----------
    port : Port
        ``port.m_flow`` is the mass flow into the source (negative when it delivers).
    p_in : Input [Pa]
        Imposed absolute pressure (only if ``use_input``).

    References
    ----------
    MathWorks Simscape Fluids, *Pressure Source (IL)* block documentation.
    Hopsan component library, *Pressure Source* (``HydraulicPressureSourceC``).
    """

    p = Parameter(1.01325e5, unit="Pa", min=0.0, doc="Imposed absolute pressure (used if not ``use_input``)")
    port = Port(doc="Source port")

    source_parameter = "p"

    def equations(self) -> list:
        return [eq(self.port.p, self.source_value())]
