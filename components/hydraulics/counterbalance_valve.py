"""Pilot-assisted counterbalance (load-holding) valve with integral check valve."""

from __future__ import annotations

import math
from typing import Any

import casadi as ca

from flexlib import Component, Parameter, Variable, der, eq
from flexlib.core.options import flag

from ._checks import PositiveParameters, store_fluid
from ._smooth import smooth_clamp
from .flow_laws import critical_pressure, orifice_mass_flow
from .fluid import HLP46, Fluid
from .interfaces import P_NOMINAL, Port

__all__ = ["CounterbalanceValve"]


def _clip01(h: Any, fillet: Any) -> ca.SX:
    """``h`` clipped to [0, 1], continuous (no events); corners rounded over ``±fillet`` (C1) if ``fillet > 0``."""
    return smooth_clamp(h, 0.0, 1.0, fillet)


class CounterbalanceValve(PositiveParameters, Component):
    """Counterbalance valve: free flow into the load through a check valve, pilot-assisted relief out of it.

    Mounted in the line of a cylinder chamber that carries the load (``port_load`` on the cylinder,
    ``port_valve`` towards the directional valve, ``port_pilot`` on the opposite cylinder line).

    *Check valve* (flow valve → load): opening fraction
    ``h_c = clip((p_valve − p_load − p_check)/dp_check, 0, 1)``, area ``A_c = A_c,max·h_c``.

    *Counterbalance (relief) poppet* (flow load → valve): it opens when the load pressure, helped by the
    pilot pressure at the pilot ratio, overcomes the spring setting ``p_crack``; the opening grows
    proportionally over ``dp_open`` (Sun Hydraulics standard, non-vented: the spring chamber is
    referenced to the valve port, so back-pressure at the valve port adds to the setting)::

        p_open = (p_load − p_ref) + pilot_ratio·(p_pilot − p_ref),
        p_ref = p_valve (vented=False) or fluid.p_ref (vented=True, spring chamber to atmosphere)
        h_r = clip((p_open − p_crack)/dp_open, 0, 1),   A_r = A_r,max·h_r

    Both areas get the leakage area ``A_leak``; each path is an orifice with a smooth laminar transition
    (:func:`~.flow_laws.orifice_mass_flow`), so a path conducts in either direction when it is open.
    Maximum areas follow from nominal flows at a nominal pressure drop:
    ``A_max = Q_nom/(Cd·sqrt(2·dp_nom/rho_ref))``. The pilot port takes no flow (pilot volume neglected).
    The check valve opening is a static function of the pressures; so is the poppet opening unless
    ``use_dynamics``: then it follows the control pressure ``p_c``, a first-order lag of ``p_open`` (the
    damping orifice of the pilot, Simscape's *opening dynamics*)::

        T·der(p_c) = p_open − p_c,   h_r = clip((p_c − p_crack)/dp_open, 0, 1)

    ``p_c`` then starts at 0 (closed valve; override with ``init={"p_c": ...}``), or with ``steady_start`` at
    rest, ``der(p_c) = 0`` (``p_c = p_open``: a valve that has been holding its load). No events anywhere.
    The openings are weighted in the error test as the pressures they follow (nominal ``1e7 Pa / dp_check`` and
    ``1e7 Pa / dp_open``, at least 1), so that a check valve hovering at its cracking pressure does not set the step
    size (``docs/decisions/032-hydraulic-nominals-follow-the-states.md``).

    Counterbalance circuits are prone to oscillation: the pilot pressure, fed by a pump, integrates the
    speed error, and a high pilot ratio or a restriction downstream of the non-vented valve (the meter-out
    edge of the directional valve) destabilises the load — Sun recommends 1.5:1 for unstable loads, 3:1
    standard, 8:1 for stable ones. The model reproduces this (and a pilot lag adds phase lag): size the
    pilot ratio and the damping as for the real valve.

    Parameters
    ----------
    use_dynamics : bool
        True if the poppet opening lags the pressures by ``T`` (structural; adds the state ``p_c``).
    steady_start : bool
        With ``use_dynamics``: True if the control pressure starts at rest (``der(p_c) = 0``, an initial equation)
        instead of at 0 (structural; default False).
    vented : bool
        True if the spring chamber is vented to atmosphere (structural; default False: referenced to
        the valve port, the standard Sun Hydraulics counterbalance).
    fluid : Fluid
        Fluid property record (structural; default HLP46).

    Connectors
    ----------
    port_valve : Port
        Towards the directional valve (Sun port 1).
    port_load : Port
        Towards the cylinder chamber holding the load (Sun port 2).
    port_pilot : Port
        Pilot from the opposite cylinder line (Sun port 3); no flow.

    Notes
    -----
    With ``smoothing > 0`` each opening is C1 and exact outside ``±smoothing/2`` of its range around cracking
    and full opening (Simscape Fluids' *smoothing factor*): a valve crossing its corners often (a closed loop
    holding a load) then costs the integrator no corner restarts.

    ``p_crack``, ``pilot_ratio``, ``dp_open``, ``Q_nom``, ``dp_check``, ``Q_nom_check``, ``dp_nom``, ``Cd``,
    ``Re_cr`` and ``T`` must be > 0 (checked at construction, at flatten and for run-time ``params``).

    References
    ----------
    Sun Hydraulics, *Counterbalance valves* technical tips ("pilot ratio", "setting = 1.3 × load";
    back-pressure at port 1 is additive to the setting).
    Hopsan component library, *Counterbalance Valve* (``HydraulicCounterBalanceValve``):
    pressure-controlled poppet with pilot and integral check valve.
    MathWorks Simscape Fluids, *Counterbalance Valve (IL)* block documentation.
    """

    _positive = ("p_crack", "pilot_ratio", "dp_open", "Q_nom", "dp_check", "Q_nom_check", "dp_nom", "Cd", "Re_cr",
                 "T")

    p_crack = Parameter(unit="Pa", min=0.0,
                        doc=("Setting: opening pressure difference at zero pilot pressure (typically 1.3 × the maximum "
                             "load-holding pressure)"))
    pilot_ratio = Parameter(3.0, unit="1", min=0.0,
                            doc=("Pilot ratio, pilot area / load area of the poppet (3:1 standard, 1.5:1 for unstable "
                                 "loads, 8:1 for stable ones)"))
    dp_open = Parameter(20e5, unit="Pa", min=0.0, doc="Pressure rise above the setting for full opening of the poppet")
    Q_nom = Parameter(6e-4, unit="m3/s", min=0.0, doc="Flow of the fully open poppet at ``dp_nom``")
    p_check = Parameter(1e5, unit="Pa", min=0.0, doc="Cracking pressure of the check valve")
    dp_check = Parameter(2e5, unit="Pa", min=0.0,
                         doc="Pressure rise above ``p_check`` for full opening of the check valve")
    Q_nom_check = Parameter(6e-4, unit="m3/s", min=0.0, doc="Flow of the fully open check valve at ``dp_nom``")
    dp_nom = Parameter(10e5, unit="Pa", min=0.0, doc="Pressure drop of the nominal flows")
    Cd = Parameter(0.7, unit="1", min=0.0, doc="Discharge coefficient")
    A_leak = Parameter(1e-12, unit="m2", min=0.0, doc="Leakage area of each closed path")
    Re_cr = Parameter(12.0, unit="1", min=0.0, doc="Critical Reynolds number of the laminar–turbulent transition")
    T = Parameter(0.02, unit="s", min=0.0, doc="Time constant of the poppet opening (used if ``use_dynamics``)")
    smoothing = Parameter(0.0, unit="1", min=0.0, max=1.0,
                          doc=("Width of the corner fillets of both openings as a fraction of their opening ranges "
                               "``dp_check`` and ``dp_open`` (0: sharp corners)"))

    m_check = Variable(unit="kg/s", doc="Mass flow valve -> load through the check valve")
    m_relief = Variable(unit="kg/s", doc="Mass flow load -> valve through the poppet")
    h_check = Variable(unit="1", doc="Opening fraction of the check valve")
    h_relief = Variable(unit="1", doc="Opening fraction of the poppet")
    p_open = Variable(unit="Pa", nominal=1e7, doc="Opening pressure acting on the poppet")
    p_c = Variable(unit="Pa", nominal=1e7, start=0.0, fixed=True,
                   doc="Control pressure setting the poppet opening (= ``p_open`` without dynamics)")

    port_valve = Port(doc="Towards the directional valve")
    port_load = Port(doc="Towards the load (cylinder)")
    port_pilot = Port(doc="Pilot")

    def __init__(self, use_dynamics: bool = False, vented: bool = False, fluid: Fluid = HLP46,
                 steady_start: bool = False, **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.use_dynamics = flag(self, "use_dynamics", use_dynamics, structural=True)
        self.steady_start = flag(self, "steady_start", steady_start, structural=True) and self.use_dynamics
        self.vented = flag(self, "vented", vented)
        if (self.steady_start or not self.use_dynamics) and "p_c" not in self._starts:
            self.set_start("p_c", 0.0, fixed=False)  # a guess: p_c = p_open (algebraic) or der(p_c) = 0 fixes it

    def nominals(self) -> dict[str, float]:
        """Nominals at the build's values (:mod:`flexlib.compile.scaling`). The openings are functions of pressures
        (nominal ``P_NOMINAL``): weighted as the pressures are. The path and port flows weighted as the pressures
        they follow: each path's flow rises by
        ``rho_ref·Q·P_NOMINAL/dp_span·sqrt(dp_span/dp_nom)`` for a pressure change of ``P_NOMINAL`` through its
        opening range (the steepest part of its law), so that a check path in its opening range is tested no tighter
        than the pressures behind it (``docs/decisions/032-hydraulic-nominals-follow-the-states.md``)."""
        out = {}
        for h, span in (("h_check", "dp_check"), ("h_relief", "dp_open")):
            value = self.parameter_value(span)
            if value is not None and float(value) > 0:
                out[h] = max(1.0, P_NOMINAL / float(value))
        val = {n: self.parameter_value(n) for n in ("Q_nom", "Q_nom_check", "dp_nom", "dp_check", "dp_open")}
        if any(v is None or not float(v) > 0 for v in val.values()):
            return out
        rho = float(self.fluid.rho_ref)

        def gain(Q: Any, span: Any) -> float:
            return rho * float(Q) * P_NOMINAL / float(span) * math.sqrt(min(1.0, float(span) / float(val["dp_nom"])))

        g_check, g_relief = gain(val["Q_nom_check"], val["dp_check"]), gain(val["Q_nom"], val["dp_open"])
        port = max(1.0, g_check, g_relief)
        return {**out, "m_check": max(1.0, g_check), "m_relief": max(1.0, g_relief), "port_valve.m_flow": port,
                "port_load.m_flow": port}

    def _path(self, opening: Any, Q_nom: Any, p_up: Any, p_down: Any) -> ca.SX:
        fl = self.fluid
        area = Q_nom / (self.Cd * ca.sqrt(2.0 * self.dp_nom / fl.rho_ref)) * opening + self.A_leak
        rho = fl.density(0.5 * (p_up + p_down))
        return orifice_mass_flow(p_up - p_down, area, self.Cd, rho, critical_pressure(area, self.Cd, rho, fl.nu,
                                                                                      self.Re_cr))

    def initial_equations(self) -> list:
        """``steady_start``: the control pressure at rest."""
        return [eq(der(self.p_c), 0.0, label="steady control pressure")] if self.steady_start else []

    def equations(self) -> list:
        V, L, X = self.port_valve, self.port_load, self.port_pilot
        p_ref = self.fluid.p_ref if self.vented else V.p
        return [
            eq(self.h_check, _clip01((V.p - L.p - self.p_check) / self.dp_check, 0.5 * self.smoothing)),
            eq(self.p_open, (L.p - p_ref) + self.pilot_ratio * (X.p - p_ref)),
            eq(self.T * der(self.p_c), self.p_open - self.p_c) if self.use_dynamics else eq(self.p_c, self.p_open),
            eq(self.h_relief, _clip01((self.p_c - self.p_crack) / self.dp_open, 0.5 * self.smoothing)),
            eq(self.m_check, self._path(self.h_check, self.Q_nom_check, V.p, L.p)),
            eq(self.m_relief, self._path(self.h_relief, self.Q_nom, L.p, V.p)),
            eq(V.m_flow, self.m_check - self.m_relief),
            eq(L.m_flow, self.m_relief - self.m_check),
            eq(X.m_flow, 0.0),
        ]
