"""Fixed sharp-edged orifice."""

from __future__ import annotations

from flexlib import Parameter, eq

from ._checks import PositiveParameters
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

    Notes
    -----
    ``A``, ``Cd`` and ``Re_cr`` must be > 0 (checked at construction, at flatten and for run-time ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Orifice (IL)* and *Local Restriction (IL)* block documentation.
    Hopsan component library, *Turbulent Orifice* (``HydraulicTurbulentOrifice``).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §3.2 (orifice flow).
    """

    _positive = ("A", "Cd", "Re_cr")
    A = Parameter(unit="m2", min=0.0, doc="Opening area")
    Cd = Parameter(0.64, unit="1", min=0.0, doc="Discharge coefficient")
    Re_cr = Parameter(12.0, unit="1", min=0.0, doc="Critical Reynolds number of the laminar–turbulent transition")

    def equations(self) -> list:
        return [*super().equations(), eq(self.m_flow, self.orifice_flow(self.dp, self.A))]
