"""Orifice with its opening area given by a signal."""

from __future__ import annotations

import casadi as ca

from flexlib import Input, Parameter, eq

from ._checks import PositiveParameters
from .interfaces import PartialTwoPort

__all__ = ["VariableOrifice"]


class VariableOrifice(PositiveParameters, PartialTwoPort):
    """Orifice whose opening area is the input signal ``A`` (a valve edge, a throttle).

    Same flow law as :class:`Orifice` with the effective area
    ``A_eff = A_leak + max(A, 0)``: a negative or zero command closes the orifice down to
    the leakage area, which keeps the laminar transition pressure finite.

    Notes
    -----
    ``Cd``, ``A_leak`` and ``Re_cr`` must be > 0 (checked at construction, at flatten and for run-time
    ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Orifice (IL)* block documentation (variable orifice, area
    parameterization).
    Hopsan component library, *2/2 Valve* (``Hydraulic22Valve``, turbulent flow through a commanded area).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §3.2 (orifice flow).
    """

    _positive = ("Cd", "A_leak", "Re_cr")
    Cd = Parameter(0.64, unit="1", min=0.0, doc="Discharge coefficient")
    A_leak = Parameter(1e-12, unit="m2", min=0.0, doc="Leakage area of the closed orifice")
    Re_cr = Parameter(12.0, unit="1", min=0.0, doc="Critical Reynolds number of the laminar–turbulent transition")
    A = Input(unit="m2", doc="Opening area command")

    def equations(self) -> list:
        area = self.A_leak + ca.fmax(self.A, 0.0)
        return [*super().equations(), eq(self.m_flow, self.orifice_flow(self.dp, area))]
