"""Pressure-compensated (optionally load-sensing) variable-displacement pump."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Parameter, Variable, der, eq
from flexlib.core.options import flag

from ._pump import PartialPump
from ._smooth import smooth_clamp
from .fluid import HLP46, Fluid
from .interfaces import Port

__all__ = ["PressureCompensatedPump"]


class PressureCompensatedPump(PartialPump):
    """Variable-displacement pump with a pressure compensator (and optional load sensing).

    The compensator reduces the displacement linearly from ``D_max`` at the pressure
    setting ``p_set`` to zero at ``p_set + dp_reg`` (``dp = p_b - p_a``); with load sensing
    a second controller holds the delivery pressure ``dp_margin`` above the load-sensing
    port pressure, and the smaller displacement wins:

    .. math::

        \\varepsilon_{pc} = \\mathrm{clamp}\\Big(1 - \\frac{\\Delta p - p_{set}}{\\Delta p_{reg}}\\Big), \\quad
        \\varepsilon_{ls} = \\mathrm{clamp}\\Big(1 - \\frac{p_b - p_{ls} - \\Delta p_{margin}}{\\Delta p_{reg}}\\Big),
        \\quad \\varepsilon_{ss} = \\min(\\varepsilon_{pc}, \\varepsilon_{ls})

    ``q = eta_v * eps * D_max * w - C_leak * dp`` and ``tau = eps * D_max * dp / eta_m`` as
    for :class:`FixedDisplacementPump` (counted at the suction density). Below ``p_set`` the
    flow is limited by ``D_max * w``; a blocked pump settles between ``p_set`` and
    ``p_set + dp_reg`` (at the upper end without leakage). The clamp corners are rounded
    (fraction ``smoothing`` of ``dp_reg``; no events). With ``use_dynamics`` the
    displacement follows ``eps_ss`` with a first-order lag ``T`` (swash-plate dynamics) and
    starts at full stroke, ``eps = 1`` (a fixed start value: override it with ``init={"eps": ...}``,
    or release it with ``guess={"eps": ...}`` for a steady-state start).

    Parameters
    ----------
    use_load_sensing : bool
        True to add the load-sensing port ``port_ls`` and controller (structural).
    use_dynamics : bool
        True if the displacement follows its set value with the lag ``T`` (structural).

    Connectors
    ----------
    port_ls : Port
        Load-sensing pressure (only if ``use_load_sensing``; no flow).

    Notes
    -----
    ``D_max``, ``dp_reg``, ``eta_v``, ``eta_m`` and ``T`` must be > 0 (checked at construction, at flatten and
    for run-time ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Pressure-Compensated Pump (IL)* block documentation (pressure
    setting, pressure regulation range).
    Hopsan component library, *Variable Displacement Pump* (``HydraulicVariableDisplacementPump``).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §6.2.
    """

    _positive = ("D_max", "dp_reg", "eta_v", "eta_m", "T")
    D_max = Parameter(unit="m3/rad", min=0.0, doc="Maximum displacement")
    p_set = Parameter(unit="Pa", min=0.0,
                      doc="Compensator pressure setting (pressure rise at which de-stroking starts)")
    dp_reg = Parameter(1e6, unit="Pa", min=0.0, doc="Pressure regulation range, from full to zero displacement")
    dp_margin = Parameter(1.5e6, unit="Pa", min=0.0,
                          doc="Load-sensing margin, delivery minus load pressure (used if ``use_load_sensing``)")
    eta_v = Parameter(1.0, unit="1", min=0.0, max=1.0, doc="Volumetric efficiency")
    eta_m = Parameter(1.0, unit="1", min=0.0, max=1.0, doc="Mechanical efficiency")
    C_leak = Parameter(0.0, unit="m3/(s.Pa)", min=0.0, doc="Laminar leakage coefficient from delivery to suction")
    smoothing = Parameter(0.05, unit="1", min=0.0, max=1.0,
                          doc="Width of the corner fillets as a fraction of ``dp_reg``")
    T = Parameter(0.02, unit="s", min=0.0, doc="Time constant of the displacement control (used if ``use_dynamics``)")
    eps = Variable(unit="1", start=1.0, fixed=True,
                   doc="Relative displacement ``D / D_max`` (a state starting at 1 with dynamics)")

    def __init__(self, use_flange: bool = False, use_load_sensing: bool = False, use_dynamics: bool = False,
                 fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(use_flange=use_flange, fluid=fluid, **kw)
        self.use_load_sensing = flag(self, "use_load_sensing", use_load_sensing, structural=True)
        self.use_dynamics = flag(self, "use_dynamics", use_dynamics, structural=True)
        if not self.use_dynamics and "eps" not in self._starts:
            self.set_start("eps", 1.0, fixed=False)  # algebraic (= eps_ss) without dynamics
        if self.use_load_sensing:
            self.port_ls = Port(doc="Load-sensing pressure port (no flow)")

    def displacement(self) -> Any:
        return self.eps * self.D_max

    def equations(self) -> list:
        h = 0.5 * self.smoothing
        dp = self.port_b.p - self.port_a.p  # not self.dp: a Newton start then sees the right stroke
        eps_ss = smooth_clamp(1.0 - (dp - self.p_set) / self.dp_reg, 0.0, 1.0, h)
        eqs = super().equations()
        if self.use_load_sensing:
            margin = self.port_b.p - self.port_ls.p - self.dp_margin
            eps_ss = ca.fmin(eps_ss, smooth_clamp(1.0 - margin / self.dp_reg, 0.0, 1.0, h))
            eqs.append(eq(self.port_ls.m_flow, 0.0))
        if self.use_dynamics:
            return [*eqs, eq(self.T * der(self.eps), eps_ss - self.eps)]
        return [*eqs, eq(self.eps, eps_ss)]
