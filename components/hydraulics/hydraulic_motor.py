"""Fixed-displacement hydraulic motor."""

from __future__ import annotations

from flexlib import Variable, der, eq

from ..mechanics.rotational.interfaces import Flange
from ._checks import PositiveParameters
from ._pump import DisplacementParameters
from .interfaces import PartialFluidComponent, Port

__all__ = ["HydraulicMotor"]


class HydraulicMotor(DisplacementParameters, PositiveParameters, PartialFluidComponent):
    """Fixed-displacement hydraulic motor with volumetric and mechanical efficiency.

    Flow from the inlet ``port_a`` to the outlet ``port_b`` turns the shaft; with
    ``dp = p_a - p_b``, ``w = der(flange.phi)`` and the consumed volume flow ``q`` counted
    at the inlet density:

    .. math::

        q = \\frac{D\\,\\omega}{\\eta_v} + C_{leak}\\,\\Delta p, \\qquad
        \\dot m = \\rho(p_a)\\, q, \\qquad \\tau = \\eta_m D\\,\\Delta p

    ``tau`` is the torque the motor delivers to the shaft (``flange.tau = -tau``); so a
    motor fed with ``q`` (no leakage) turns at ``w = eta_v q / D`` and holds a load torque
    ``tau_load`` with ``dp = tau_load / (eta_m D)``. The laws hold for motoring
    (``w >= 0``, ``dp >= 0``); the rotor inertia is a separate
    :class:`~flexlib.components.mechanics.rotational.Inertia`.

    Connectors
    ----------
    port_a : Port
        Inlet (high pressure for positive rotation).
    port_b : Port
        Outlet.
    flange : Flange
        Motor shaft; ``flange.tau = -tau``.

    Notes
    -----
    ``D``, ``eta_v`` and ``eta_m`` must be > 0 (checked at construction, at flatten and for run-time
    ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Fixed-Displacement Motor (IL)* block documentation.
    Hopsan component library, *Fixed Displacement Motor* (``HydraulicFixedDisplacementMotorQ``).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §6.2 (pump and motor equations).
    """

    port_a = Port(doc="Inlet port")
    port_b = Port(doc="Outlet port")
    flange = Flange(doc="Motor shaft")
    w = Variable(unit="rad/s", nominal=100.0, doc="Shaft angular velocity")
    q = Variable(unit="m3/s", nominal=1e-3, doc="Consumed volume flow at inlet density")
    m_flow = Variable(unit="kg/s", doc="Mass flow from a to b")
    dp = Variable(unit="Pa", nominal=1e7, doc="Pressure drop p_a - p_b")
    tau = Variable(unit="N.m", nominal=100.0, doc="Torque delivered to the shaft")

    def equations(self) -> list:
        a, b = self.port_a, self.port_b
        return [eq(self.dp, a.p - b.p), eq(self.w, der(self.flange.phi)),
                eq(self.q, self.D * self.w / self.eta_v + self.C_leak * self.dp),
                eq(self.m_flow, self.fluid.density(a.p) * self.q),
                eq(a.m_flow, self.m_flow), eq(b.m_flow, -self.m_flow),
                eq(self.tau, self.eta_m * self.D * self.dp), eq(self.flange.tau, -self.tau)]
