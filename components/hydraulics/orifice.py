"""Fixed sharp-edged orifice."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, eq

from ._checks import PositiveParameters, store_fluid
from .flow_laws import critical_pressure, orifice_mass_flow
from .fluid import HLP46, Fluid
from .interfaces import PartialTwoPort

__all__ = ["Orifice"]


class Orifice(PositiveParameters, PartialTwoPort):
    """Fixed orifice: turbulent flow with a smooth laminar transition, no stored mass.

    .. math::

        \\dot m = C_d A \\sqrt{2\\rho}\\, \\frac{\\Delta p}{(\\Delta p^2 + p_{cr}^2)^{1/4}},
        \\qquad p_{cr} = \\frac{\\rho}{2}\\Big(\\frac{Re_{cr}\\,\\nu}{C_d D_h}\\Big)^2,
        \\quad D_h = \\sqrt{4A/\\pi}

    (:func:`orifice_mass_flow`, :func:`critical_pressure`), with ``rho`` at the mean port
    pressure. For ``|dp| >> p_cr`` this is ``q = Cd*A*sqrt(2*|dp|/rho)*sign(dp)``; through
    ``dp = 0`` the flow is odd, smooth and laminar with the slope ``Cd*A*sqrt(2*rho/p_cr)``.

    Parameters
    ----------
    A : float
        Opening area [m2], > 0.
    Cd : float
        Discharge coefficient [1], > 0.
    Re_cr : float
        Critical Reynolds number of the laminar–turbulent transition [1], > 0.
    fluid : Fluid
        Fluid property record (structural; default HLP46).

    Connectors
    ----------
    port_a, port_b : Port
        Flow from a to b is positive.

    Variables
    ---------
    m_flow : kg/s
        Mass flow from a to b.
    q : m3/s
        Volume flow from a to b (mean-pressure density).
    dp : Pa
        Pressure drop ``port_a.p - port_b.p``.

    References
    ----------
    MathWorks Simscape Fluids, *Orifice (IL)* and *Local Restriction (IL)* block documentation.
    Hopsan component library, *Turbulent Orifice* (``HydraulicTurbulentOrifice``).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §3.2 (orifice flow).
    """

    _positive = ("A", "Cd", "Re_cr")
    A = Parameter(unit="m2", min=0.0, doc="Opening area")
    Cd = Parameter(0.64, unit="1", min=0.0, doc="Discharge coefficient")
    Re_cr = Parameter(12.0, unit="1", min=0.0, doc="Critical Reynolds number")

    def __init__(self, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(fluid=fluid, **kw)
        store_fluid(self, fluid)

    def equations(self) -> list:
        rho = self.fluid.density(0.5 * (self.port_a.p + self.port_b.p))
        p_cr = critical_pressure(self.A, self.Cd, rho, self.fluid.nu, self.Re_cr)
        return [*super().equations(), eq(self.m_flow, orifice_mass_flow(self.dp, self.A, self.Cd, rho, p_cr))]
