"""Ideal pressure source."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Input, Parameter, eq

from ._checks import flag, store_fluid
from .fluid import HLP46, Fluid
from .interfaces import Port

__all__ = ["PressureSource"]


class PressureSource(Component):
    """Ideal pressure source: ``port.p = p`` (or ``p_in``), any flow.

    Parameters
    ----------
    p : float
        Imposed absolute pressure [Pa], >= 0 (used if not ``use_input``).
    use_input : bool
        True if the pressure comes from the signal input ``p_in`` (structural).
    fluid : Fluid
        Fluid property record (structural; default HLP46).

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

    p = Parameter(1.01325e5, unit="Pa", min=0.0, doc="Imposed absolute pressure")
    port = Port(doc="Source port")

    def __init__(self, use_input: bool = False, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.use_input = flag(self, "use_input", use_input, structural=True)
        if self.use_input:
            self.p_in = Input(unit="Pa", doc="Imposed absolute pressure")

    def equations(self) -> list:
        return [eq(self.port.p, self.p_in if self.use_input else self.p)]
