"""Lumped hydraulic line (pipe or hose): capacitance, friction and optional inertance."""

from __future__ import annotations

import math
from typing import Any

from flexlib import Component, Parameter, Variable, der, eq
from flexlib.core.options import flag

from ._checks import PositiveParameters, pressure_start, store_fluid
from .fluid import HLP46, Fluid
from .interfaces import Port, chamber_equations, chamber_mass_nominal, check_chamber_form

__all__ = ["Line"]

#: Blasius over laminar friction factor: f_t / f_lam = (0.3164 / 64) Re**0.75.
_C_BLASIUS = 0.3164 / 64.0


class Line(PositiveParameters, Component):
    """Lumped line of circular bore (pipe, tube or hose), π lumping.

    The fluid volume ``V = pi d**2 / 4 * L`` is split into two chambers of ``V/2`` at the
    ends (the port pressures ``p_a``, ``p_b``; each a :func:`chamber_equations` mass balance);
    between them the mass flow ``m_flow`` (a to b) meets the friction drop and, optionally,
    the fluid inertance:

    .. math::

        \\frac{L}{A}\\,\\dot{\\dot m} = p_a - p_b - \\Delta p_f \\quad (\\text{inertance; else } 0),
        \\qquad \\Delta p_f = R_{lam}\\, q\\, \\big(1 + (c\\,Re^{3/4})^8\\big)^{1/8}

    with ``q = m_flow / rho`` (mean pressure), the Hagen–Poiseuille resistance
    ``R_lam = 128 mu L / (pi d**4)``, ``mu = nu * rho``, ``Re = |q| d / (A nu)`` and
    ``c = 0.3164 / 64``: the laminar law for small ``Re`` and Blasius' smooth-pipe friction
    ``f = 0.3164 Re**-0.25`` for turbulent flow, blended by an 8-norm of the two friction
    factors (an analytic function of ``q**2``: smooth through zero, no events; +9 % at the
    intersection ``Re ≈ 1190``, < 0.1 % below ``Re = 500`` and above ``Re = 3000``). With
    ``use_turbulence=False`` the friction is purely laminar.

    Wall compliance (hoses): each half volume grows with pressure,
    ``V(p) = V/2 * (1 + k_wall * (p - p_ref))``, so the effective bulk modulus is
    ``1 / (1/beta + k_wall)``; ``k_wall = 0`` is a rigid pipe. One lump resolves the first
    mode only; for wave effects put several lines in series (the inner half volumes of
    neighbours then add up to full segments).

    Parameters
    ----------
    p_start : float or None
        Initial pressure of both ends [Pa] (structural; also fixes ``m_flow = 0`` at the start
        with inertance). ``None`` leaves them free (``init=`` or steady state). Do not fix
        it as well in a volume connected to the same node.
    use_turbulence : bool
        True to add the turbulent (Blasius) friction to the laminar one (structural).
    use_inertance : bool
        True to model the fluid inertance ``L / A`` (structural; adds the state ``m_flow``
        and a fast mode).
    fluid : Fluid
        Fluid property record (structural; default HLP46).
    chamber_form : str
        ``"mass"`` (default), ``"pressure"`` or ``"mass_total"`` (structural; see :func:`chamber_equations`).

    Connectors
    ----------
    port_a, port_b : Port
        Line ends; ``m_flow`` is positive from a to b.

    Notes
    -----
    ``L`` and ``d`` must be > 0 (checked at construction, at flatten and for run-time ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Pipe (IL)* block documentation (laminar and turbulent friction,
    fluid inertia, flexible wall).
    Hopsan component library, ``HydraulicLaminarOrifice`` (laminar resistance) and
    ``HydraulicTLMlossless`` (line capacitance and wave propagation).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §2.4 (lumped line parameters).
    F. M. White, *Fluid Mechanics*, 7th ed., §6.4 (Hagen–Poiseuille) and §6.6 (Blasius).
    """

    _positive = ("L", "d")
    L = Parameter(unit="m", min=0.0, doc="Length")
    d = Parameter(unit="m", min=0.0, doc="Inner (bore) diameter")
    k_wall = Parameter(0.0, unit="1/Pa", min=0.0,
                       doc="Wall compliance, relative volume change per pressure (1 / wall bulk modulus)")
    port_a = Port(doc="End a")
    port_b = Port(doc="End b")
    p_a = Variable(unit="Pa", nominal=1e7, start=1.01325e5, doc="Pressure at end a")
    p_b = Variable(unit="Pa", nominal=1e7, start=1.01325e5, doc="Pressure at end b")
    m_a = Variable(unit="kg", nominal=0.1, doc="Mass in the half at end a")
    m_b = Variable(unit="kg", nominal=0.1, doc="Mass in the half at end b")
    dm_a = Variable(unit="kg", nominal=1e-3, state_select="prefer",
                    doc="Deviation of ``m_a`` from ``rho(p_zero)·V/2`` (a state)")
    dm_b = Variable(unit="kg", nominal=1e-3, state_select="prefer",
                    doc="Deviation of ``m_b`` from ``rho(p_zero)·V/2`` (a state)")
    m_flow = Variable(unit="kg/s", nominal=1.0, doc="Mass flow from a to b through the friction element")
    q = Variable(unit="m3/s", nominal=1e-3, doc="Volume flow from a to b at the mean-pressure density")
    dp_f = Variable(unit="Pa", nominal=1e6, doc="Friction pressure drop")

    def __init__(self, p_start: float | None = None, use_turbulence: bool = True, use_inertance: bool = False,
                 fluid: Fluid = HLP46, chamber_form: str = "mass", **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.chamber_form = check_chamber_form(self, chamber_form)
        p_start = pressure_start(self, p_start)
        self.use_turbulence = flag(self, "use_turbulence", use_turbulence)
        self.use_inertance = flag(self, "use_inertance", use_inertance, structural=True)
        for name in ("p_a", "p_b"):
            self.set_start(name, fluid.p_ref if p_start is None else p_start, fixed=p_start is not None)
        if use_inertance and p_start is not None:
            self.set_start("m_flow", 0.0, fixed=True)

    def nominals(self) -> dict[str, float]:
        """The halves' masses by their volumes at the build's values (``interfaces.P_NOMINAL``;
        :mod:`flexlib.compile.scaling`)."""
        L, d = self.parameter_value("L"), self.parameter_value("d")
        if L is None or d is None:
            return {}
        v_half = math.pi / 8.0 * float(d) ** 2 * float(L)
        m, dm = self.fluid.rho_ref * v_half, chamber_mass_nominal(self.fluid, v_half)
        return {"m_a": m, "m_b": m, "dm_a": dm, "dm_b": dm}

    def equations(self) -> list:
        fl, a, b = self.fluid, self.port_a, self.port_b
        area = math.pi / 4.0 * self.d**2
        v_half = 0.5 * area * self.L
        form = self.chamber_form
        rho = fl.density(0.5 * (self.p_a + self.p_b))
        r_lam = 128.0 * fl.nu * rho * self.L / (math.pi * self.d**4)
        friction = r_lam * self.q
        if self.use_turbulence:
            re2 = (self.q * self.d / (area * fl.nu)) ** 2
            friction = friction * (1.0 + _C_BLASIUS**8 * re2**3) ** 0.125
        eqs = [eq(a.p, self.p_a), eq(b.p, self.p_b),
               *chamber_equations(fl, self.m_a, self.p_a, v_half * (1.0 + self.k_wall * (self.p_a - fl.p_ref)),
                                  a.m_flow - self.m_flow, dm=self.dm_a, V_ref=v_half,
                                  dV=v_half * self.k_wall * (self.p_a - fl.p_ref), form=form),
               *chamber_equations(fl, self.m_b, self.p_b, v_half * (1.0 + self.k_wall * (self.p_b - fl.p_ref)),
                                  b.m_flow + self.m_flow, dm=self.dm_b, V_ref=v_half,
                                  dV=v_half * self.k_wall * (self.p_b - fl.p_ref), form=form),
               eq(self.m_flow, rho * self.q), eq(self.dp_f, friction)]
        if form != "mass":
            rho_0 = float(fl.density(fl.p_zero))
            eqs += [eq(self.dm_a, self.m_a - rho_0 * v_half), eq(self.dm_b, self.m_b - rho_0 * v_half)]
        if self.use_inertance:
            return [*eqs, eq(self.L / area * der(self.m_flow), self.p_a - self.p_b - self.dp_f)]
        return [*eqs, eq(self.p_a - self.p_b, self.dp_f)]
