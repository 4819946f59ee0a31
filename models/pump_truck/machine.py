"""The boom parts of a machine on a design record: each part of :mod:`flexlib.models.boom` made from the record.

Functions shared by the machines composed on a :class:`~models.pump_truck.parameters.PumpTruckParameters` record of
N = 4 … 6 sections (the 42 m :class:`~models.pump_truck.model.PumpTruck`, the 32 m
:class:`~flexlib.models.boom32.Boom32`): each returns a part (or a few) sized and placed as the record says, at rest
in the start pose; the machine's class names them and connects them (its composition). The choices are PumpTruck's
(its module docstring): cylinders sized once on the worst case (:func:`~models.pump_truck.statics.sizing`) with
``STOP_MARGIN`` of stroke at each end, valves rated for ``W_MAX`` at the largest lever arm, counterbalance valves on
both lines at 1.3 × the line's worst holding pressure (Sun Hydraulics; at least ``P_CRACK_MIN``), the free chamber
at tank pressure at the start, joint references as jerk-limited moves (``A_MAX``, ``J_MAX``) mapped to cylinder
lengths within ``LENGTH_TOL``, their feed-forward ``FF_LEAD`` ahead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from flexlib.components.control import TimeTable
from flexlib.components.hydraulics.fluid import HLP46
from flexlib.components.mechanics.multibody import FixedTranslation, Revolute
from flexlib.models.boom import (
    AngleController,
    BoomSection,
    HydraulicAxis,
    JointController,
    LeverLink,
    SlewDrive,
    SmoothReference,
    Turret,
    joint_to_length,
    motion_profile,
    waypoint_moves,
)
from flexlib.models.boom.axis import VALVE_HZ, VALVE_ZETA
from flexlib.models.boom.controller import OMEGA_C, T_CMD
from flexlib.models.boom.slew import D_MOTOR as SLEW_D
from flexlib.models.boom.slew import Q_VALVE as SLEW_Q
from flexlib.models.boom.slew import RATIO as SLEW_RATIO

from .arguments import check_commands, check_sources, check_table, check_targets, joint_names
from .geometry import LINK_PLATE, linkage_masses, section_mass_properties
from .parameters import PumpTruckParameters
from .statics import design_cylinders, design_sizing

__all__ = ["A_MAX", "J_MAX", "LENGTH_TOL", "P_TANK", "STOP_MARGIN", "W_MAX", "HeldStart", "boom_joint", "boom_section",
           "design_sizing", "feed_and_drive", "fixed_turret", "hydraulic_axis", "joint_inputs", "joint_loop",
           "lever_link", "slewing_turret"]

P_TANK = HLP46.p_ref  # tank pressure [Pa] (atmospheric)
STOP_MARGIN = 0.03  # cylinder stroke beyond the record's range at each end [m]
W_MAX = 0.03  # joint speed at full valve command at the largest lever arm [rad/s] (valve sizing)
A_MAX = 0.01  # joint acceleration of the reference moves [rad/s2]
J_MAX = 0.01  # joint jerk of the reference moves [rad/s3]
FF_LEAD = T_CMD + 2 * VALVE_ZETA / (2 * math.pi * VALVE_HZ)  # feed-forward lead: command filter + spool lag [s]
P_CRACK_MIN = 70e5  # counterbalance setting of a line that holds no load over the sizing sweep [Pa]
LENGTH_TOL = 1e-6  # length references within 1 µm of the kinematics [m]


class HeldStart:
    """A machine's start pose and holding forces, kept as values (``_q0``, ``_F_hold``), not structure: attributes
    without a leading underscore enter the build's key, so one build serves every start pose."""

    _q0: np.ndarray
    _F_hold: np.ndarray

    @property
    def q0(self) -> np.ndarray:
        """Start angles [rad] (slew, q1 … qN)."""
        return self._q0.copy()

    @property
    def F_hold(self) -> np.ndarray:
        """Holding forces of the cylinders at the start, by the hand statics [N] (positive pushes)."""
        return self._F_hold.copy()


def joint_inputs(record: PumpTruckParameters, targets: Mapping[str, Any] | None,
                 commands: Mapping[str, Any] | None, model: str = "PumpTruck"
                 ) -> tuple[dict[int, list], dict[int, TimeTable]]:
    """A machine's ``targets`` and ``commands`` tables checked (:mod:`~models.pump_truck.arguments`: the record's
    joints, ranges, valve commands within −1 … 1, no joint in both; errors name ``model``), per joint index (0 the
    slew): the jerk-limited moves (:func:`~flexlib.models.boom.waypoint_moves`, ``A_MAX``, ``J_MAX``) through its
    waypoints [deg], and the open-loop valve commands as ``TimeTable``s."""
    joints = joint_names(record)
    t_ref, ref_cols = check_table("targets", targets, model=model, joints=joints) if targets is not None \
        else (np.zeros(1), {})
    t_cmd, cmd_cols = check_table("commands", commands, model=model, joints=joints) if commands is not None \
        else (np.zeros(1), {})
    check_sources(ref_cols, cmd_cols, model, joints)
    check_commands(cmd_cols, model)
    check_targets(ref_cols, record, model)
    moves = {joints.index(name): waypoint_moves(t_ref, np.radians(col), a_max=A_MAX, j_max=J_MAX)
             for name, col in ref_cols.items()}
    return moves, {joints.index(name): TimeTable(t=t_cmd, y=col) for name, col in cmd_cols.items()}


def boom_joint(q: float) -> Revolute:
    """A boom joint (revolute about ``z``) at rest at ``q`` [rad]; its angle and speed are the machine's states
    (``state_select="always"``: a lever-and-link loop's other angles follow them)."""
    return Revolute(use_axis_flange=True, init={"phi": q, "w": 0.0, "a": 0.0},
                    state_select={"phi": "always", "w": "always"})


def boom_section(record: PumpTruckParameters, n: int, modes: int | Mapping[int, Sequence[int]] | None = None
                 ) -> BoomSection:
    """Section ``n`` with its pins (bracket ``C``, next joint's lever pivot ``P_next`` and housing ``H_next``):
    rigid with the record's mass properties, or (``modes`` given: a count or ``{section: indices}``) flexible from
    its Craig–Bampton modal data (:func:`~models.pump_truck.flexible.section_modal_data`)."""
    from .flexible import PIN_POINTS, attachment_points, section_modal_data

    points = attachment_points(record, n)
    pins = {name: points[point] for name, point in PIN_POINTS.items() if point in points}
    length = record.sections[n - 1].length
    if modes is not None:
        data, _ = section_modal_data(record, n)
        return BoomSection(length, pins=pins, modal_data=data, modes=modes if isinstance(modes, int) else modes[n])
    mp = section_mass_properties(record, n - 1)
    return BoomSection(length, m=mp["m"], r_CM=mp["com"], I=mp["I"], pins=pins)


def lever_link(record: PumpTruckParameters, n: int, q: float, link_plate: float = LINK_PLATE) -> LeverLink:
    """Joint ``n``'s lever and link (steel bars of cross-section ``link_plate`` at joint scale 3 [m2]), assembled
    at the joint angle ``q`` [rad]."""
    drive = record.drive(n)
    m_lever, m_link = linkage_masses(record, n, link_plate)
    return LeverLink.at_pose(q, drive.P, drive.c, drive.r, drive.s, drive.sigma, m_lever, m_link)


def hydraulic_axis(record: PumpTruckParameters, n: int, row: Mapping[str, Any], F_start: float
                   ) -> tuple[HydraulicAxis, dict[str, Any]]:
    """Joint ``n``'s hydraulic axis, sized by its ``row`` of :func:`~models.pump_truck.statics.sizing`, at rest
    holding ``F_start`` [N] (the hand statics' cylinder force in the start pose, positive pushes).

    Returns the axis and its design: ``bore``, ``rod``, ``stroke``, ``L0`` [m], ``hold`` (``"A"`` or ``"B"``, the
    line holding the load over the sizing sweep), ``Q_nom`` [m3/s]."""
    drive = record.drive(n)
    bore, rod = row["bore"], row["rod"]
    A_p, A_r = math.pi / 4 * bore**2, math.pi / 4 * (bore**2 - rod**2)
    arm = max(abs(drive.state(float(q)).lever_arm) for q in np.linspace(drive.q_min, drive.q_max, 37))
    Q_nom = A_p * arm * W_MAX
    hold, free = ("A", "B") if row["F"] >= 0 else ("B", "A")
    p_hold = 1.3 * row[f"p_worst_{hold}"]  # Sun: 1.3 × the worst holding pressure of the line
    p_free = max(1.3 * row[f"p_worst_{free}"], P_CRACK_MIN)
    stroke, L0 = row["stroke"] + 2 * STOP_MARGIN, row["l_min"] - STOP_MARGIN
    cyl = design_cylinders(record)[n - 1]  # housing and rod masses where the hand statics puts them
    axis = HydraulicAxis(d_bore=bore, d_rod=rod, stroke=stroke, L0=L0, Q_nom=Q_nom, hold=hold, over_centre=True,
                         m_housing=cyl["m_housing"], L_housing=cyl["L_housing"], m_rod=cyl["m_rod"],
                         L_rod=cyl["L_rod"], p_system=record.p_system,
                         **{f"p_crack_{hold}": p_hold, f"p_crack_{free}": p_free})
    # at rest: the chamber the hand statics says holds carries the load, the other is at tank (a parameter: one
    # build serves every pose); the statics' pressure is the holding chamber's start guess
    axis.free_A = 1.0 if F_start < 0 else 0.0
    axis.cylinder.cylinder.set_start("p_A" if F_start >= 0 else "p_B",
                                     P_TANK + abs(F_start) / (A_p if F_start >= 0 else A_r), fixed=False)
    return axis, {"bore": bore, "rod": rod, "stroke": stroke, "L0": L0, "hold": hold, "Q_nom": Q_nom}


def joint_loop(record: PumpTruckParameters, n: int, cylinder: Mapping[str, Any], q: float,
               moves: Sequence[tuple]) -> tuple[JointController, SmoothReference]:
    """Joint ``n``'s cylinder-length loop (tared at the start angle ``q`` [rad]) and its smooth reference from the
    joint's ``moves`` (the joint-angle profile mapped to the cylinder length within ``LENGTH_TOL``), for the
    ``cylinder`` design :func:`hydraulic_axis` returned."""
    drive = record.drive(n)
    A_p = math.pi / 4 * cylinder["bore"] ** 2
    A_r = A_p - math.pi / 4 * cylinder["rod"] ** 2
    loop = JointController(A_p=A_p, Q_nom=cylinder["Q_nom"], L_start=drive.state(q).length, omega_c=OMEGA_C)
    knots = joint_to_length(motion_profile(q, moves), drive.length, tol=LENGTH_TOL)
    return loop, SmoothReference(*knots, ff_gain=(A_p / cylinder["Q_nom"], A_r / cylinder["Q_nom"]), ff_lead=FF_LEAD)


def slewing_turret(record: PumpTruckParameters, q: float, moves: Sequence[tuple]
                   ) -> tuple[Turret, SlewDrive, AngleController, SmoothReference]:
    """The turret on its slewing bearing (at rest at ``q`` [rad]), its drive, angle loop and smooth reference from
    the slew's ``moves``."""
    tr = record.turret
    turret = Turret(mass=tr.mass, J_slew=tr.J_slew, height=tr.height, H1=record.joint1.H, phi_start=q,
                    friction=tr.friction)
    loop = AngleController(K_v=SLEW_Q / SLEW_D / SLEW_RATIO, use_feed_forward=False)
    return turret, SlewDrive(p_system=record.p_system), loop, SmoothReference(*motion_profile(q, moves))


def fixed_turret(record: PumpTruckParameters) -> tuple[FixedTranslation, FixedTranslation]:
    """The turret fixed to the ground (no slewing): the offset from the ground to joint 1 (``frame_b`` joint 1's
    frame) and from there to joint 1's cylinder housing pin ``H``."""
    top = FixedTranslation(r=[0.0, record.turret.height, 0.0])
    return top, FixedTranslation(r=[*record.joint1.H, 0.0])


def feed_and_drive(owner: Any, power: Any, drive: Any, loop: Any, command: TimeTable | None = None,
                   name: str = "") -> None:
    """Connect a hydraulic ``drive`` (an axis, the slew drive) in ``owner``: its supply and tank lines to the
    ``power`` unit's ``port_P`` and ``port_T``, its valve command ``u`` to the joystick's ``command`` (a TimeTable,
    added to ``owner`` as ``name``: open loop) or else to its controller ``loop``'s output ``y``."""
    owner.connect(power.port_P, drive.port_P)
    owner.connect(power.port_T, drive.port_T)
    if command is not None:
        setattr(owner, name, command)
        owner.connect(command.y, drive.u)
    else:
        owner.connect(loop.y, drive.u)
