"""Check (non-return) valve."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, Variable, eq
from flexlib.errors import ParameterError

from ._checks import PositiveParameters
from ._smooth import smooth_clamp
from .interfaces import PartialTwoPort

__all__ = ["CheckValve"]


class CheckValve(PositiveParameters, PartialTwoPort):
    """Check valve: opens for flow from a to b above a cracking pressure, blocks reverse flow.

    The opening fraction grows linearly with the pressure drop ``dp = p_a - p_b`` from 0 at
    ``p_crack`` to 1 at ``p_open`` (quasi-static poppet, no inertia); the area goes from the
    leakage area to ``A_max`` and the flow is the :class:`Orifice` law:

    .. math::

        x = \\mathrm{clamp}\\Big(\\frac{\\Delta p - p_{crack}}{p_{open} - p_{crack}}, 0, 1\\Big),
        \\quad A = A_{leak} + x\\,(A_{max} - A_{leak}),
        \\quad \\dot m = C_d A \\sqrt{2\\rho}\\,\\frac{\\Delta p}{(\\Delta p^2 + p_{cr}(A)^2)^{1/4}}

    The two corners of the clamp are rounded by quadratic fillets over a fraction
    ``smoothing`` of the opening range (centred on ``p_crack`` and ``p_open``), so the
    characteristic is continuous with a continuous slope and creates **no events** (a valve
    chattering around its cracking pressure costs no event iterations). Below
    ``p_crack - smoothing*(p_open - p_crack)/2`` the valve is exactly closed (leakage area
    only), in particular for any reverse pressure difference.

    A closed valve passes only its leakage, so an ideal flow source or pump feeding it through
    a node without capacitance leaves that node's pressure almost undetermined; give such a
    node a :class:`Volume` (a real pump outlet has one).

    Connectors
    ----------
    port_a, port_b : Port
        Inlet a, outlet b; free flow from a to b.

    Notes
    -----
    ``A_max``, ``A_leak``, ``Cd`` and ``Re_cr`` must be > 0 (checked at construction, at flatten and for
    run-time ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Check Valve (IL)* block documentation (linear opening between
    cracking and maximum opening pressure differential, leakage area, smoothing factor).
    Hopsan component library, *Check Valve* (``HydraulicCheckValve``).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §3.2 (orifice flow).
    """

    _positive = ("A_max", "A_leak", "Cd", "Re_cr")
    p_crack = Parameter(1e5, unit="Pa", min=0.0, doc="Cracking pressure difference")
    p_open = Parameter(2e5, unit="Pa", min=0.0, doc="Pressure difference at full opening, > ``p_crack``")
    A_max = Parameter(unit="m2", min=0.0, doc="Fully open area")
    A_leak = Parameter(1e-12, unit="m2", min=0.0, doc="Leakage area of the closed valve, < ``A_max``")
    Cd = Parameter(0.64, unit="1", min=0.0, doc="Discharge coefficient")
    smoothing = Parameter(0.05, unit="1", min=0.0, max=1.0,
                          doc="Width of the corner fillets as a fraction of ``p_open - p_crack``")
    Re_cr = Parameter(12.0, unit="1", min=0.0, doc="Critical Reynolds number of the laminar–turbulent transition")
    x = Variable(unit="1", doc="Opening fraction")

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        label = self.where
        pc, po = values.get("p_crack"), values.get("p_open")
        if pc is not None and po is not None and not po > pc:
            raise ParameterError(f"{label}: p_open = {float(po)!r} Pa must be > p_crack = {float(pc)!r} Pa")
        a_max, a_leak = values.get("A_max"), values.get("A_leak")
        if a_max is not None and a_leak is not None and not a_leak < a_max:
            raise ParameterError(f"{label}: A_leak = {float(a_leak)!r} m2 must be < A_max = {float(a_max)!r} m2")

    def equations(self) -> list:
        a, b = self.port_a, self.port_b
        dp = a.p - b.p  # the port pressures, not self.dp: a Newton start then sees the right opening
        span = self.p_open - self.p_crack
        area = self.A_leak + self.x * (self.A_max - self.A_leak)
        return [*super().equations(),
                eq(self.x, smooth_clamp((dp - self.p_crack) / span, 0.0, 1.0, 0.5 * self.smoothing)),
                eq(self.m_flow, self.orifice_flow(dp, area))]
