"""The parallel Cartesian manipulator of seed 002 (§3): three identical PRRR legs between the frame and the tip.

Seed 002 describes the robot (Warsaw University of Technology; its Fig. 2) as three identical assemblies of a
linear drive and two arms joined by revolute joints, from the frame to the tip; the structure is over-constrained
(Grübler count 0) but has 3 real degrees of freedom: the tip translates along three axes without rotating. The
paper gives no dimensions. We build the architecture that has exactly these properties, the 3-PRRR *Tripteron*
(Gosselin et al., "Kinematic analysis, optimization and programming of parallel robotic manipulators", ASME
J. Mech. Des. 2004; Kong & Gosselin 2002): leg ``i`` has a prismatic drive along the world axis ``e_i`` and three
revolute joints with axes parallel to ``e_i``. Each leg then lets the tip rotate only about ``e_i``; three legs
with orthogonal ``e_i`` leave pure translation, and the tip coordinate along ``e_i`` equals the drive stroke
``s_i`` (decoupled kinematics).

Mobility. Bodies: frame, 3 × (slider, arm 4, arm 6), tip: ``n = 11``; joints: 3 × (P + 3 R) = 12 one-DOF joints:
Grübler–Kutzbach ``M = 6 (n − 1 − j) + Σ f = 6 (11 − 1 − 12) + 12 = 0`` (the seed's count); real mobility 3. The
two closed loops give 12 constraint rows of which 9 are independent: flexlib drops 3 (the tip-orientation rows the
legs repeat) and says so in ``sim.report``.

All numbers are in :class:`CartesianParameters` (assumed, representative of a desktop-size robot: 0.3 m steel
box-tube arms, 25 × 25 × 2 mm, the "thin-walled square tube" of the paper). Each arm is a
:class:`~flexlib.components.mechanics.flexible.FlexibleBody` from the beam mesher (interface nodes at both ends,
Craig–Bampton): with ``flexible=False`` the same body with zero modes, i.e. the rigid arm with the FE model's mass
properties, so the rigid and flexible robots differ only in the elastic modes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.components.control import Constant, TimeTable, Trapezoid, Trim
from flexlib.components.mechanics import translational
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.components.mechanics.multibody import Body, FixedRotation, FixedTranslation, Prismatic, Revolute, World
from flexlib.fe import beam_mesh, box, modal_data_from_fe

from .statics import energy_gradient

__all__ = ["CartesianParameters", "CartesianRobot", "arm_mass", "arm_modal_data", "holding_forces", "leg_angles",
           "potential_energy"]

#: Leg i: drive axis e_i (world), the in-plane axis u_i (toward the tip) and w_i = e_i × u_i; the leg frame is the
#: world frame turned by 0°, 120°, 240° about (1, 1, 1): x_leg = u_i, y_leg = w_i, z_leg = e_i
LEG_AXES = ((2, 0), (0, 1), (1, 2))  # (index of e_i, index of u_i): z/x, x/y, y/z
LEG_TURN = {2: 0.0, 0: 2 * math.pi / 3, 1: 4 * math.pi / 3}


@dataclass(frozen=True)
class CartesianParameters:
    """Every number of the Cartesian robot (SI units). Assumed: the paper gives the architecture, not sizes.

    Attributes
    ----------
    L_arm : float
        Length of each arm (4 and 6) between its joint axes [m].
    section : tuple of float
        Box tube of the arms: outer width, outer height, wall thickness [m] (25 × 25 × 2 mm).
    E, rho : float
        Steel: Young's modulus [Pa], density [kg/m3].
    n_elements : int
        Beam elements per arm.
    n_modes : int
        Fixed-interface modes per flexible arm (Craig–Bampton, both ends interface).
    guide_offset : float
        Distance of each drive's guide line from the tip's home position, along ``−u_i`` [m].
    tip_offset : float
        Distance of each leg's attachment on the tip from the tip centre, along ``−u_i`` [m].
    m_slider, m_tip : float
        Slider (carriage of the linear drive) and tip platform masses [kg].
    I_slider, I_tip : float
        Their moments of inertia about every axis through their centres [kg.m2] (compact blocks).
    g : float
        Gravity, along ``−z`` [m/s2].
    """

    L_arm: float = 0.30
    section: tuple[float, float, float] = (0.025, 0.025, 0.002)
    E: float = 2.1e11
    rho: float = 7850.0
    n_elements: int = 12
    n_modes: int = 4
    guide_offset: float = 0.45
    tip_offset: float = 0.05
    m_slider: float = 1.2
    I_slider: float = 2.0e-3
    m_tip: float = 1.0
    I_tip: float = 1.5e-3
    g: float = 9.81
    extra: dict = field(default_factory=dict, compare=False)

    @property
    def span(self) -> float:
        """In-plane distance between a leg's slider axis and its tip attachment at the home pose [m]."""
        return self.guide_offset - self.tip_offset


def leg_angles(par: CartesianParameters, tip: np.ndarray | None = None) -> list[tuple[float, float, float]]:
    """Joint angles (slider, elbow, tip revolute) [rad] of the three legs for a tip position [m] (inverse
    kinematics of each leg's planar 2R chain in the plane normal to its drive axis; elbow on the ``+w`` side)."""
    p = np.zeros(3) if tip is None else np.asarray(tip, dtype=float)
    out = []
    for ei, ui in LEG_AXES:
        wi = 3 - ei - ui
        d_u = par.span + p[ui]
        d_w = p[wi]
        dist = math.hypot(d_u, d_w)
        if not dist < 2 * par.L_arm:
            raise fl.ParameterError(f"CartesianRobot: tip {p.tolist()} out of reach of leg {ei} "
                                    f"({dist:.3f} m >= {2 * par.L_arm:.3f} m)")
        half = math.acos(dist / (2 * par.L_arm))
        base = math.atan2(d_w, d_u)
        out.append((base + half, -2 * half, -(base - half)))
    return out


def arm_mass(par: CartesianParameters) -> float:
    """Mass of one arm, ``ρ A L`` [kg] (the beam model's mass; centre of mass at mid-length)."""
    b, h, t = par.section
    return par.rho * box(b, h, t).A * par.L_arm


def potential_energy(par: CartesianParameters, tip: Any) -> float:
    """Gravitational potential energy [J] of the robot with its tip at ``tip`` [m] (heights along +z): tip, the
    z-drive's slider (the others move horizontally) and the six arms (mid-length points of the 2R chains)."""
    p = np.asarray(tip, dtype=float)
    m_arm = arm_mass(par)
    V = par.m_tip * p[2]
    for (ei, ui), (a1, a2, _a3) in zip(LEG_AXES, leg_angles(par, p), strict=True):
        wi = 3 - ei - ui
        e, u, w = np.eye(3)[ei], np.eye(3)[ui], np.eye(3)[wi]
        S = -par.guide_offset * u + p[ei] * e
        dA = math.cos(a1) * u + math.sin(a1) * w
        dB = math.cos(a1 + a2) * u + math.sin(a1 + a2) * w
        V += par.m_slider * S[2] + m_arm * (S + 0.5 * par.L_arm * dA)[2]
        V += m_arm * (S + par.L_arm * dA + 0.5 * par.L_arm * dB)[2]
    return par.g * V


def holding_forces(par: CartesianParameters, tip: Any = (0.0, 0.0, 0.0), h: float = 1e-6) -> np.ndarray:
    """Hand statics by virtual work: the drive forces [N] (legs 1–3, along their axes) that hold the robot at rest
    at ``tip`` [m]. The kinematics are decoupled (drive ``i`` strokes the tip coordinate ``e_i``), so
    ``F_i = ∂V/∂p_(e_i)`` of :func:`potential_energy` (central difference of the closed-form energy, step ``h``)."""
    grad = energy_gradient(lambda p: potential_energy(par, p), np.asarray(tip, dtype=float), h)
    return grad[[ei for ei, _ui in LEG_AXES]]


@lru_cache(maxsize=8)
def arm_modal_data(par: CartesianParameters) -> Any:
    """Craig–Bampton modal data of one arm: beam along local x from 0 to ``L_arm``, interface nodes at both ends,
    reference frame at the first node (cached per parameter record)."""
    b, h, t = par.section
    fe = beam_mesh((0.0, 0.0, 0.0), (par.L_arm, 0.0, 0.0), par.n_elements, box(b, h, t), E=par.E, rho=par.rho)
    return modal_data_from_fe(fe, [0, par.n_elements], par.n_modes, reference_node=0, attachment="pinned",
                              title=f"Cartesian robot arm {par.L_arm} m box {b}x{h}x{t} m")


class CartesianRobot(fl.Model):
    """The parallel Cartesian manipulator (module docstring).

    Parameters
    ----------
    flexible : bool
        Arms as flexible bodies (``n_modes`` fixed-interface modes each) instead of rigid ones.
    drive : {"motion", "force", "trim", "free"}
        ``"motion"``: each drive follows a trapezoidal speed profile (``speeds``); ``"force"``: each drive pushes
        with a force constant over time intervals (``forces``); ``"trim"``: each drive pushes with the force that
        holds the robot at rest at ``tip`` — found by the initialisation (``trim{k}``, a
        :class:`~flexlib.components.control.Trim`: for the flexible robot it differs from the rigid hand statics by
        the arms' sag) — plus the interval forces ``forces`` (the seed's force-driven runs, started at rest with
        ``run(steady_state=True)`` when flexible); ``"free"``: each drive carries the constant force
        ``f_drive`` that holds the rigid robot at rest at ``tip`` (:func:`holding_forces`; static analysis,
        linearisation, modal analysis with the drives locked).
    speeds : sequence of (float, float, float, float)
        Per drive: peak speed [m/s], ramp time [s], plateau time [s], start time [s] of a trapezoidal speed profile
        (a zero peak: the drive stands still).
    forces : sequence of (times, values)
        Per drive: breakpoints [s] and drive forces [N], held constant from each breakpoint to the next (with
        ``drive="trim"``, added to the holding force).
    tip : sequence of float
        Tip start position [m] (home: the origin).
    params : CartesianParameters
        The numbers.
    """

    def __init__(self, *, flexible: bool = False, drive: str = "motion",
                 speeds: Any = ((0.2, 0.1, 0.3, 0.1), (0.0, 0.1, 0.3, 0.1), (0.0, 0.1, 0.3, 0.1)),
                 forces: Any = None, tip: Any = (0.0, 0.0, 0.0), params: CartesianParameters | None = None) -> None:
        super().__init__()
        par = params or CartesianParameters()
        if drive not in ("motion", "force", "trim", "free"):
            raise fl.ParameterError(f"CartesianRobot: drive={drive!r} is not one of 'motion', 'force', 'trim', "
                                    "'free'")
        self.par, self.flexible, self.drive = par, bool(flexible), drive
        tip = np.asarray(tip, dtype=float)
        angles = leg_angles(par, tip)
        hold = holding_forces(par, tip)  # "free": the drives hold the robot at rest with these constant forces
        data = arm_modal_data(par)
        self.world = World(g=par.g, n=[0.0, 0.0, -1.0])
        self.tip = Body(m=par.m_tip, r_CM=[0.0, 0.0, 0.0], I=np.eye(3) * par.I_tip)
        for k, ((ei, ui), (a1, a2, a3)) in enumerate(zip(LEG_AXES, angles, strict=True), start=1):
            u = np.zeros(3)
            u[ui] = 1.0
            turn = LEG_TURN[ei]
            base = FixedTranslation(r=(-par.guide_offset * u).tolist())
            orient = FixedRotation(n=[1.0, 1.0, 1.0], angle=turn)
            # the tip position is the initial condition (through the drive strokes); the joint angles are
            # guesses that the loop closure corrects
            init = {"motion": {"s": float(tip[ei])}, "trim": {"s": float(tip[ei]), "v": 0.0, "a": 0.0}}.get(
                drive, {"s": float(tip[ei]), "v": 0.0})
            guide = Prismatic(n=[0.0, 0.0, 1.0], use_axis_flange=drive != "free", init=init,
                              f_drive=float(hold[k - 1]) if drive == "free" else 0.0)
            slider = Body(m=par.m_slider, r_CM=[0.0, 0.0, 0.0], I=np.eye(3) * par.I_slider)
            j1 = Revolute(n=[0.0, 0.0, 1.0], guess={"phi": a1})
            arm4 = FlexibleBody(data, modes=None if flexible else 0)
            j2 = Revolute(n=[0.0, 0.0, 1.0], guess={"phi": a2})
            arm6 = FlexibleBody(data, modes=None if flexible else 0)
            j3 = Revolute(n=[0.0, 0.0, 1.0], guess={"phi": a3})
            to_tip = FixedTranslation(r=[par.tip_offset, 0.0, 0.0])
            back = FixedRotation(n=[1.0, 1.0, 1.0], angle=-turn)
            for name, comp in (("base", base), ("orient", orient), ("guide", guide), ("slider", slider),
                               ("j1", j1), ("arm4", arm4), ("j2", j2), ("arm6", arm6), ("j3", j3),
                               ("to_tip", to_tip), ("back", back)):
                setattr(self, f"{name}{k}", comp)
            self.connect(self.world.frame_b, base.frame_a)
            self.connect(base.frame_b, orient.frame_a)
            self.connect(orient.frame_b, guide.frame_a)
            self.connect(guide.frame_b, slider.frame_a)
            self.connect(guide.frame_b, j1.frame_a)
            self.connect(j1.frame_b, arm4.frame_a)
            self.connect(arm4.frame_b, j2.frame_a)
            self.connect(j2.frame_b, arm6.frame_a)
            self.connect(arm6.frame_b, j3.frame_a)
            self.connect(j3.frame_b, to_tip.frame_a)
            self.connect(to_tip.frame_b, back.frame_a)
            self.connect(back.frame_b, self.tip.frame_a)
            if drive == "motion":
                peak, ramp, plateau, start = (float(v) for v in speeds[k - 1])
                profile = Trapezoid(amplitude=peak, rising=ramp, width=plateau, falling=ramp,
                                    period=2 * ramp + plateau + 1e3, nperiod=1, start_time=start)
                src = translational.Speed()
                setattr(self, f"profile{k}", profile)
                setattr(self, f"speed{k}", src)
                self.connect(profile.y, src.v_ref)
                self.connect(src.flange, guide.axis)
            elif drive in ("force", "trim"):
                times, values = forces[k - 1] if forces is not None else ((0.0,), (0.0,))
                table = (TimeTable([float(tk) for tk in times], [float(v) for v in values], smoothness="constant")
                         if len(times) > 1 else Constant(k=float(values[0])))
                push = translational.Force()
                setattr(self, f"force_table{k}", table)
                setattr(self, f"push{k}", push)
                if drive == "trim":
                    trim = Trim(guess={"b": float(hold[k - 1])})
                    setattr(self, f"trim{k}", trim)
                    self.connect(table.y, trim.u)
                    self.connect(trim.y, push.f)
                else:
                    self.connect(table.y, push.f)
                self.connect(push.flange, guide.axis)
