"""A concrete-pump-like boom of five rigid sections, hydraulically driven and position-controlled.

Built from ordinary library components only: 3D multibody (World, Fixed, Revolute, FixedTranslation, Body),
hydraulics (FixedDisplacementPump, PressureReliefValve, Volume, Tank, DirectionalValve43, LineCylinder),
control (Ramp, LimPID) and a rotational AngleSensor on each main joint's axis flange.

Mechanics (vertical x–y plane, gravity 9.81 m/s² along −y, all joint axes along z):

* Five sections of lengths 9 / 7.7 / 7.6 / 7.4 / 5.9 m and masses 2200 / 1500 / 1000 / 650 / 350 kg.
  The masses taper like a real boom's (the root sections carry the bigger tubes, cylinders and pipe
  clamps); each section's centre of mass sits at 45 % of its length from its root joint (the root end
  is heavier: joint heads, cylinder brackets), with a slender-beam inertia ``m L²/12`` about it.
* Joint 1 (turret, at the world origin) is driven directly by a cylinder between a base pin and a bracket
  on section 1. Joints 2–5 are driven through a four-bar linkage each, as in a concrete-pump boom: a rocker
  (50 kg) pivoted on section k−1 behind joint k, a link (30 kg) from the rocker tip to a bracket on
  section k, and the cylinder from section k−1 to the rocker tip. Option ``linkages=False`` drives joints
  2–5 by a cylinder between section k−1 and a bracket on section k directly.
* Start pose (relative joint angles) 45°, −30°, −25°, −20°, −20°; set-points ramp linearly by +10°, −10°,
  +10°, −10°, +10° over 20 s (0.5°/s).

Hydraulics: one fixed-displacement pump (150 L/min at 1500 rpm) into a 2 L supply volume with a relief
valve cracking at 300 bar (+10 bar at full flow); per joint a closed-centre proportional 4/3 valve (30 Hz
spool) feeding one double-acting cylinder (rod/bore diameter ratio 0.6, stroke 1.2 m, started mid-stroke).
Each cylinder is **sized for 200 bar at its holding load**:
the area of the holding chamber (piston side when the cylinder pushes, annulus when it pulls) is
``|F_hold| / 200 bar``, with ``F_hold`` the cylinder force that balances gravity in the start pose. The
chambers **start at the holding pressures**: holding chamber 200 bar, the other one 20 bar (gauge).
``F_hold`` comes from virtual work, ``Q_k + F_k ∂l_k/∂q_k = 0`` with ``Q_k = −∂V/∂q_k`` (``V`` the
potential energy of sections, rockers and links) and ``l_k(q_k)`` the pin-to-pin length of cylinder k,
differentiated exactly by CasADi (:func:`statics`). Valves are sized for 3× the flow of their ramp.

Control: per joint a PI controller (``LimPID``, output limited to ±1 = the valve command, Ti = 1 s) on the
joint angle measured at the joint's axis flange; the gain ``k = 2 rad/s / K_v`` with the valve–cylinder
velocity gain ``K_v = Q_nom/(A_p ∂l/∂q)`` gives about 2 rad/s crossover.

References
----------
Schwing / Putzmeister 36–38 m truck-mounted concrete pumps (5-section booms, 28–38 m reach), data sheets:
section lengths and masses of this order. H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967 (valve–
cylinder sizing). Modelica Standard Library 4.0, ``Blocks.Continuous.LimPID``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

import flexlib as fl
from flexlib.components.control import Constant, LimPID, Ramp
from flexlib.components.hydraulics import (
    DirectionalValve43,
    FixedDisplacementPump,
    LineCylinder,
    PressureReliefValve,
    Tank,
    Volume,
)
from flexlib.components.hydraulics.fluid import HLP46
from flexlib.components.mechanics import rotational
from flexlib.components.mechanics.multibody import Body, Fixed, FixedTranslation, Revolute, World

__all__ = ["BoomGeometry", "BoomProxy", "cylinder_sizing", "link_body", "statics"]

BAR = 1e5
G = 9.81
P_AMB = HLP46.p_ref
#: Section lengths [m] and masses [kg].
LENGTHS = (9.0, 7.7, 7.6, 7.4, 5.9)
MASSES = (2200.0, 1500.0, 1000.0, 650.0, 350.0)
CM_FRACTION = 0.45
Q0_DEG = (45.0, -30.0, -25.0, -20.0, -20.0)
RAMP_DEG = (10.0, -10.0, 10.0, -10.0, 10.0)
T_RAMP = 20.0
P_HOLD = 200 * BAR
P_BACK = 20 * BAR
M_ROCKER, M_LINK = 50.0, 30.0
#: Joint 1 cylinder: base pin in world, bracket on section 1 [m].
BASE_PIN, BRACKET_1 = (0.8, -1.6), (2.2, -0.5)
#: Linkage geometry relative to joint k, in section k−1's frame (rocker pivot, cylinder housing) and in
#: section k's frame (link bracket C); direct drive: housing and bracket [m].
ROCKER_PIVOT, HOUSING, LINK_BRACKET = (-0.8, -0.8), (-3.6, -0.4), (0.9, -0.8)
DIRECT_HOUSING, DIRECT_BRACKET = (-2.6, -0.55), (0.8, -0.55)
OMEGA_C = 1.0  # crossover of the joint loops [rad/s]
T_I = 1.0  # integral time of the joint loops [s]
Q_MIN = 2.0 / 60000  # smallest valve rating [m3/s]
T_OFFSET = 0.6  # rocker tip: midpoint of pivot–bracket moved this far to the lower side [m]


def _rot(th):
    c, s = ca.cos(th), ca.sin(th)
    return ca.vertcat(ca.horzcat(c, -s), ca.horzcat(s, c))


@dataclass
class BoomGeometry:
    """Pins, bodies and lengths of the boom as CasADi expressions of the 5 relative joint angles ``q``.

    Attributes
    ----------
    q : casadi.SX
        Relative joint angles [rad] (symbols).
    points : dict
        World positions [m] of named points (``joint{k}``, ``bracket{k}``, ``housing{k}``, ``pivot{k}``,
        ``tip{k}`` rocker tip, ``C{k}`` link bracket).
    theta : dict
        Absolute angles [rad] of ``section{k}``, ``rocker{k}``, ``link{k}``.
    length : list
        Pin-to-pin length of cylinder k [m].
    V : casadi.SX
        Potential energy [J].
    rocker_len, link_len : dict
        Rocker and link lengths [m] (linkage joints).
    """

    q: ca.SX
    points: dict
    theta: dict
    length: list
    V: ca.SX
    rocker_len: dict
    link_len: dict


def boom_geometry(linkages: bool = True) -> BoomGeometry:
    """Geometry of the boom (see the module docstring); rocker/link lengths fixed in the start pose."""
    q = ca.SX.sym("q", 5)
    q0 = np.radians(Q0_DEG)
    pts, th, length = {}, {}, []
    V = 0.0
    origin = ca.DM([0.0, 0.0])
    rocker_len, link_len = {}, {}
    th_prev, J = 0.0, origin
    for k in range(5):
        th_k = th_prev + q[k]
        th[f"section{k + 1}"] = th_k
        pts[f"joint{k + 1}"] = J
        R_prev, R_k = _rot(th_prev), _rot(th_k)
        cm = J + ca.mtimes(R_k, ca.DM([CM_FRACTION * LENGTHS[k], 0.0]))
        V += MASSES[k] * G * cm[1]
        if k == 0:
            pts["housing1"] = ca.DM(BASE_PIN)
            pts["bracket1"] = J + ca.mtimes(R_k, ca.DM(BRACKET_1))
            length.append(ca.norm_2(pts["bracket1"] - pts["housing1"]))
        elif not linkages:
            pts[f"housing{k + 1}"] = J + ca.mtimes(R_prev, ca.DM(DIRECT_HOUSING))
            pts[f"bracket{k + 1}"] = J + ca.mtimes(R_k, ca.DM(DIRECT_BRACKET))
            length.append(ca.norm_2(pts[f"bracket{k + 1}"] - pts[f"housing{k + 1}"]))
        else:
            P = J + ca.mtimes(R_prev, ca.DM(ROCKER_PIVOT))
            C = J + ca.mtimes(R_k, ca.DM(LINK_BRACKET))
            # start-pose lengths: tip = midpoint of P–C moved T_OFFSET to the lower side of P→C
            f0 = ca.Function("f0", [q], [P, C])
            P0, C0 = (np.asarray(v).ravel() for v in f0(q0))
            d0 = C0 - P0
            n0 = np.array([d0[1], -d0[0]]) / np.linalg.norm(d0)  # right-hand normal of P→C (lower side)
            T0 = 0.5 * (P0 + C0) + T_OFFSET * n0
            r, lk = float(np.linalg.norm(T0 - P0)), float(np.linalg.norm(T0 - C0))
            rocker_len[k + 1], link_len[k + 1] = r, lk
            d = C - P
            dist = ca.norm_2(d)
            x = (r**2 - lk**2 + dist**2) / (2 * dist)
            h = ca.sqrt(r**2 - x**2)
            ex = d / dist
            T = P + x * ex + h * ca.vertcat(ex[1], -ex[0])  # same (right-hand) side as T0
            pts[f"pivot{k + 1}"], pts[f"C{k + 1}"], pts[f"tip{k + 1}"] = P, C, T
            pts[f"housing{k + 1}"] = J + ca.mtimes(R_prev, ca.DM(HOUSING))
            th[f"rocker{k + 1}"] = ca.atan2(T[1] - P[1], T[0] - P[0])
            th[f"link{k + 1}"] = ca.atan2(C[1] - T[1], C[0] - T[0])
            V += M_ROCKER * G * 0.5 * (P[1] + T[1]) + M_LINK * G * 0.5 * (T[1] + C[1])
            length.append(ca.norm_2(T - pts[f"housing{k + 1}"]))
        J = J + ca.mtimes(R_k, ca.DM([LENGTHS[k], 0.0]))
        th_prev = th_k
    return BoomGeometry(q, pts, th, length, V, rocker_len, link_len)


def statics(linkages: bool = True, q: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Holding forces of the cylinders in a pose by virtual work (exact CasADi derivatives).

    Parameters
    ----------
    linkages : bool
        Linkage-driven joints 2–5 (True) or direct cylinders.
    q : array_like, optional
        Relative joint angles [rad]; default the start pose.

    Returns
    -------
    dict
        ``F`` holding (extending) force per cylinder [N], ``Q`` gravity generalized forces [N.m],
        ``dl`` ∂l_k/∂q_k [m/rad], ``l`` cylinder pin-to-pin lengths [m].
    """
    geo = boom_geometry(linkages)
    q = np.radians(Q0_DEG) if q is None else np.asarray(q, dtype=float)
    lengths = ca.vertcat(*geo.length)
    f = ca.Function("statics", [geo.q], [-ca.gradient(geo.V, geo.q), ca.diag(ca.jacobian(lengths, geo.q)), lengths,
                                         ca.jacobian(lengths, geo.q)])
    Q, dl, ll, Jl = (np.asarray(v) for v in f(q))
    assert np.allclose(Jl - np.diag(np.diag(Jl)), 0.0, atol=1e-12)  # cylinder k spans joint k only
    return {"F": -Q.ravel() / dl.ravel(), "Q": Q.ravel(), "dl": dl.ravel(), "l": ll.ravel()}


def link_body(m: float, L: float) -> Body:
    """A slender link of mass ``m`` [kg] and length ``L`` [m]: centre of mass at mid-length, inertia ``m L²/12``
    about each axis through it (a rocker or a link of a four-bar linkage)."""
    return Body(m=m, r_CM=[L / 2, 0.0, 0.0], I=np.diag([m * L**2 / 12] * 3))


def _world_to_local(point: np.ndarray, origin: np.ndarray, theta: float) -> list[float]:
    """A world point (x–y plane) in the frame at ``origin`` rotated by ``theta`` about z [m]."""
    c, s = math.cos(theta), math.sin(theta)
    d = point - origin
    return [c * d[0] + s * d[1], -s * d[0] + c * d[1], 0.0]


def cylinder_sizing(F: float, ratio: float = 0.6) -> tuple[float, float, float, float, float]:
    """Bore for 200 bar at holding force ``F`` [N] (positive: pushing) and the start pressures of its chambers.

    The holding chamber is at ``P_HOLD``, the other at ``P_BACK`` (gauge): pushing ``F = A_p (P_HOLD − ann P_BACK)``,
    pulling ``−F = A_r (P_HOLD − P_BACK / ann)``. Returns ``(d_bore [m], A_p [m2], A_r [m2], p_A [Pa], p_B [Pa])``
    (absolute pressures).
    """
    ann = 1.0 - ratio**2  # annulus / piston area
    A_p_needed = F / (P_HOLD - ann * P_BACK) if F >= 0 else -F / (ann * (P_HOLD - P_BACK / ann))
    d_bore = math.sqrt(4 * A_p_needed / math.pi)
    A_p = math.pi / 4 * d_bore**2
    A_r = A_p * (1 - ratio**2)
    if F >= 0:  # F_hyd = p_A A_p − p_B A_r − p_amb (A_p − A_r) = F
        p_B = P_BACK + P_AMB
        p_A = (F + p_B * A_r + P_AMB * (A_p - A_r)) / A_p
    else:
        p_A = P_BACK + P_AMB
        p_B = (p_A * A_p - P_AMB * (A_p - A_r) - F) / A_r
    return d_bore, A_p, A_r, p_A, p_B


class BoomProxy(fl.Model):
    """Five-section hydraulic boom with PI joint control (see the module docstring).

    Parameters
    ----------
    linkages : bool
        True (default): joints 2–5 driven through four-bar linkages; False: by cylinders directly
        (structural).

    Attributes
    ----------
    holding : dict
        Result of :func:`statics` in the start pose (holding forces, lever arms ``dl``).
    bores : list of float
        Cylinder bores [m] (rods 0.6 × bore).
    """

    experiment = fl.Experiment(t_end=T_RAMP, dt_out=0.01, rtol=1e-6, atol=1e-8)

    def __init__(self, linkages: bool = True) -> None:
        super().__init__()
        self.linkages = bool(linkages)
        geo = boom_geometry(self.linkages)
        q0 = np.radians(Q0_DEG)
        ev = ca.Function("ev", [geo.q], [*geo.points.values(), *geo.theta.values()])
        vals = [np.asarray(v).ravel() for v in ev(q0)]
        self._P = dict(zip(geo.points, vals[: len(geo.points)], strict=True))
        self._TH = {k: float(v[0]) for k, v in zip(geo.theta, vals[len(geo.points):], strict=True)}
        st = statics(self.linkages)
        self.holding = st

        self.world = World(g=G)
        self.base = Fixed(r=[*BASE_PIN, 0.0])
        tank_ports, supply_ports = self._power_unit()
        self.bores: list[float] = []
        self._sections = self._boom(q0)
        self._th_sec = [self._TH[f"section{n}"] for n in range(1, 6)]
        self._joints = [self._P[f"joint{n}"] for n in range(1, 6)]
        for k in range(5):
            cyl, A_p = self._cylinder(k, float(st["F"][k]), float(st["l"][k]))
            self._mount(k, cyl, geo)
            valve = self._joint_loop(k, cyl, A_p, float(st["dl"][k]), float(q0[k]))
            tank_ports.append(valve.port_T)
            supply_ports.append(valve.port_P)
        self.connect(*tank_ports)
        self.connect(*supply_ports)

    def _power_unit(self) -> tuple[list, list]:
        """Tank, pump at 1500 rpm, supply volume and relief valve; the tank-side and supply-side ports."""
        self.tank = Tank()
        self.pump = FixedDisplacementPump(D=100e-6 / (2 * math.pi))  # 100 cm3/rev
        self.speed = Constant(k=1500 * 2 * math.pi / 60)  # rad/s
        self.supply = Volume(V=2e-3, p_start=310 * BAR)  # ~ relief pressure at full pump flow
        self.relief = PressureReliefValve(p_crack=300 * BAR, p_grad=4e8)  # +10 bar at 150 L/min
        self.connect(self.speed.y, self.pump.w)
        return [self.tank.port, self.pump.port_a, self.relief.port_b], [self.pump.port_b, self.supply.port,
                                                                         self.relief.port_a]

    def _boom(self, q0: np.ndarray) -> list:
        """The five sections on their joints, each joint angle measured on its axis flange; the sections' root
        frames."""
        prev_frame = self.world.frame_b
        sections = []
        for k in range(5):
            n = k + 1
            joint = Revolute(use_axis_flange=True, init={"phi": float(q0[k]), "w": 0.0})
            L = LENGTHS[k]
            body = Body(m=MASSES[k], r_CM=[CM_FRACTION * L, 0.0, 0.0],
                        I=np.diag([MASSES[k] * L**2 / 12] * 3))
            setattr(self, f"joint{n}", joint)
            setattr(self, f"section{n}", body)
            self.connect(prev_frame, joint.frame_a)
            self.connect(joint.frame_b, body.frame_a)
            # joint-angle measurement on the axis flange
            housing, sensor = rotational.Fixed(), rotational.AngleSensor()
            setattr(self, f"housing_fix{n}", housing)
            setattr(self, f"angle{n}", sensor)
            self.connect(housing.flange, joint.support)
            self.connect(joint.axis, sensor.flange)
            sections.append(joint.frame_b)
            if n < 5:
                tip = FixedTranslation(r=[L, 0.0, 0.0])
                setattr(self, f"section{n}_tip", tip)
                self.connect(joint.frame_b, tip.frame_a)
                prev_frame = tip.frame_b
        return sections

    def _pin_on(self, k: int, name: str, point: np.ndarray) -> object:
        """A FixedTranslation on section k (0-based) ending at the world point (start pose)."""
        rod = FixedTranslation(r=_world_to_local(point, self._joints[k], self._th_sec[k]))
        setattr(self, name, rod)
        self.connect(self._sections[k], rod.frame_a)
        return rod.frame_b

    def _cylinder(self, k: int, F: float, length: float) -> tuple[LineCylinder, float]:
        """Cylinder k sized for its holding force ``F`` [N], started mid-stroke at pin-to-pin ``length`` [m] with
        the holding pressures; the cylinder and its piston area [m2]."""
        ratio = 0.6
        d_bore, A_p, _, p_A, p_B = cylinder_sizing(F, ratio)
        self.bores.append(d_bore)
        stroke = 1.2
        L0 = length - 0.5 * stroke
        cyl = LineCylinder(d_bore=d_bore, d_rod=ratio * d_bore, stroke=stroke, L0=L0, m=20.0, d=2e4,
                           V_dead_A=2e-4, V_dead_B=2e-4, p_A_start=p_A, p_B_start=p_B)
        setattr(self, f"cylinder{k + 1}", cyl)
        return cyl, A_p

    def _mount(self, k: int, cyl: LineCylinder, geo: BoomGeometry) -> None:
        """Cylinder k between its pins: base and section 1, sections k−1 and k directly, or section k−1 and the
        rocker tip of a four-bar linkage (rocker, link and their three revolutes)."""
        n, P, TH = k + 1, self._P, self._TH
        if n == 1:
            self.connect(self.base.frame_b, cyl.frame_a)
            self.connect(self._pin_on(0, "bracket1", P["bracket1"]), cyl.frame_b)
            return
        if not self.linkages:
            self.connect(self._pin_on(k - 1, f"housing{n}", P[f"housing{n}"]), cyl.frame_a)
            self.connect(self._pin_on(k, f"bracket{n}", P[f"bracket{n}"]), cyl.frame_b)
            return
        r, lk = geo.rocker_len[n], geo.link_len[n]
        th_r, th_l = TH[f"rocker{n}"], TH[f"link{n}"]
        rocker_joint = Revolute(guess={"phi": th_r - self._th_sec[k - 1]})
        rocker, rocker_tip = link_body(M_ROCKER, r), FixedTranslation(r=[r, 0.0, 0.0])
        link_joint = Revolute(guess={"phi": th_l - th_r})
        link, link_tip = link_body(M_LINK, lk), FixedTranslation(r=[lk, 0.0, 0.0])
        close = Revolute(guess={"phi": self._th_sec[k] - th_l})
        for name, comp in (("rocker_joint", rocker_joint), ("rocker", rocker), ("rocker_tip", rocker_tip),
                           ("link_joint", link_joint), ("link", link), ("link_tip", link_tip),
                           ("link_pin", close)):
            setattr(self, f"{name}{n}", comp)
        self.connect(self._pin_on(k - 1, f"pivot{n}", P[f"pivot{n}"]), rocker_joint.frame_a)
        self.connect(rocker_joint.frame_b, rocker.frame_a, rocker_tip.frame_a)
        self.connect(rocker_tip.frame_b, link_joint.frame_a, cyl.frame_b)
        self.connect(link_joint.frame_b, link.frame_a, link_tip.frame_a)
        self.connect(link_tip.frame_b, close.frame_a)
        self.connect(close.frame_b, self._pin_on(k, f"bracket{n}", P[f"C{n}"]))
        self.connect(self._pin_on(k - 1, f"housing{n}", P[f"housing{n}"]), cyl.frame_a)

    def _joint_loop(self, k: int, cyl: LineCylinder, A_p: float, dl: float, q_start: float) -> DirectionalValve43:
        """Valve of joint k (sized for 3x the ramp flow of the moving chamber at ~35 bar per edge) on cylinder k,
        and the PI loop on the joint angle following the set-point ramp; the valve."""
        n = k + 1
        q_ramp = A_p * abs(dl) * math.radians(abs(RAMP_DEG[k])) / T_RAMP
        Q_nom = max(3 * q_ramp, Q_MIN)  # m3/s
        valve = DirectionalValve43(Q_nom=Q_nom, dp_nom=35 * BAR, omega=2 * math.pi * 30,
                                   zeta=0.7, A_leak=1e-10)
        setattr(self, f"valve{n}", valve)
        # positive command extends the cylinder; if extending closes the joint, cross the lines
        a_port, b_port = (cyl.port_A, cyl.port_B) if dl > 0 else (cyl.port_B, cyl.port_A)
        self.connect(valve.port_A, a_port)
        self.connect(valve.port_B, b_port)
        # PI on the joint angle: valve gain K_v [rad/s per unit command, at dp_nom per edge] -> crossover
        # ~2 rad/s
        K_v = Q_nom / (A_p * abs(dl))
        ramp = Ramp(height=math.radians(RAMP_DEG[k]), duration=T_RAMP, offset=q_start)
        pid = LimPID(controller_type="PI", k=OMEGA_C / K_v, Ti=T_I, y_max=1.0, y_min=-1.0)
        setattr(self, f"set_point{n}", ramp)
        setattr(self, f"controller{n}", pid)
        self.connect(ramp.y, pid.u_s)
        self.connect(getattr(self, f"angle{n}").phi, pid.u_m)
        self.connect(pid.y, valve.u)
        return valve
