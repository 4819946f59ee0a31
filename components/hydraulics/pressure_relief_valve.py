"""Pressure relief valve with a linear pressure–flow characteristic."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Parameter, Variable, der, eq
from flexlib.core.options import flag

from ._checks import PositiveParameters
from ._smooth import smooth_ramp
from .fluid import HLP46, Fluid
from .interfaces import PartialTwoPort

__all__ = ["PressureReliefValve"]


class PressureReliefValve(PositiveParameters, PartialTwoPort):
    """Pressure relief valve: opens above a cracking pressure, ``dp = p_crack + p_grad * q``.

    Static characteristic (AMESim-style: cracking pressure and flow–pressure gradient), with
    ``dp = p_a - p_b`` and the volume flow ``q`` from a to b:

    .. math::

        q = G_{leak}\\,\\Delta p + \\frac{\\max(\\Delta p - p_{crack}, 0)}{p_{grad}}

    so in steady state an open valve passing ``q`` holds ``dp = (p_crack + p_grad*q) /
    (1 + G_leak*p_grad)`` (= ``p_crack + p_grad*q`` without leakage). The corner at
    ``p_crack`` is rounded by a quadratic fillet of half-width ``dp_smooth`` (C1, no events);
    for ``dp >= p_crack + dp_smooth`` the law above is exact.

    **Poppet dynamics** (``use_dynamics=True``): the poppet does not follow the pressure at
    once. The control pressure ``dp_c`` that sets the opening lags ``dp`` by a first-order
    filter (Simscape's *opening dynamics*), and the open valve acts as a conductance:

    .. math::

        T\\,\\dot{\\Delta p}_c = \\Delta p - \\Delta p_c, \\qquad
        q = \\Big(G_{leak} + \\frac{\\max(\\Delta p_c - p_{crack}, 0)}{p_{grad}\\,\\Delta p_c}\\Big)\\Delta p

    which has the same steady state and never lets flow run against the pressure difference.
    ``dp_c`` starts at 0 (closed valve; a fixed start value: override it with
    ``init={"dp_c": ...}``, or release it with ``guess={"dp_c": ...}`` for a steady-state start).

    Parameters
    ----------
    use_dynamics : bool
        True if the opening follows the pressure with the first-order lag ``T`` (structural;
        adds the state ``dp_c``).

    Connectors
    ----------
    port_a, port_b : Port
        Inlet (pressure side) a, outlet (tank side) b.

    Notes
    -----
    ``p_grad`` and ``T`` must be > 0 (checked at construction, at flatten and for run-time ``params``).

    References
    ----------
    Siemens Simcenter Amesim, Hydraulic library, *RV00* relief valve (cracking pressure and
    flow rate pressure gradient).
    MathWorks Simscape Fluids, *Pressure Relief Valve (IL)* block documentation (leakage area,
    opening dynamics with a time constant).
    Hopsan component library, *Pressure Relief Valve* (``HydraulicPressureReliefValve``, first-order
    spool dynamics).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §3.2.
    """

    _positive = ("p_grad", "T")
    p_crack = Parameter(unit="Pa", min=0.0, doc="Cracking pressure difference")
    p_grad = Parameter(unit="Pa.s/m3", min=0.0,
                       doc="Pressure gradient of the open valve, d(dp)/dq (e.g. 10 bar per 100 L/min = 6e8 Pa.s/m3)")
    G_leak = Parameter(1e-14, unit="m3/(s.Pa)", min=0.0, doc="Laminar leakage conductance of the closed valve")
    dp_smooth = Parameter(1e4, unit="Pa", min=0.0, doc="Half-width of the fillet rounding the cracking corner")
    T = Parameter(1e-3, unit="s", min=0.0,
                  doc="Time constant of the poppet (opening) dynamics (used if ``use_dynamics``)")
    dp_c = Variable(unit="Pa", nominal=1e7, start=0.0, fixed=True,

                        doc=("Control pressure difference setting the opening (= dp without dynamics; a state starting "
                             "at 0 with dynamics)"))

    def __init__(self, use_dynamics: bool = False, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(fluid=fluid, **kw)
        self.use_dynamics = flag(self, "use_dynamics", use_dynamics, structural=True)
        if not self.use_dynamics and "dp_c" not in self._starts:
            self.set_start("dp_c", 0.0, fixed=False)  # algebraic (= dp) without dynamics

    def equations(self) -> list:
        eqs = super().equations()
        if not self.use_dynamics:
            dp = self.port_a.p - self.port_b.p  # not self.dp: a Newton start then sees the right opening
            opening = smooth_ramp(dp - self.p_crack, self.dp_smooth)
            return [*eqs, eq(self.dp_c, self.dp), eq(self.q, self.G_leak * dp + opening / self.p_grad)]
        opening = smooth_ramp(self.dp_c - self.p_crack, self.dp_smooth)
        # opening / dp_c is the open conductance; the floor only matters where opening == 0
        g_open = opening / (self.p_grad * ca.fmax(self.dp_c, ca.fmax(self.p_crack - self.dp_smooth, 0.0) + 1.0))
        return [*eqs, eq(self.T * der(self.dp_c), self.dp - self.dp_c),
                eq(self.q, (self.G_leak + g_open) * self.dp)]
