"""Reservoir at constant pressure."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Parameter, eq

from ._checks import store_fluid
from .fluid import HLP46, Fluid
from .interfaces import Port

__all__ = ["Tank"]


class Tank(Component):
    """Reservoir (tank) at a constant absolute pressure: ``port.p = p``.

    The tank is an infinite reservoir: it takes or gives any mass flow without changing its
    pressure (several ports of a circuit may be connected to the same tank).

    Parameters
    ----------
    fluid : Fluid
        Fluid property record (structural; default HLP46).

    Connectors
    ----------
    port : Port
        ``port.m_flow`` is the mass flow into the tank.

    References
    ----------
    MathWorks Simscape Fluids, *Reservoir (IL)* block documentation.
    Hopsan component library, *Tank* (``HydraulicTankC``).
    """

    p = Parameter(1.01325e5, unit="Pa", min=0.0, doc="Absolute pressure of the reservoir (default: atmospheric)")
    port = Port(doc="Tank port")

    def __init__(self, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)

    def equations(self) -> list:
        return [eq(self.port.p, self.p)]
