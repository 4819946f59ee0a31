"""HydraulicAxis bench: a vertical axis lifting, holding and lowering a mass (MSL ``RobotR3`` ``OneAxis`` idea).

References: H. E. Merritt, *Hydraulic Control Systems* (1967), §5: the static force balance of a valve-controlled
cylinder, ``p_A A_p − p_B A_r − p_amb (A_p − A_r) = F`` (absolute pressures, ambient on the rod section), and the
flow continuity ``Q = A v``; the pressure-compensated meter-in edge passes ``Q_nom`` at full spool stroke
(Danfoss PVG 32 / Murrenhoff ch. 8); the orifice law bounds the leakage of the closed valves.

The bench: housing pin at the world origin, rod pin on a vertical slide carrying a 12 t body; cylinder Ø100/63 mm,
1 m stroke; housing 40 kg at 0.5 m from its pin, rod 25 kg at 0.55 m from its pin; supply at 350 bar, tank at
ambient pressure; counterbalance valve on the cap side (the cylinder pushes) set at 1.3 × the holding pressure,
and in a second build one on the rod side as well (set at 100 bar).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.hydraulics import HLP46, PressureSource, Tank
from flexlib.components.mechanics.multibody import Body, Prismatic, World
from flexlib.models.boom import HydraulicAxis
from flexlib.models.boom.axis import CBV_A_LEAK, SHOCK_LEAK
from flexlib.units import g_n

G = g_n  # standard gravity: the World's default, as MSL's
P_T = HLP46.p_ref
P_SYS = 35e6
BORE, ROD, STROKE = 0.1, 0.063, 1.0
A_P, A_R = math.pi / 4 * BORE**2, math.pi / 4 * (BORE**2 - ROD**2)
M, M_H, L_H, M_R, L_R = 12000.0, 40.0, 0.5, 25.0, 0.55
Q_NOM = 5e-4  # 30 L/min
S0, X0 = 1.6, 0.45  # pin-to-pin length and piston position at start [m]
P_HOLD = (M + M_R) * G / A_P  # gauge holding pressure: the load and the rod on the oil; the housing on its pin


class Bench(fl.Model):
    def __init__(self, u: float, over_centre: bool = False) -> None:
        super().__init__()
        self.world = World()
        self.slide = Prismatic(n=[0, 1, 0], init={"s": S0, "v": 0.0, "a": 0.0})
        self.load = Body(m=M)
        self.axis = HydraulicAxis(d_bore=BORE, d_rod=ROD, stroke=STROKE, L0=S0 - X0, Q_nom=Q_NOM, hold="A",
                                  over_centre=over_centre, p_crack_A=1.3 * P_HOLD, p_crack_B=1e7, m_housing=M_H,
                                  L_housing=L_H, m_rod=M_R, L_rod=L_R, p_system=P_SYS, p_A_start=P_T + P_HOLD)
        self.supply, self.tank = PressureSource(p=P_T + P_SYS), Tank()
        self.command = Constant(k=u)
        self.connect(self.world.frame_b, self.slide.frame_a, self.axis.frame_a)
        self.connect(self.slide.frame_b, self.load.frame_a, self.axis.frame_b)
        self.connect(self.supply.port, self.axis.port_P)
        self.connect(self.tank.port, self.axis.port_T)
        self.connect(self.command.y, self.axis.u)


@pytest.fixture(scope="module", params=[False, True], ids=["hold-A", "both-lines"])
def sim(request) -> fl.Simulation:
    """The bench with the counterbalance valve on the cap side only, and on both lines (``over_centre=True``: the
    load-holding valve on the rod side too, issue 28's joint 1); the checks are the same."""
    return fl.Simulation(Bench(0.0, over_centre=request.param))


def run(sim: fl.Simulation, u: float, t_end: float) -> fl.Result:
    return sim.run(t_end, params={"command.k": u}, dt_out=0.01, rtol=1e-7, atol=1e-9, progress=False)


def test_holding_pressure_and_drift(sim):
    """(a) u = 0, supply at 350 bar: the load held by the closed counterbalance valve.

    Merritt's static balance (gauge, ambient on the rod section, the free chamber at tank pressure at start):
    ``p_A − p_T = (M + m_rod) g / A_p`` (the housing's weight rests on its pin, the rod's on the load); at 2 s with
    the measured rod-side pressure ``p_B``: ``p_A − p_T = (M + m_rod) g / A_p + (p_B − p_T) A_r / A_p``. Tolerance
    1e-4 relative (measured 2e-16 at the start, 4e-6 at 2 s). Drift over 2 s: at most what the closed paths out of
    the cap chamber let through, bounded by the turbulent orifice law above the laminar leakage (counterbalance
    valve: two paths of ``CBV_A_LEAK``, Cd 0.7; make-up check valve: 1e-12 m², Cd 0.64; shock valve:
    ``SHOCK_LEAK·Δp``), plus the chamber's compression ``V_A Δp_A / β`` (measured drift 1.4 µm against a bound of
    1.6 µm).
    """
    res = run(sim, 0.0, 2.0)
    p_A, p_B = res["axis.cylinder.cylinder.p_A"], res["axis.cylinder.cylinder.p_B"]
    assert p_B[0] == pytest.approx(P_T, rel=1e-12)
    assert p_A[0] - P_T == pytest.approx(P_HOLD, rel=1e-4)
    assert p_A[-1] - P_T == pytest.approx(P_HOLD + (p_B[-1] - P_T) * A_R / A_P, rel=1e-4)
    dp = p_A.max() - P_T
    speed = math.sqrt(2 * dp / HLP46.rho_ref)
    q_leak = 0.7 * 2 * CBV_A_LEAK * speed + 0.64 * 1e-12 * speed + SHOCK_LEAK * dp
    V_A = res["axis.cylinder.cylinder.V_A"][0]
    bound = (q_leak * 2.0 + V_A * np.ptp(p_A) / HLP46.beta) / A_P
    drift = abs(res["slide.s"][-1] - S0)
    assert 0 < drift <= bound


def test_lifting_at_the_rated_flow(sim):
    """(b) u = 1: the pressure-compensated meter-in edge passes ``Q_nom``, the piston rises at ``Q_nom/A_p``.

    Tolerance 1 % (measured −0.2 %): ``Q_nom`` is rated at the reference density, the compensated edge meters the
    mass flow ``ρ(p̄)·Q`` at its mean pressure and the chamber takes it at ``ρ(p_A)``; ``p/β`` ≤ 2 % at 350 bar, of
    which the ratios leave a fraction. Supply mass flow = ``ρ(p_A)·A_p·v`` (continuity, Merritt) to 1e-3 (the
    closed edges' and the cartridges' leakage, ~1e-5 of the flow; measured 5e-5).
    """
    res = run(sim, 1.0, 1.5)
    v = res["slide.v"][-1]
    assert v == pytest.approx(Q_NOM / A_P, rel=1e-2)
    assert np.ptp(res["slide.v"][-20:]) < 1e-3 * v  # steady
    rho_A = float(HLP46.density(res["axis.cylinder.cylinder.p_A"][-1]))
    assert res["axis.port_P.m_flow"][-1] == pytest.approx(rho_A * A_P * v, rel=1e-3)


def test_lowering_through_the_counterbalance_valve(sim):
    """(c) u = −1: the load goes down at ``Q_nom/A_r`` (the compensated P→B edge sets the speed; the counterbalance
    valve opens as far as the pilot needs) without cavitation.

    After the start transient (the counterbalance lowering oscillation, decaying under the seal friction) the mean
    speed over 3.0 … 3.5 s is ``Q_nom/A_r`` within 2 % (density ratios as in (b), plus the residue of the decaying
    oscillation; measured 0.15 %). Both chamber pressures stay above 0.5 bar absolute throughout.
    """
    res = run(sim, -1.0, 3.5)
    t, s = res["time"], res["slide.s"]
    i = int(np.searchsorted(t, 3.0))
    v_mean = (s[-1] - s[i]) / (t[-1] - t[i])
    assert v_mean == pytest.approx(-Q_NOM / A_R, rel=2e-2)
    assert res["axis.cbv_hold.h_relief"][-1] > 0.1  # the load passes the counterbalance valve
    for p in ("p_A", "p_B"):
        assert res[f"axis.cylinder.cylinder.{p}"].min() > 0.5e5


def test_both_lines_hold_and_names():
    """``over_centre=True`` builds the second counterbalance valve and hose; names are hierarchical."""
    axis = HydraulicAxis(d_bore=BORE, d_rod=ROD, stroke=STROKE, L0=1.0, Q_nom=Q_NOM, hold="B", over_centre=True,
                         p_crack_A=2e7, p_crack_B=1e7)
    assert {"cbv_hold", "hose_hold", "cbv_over", "hose_over", "shock_A", "makeup_B"} <= set(vars(axis))
    assert axis.cbv_hold.parameter_value("p_crack") == 1e7 and axis.cbv_over.parameter_value("p_crack") == 2e7
    assert not hasattr(HydraulicAxis(d_bore=BORE, d_rod=ROD, stroke=STROKE, L0=1.0, Q_nom=Q_NOM, p_crack_A=2e7),
                       "cbv_over")
    assert [float(axis.valve.parameter_value(f"lap_{e}")) for e in ("PA", "PB", "AT", "BT")] == [0.02] * 4  # default
    zero = HydraulicAxis(d_bore=BORE, d_rod=ROD, stroke=STROKE, L0=1.0, Q_nom=Q_NOM, p_crack_A=2e7, lap=0.0)
    assert [float(zero.valve.parameter_value(f"lap_{e}")) for e in ("PA", "PB", "AT", "BT")] == [0.0] * 4


@pytest.mark.parametrize(
    ("kw", "match"),
    [({"d_rod": 0.1}, r"HydraulicAxis: d_rod = 0.1 must be < d_bore"),
     ({"hold": "C"}, r"HydraulicAxis: hold must be 'A' or 'B'"),
     ({"m_rod": -1.0}, r"HydraulicAxis: m_rod must be a finite number >= 0"),
     ({"m_housing": -5.0}, r"HydraulicAxis: m_housing must be a finite number >= 0"),
     ({"p_crack_A": None}, r"HydraulicAxis: p_crack_A is needed"),
     ({"over_centre": True}, r"HydraulicAxis: p_crack_B is needed"),
     ({"Q_nom": 0.0}, r"HydraulicAxis: Q_nom must be a finite number > 0"),
     ({"lap": -0.01}, r"HydraulicAxis: lap must be a finite number >= 0"),
     ({"lap": 0.5}, r"HydraulicAxis: lap = 0.5 must be < 0.5")],
)
def test_bad_arguments(kw, match):
    args = {"d_bore": BORE, "d_rod": ROD, "stroke": STROKE, "L0": 1.0, "Q_nom": Q_NOM, "p_crack_A": 2e7, **kw}
    with pytest.raises(fl.ParameterError, match=match):
        HydraulicAxis(**args)
