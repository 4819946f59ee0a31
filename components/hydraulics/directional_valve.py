"""Proportional 4/3 directional valve with spool dynamics."""

from __future__ import annotations

import math
from typing import Any

import casadi as ca
import numpy as np

from flexlib import Component, Input, Parameter, Variable, assert_, der, eq, no_event
from flexlib.core.options import flag, remember_option
from flexlib.errors import ModelError, ParameterError

from ._checks import PositiveParameters, store_fluid
from ._smooth import smooth_ramp
from .flow_laws import critical_pressure, orifice_mass_flow
from .fluid import HLP46, Fluid
from .interfaces import Port

__all__ = ["DirectionalValve43"]

#: Normalised laps (P→A, P→B, A→T, B→T) of the centre configurations; negative = underlap (open).
CENTRES = {
    "closed": (0.0, 0.0, 0.0, 0.0),
    "open": (-0.1, -0.1, -0.1, -0.1),
    "float": (0.0, 0.0, -0.1, -0.1),
    "tandem": (0.1, 0.1, 0.1, 0.1),
}


def _centre(valve: Any, centre: Any) -> str:
    """``centre`` if it is one of :data:`CENTRES` (a list or dict is refused too, not a TypeError)."""
    if not isinstance(centre, str) or centre not in CENTRES:
        raise ModelError(f"{type(valve).__name__}: centre must be one of {sorted(CENTRES)}, got {centre!r}")
    remember_option(valve, "centre", lambda v: _centre(valve, v), structural=True)
    return centre


class DirectionalValve43(PositiveParameters, Component):
    """Proportional 4/3 directional valve (4 ports, 3 positions): spool dynamics and four metering edges.

    Spool: the command ``u`` (normalised, −1…1) is clipped to [−1, 1] and drives the normalised spool
    position ``xs`` through a second-order lag (default)::

        der(xs) = vs,   der(vs) = omega²·(clip(u) − xs) − 2·zeta·omega·vs

    or, with ``ideal_spool=True``, instantaneously: ``xs = clip(u)`` (no spool states; ``vs = 0`` is not
    computed; ``omega`` and ``zeta`` are unused). The ideal spool is the valve model of published boom and
    crane studies that take the spool as much faster than the mechanics; it removes the spool mode
    (30 Hz by default) and the step-size limit it sets.

    Edges P→A and B→T open for ``xs > 0``, P→B and A→T for ``xs < 0``. Each edge ``e`` has the normalised
    lap ``lap_e`` (> 0 overlap: the edge opens only beyond ``lap_e``; < 0 underlap: open in the centre)
    and the opening fraction (continuous, no events; clipped to [0, 1])::

        h_PA = (xs − lap_PA)/(1 − lap_PA),  h_BT = (xs − lap_BT)/(1 − lap_BT),
        h_PB = (−xs − lap_PB)/(1 − lap_PB), h_AT = (−xs − lap_AT)/(1 − lap_AT),
        A_e = A_max·clip(h_e, 0, 1) + A_leak

    so every edge is fully open at full stroke. ``A_max`` follows from the nominal flow of one fully open
    edge at the nominal pressure drop across that edge (data-sheet rating "Q_nom at Δp_nom per control
    edge"): ``Q_nom = Cd·A_max·sqrt(2·dp_nom/rho_ref)``. The edge flow is the orifice law with a smooth
    laminar transition (:func:`~.flow_laws.orifice_mass_flow`, density at the mean edge pressure), so the
    leakage area ``A_leak`` of a closed edge gives a laminar leakage. The valve stores no fluid::

        port_P.m_flow = m_PA + m_PB (+ m_PT),  port_A.m_flow = m_AT − m_PA,
        port_B.m_flow = m_BT − m_PB,           port_T.m_flow = −(m_AT + m_BT (+ m_PT))

    Pressure-compensated meter-in (``compensated=True``, structural): an individual 2-way pressure compensator
    upstream of the spool (the load-sensing valve sections of mobile machines) keeps the drop across an open
    meter-in edge (P→A, P→B) at ``dp_comp`` whenever the supply allows it, so their flow follows the spool and
    not the load::

        Δp_eff = Δp − ramp(Δp − dp_comp)   (a min with its corner rounded over ±5 % of dp_comp, C1)

    replaces ``Δp = p_P − p_A`` (``p_P − p_B``) in the meter-in orifice law; the compensator's own dynamics are
    neglected (much faster than the spool). With ``dp_comp = dp_nom`` the meter-in edges pass ``Q_nom·h`` at
    any supply pressure above the load pressure + ``dp_nom``; the meter-out edges are unchanged.

    Centre configurations (``centre``, structural) set the default laps: ``"closed"`` (all 0: critical
    centre, all ports blocked in neutral), ``"open"`` (all −0.1: all ports connected), ``"float"`` (P
    edges 0, tank edges −0.1: A and B to T, P blocked), ``"tandem"`` (all 0.1, plus a P→T bypass of
    nominal flow ``Q_nom_PT`` whose opening ``1 − |xs|/xs_PT`` closes at ``|xs| = xs_PT``). Laps passed
    explicitly override the preset.

    Parameters
    ----------
    centre : str
        ``"closed"`` (default), ``"open"``, ``"float"`` or ``"tandem"`` (structural; see above).
    compensated : bool
        True for pressure-compensated meter-in edges (structural; default False).
    ideal_spool : bool
        True for an instantaneous spool, ``xs = clip(u)`` (structural; default False: second-order lag).
    fluid : Fluid
        Fluid property record (structural; default HLP46).

    Connectors
    ----------
    port_P, port_T, port_A, port_B : Port
        Supply, tank and the two consumer ports; m_flow positive into the valve.

    Variables
    ---------
    m_PT : kg/s
        Mass flow through the tandem bypass P->T (only if ``centre="tandem"``).

    Notes
    -----
    A signal cannot be checked when the model is built: a command leaving [−1 − 1e-6, 1 + 1e-6] stops
    the run with a :class:`~flexlib.SolverError` naming the valve and the time (``flexlib.assert_``,
    located by root finding; the 1e-6 margin keeps a controller output saturated at exactly ±1 from
    sitting on the indicator's zero). Within the margin the command is clipped continuously. The edge
    openings are clipped without events too (a servo valve around its null would otherwise make an
    event at every crossing).

    ``Q_nom``, ``dp_nom``, ``Cd``, ``omega``, ``zeta``, ``xs_PT``, ``Re_cr`` and ``dp_comp`` must be > 0
    (checked at construction, at flatten and for run-time ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *4-Way 3-Position Directional Valve (IL)* block documentation (edges,
    laps, leakage area).
    Danfoss, *PVG 32 proportional valve group*, technical information (pressure-compensated sections); H. Murrenhoff,
    *Grundlagen der Fluidtechnik, Teil 1: Hydraulik*, Shaker 2005, ch. 8 (load sensing, individual compensators).
    Hopsan component library, *4/3 Directional Valve* (``Hydraulic43Valve``): spool second-order
    dynamics, overlaps per edge.
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §3.4–3.5 (four-way spool valves, rated flow).
    """

    _positive = ("Q_nom", "dp_nom", "Cd", "omega", "zeta", "xs_PT", "Re_cr", "dp_comp")

    Q_nom = Parameter(6e-4, unit="m3/s", min=0.0, doc="Nominal volume flow of one fully open edge at ``dp_nom``")
    dp_nom = Parameter(35e5, unit="Pa", min=0.0,
                       doc=("Nominal pressure drop per edge for ``Q_nom`` (35 bar per edge for servo valves, 5–10 bar "
                            "for proportional valves)"))
    Cd = Parameter(0.7, unit="1", min=0.0, doc="Discharge coefficient")
    omega = Parameter(2 * math.pi * 30.0, unit="rad/s", min=0.0, doc="Spool natural frequency")
    zeta = Parameter(0.8, unit="1", min=0.0, doc="Spool damping ratio")
    lap_PA = Parameter(0.0, unit="1", max=0.99, doc="Normalised lap of edge P->A (> 0 overlap, < 0 underlap)")
    lap_PB = Parameter(0.0, unit="1", max=0.99, doc="Normalised lap of edge P->B (> 0 overlap, < 0 underlap)")
    lap_AT = Parameter(0.0, unit="1", max=0.99, doc="Normalised lap of edge A->T (> 0 overlap, < 0 underlap)")
    lap_BT = Parameter(0.0, unit="1", max=0.99, doc="Normalised lap of edge B->T (> 0 overlap, < 0 underlap)")
    A_leak = Parameter(1e-12, unit="m2", min=0.0, doc="Leakage area of every edge (added to the opening)")
    Q_nom_PT = Parameter(6e-4, unit="m3/s", min=0.0,
                         doc='Nominal flow of the tandem-centre P->T bypass at ``dp_nom`` (``centre="tandem"`` only)')
    xs_PT = Parameter(0.1, unit="1", min=0.0, doc="Spool position at which the tandem bypass is closed")
    Re_cr = Parameter(12.0, unit="1", min=0.0, doc="Critical Reynolds number of the laminar–turbulent transition")
    dp_comp = Parameter(10e5, unit="Pa", min=0.0,
                        doc="Pressure drop held across an open meter-in edge by the compensator (``compensated`` only)")

    u = Input(unit="1", doc="Spool command, -1..1 (clipped; see Notes)")
    xs = Variable(unit="1", fixed=True, state_select="prefer",
                  doc="Normalised spool position (a state starting at 0; ``u_sat`` with ``ideal_spool``)")
    vs = Variable(unit="1/s", fixed=True, state_select="prefer", nominal=100.0,
                  doc="Spool velocity (a state starting at 0; 0 with ``ideal_spool``)")
    u_sat = Variable(unit="1", doc="Spool command clipped to [-1, 1]")
    m_PA = Variable(unit="kg/s", doc="Mass flow through edge P->A")
    m_PB = Variable(unit="kg/s", doc="Mass flow through edge P->B")
    m_AT = Variable(unit="kg/s", doc="Mass flow through edge A->T")
    m_BT = Variable(unit="kg/s", doc="Mass flow through edge B->T")
    q_A = Variable(unit="m3/s", nominal=1e-3, doc="Volume flow out of port A")
    q_B = Variable(unit="m3/s", nominal=1e-3, doc="Volume flow out of port B")

    port_P = Port(doc="Supply")
    port_T = Port(doc="Tank")
    port_A = Port(doc="Consumer A")
    port_B = Port(doc="Consumer B")

    def __init__(self, centre: str = "closed", fluid: Fluid = HLP46, ideal_spool: bool = False,
                 compensated: bool = False, **kw: Any) -> None:
        _centre(self, centre)
        for name, lap in zip(("lap_PA", "lap_PB", "lap_AT", "lap_BT"), CENTRES[centre], strict=True):
            kw.setdefault(name, lap)
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.centre = _centre(self, centre)  # decided the laps' defaults and the tandem bypass: fixed once built
        self.ideal_spool = flag(self, "ideal_spool", ideal_spool, structural=True)
        self.compensated = flag(self, "compensated", compensated)
        if self.ideal_spool:  # xs and vs follow from the command: no initial conditions of their own
            self.set_start("xs", 0.0, fixed=False)
            self.set_start("vs", 0.0, fixed=False)
        if centre == "tandem":
            self.m_PT = Variable(unit="kg/s", doc="Mass flow through the tandem bypass P->T")

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        for name in ("lap_PA", "lap_PB", "lap_AT", "lap_BT"):
            if name in values and not np.all(values[name] < 1.0):
                raise ParameterError(f"{self.param_label(name)} = {float(values[name])!r} must be < 1 (normalised lap)")

    # -- edges -----------------------------------------------------------------------------------
    @property
    def A_max(self) -> ca.SX:
        """Area of a fully open edge from the nominal rating [m2]."""
        return self.Q_nom / (self.Cd * ca.sqrt(2.0 * self.dp_nom / self.fluid.rho_ref))

    def _edge(self, opening: Any, A_max: Any, p_up: Any, p_down: Any, meter_in: bool = False) -> ca.SX:
        """Mass flow through one edge of normalised opening ``opening`` (clipped to [0, 1]); a ``meter_in`` edge of
        a compensated valve sees at most ``dp_comp``."""
        h = no_event(opening > 0.0, no_event(opening < 1.0, opening, 1.0), 0.0)
        area = A_max * h + self.A_leak
        rho = self.fluid.density(0.5 * (p_up + p_down))
        p_cr = critical_pressure(area, self.Cd, rho, self.fluid.nu, self.Re_cr)
        dp = p_up - p_down
        if meter_in and self.compensated:
            dp = dp - smooth_ramp(dp - self.dp_comp, 0.05 * self.dp_comp)
        return orifice_mass_flow(dp, area, self.Cd, rho, p_cr)

    def equations(self) -> list:
        assert_(self.u <= 1.0 + 1e-6, "spool command above +1")
        assert_(self.u >= -1.0 - 1e-6, "spool command below -1")
        P, T, A, B = self.port_P, self.port_T, self.port_A, self.port_B
        xs, w = self.xs, self.omega
        eqs = [
            eq(self.u_sat, no_event(self.u > 1.0, 1.0, no_event(self.u < -1.0, -1.0, self.u))),
            *([eq(xs, self.u_sat), eq(self.vs, 0.0)] if self.ideal_spool else
              [eq(der(xs), self.vs), eq(der(self.vs), w**2 * (self.u_sat - xs) - 2.0 * self.zeta * w * self.vs)]),
            eq(self.m_PA, self._edge((xs - self.lap_PA) / (1.0 - self.lap_PA), self.A_max, P.p, A.p, True)),
            eq(self.m_BT, self._edge((xs - self.lap_BT) / (1.0 - self.lap_BT), self.A_max, B.p, T.p)),
            eq(self.m_PB, self._edge((-xs - self.lap_PB) / (1.0 - self.lap_PB), self.A_max, P.p, B.p, True)),
            eq(self.m_AT, self._edge((-xs - self.lap_AT) / (1.0 - self.lap_AT), self.A_max, A.p, T.p)),
            eq(A.m_flow, self.m_AT - self.m_PA), eq(B.m_flow, self.m_BT - self.m_PB),
            eq(self.q_A, -A.m_flow / self.fluid.density(A.p)), eq(self.q_B, -B.m_flow / self.fluid.density(B.p)),
        ]
        if self.centre == "tandem":
            A_PT = self.Q_nom_PT / (self.Cd * ca.sqrt(2.0 * self.dp_nom / self.fluid.rho_ref))
            abs_xs = no_event(xs > 0.0, xs, -xs)
            eqs += [eq(self.m_PT, self._edge(1.0 - abs_xs / self.xs_PT, A_PT, P.p, T.p)),
                    eq(P.m_flow, self.m_PA + self.m_PB + self.m_PT),
                    eq(T.m_flow, -(self.m_AT + self.m_BT + self.m_PT))]
        else:
            eqs += [eq(P.m_flow, self.m_PA + self.m_PB), eq(T.m_flow, -(self.m_AT + self.m_BT))]
        return eqs
