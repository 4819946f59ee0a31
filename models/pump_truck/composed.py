"""DRAFT (issue 28, not registered): the pump-truck boom composed of the parts in :mod:`flexlib.models.boom`.

The composition :class:`PumpTruck` in ``model.py`` will become once it reproduces the old model's statics and
its goldens are regenerated (see /work/helpers/plan28.md). Names are hierarchical: ``section3.frame_tip.r_0``,
``axis2.cylinder.cylinder.p_A``, ``loop2.pid.y``, ``joint2.phi``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.components.control import TimeTable
from flexlib.components.mechanics.multibody import FixedTranslation, Revolute, World
from flexlib.models.boom import (
    AngleController,
    BoomSection,
    HydraulicAxis,
    JointController,
    LeverLink,
    PowerUnit,
    SlewDrive,
    SmoothReference,
    Turret,
    joint_to_length,
    motion_profile,
    waypoint_moves,
)

from .arguments import JOINTS, check_pose, check_sources, check_table
from .flexible import PIN_POINTS, attachment_points, section_modal_data
from .geometry import linkage_masses, section_mass_properties, sizing
from .parameters import PumpTruckParameters
from .statics import cylinder_forces, design_cylinders

__all__ = ["ComposedPumpTruck"]

STOP_MARGIN = 0.03  # cylinder stroke beyond the record's range at each end [m]
W_MAX = 0.03  # joint speed at full valve command at the largest lever arm [rad/s] (valve sizing)
SLEW_D = 50e-6 / (2 * math.pi)  # slewing motor [m3/rad]
SLEW_RATIO = 300.0
SLEW_Q = 25.0 / 60000  # slew valve rating [m3/s]
A_MAX = 0.01  # joint acceleration of the reference moves [rad/s2]
J_MAX = 0.01  # joint jerk of the reference moves [rad/s3]
import os
TOLK = float(os.environ.get("TOLK", 1e-6))
TRANSPORT_POSE_DEG = (0.0, 0.0, 176.0, -176.0, 176.0, -176.0)


class ComposedPumpTruck(fl.Model):
    """The five-section boom as a composition of boom parts (draft; arguments as :class:`PumpTruck`'s)."""

    def __init__(self, record: PumpTruckParameters | None = None, pose: Sequence[float] | None = None,
                 targets: Mapping[str, Any] | None = None, commands: Mapping[str, Any] | None = None,
                 filled: bool | None = None, flexible: bool = False, slewing: bool = True, modes: int = 8,
                 q0: Sequence[float] | None = None, moves: Mapping[int, Sequence[tuple]] | None = None) -> None:
        super().__init__()
        record = PumpTruckParameters() if record is None else record
        if filled is not None:  # the load only: the machine is sized on its worst case (statics.sizing)
            record = replace(record, pipe=replace(record.pipe, filled=filled))
        self.record = record
        if q0 is None:  # the start pose [deg], each joint inside its range (a pose outside gave a garbage start)
            q0 = check_pose(TRANSPORT_POSE_DEG if pose is None else pose, record)
        q0 = np.asarray(q0, dtype=float)
        t_ref, ref_cols = check_table("targets", targets) if targets is not None else (np.zeros(1), {})
        t_cmd, cmd_cols = check_table("commands", commands) if commands is not None else (np.zeros(1), {})
        check_sources(ref_cols, cmd_cols)
        moves = dict(moves or {})
        for name, col in ref_cols.items():  # the targets' knots as waypoints of jerk-limited moves (C1 speed)
            k = JOINTS.index(name)
            if k > 0:
                moves[k] = waypoint_moves(t_ref, np.radians(col), a_max=A_MAX, j_max=J_MAX)
        self._commands = {JOINTS.index(name): (t_cmd, col) for name, col in cmd_cols.items()}
        rows = sizing(record)
        self._F_hold = cylinder_forces(record, q0[1:], design_cylinders(record))[0]
        self.world = World()
        self.power = PowerUnit(p_relief=record.p_system)
        if slewing:
            self.turret = Turret(mass=record.turret.mass, J_slew=record.turret.J_slew, height=record.turret.height,
                                 H1=record.joint1.H, phi_start=float(q0[0]))
            self.connect(self.world.frame_b, self.turret.frame_a)
            parent, housing1 = self.turret.frame_joint1, self.turret.frame_housing1
            self.slew_drive = SlewDrive(D=SLEW_D, ratio=SLEW_RATIO, Q_nom=SLEW_Q)
            self.slew_loop = AngleController(K_v=SLEW_Q / SLEW_D / SLEW_RATIO, use_feed_forward=False)
            slew_moves = (waypoint_moves(t_ref, np.radians(ref_cols["slew"]), a_max=A_MAX, j_max=J_MAX)
                          if "slew" in ref_cols else [])
            self.slew_ref = SmoothReference(*motion_profile(float(q0[0]), slew_moves))
            self.connect(self.slew_drive.flange, self.turret.axis, self.slew_loop.flange)
            self.connect(self.slew_ref.y, self.slew_loop.u_ref)
            if 0 in self._commands:
                self.slew_command = TimeTable(t=self._commands[0][0], y=self._commands[0][1])
                self.connect(self.slew_command.y, self.slew_drive.u)
            else:
                self.connect(self.slew_loop.y, self.slew_drive.u)
            self.connect(self.power.port_P, self.slew_drive.port_P)
            self.connect(self.power.port_T, self.slew_drive.port_T)
        else:
            self.turret_top = FixedTranslation(r=[0.0, record.turret.height, 0.0])
            self.housing1 = FixedTranslation(r=[*record.joint1.H, 0.0])
            self.connect(self.world.frame_b, self.turret_top.frame_a)
            self.connect(self.turret_top.frame_b, self.housing1.frame_a)
            parent, housing1 = self.turret_top.frame_b, self.housing1.frame_b
        prev = None
        for k in range(5):
            n = k + 1
            joint = Revolute(use_axis_flange=True, init={"phi": float(q0[n]), "w": 0.0, "a": 0.0},
                             state_select={"phi": "always", "w": "always"})
            section = self._section(n, flexible, modes)
            axis, ctrl, ref = self._drive(n, rows[k], float(q0[n]), moves.get(n, []))
            for name, part in (("joint", joint), ("section", section), ("axis", axis), ("loop", ctrl),
                               ("ref", ref)):
                setattr(self, f"{name}{n}", part)
            self.connect(parent, joint.frame_a)
            self.connect(joint.frame_b, section.frame_root)
            if n == 1:
                housing, rod_end = housing1, section.frame_C
            else:
                drive = record.drive(n)
                m_lever, m_link = linkage_masses(record, n)
                link = LeverLink.at_pose(float(q0[n]), drive.P, drive.c, drive.r, drive.s, drive.sigma,
                                         m_lever, m_link)
                setattr(self, f"linkage{n}", link)
                self.connect(prev.frame_P_next, link.frame_pivot)
                self.connect(link.frame_bracket, section.frame_C)
                housing, rod_end = prev.frame_H_next, link.frame_tip
            self.connect(housing, axis.frame_a, ctrl.frame_a)
            self.connect(rod_end, axis.frame_b, ctrl.frame_b)
            self.connect(self.power.port_P, axis.port_P)
            self.connect(self.power.port_T, axis.port_T)
            self.connect(ref.y, ctrl.u_ref)
            self.connect(ref.ff, ctrl.u_ff)
            if n in self._commands:  # open loop: the joystick's valve command
                command = TimeTable(t=self._commands[n][0], y=self._commands[n][1])
                setattr(self, f"command{n}", command)
                self.connect(command.y, axis.u)
            else:
                self.connect(ctrl.y, axis.u)
            parent, prev = section.frame_tip, section

    def _section(self, n: int, flexible: bool, modes: int) -> BoomSection:
        """Section ``n`` with its pins (bracket ``C``, next joint's lever pivot and housing), rigid or flexible."""
        points = attachment_points(self.record, n)
        pins = {name: points[point] for name, point in PIN_POINTS.items() if point in points}
        length = self.record.sections[n - 1].length
        if flexible:
            data, _ = section_modal_data(self.record, n)
            return BoomSection(length, pins=pins, modal_data=data, modes=modes)
        mp = section_mass_properties(self.record, n - 1)
        return BoomSection(length, m=mp["m"], r_CM=mp["com"], I=mp["I"], pins=pins)

    def _drive(self, n: int, row: Mapping[str, Any], q0: float,
               moves: Sequence[tuple]) -> tuple[HydraulicAxis, JointController, SmoothReference]:
        """Joint ``n``'s hydraulic axis (sized by ``row``), its length loop and its smooth reference."""
        record, drive = self.record, self.record.drive(n)
        bore, rod = row["bore"], row["rod"]
        A_p, A_r = math.pi / 4 * bore**2, math.pi / 4 * (bore**2 - rod**2)
        arm = max(abs(drive.state(float(q)).lever_arm) for q in np.linspace(drive.q_min, drive.q_max, 37))
        Q_nom = A_p * arm * W_MAX
        hold, free = ("A", "B") if row["F"] >= 0 else ("B", "A")
        crack = {f"p_crack_{hold}": 1.3 * row[f"p_worst_{hold}"]}
        over = row[f"p_worst_{free}"] > 0
        if over:
            crack[f"p_crack_{free}"] = 1.3 * row[f"p_worst_{free}"]
        stroke = row["stroke"] + 2 * STOP_MARGIN
        cyl = design_cylinders(record)[n - 1]  # housing and rod masses and where they sit (statics.cylinder_masses)
        axis = HydraulicAxis(d_bore=bore, d_rod=rod, stroke=stroke, L0=row["l_min"] - STOP_MARGIN, Q_nom=Q_nom,
                             hold=hold, over_centre=over, m_housing=cyl["m_housing"], L_housing=cyl["L_housing"],
                             m_rod=cyl["m_rod"], L_rod=cyl["L_rod"], p_system=record.p_system, **crack)
        # at rest in the start pose: the chamber the hand statics says holds carries the load, the other is at tank
        # (a parameter: one build serves every pose); the statics' pressure is the holding chamber's start guess
        F = self._F_hold[n - 1]
        axis.free_A = 1.0 if F < 0 else 0.0
        axis.cylinder.cylinder.set_start("p_A" if F >= 0 else "p_B", 1.01325e5 + abs(F) / (A_p if F >= 0 else A_r),
                                         fixed=False)
        L0 = drive.state(q0).length
        ctrl = JointController(A_p=A_p, Q_nom=Q_nom, L_start=L0)
        knots = motion_profile(q0, moves)
        ref = SmoothReference(*joint_to_length(knots, lambda q: drive.state(q).length, tol=TOLK),
                              ff_gain=(A_p / Q_nom, A_r / Q_nom))
        return axis, ctrl, ref


