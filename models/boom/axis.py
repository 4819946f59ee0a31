"""One hydraulic axis of a boom: valve section, load-holding valves, port cartridges and cylinder (issue 28)."""

from __future__ import annotations

import math

import flexlib as fl
from flexlib import Input
from flexlib.components.hydraulics import (
    HLP46,
    CheckValve,
    CounterbalanceValve,
    DirectionalValve43,
    LineCylinder,
    Port,
    PressureReliefValve,
    Volume,
)
from flexlib.components.mechanics.multibody import Frame
from flexlib.errors import ParameterError

from ._checks import positive

__all__ = ["HydraulicAxis"]

PART = "HydraulicAxis"

# Defaults: the values of models/pump_truck/model.py's constants of the same name (generic valve-block and seal data;
# their sources are given there and in the docstring below).
P_TANK = HLP46.p_ref  # tank pressure [Pa] (atmospheric)
V_HOSE = 1.0e-3  # hose volume between directional and counterbalance valve [m3]
VALVE_DP = 35e5  # nominal pressure drop per edge, and the compensators' setting [Pa]
VALVE_HZ = 20.0  # spool bandwidth [Hz]
VALVE_ZETA = 0.7  # spool damping ratio [1]
CYL_FC = 0.01  # seal friction / force of the system pressure on the piston [1] (3.5 bar at 350 bar)
CYL_VREG = 0.005  # regularisation velocity of the seal friction [m/s]
D_CYL = 5e4  # viscous friction of the cylinder [N.s/m]
PILOT_RATIO = 3.0  # counterbalance pilot ratio (Sun standard 3:1)
CBV_T = 0.05  # counterbalance poppet lag: pilot damping orifice [s]
CBV_DP_OPEN = 30e5  # counterbalance: pressure rise above the setting for full opening [Pa]
CBV_DP_CHECK = 2e5  # counterbalance: check valve pressure rise for full opening [Pa]
CBV_SMOOTHING = 0.1  # counterbalance openings: C1 corners over 10 % of their ranges
CBV_A_LEAK = 1e-11  # counterbalance: leakage area of both paths [m2]
SHOCK_FACTOR = 1.1  # shock relief valves: setting / system pressure [1]
SHOCK_LEAK = 1e-16  # shock relief valves: leakage conductance [m3/(s.Pa)]
MAKEUP_CRACK = 0.2e5  # anti-cavitation make-up check valves: cracking pressure [Pa]
MAKEUP_OPEN = 1e5  # ... pressure difference at full opening [Pa]
MAKEUP_AREA = 2e-4  # ... full opening area [m2]
VALVE_LEAK = 1e-10  # leakage area of each spool edge [m2]
VALVE_LAP = 0.02  # overlap of the four spool edges [1 of the spool stroke]: a dead band around neutral


class HydraulicAxis(fl.Model):
    """A boom cylinder drive: valve section, counterbalance valves, hoses, port cartridges, cylinder with weight.

    Diagram (as ``PumpTruck`` builds each boom joint, ``models/pump_truck/model.py``)::

        port_P ─┐                      ┌─ hose_hold ─ cbv_hold ─┐                 ┌── shock_A ─→ port_T
                valve (4/3, u) ─ hold ─┤                         ├─ cylinder port ─┤
        port_T ─┘      └─ other line ──┴─ (hose_over ─ cbv_over) ┘   (A and B)    └── makeup_A ←─ port_T
                                                                                   (and shock_B, makeup_B)

    - ``cylinder``: :class:`~flexlib.components.hydraulics.LineCylinder` between ``frame_a`` (housing pin) and
      ``frame_b`` (rod pin), ISO bore/rod/stroke, closed length ``L0``, dead volumes 10 % of each chamber's swept
      volume + 0.1 L, housing and rod point masses on the line (weight and inertia, MSL ``LineForceWithTwoMasses``;
      the cylinder's along-line mass ``m`` is 0: ``m_rod`` carries the rod), seal friction: Coulomb
      ``p_friction·A_p`` (3.5 bar breakaway pressure, Rexroth data 3–5 bar) below ``v_reg`` plus viscous ``d``.
    - ``valve``: closed-centre proportional :class:`~flexlib.components.hydraulics.DirectionalValve43`, ``Q_nom`` at
      ``dp_nom`` per edge, spool second order (``f_spool``, ζ = 0.7), pressure-compensated meter-in edges
      (``dp_comp = dp_nom``: the individual compensators of load-sensing valve blocks; the flow follows the spool,
      not the load). Valve port A feeds the cap side: ``u > 0`` extends the cylinder. All four edges overlap by
      ``lap`` (2 % of the spool stroke), the dead band around neutral that a closed-centre proportional spool keeps
      after its electronics' dead-band compensation: the small corrections
      of a joint loop holding its pose (a few 10⁻³ of the command) pass no oil. With zero lap each of them opened
      an edge to a trickle, and the expand-fold took twice the integration steps (57 616 against 28 569), and
      the move starts were rougher (``benchmarks/pump_truck_flows.py``: 10 against 16 of 20 smooth). Overlapping
      the return edges alone (``lap_AT``, ``lap_BT`` of ``valve``) made the loops pump the inlet chambers while
      holding (``docs/pump_truck.md``, "Known limits").
    - ``cbv_hold`` + ``hose_hold``: :class:`~flexlib.components.hydraulics.CounterbalanceValve` on the holding line
      ``hold`` (``"A"``: cap side holds, the cylinder pushes), pilot from the other line, pilot ratio 3:1, setting
      ``p_crack_<hold>`` (Sun: 1.3 × the worst holding pressure), poppet lag ``CBV_T`` (pilot damping orifice,
      steady at start), both paths rated ``2·Q_nom`` at ``dp_nom``; the hose volume between it and the valve.
    - ``cbv_over`` + ``hose_over`` (``over_centre=True``): the same on the other line, set at its own ``p_crack``,
      each valve piloted from the other line's hose (a joint that folds over centre, or a load-holding valve on
      both sides of a cylinder that always pushes).
    - ``shock_A``/``shock_B``: shock relief cartridges to tank at ``1.1·p_system``; ``makeup_A``/``makeup_B``:
      anti-cavitation make-up check valves from tank (0.2 bar cracking, 2 cm² at 1 bar).

    At start (``free_start=True``) the free chamber (parameter ``free_A``: 1 the cap side, 0 the rod side;
    default the chamber that does not hold) is at ``p_free_start``; the holding chamber's pressure is what holds
    the load at rest (Merritt's static balance, gauge pressures: ``p_hold = (F + p_free·A_free)/A_hold``), its start
    value only a guess.

    Connectors
    ----------
    frame_a, frame_b : multibody Frame
        Housing pin and rod pin.
    port_P, port_T : Port
        Supply and tank.
    u : Input [1]
        Valve command, −1 … 1.

    Parameters
    ----------
    d_bore, d_rod, stroke, L0 : float
        Bore and rod diameters (``d_rod < d_bore``), stroke and closed pin-to-pin length [m].
    Q_nom : float
        Valve rating: flow of one fully open edge at ``dp_nom`` [m3/s].
    hold : {"A", "B"}
        The line that carries ``cbv_hold`` (structural).
    over_centre : bool
        True: the other line carries ``cbv_over`` as well (structural).
    p_crack_A, p_crack_B : float or None
        Counterbalance settings of the lines that carry one [Pa] (relative to the valve port).
    m_housing, L_housing, m_rod, L_rod : float
        Housing mass [kg] at ``L_housing`` [m] from frame_a; rod (with piston) mass [kg] at ``L_rod`` [m] from frame_b.
    p_system : float
        System pressure [Pa]; the shock valves are set at ``1.1·p_system``.
    p_friction : float
        Seal friction pressure [Pa]: Coulomb force ``p_friction·A_p`` (``CYL_FC·350 bar``).
    d, v_reg : float
        Viscous friction [N.s/m] and regularisation velocity of the seal friction [m/s].
    dp_nom, f_spool, pilot_ratio, V_hose : float
        Valve edge pressure drop [Pa], spool bandwidth [Hz], counterbalance pilot ratio [1], hose volume [m3].
    lap : float
        Overlap of the valve's four edges [1, fraction of the spool stroke], ``0 <= lap < 0.5`` (0: zero lap).
    p_free_start, p_A_start, p_B_start : float
        Free chamber's start pressure [Pa]; start guesses of the chamber pressures [Pa].
    free_start : bool
        True: the initial equation ``free chamber = p_free_start`` (structural).

    References
    ----------
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §5 (valve-controlled actuator, static load balance).
    Sun Hydraulics, *Counterbalance valves* (setting 1.3 × load, pilot ratio 3:1, non-vented).
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.LineForceWithTwoMasses``;
    ``Modelica.Mechanics.MultiBody.Examples.Systems.RobotR3.OneAxis`` (one drive tested alone).
    """

    def __init__(self, d_bore: float, d_rod: float, stroke: float, L0: float, Q_nom: float, hold: str = "A",
                 over_centre: bool = False, p_crack_A: float | None = None, p_crack_B: float | None = None,
                 m_housing: float = 0.0, L_housing: float = 0.0, m_rod: float = 0.0, L_rod: float = 0.0,
                 p_system: float = 35e6, p_friction: float = CYL_FC * 35e6, d: float = D_CYL, v_reg: float = CYL_VREG,
                 dp_nom: float = VALVE_DP, f_spool: float = VALVE_HZ, pilot_ratio: float = PILOT_RATIO,
                 V_hose: float = V_HOSE, lap: float = VALVE_LAP, p_free_start: float = P_TANK,
                 p_A_start: float = P_TANK, p_B_start: float = P_TANK, free_start: bool = True) -> None:
        super().__init__()
        bore, rod = positive(PART, "d_bore", d_bore, "m"), positive(PART, "d_rod", d_rod, "m")
        if rod >= bore:
            raise ParameterError(f"HydraulicAxis: d_rod = {rod!r} must be < d_bore = {bore!r} [m]")
        if hold not in ("A", "B"):
            raise ParameterError(f"HydraulicAxis: hold must be 'A' or 'B' (the line with the counterbalance valve), "
                                 f"got {hold!r}")
        if not isinstance(over_centre, bool) or not isinstance(free_start, bool):
            raise ParameterError("HydraulicAxis: over_centre and free_start must be True or False")
        other = "B" if hold == "A" else "A"
        crack = {"A": p_crack_A, "B": p_crack_B}
        for side in (hold, other) if over_centre else (hold,):
            if crack[side] is None:
                raise ParameterError(f"HydraulicAxis: p_crack_{side} is needed (line {side} carries a counterbalance "
                                     "valve)")
            positive(PART, f"p_crack_{side}", crack[side], "Pa")
        masses = {name: positive(PART, name, value, unit, allow_zero=True) for name, value, unit in
                  (("m_housing", m_housing, "kg"), ("L_housing", L_housing, "m"), ("m_rod", m_rod, "kg"),
                   ("L_rod", L_rod, "m"))}
        A_p, A_r = math.pi / 4 * bore**2, math.pi / 4 * (bore**2 - rod**2)
        stroke, Q_nom = positive(PART, "stroke", stroke, "m"), positive(PART, "Q_nom", Q_nom, "m3/s")
        p_system = positive(PART, "p_system", p_system, "Pa")
        self.frame_a, self.frame_b = Frame(doc="Housing pin"), Frame(doc="Rod pin")
        self.port_P, self.port_T = Port(doc="Supply"), Port(doc="Tank")
        self.u = Input(unit="1", doc="Valve command, -1 ... 1 (u > 0 extends the cylinder)")
        friction = positive(PART, "p_friction", p_friction, "Pa", allow_zero=True) * A_p
        self.cylinder = LineCylinder(d_bore=bore, d_rod=rod, stroke=stroke, L0=positive(PART, "L0", L0, "m"), m=0.0,
                                     d=positive(PART, "d", d, "N.s/m", allow_zero=True),
                                     v_reg=positive(PART, "v_reg", v_reg, "m/s"), F_c=friction,
                                     V_dead_A=0.1 * A_p * stroke + 1e-4, V_dead_B=0.1 * A_r * stroke + 1e-4,
                                     p_fixed=False, **masses)
        self.cylinder.cylinder.set_start("p_A", positive(PART, "p_A_start", p_A_start, "Pa"), fixed=False)
        self.cylinder.cylinder.set_start("p_B", positive(PART, "p_B_start", p_B_start, "Pa"), fixed=False)
        dp_nom, omega = positive(PART, "dp_nom", dp_nom, "Pa"), 2 * math.pi * positive(PART, "f_spool", f_spool, "Hz")
        lap = positive(PART, "lap", lap, "1", allow_zero=True)
        if lap >= 0.5:
            raise ParameterError(f"HydraulicAxis: lap = {lap!r} must be < 0.5 (a fraction of the spool stroke)")
        self.valve = DirectionalValve43(Q_nom=Q_nom, dp_nom=dp_nom, omega=omega, zeta=VALVE_ZETA,
                                        A_leak=VALVE_LEAK, compensated=True, dp_comp=dp_nom, lap_PA=lap, lap_PB=lap,
                                        lap_AT=lap, lap_BT=lap)
        cbv = {"pilot_ratio": positive(PART, "pilot_ratio", pilot_ratio, "1"), "Q_nom": 2 * Q_nom, "dp_nom": dp_nom,
               "V_hose": positive(PART, "V_hose", V_hose, "m3")}
        self.cbv_hold, self.hose_hold = _counterbalance(crack[hold], **cbv)
        if over_centre:
            self.cbv_over, self.hose_over = _counterbalance(crack[other], **cbv)
        self.shock_A, self.makeup_A = port_cartridges(p_system)
        self.shock_B, self.makeup_B = port_cartridges(p_system)
        self.hold, self.over_centre, self.free_start = hold, over_centre, free_start
        self.free_A = fl.Parameter(1.0 if hold == "B" else 0.0, unit="1",
                                   doc="1: the cap chamber (A) starts at p_free_start; 0: the rod chamber (B) does")
        self.p_free_start = fl.Parameter(positive(PART, "p_free_start", p_free_start, "Pa"), unit="Pa",
                                         doc="Start pressure of the free chamber")
        self._connect_lines(hold, other)

    def _connect_lines(self, hold: str, other: str) -> None:
        """Valve, holding valves and hoses between the valve's and the cylinder's ports; cartridges on both ports."""
        cyl, valve = self.cylinder, self.valve
        self.connect(self.frame_a, cyl.frame_a)
        self.connect(self.frame_b, cyl.frame_b)
        self.connect(self.u, valve.u)
        self.connect(self.port_P, valve.port_P)
        self.connect(self.port_T, valve.port_T, self.shock_A.port_b, self.shock_B.port_b, self.makeup_A.port_a,
                     self.makeup_B.port_a)
        self.connect(cyl.port_A, self.shock_A.port_a, self.makeup_A.port_b)
        self.connect(cyl.port_B, self.shock_B.port_a, self.makeup_B.port_b)
        v_port = {"A": valve.port_A, "B": valve.port_B}
        c_port = {"A": cyl.port_A, "B": cyl.port_B}
        self.connect(v_port[hold], self.hose_hold.port, self.cbv_hold.port_valve)
        self.connect(self.cbv_hold.port_load, c_port[hold])
        if self.over_centre:
            self.connect(v_port[other], self.hose_over.port, self.cbv_over.port_valve, self.cbv_hold.port_pilot)
            self.connect(self.cbv_over.port_load, c_port[other])
            self.connect(self.cbv_over.port_pilot, self.hose_hold.port)
        else:
            self.connect(v_port[other], c_port[other], self.cbv_hold.port_pilot)

    def initial_equations(self) -> list:
        """``free_start``: the free chamber at ``p_free_start``,
        ``s (p_A − p_free_start) + (1 − s)(p_B − p_free_start) = 0`` with ``s = free_A``."""
        if not self.free_start:
            return []
        s, c = self.free_A, self.cylinder.cylinder
        return [fl.eq(s * (c.p_A - self.p_free_start) + (1 - s) * (c.p_B - self.p_free_start), 0.0,
                      label="free chamber at its start pressure")]


def _counterbalance(p_crack: float, *, pilot_ratio: float, Q_nom: float, dp_nom: float,
                    V_hose: float) -> tuple[CounterbalanceValve, Volume]:
    """A counterbalance valve set at ``p_crack`` [Pa], both paths rated ``Q_nom`` at ``dp_nom``, and its hose."""
    cbv = CounterbalanceValve(p_crack=p_crack, pilot_ratio=pilot_ratio, dp_open=CBV_DP_OPEN, dp_check=CBV_DP_CHECK,
                              smoothing=CBV_SMOOTHING, Q_nom=Q_nom, Q_nom_check=Q_nom, dp_nom=dp_nom,
                              use_dynamics=True, T=CBV_T, A_leak=CBV_A_LEAK, steady_start=True)
    return cbv, Volume(V=V_hose, p_start=P_TANK)


def port_cartridges(p_system: float) -> tuple[PressureReliefValve, CheckValve]:
    """The valve block's cartridges on one cylinder port: shock relief to tank, make-up check from tank."""
    return (PressureReliefValve(p_crack=SHOCK_FACTOR * p_system, p_grad=1e10, G_leak=SHOCK_LEAK),
            CheckValve(p_crack=MAKEUP_CRACK, p_open=MAKEUP_OPEN, A_max=MAKEUP_AREA))
