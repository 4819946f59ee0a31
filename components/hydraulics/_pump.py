"""Shared shaft and port equations of the displacement pumps (private helper)."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Input, Parameter, Variable, der, eq
from flexlib.core.options import flag

from ..mechanics.rotational.interfaces import Flange
from ._checks import PositiveParameters, store_fluid
from .fluid import HLP46, Fluid
from .interfaces import Port

__all__ = ["DisplacementParameters", "PartialPump"]


class DisplacementParameters:
    """Mixin: the parameters of a fixed-displacement machine (pump or motor), all but ``C_leak`` > 0."""

    _positive = ("D", "eta_v", "eta_m")
    D = Parameter(unit="m3/rad", min=0.0, doc="Displacement per radian (a value in cm3/rev times ``1e-6 / (2 pi)``)")
    eta_v = Parameter(1.0, unit="1", min=0.0, max=1.0, doc="Volumetric efficiency")
    eta_m = Parameter(1.0, unit="1", min=0.0, max=1.0, doc="Mechanical (hydro-mechanical) efficiency")
    C_leak = Parameter(0.0, unit="m3/(s.Pa)", min=0.0,
                       doc=("Laminar leakage coefficient across the unit (pump: delivery to suction; motor: inlet to "
                            "outlet)"))


class PartialPump(PositiveParameters, Component):
    """Pump with suction ``port_a``, delivery ``port_b`` and a shaft (speed signal or flange).

    A subclass provides :meth:`displacement` (the effective displacement [m3/rad]) and may add
    equations. The pump stores no mass; volume flows are counted at the suction density:

        q = eta_v * D_eff * w - C_leak * dp,   port_a.m_flow = rho(port_a.p) * q = -port_b.m_flow
        tau = D_eff * dp / eta_m,              dp = port_b.p - port_a.p

    Parameters
    ----------
    use_flange : bool
        True if the pump is driven by the rotational ``flange``, otherwise by the speed
        signal ``w`` (structural).
    fluid : Fluid
        Fluid property record (structural; default HLP46).

    Connectors
    ----------
    port_a : Port
        Suction (inlet).
    port_b : Port
        Delivery (outlet, pressure side).
    w : Input [rad/s]
        Shaft speed (only if not ``use_flange``; otherwise a variable, ``der(flange.phi)``).
    flange : Flange
        Drive shaft (only if ``use_flange``); ``flange.tau = tau`` is the torque driven into the pump.
    """

    port_a = Port(doc="Suction (inlet) port")
    port_b = Port(doc="Delivery (outlet, pressure) port")
    q = Variable(unit="m3/s", nominal=1e-3, doc="Delivered volume flow at suction density")
    m_flow = Variable(unit="kg/s", nominal=1.0, doc="Delivered mass flow (a to b)")
    dp = Variable(unit="Pa", nominal=1e7, doc="Pressure rise port_b.p - port_a.p")
    tau = Variable(unit="N.m", nominal=100.0, doc="Shaft torque needed to drive the pump")

    def __init__(self, use_flange: bool = False, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.use_flange = flag(self, "use_flange", use_flange, structural=True)
        if self.use_flange:
            self.flange = Flange(doc="Drive shaft; flange.tau is the driving torque into the pump")
            self.w = Variable(unit="rad/s", nominal=100.0, doc="Shaft angular velocity")
        else:
            self.w = Input(unit="rad/s", doc="Shaft angular velocity")

    def displacement(self) -> Any:
        """Effective displacement [m3/rad]."""
        raise NotImplementedError

    def equations(self) -> list:
        a, b = self.port_a, self.port_b
        d_eff = self.displacement()
        eqs = [eq(self.dp, b.p - a.p),
               eq(self.q, self.eta_v * d_eff * self.w - self.C_leak * self.dp),
               eq(self.m_flow, self.fluid.density(a.p) * self.q),
               eq(a.m_flow, self.m_flow), eq(b.m_flow, -self.m_flow),
               eq(self.tau, d_eff * self.dp / self.eta_m)]
        if self.use_flange:
            eqs += [eq(self.w, der(self.flange.phi)), eq(self.flange.tau, self.tau)]
        return eqs
