"""The 42 m pump-truck boom, rigid or flexible: a composition of the boom parts on the design record.

:class:`PumpTruck` connects parts of :mod:`flexlib.models.boom` (each with its own bench test and docstring) as the
design record :class:`~models.pump_truck.parameters.PumpTruckParameters` says; the choices below are what the
composition adds. Result names are hierarchical (the table in ``docs/pump_truck.md``): ``axis2.cylinder.cylinder.p_A``,
``joint2.frame_b.f``, ``section3.frame_tip.r_0``, ``loop2.pid.y``, ``ref2.y``, ``turret.slew.phi``.

Mechanics (world ``y`` up, gravity along ``−y``): the boom moves in the vertical ``x``–``y`` plane on a
:class:`~flexlib.models.boom.Turret` (the slewing bearing, a revolute about world ``y`` with ring friction, and the
turret body; ``slewing=False`` fixes it), so slewing and the boom's motion are coupled in 3D. Joint ``n`` is a
``Revolute`` about ``z`` between section ``n−1`` (the turret for ``n = 1``) and section ``n``, with ``q = 0`` all
sections in line; the joint angles are the machine's states (``state_select="always"``: the lever-and-link loops'
other angles follow them, with no switch of state selection during a run). Each section a
:class:`~flexlib.models.boom.BoomSection`: rigid with the record's mass properties (steel box, pipe filled or
empty, end hose on the last section; :func:`~models.pump_truck.geometry.section_mass_properties`), or
(``flexible=True``) a Craig–Bampton FlexibleBody from its beam mesh behind the same named pins (``C`` the drive
bracket, ``P_next`` and ``H_next`` the next joint's lever pivot and cylinder housing), its modes chosen by the modal
participation factor method (:func:`~models.pump_truck.flexible.mpf_modes`). Joint 1 is driven by a direct cylinder
from the turret, joints 2… through a :class:`~flexlib.models.boom.LeverLink` (lever pivoted on the section
before, link to the bracket, cylinder to the lever tip); levers and links are steel bars (``link_plate``).

Hydraulics: a :class:`~flexlib.models.boom.PowerUnit` (pressure-compensated pump, supply volume, relief at the
system pressure, tank) feeds one :class:`~flexlib.models.boom.HydraulicAxis` per joint: the cylinder with its
housing and rod masses on its pins (weight and inertia, as in the hand statics that size it), a closed-centre
proportional valve with pressure-compensated meter-in edges, **counterbalance valves on both lines** (3:1, each
set at 1.3 × its line's worst holding pressure over the sizing sweep, at least ``P_CRACK_MIN`` = 70 bar: a line
that never holds the load, joint 1's rod side, is not set at the holding line's 283 bar, which made the rod side's
valve meter the lift and chatter), hoses, and the shock-relief and make-up cartridges on both ports. The slewing ring is
driven by a :class:`~flexlib.models.boom.SlewDrive`.

**Designed once, on the worst case.** Bores, rods and strokes (:func:`~models.pump_truck.statics.sizing`: filled
pipe, full reach, cylinder, lever and link masses counted) and the valve settings follow from the record alone;
``filled`` changes only the load. Each cylinder has ``STOP_MARGIN`` of stroke beyond the record's range at each
end; its valve is rated ``Q_nom = A_p·arm_max·W_MAX``.

Control: per boom joint a :class:`~flexlib.models.boom.JointController` closes a PI loop on the cylinder's
pin-to-pin length (crossover ``OMEGA_C`` in every pose; tared at the start to the record's length there), with the
reference and its feed-forward from a :class:`~flexlib.models.boom.SmoothReference`: the ``targets`` are waypoints
of jerk-limited moves (``A_MAX``, ``J_MAX``; each joint at rest at each waypoint), mapped to the cylinder length
through the record's kinematics (:func:`~flexlib.models.boom.joint_to_length`, 1 µm), so speed and flow are
continuous. The feed-forward leads the reference by ``FF_LEAD`` = 0.171 s (the command filter ``T_CMD`` and the
spool's lag ``2ζ/ω``), so the cylinder does not trail the reference and the loop does not reverse the spool at the
end of a move (which opened the holding valve on its trapped pilot pressure and dropped the load a little). The
slewing joint has an :class:`~flexlib.models.boom.AngleController`. A joint given in ``commands`` is driven open
loop by a ``TimeTable`` of valve commands (an operator's joystick).

Static-equilibrium start in any pose: the boom joints start at ``pose`` at rest and not accelerating; each axis's
free chamber starts at tank pressure and its holding chamber's pressure is solved for (the hand statics' pressure
the guess; :func:`~models.pump_truck.statics.cylinder_forces`); with flexible sections the same conditions give the
deflected equilibrium.

References
----------
Schwing / Putzmeister 42 m booms (five sections, lever-and-link joints, counterbalance valves 3:1). H. E. Merritt,
*Hydraulic Control Systems*, Wiley 1967. Sun Hydraulics, *Counterbalance valves*. L. Biagiotti, C. Melchiorri,
*Trajectory Planning for Automatic Machines and Robots*, Springer 2008, §3.4. Modelica Standard Library 4.0,
``MultiBody.Joints.Revolute``, ``Blocks.Continuous.LimPID``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import flexlib as fl
from flexlib.components.control import TimeTable
from flexlib.components.mechanics.multibody import World
from flexlib.errors import ParameterError
from flexlib.models.boom import PowerUnit

from .arguments import JOINTS, check_modes, check_pose, option
from .geometry import LINK_PLATE
from .machine import (  # noqa: F401  (A_MAX ... W_MAX, P_TANK: the machine's constants, read from here too)
    A_MAX,
    J_MAX,
    LENGTH_TOL,
    P_TANK,
    STOP_MARGIN,
    W_MAX,
    HeldStart,
    boom_joint,
    boom_section,
    design_sizing,
    feed_and_drive,
    fixed_turret,
    hydraulic_axis,
    joint_inputs,
    joint_loop,
    lever_link,
    slewing_turret,
)
from .parameters import PumpTruckParameters
from .statics import cylinder_forces

__all__ = ["JOINTS", "TRANSPORT_POSE_DEG", "WORKING_POSE_DEG", "PumpTruck"]

#: Transport fold [deg] (slew, q1 … q5): boom resting on the truck, joints 2–5 folded to 2° before their ends.
TRANSPORT_POSE_DEG = (0.0, 0.0, 176.0, -176.0, 176.0, -176.0)
#: A working pose [deg]: boom raised 50°, sections opening downwards towards the pour.
WORKING_POSE_DEG = (0.0, 50.0, 10.0, -30.0, 20.0, -40.0)
#: Fully extended, horizontal [deg].
EXTENDED_POSE_DEG = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


class PumpTruck(HeldStart, fl.Model):
    """The pump-truck boom, rigid or with flexible sections, composed of boom parts (module docstring).

    Parameters
    ----------
    record : PumpTruckParameters, optional
        Design record (default ``PumpTruckParameters()``).
    pose : sequence of floats, optional
        Start angles [deg]: slew, then q1 … qN (default :data:`TRANSPORT_POSE_DEG`). The boom starts at rest in
        static equilibrium there.
    targets : mapping, optional
        Joint waypoints as a time table in degrees: ``{"t": [s...], "joint2": [deg...], ...}``; each joint moves from
        waypoint to waypoint on a jerk-limited profile (at rest at each; ``ParameterError`` if a waypoint cannot be
        reached in time at ``A_MAX``, ``J_MAX``). Joints not given hold their start angle.
    commands : mapping, optional
        Open-loop valve commands (−1…1) as a time table ``{"t": [...], "joint1": [...]}`` (linear between points); a
        joint given here has no controller (and must not be in ``targets``).
    filled : bool, optional
        Delivery pipe filled with concrete (default: the record's ``pipe.filled``): the load only, the machine is
        sized on the filled pipe.
    flexible : bool
        ``True``: each section a FlexibleBody (beam mesh, Craig–Bampton; :mod:`models.pump_truck.flexible`).
    slewing : bool
        ``True`` (default): the slewing bearing and its drive; ``False``: the turret fixed to the ground.
    link_plate : float
        Cross-section of levers and links at joint scale 3 [m2] (default :data:`LINK_PLATE`).
    modes : "mpf", int or mapping
        Modes of the flexible sections: ``"mpf"`` (default) the modal participation factor selection, a count (the
        lowest in-plane modes) or ``{section: [mode indices]}``; only with ``flexible=True``.

    Raises
    ------
    ParameterError
        An argument of the wrong type or out of range, a joint in both ``targets`` and ``commands``; the message
        names the argument, the value and what is accepted.

    Attributes
    ----------
    record : PumpTruckParameters
        The record used (with ``filled`` applied).
    q0 : ndarray
        Start angles [rad] (slew, q1 … qN).
    F_hold : ndarray
        Holding forces of the cylinders at the start by the hand statics [N] (positive pushes).
    cylinders : list of dict
        Per cylinder: ``bore``, ``rod``, ``stroke``, ``L0`` [m], ``hold`` (``"A"`` or ``"B"``), ``Q_nom`` [m3/s].
    """

    experiment = fl.Experiment(t_end=10.0, dt_out=0.05, rtol=1e-6, atol=1e-8, max_order=2)

    def __init__(self, record: PumpTruckParameters | None = None, pose: Sequence[float] | None = None,
                 targets: Mapping[str, Any] | None = None, commands: Mapping[str, Any] | None = None,
                 filled: bool | None = None, flexible: bool = False, slewing: bool = True,
                 link_plate: float = LINK_PLATE, modes: int | str | Mapping[int, Sequence[int]] = "mpf") -> None:
        super().__init__()
        record = PumpTruckParameters() if record is None else record
        if not isinstance(record, PumpTruckParameters):
            raise ParameterError(f"PumpTruck: record must be a PumpTruckParameters, got {type(record).__name__}")
        filled, self.flexible, self.slewing = option("filled", filled), option("flexible", flexible), option(
            "slewing", slewing)
        self.link_plate, modes = option("link_plate", link_plate), option("modes", modes)
        if not self.flexible and modes != "mpf":  # not ignored silently: the rigid boom has no modes to select
            raise ParameterError(f"PumpTruck: modes = {modes!r} selects the modes of the flexible sections, but the "
                                 "boom is rigid (flexible=False); give flexible=True as well, or leave modes out")
        if filled is not None:  # the load only: the machine is sized on its worst case (statics.sizing)
            record = replace(record, pipe=replace(record.pipe, filled=filled))
        self.record = record
        self._q0 = check_pose(TRANSPORT_POSE_DEG if pose is None else pose, record)
        self.modes = check_modes(modes, record) if self.flexible else modes
        moves, commands_by_joint = joint_inputs(record, targets, commands)
        self._F_hold = cylinder_forces(record, self._q0[1:])[0]
        self.cylinders: list[dict[str, Any]] = []

        self.world = World(g=record.g)  # the record's gravity (its statics and sizing use it)
        self.power = PowerUnit(p_relief=record.p_system)
        parent, housing1 = self._turret(moves.get(0, []), commands_by_joint.pop(0, None))
        prev = None
        for n, row in enumerate(design_sizing(record), start=1):
            q_n = float(self._q0[n])
            joint, section = boom_joint(q_n), boom_section(record, n, self.modes if self.flexible else None)
            axis, cylinder = hydraulic_axis(record, n, row, float(self._F_hold[n - 1]))
            self.cylinders.append(cylinder)
            loop, ref = joint_loop(record, n, cylinder, q_n, moves.get(n, []))
            for name, part in (("joint", joint), ("section", section), ("axis", axis), ("loop", loop), ("ref", ref)):
                setattr(self, f"{name}{n}", part)
            self.connect(parent, joint.frame_a)
            self.connect(joint.frame_b, section.frame_root)
            if prev is None:  # joint 1: the direct cylinder from the turret to the section's bracket
                housing, rod_end = housing1, section.frame_C
            else:  # the lever and link on the section before, the cylinder to the lever tip
                linkage = lever_link(record, n, q_n, self.link_plate)
                setattr(self, f"linkage{n}", linkage)
                self.connect(prev.frame_P_next, linkage.frame_pivot)
                self.connect(linkage.frame_bracket, section.frame_C)
                housing, rod_end = prev.frame_H_next, linkage.frame_tip
            self.connect(housing, axis.frame_a, loop.frame_a)
            self.connect(rod_end, axis.frame_b, loop.frame_b)
            self.connect(ref.y, loop.u_ref)
            self.connect(ref.ff, loop.u_ff)
            feed_and_drive(self, self.power, axis, loop, commands_by_joint.get(n), f"command{n}")
            parent, prev = section.frame_tip, section

    # ---- the parts, each made from the record --------------------------------------------------------------------
    def _turret(self, moves: Sequence[tuple], command: TimeTable | None) -> tuple[Any, Any]:
        """The turret on the slewing bearing with its drive and angle loop (or fixed): joint 1's frame and the
        joint-1 cylinder's housing pin."""
        if not self.slewing:
            self.turret_top, self.housing1 = fixed_turret(self.record)
            self.connect(self.world.frame_b, self.turret_top.frame_a)
            self.connect(self.turret_top.frame_b, self.housing1.frame_a)
            return self.turret_top.frame_b, self.housing1.frame_b
        self.turret, self.slew_drive, self.slew_loop, self.slew_ref = slewing_turret(
            self.record, float(self._q0[0]), moves)
        self.connect(self.world.frame_b, self.turret.frame_a)
        self.connect(self.slew_drive.flange, self.turret.axis, self.slew_loop.flange)
        self.connect(self.slew_ref.y, self.slew_loop.u_ref)
        feed_and_drive(self, self.power, self.slew_drive, self.slew_loop, command, "slew_command")
        return self.turret.frame_joint1, self.turret.frame_housing1
