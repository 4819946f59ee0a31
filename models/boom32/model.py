"""The 32 m four-section Z-fold boom: a second machine composed from the boom parts on its design record.

:class:`Boom32` connects the parts of :mod:`flexlib.models.boom` on the record
:data:`~models.pump_truck.record32.BOOM32` (four sections of 8.0/7.0/6.8/6.2 m, Z fold: joints 2 and 4 fold up,
joint 3 down; cylinder bores 180/180/180/100 mm at ≤ 80 % of 350 bar). Its diagram::

    world ── turret (slewing bearing + SlewDrive + AngleController + SmoothReference; or fixed)
               ├─ joint1 ── section1 ─ C ── axis1 (direct cylinder) ── H1 on the turret
               │              ├─ P_next ── linkage2 (lever, link) ── C of section2;  axis2 from H_next to the lever tip
               │              └─ tip ── joint2 ── section2 ── … joint3/section3, joint4/section4 likewise
    power (PowerUnit) ── port_P / port_T of every axis and of the slew drive
    ref{n} (SmoothReference) ── loop{n} (JointController on axis{n}'s pin-to-pin length) ── axis{n}.u

Every part is made from the record by :mod:`models.pump_truck.machine` with the choices of the 42 m
:class:`~models.pump_truck.model.PumpTruck` (its module docstring): designed once on the worst case
(:func:`~models.pump_truck.statics.sizing`: pipe filled, full reach, cylinder housings and rods, levers and links
counted; ``filled`` changes only the load), counterbalance valves 3:1 on both lines of every axis at 1.3 × the
line's worst holding pressure (at least 70 bar), feed-forward ahead by the command filter and spool lag,
static-equilibrium start in any pose (joints at rest, each free chamber at tank pressure), joint angles the states
(``state_select="always"``), targets as waypoints of jerk-limited moves mapped to cylinder lengths within 1 µm.
Result names are those of PumpTruck: ``axis2.cylinder.cylinder.p_A``, ``joint2.frame_b.f``,
``section4.frame_tip.r_0``, ``loop2.pid.y``, ``ref2.y``, ``turret.slew.phi``.

References
----------
Putzmeister 32Z-Meter (four-section Multi-Z boom, 28.0 m horizontal reach); the record's sources are in
:mod:`models.pump_truck.record32`; ``docs/boom32.md``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import flexlib as fl
from flexlib.components.mechanics.multibody import World
from flexlib.errors import ParameterError
from flexlib.models.boom import PowerUnit
from flexlib.models.pump_truck import machine  # the parts made from a design record
from flexlib.models.pump_truck.arguments import check_modes, check_pose, joint_names, model_options, option
from flexlib.models.pump_truck.flexible import mpf_modes, unfolding_poses
from flexlib.models.pump_truck.parameters import PumpTruckParameters
from flexlib.models.pump_truck.record32 import BOOM32
from flexlib.models.pump_truck.statics import cylinder_forces

__all__ = ["EXTENDED_POSE_DEG", "JOINTS", "OPTIONS", "TRANSPORT_POSE_DEG", "WORKING_POSE_DEG", "Boom32"]

#: Transport fold [deg] (slew, q1 … q4): the Z folded on the truck, joints 2–4 2° before their ends.
TRANSPORT_POSE_DEG = (0.0, 0.0, 176.0, -176.0, 176.0)
#: A working pose [deg]: boom raised 50°, the sections opening towards the pour.
WORKING_POSE_DEG = (0.0, 50.0, 10.0, -40.0, 20.0)
#: Fully extended, horizontal [deg].
EXTENDED_POSE_DEG = (0.0, 0.0, 0.0, 0.0, 0.0)
#: Joint names: the slew and the four boom joints.
JOINTS = joint_names(BOOM32)
#: Model options (the 42 m machine's, but the link cross-section: the record's levers and links as designed).
OPTIONS = tuple(o for o in model_options(4) if o.name != "link_plate")
NAME = "Boom32"


class Boom32(machine.HeldStart, fl.Model):
    """The 32 m four-section boom, rigid or with flexible sections, composed of boom parts (module docstring).

    Parameters
    ----------
    record : PumpTruckParameters, optional
        A four-section design record (default :data:`~models.pump_truck.record32.BOOM32`).
    pose : sequence of 5 floats, optional
        Start angles [deg]: slew, q1 … q4 (default :data:`TRANSPORT_POSE_DEG`); the boom starts at rest in static
        equilibrium there.
    targets : mapping, optional
        Joint waypoints as a time table in degrees ``{"t": [s...], "joint2": [deg...], ...}`` (jerk-limited moves,
        at rest at each waypoint); joints not given hold their start angle.
    commands : mapping, optional
        Open-loop valve commands (−1…1) ``{"t": [...], "joint1": [...]}``; a joint given here has no controller.
    filled : bool, optional
        Delivery pipe filled with concrete (default: the record's): the load only.
    flexible : bool
        Each section a FlexibleBody (Craig–Bampton, :mod:`models.pump_truck.flexible`).
    slewing : bool
        The slewing bearing and its drive (default); ``False``: the turret fixed to the ground.
    modes : "mpf", int or mapping
        Modes of the flexible sections (``"mpf"``: the modal participation factor selection on this machine).

    Raises
    ------
    ParameterError
        An argument of the wrong type or out of range (the message names ``Boom32``, the argument and the value).

    Attributes
    ----------
    record : PumpTruckParameters
        The record used (``filled`` applied). ``q0`` the start angles [rad], ``F_hold`` the hand statics' cylinder
        forces there [N], ``cylinders`` each axis's design (:func:`~models.pump_truck.machine.hydraulic_axis`).
    """

    experiment = fl.Experiment(t_end=10.0, dt_out=0.05, rtol=1e-6, atol=1e-8, max_order=2)

    def __init__(self, record: PumpTruckParameters | None = None, pose: Sequence[float] | None = None,
                 targets: Mapping[str, Any] | None = None, commands: Mapping[str, Any] | None = None,
                 filled: bool | None = None, flexible: bool = False, slewing: bool = True,
                 modes: int | str | Mapping[int, Sequence[int]] = "mpf") -> None:
        super().__init__()
        record = BOOM32 if record is None else record
        if not isinstance(record, PumpTruckParameters) or record.n_sections != 4:
            raise ParameterError(f"{NAME}: record must be a four-section PumpTruckParameters (BOOM32 or a variant of "
                                 f"it), got {type(record).__name__} {getattr(record, 'n_sections', '')}".rstrip())
        filled, self.flexible, self.slewing, modes = (option(k, v, NAME, OPTIONS) for k, v in (
            ("filled", filled), ("flexible", flexible), ("slewing", slewing), ("modes", modes)))
        if not self.flexible and modes != "mpf":
            raise ParameterError(f"{NAME}: modes = {modes!r} selects the modes of the flexible sections, but the boom "
                                 "is rigid (flexible=False); give flexible=True as well, or leave modes out")
        if filled is not None:  # the load only: the machine is sized on its worst case
            record = replace(record, pipe=replace(record.pipe, filled=filled))
        self.record, self._q0 = record, check_pose(TRANSPORT_POSE_DEG if pose is None else pose, record, NAME)
        self.modes = check_modes(modes, record, NAME, mpf_selection) if self.flexible else None
        moves, commands = machine.joint_inputs(record, targets, commands, NAME)
        self._F_hold = cylinder_forces(record, self._q0[1:])[0]  # values, not structure
        self.cylinders: list[dict[str, Any]] = []

        self.world = World(g=record.g)  # the record's gravity (its statics and sizing use it)
        self.power = PowerUnit(p_relief=record.p_system)
        if self.slewing:
            self.turret, self.slew_drive, self.slew_loop, self.slew_ref = machine.slewing_turret(
                record, float(self._q0[0]), moves.get(0, []))
            self.connect(self.world.frame_b, self.turret.frame_a)
            self.connect(self.slew_drive.flange, self.turret.axis, self.slew_loop.flange)
            self.connect(self.slew_ref.y, self.slew_loop.u_ref)
            machine.feed_and_drive(self, self.power, self.slew_drive, self.slew_loop, commands.get(0), "slew_command")
            parent, housing = self.turret.frame_joint1, self.turret.frame_housing1
        else:
            self.turret_top, self.housing1 = machine.fixed_turret(record)
            self.connect(self.world.frame_b, self.turret_top.frame_a)
            self.connect(self.turret_top.frame_b, self.housing1.frame_a)
            parent, housing = self.turret_top.frame_b, self.housing1.frame_b

        prev = None
        for n, row in enumerate(machine.design_sizing(record), start=1):  # sized once, on the worst case
            q = float(self._q0[n])
            joint, section = machine.boom_joint(q), machine.boom_section(record, n, self.modes)
            axis, cylinder = machine.hydraulic_axis(record, n, row, float(self._F_hold[n - 1]))
            loop, ref = machine.joint_loop(record, n, cylinder, q, moves.get(n, []))
            self.cylinders.append(cylinder)
            for name, part in (("joint", joint), ("section", section), ("axis", axis), ("loop", loop), ("ref", ref)):
                setattr(self, f"{name}{n}", part)
            self.connect(parent, joint.frame_a)
            self.connect(joint.frame_b, section.frame_root)
            if n > 1:  # joints 2-4: the lever pivoted on the section before, its link to this section's bracket
                linkage = machine.lever_link(record, n, q)
                setattr(self, f"linkage{n}", linkage)
                self.connect(prev.frame_P_next, linkage.frame_pivot)
                self.connect(linkage.frame_bracket, section.frame_C)
            # the cylinder and its length loop on the same pins: joint 1 from the turret to section 1's bracket (a
            # direct cylinder), the others from the section before to the lever tip
            housing, rod_end = (housing, section.frame_C) if n == 1 else (prev.frame_H_next, linkage.frame_tip)
            self.connect(housing, axis.frame_a, loop.frame_a)
            self.connect(rod_end, axis.frame_b, loop.frame_b)
            self.connect(ref.y, loop.u_ref)
            self.connect(ref.ff, loop.u_ff)
            machine.feed_and_drive(self, self.power, axis, loop, commands.get(n), f"command{n}")
            parent, prev = section.frame_tip, section



#: Poses [deg] whose static loads select the flexible sections' modes: the unfolding's stations and the extended boom.
MPF_POSES_DEG = unfolding_poses(TRANSPORT_POSE_DEG, WORKING_POSE_DEG)


def mpf_selection(record: PumpTruckParameters) -> dict[int, list[int]]:
    """Each section's modes by the modal participation factor method (:func:`~models.pump_truck.flexible.mpf_modes`)
    on the rigid boom at rest in :data:`MPF_POSES_DEG` (its free-body statics,
    :func:`~models.pump_truck.flexible.static_section_loads`: the same loads as Boom32's at rest, to 2e-14)."""
    return mpf_modes(record, poses=MPF_POSES_DEG)
