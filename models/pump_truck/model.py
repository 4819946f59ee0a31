"""Simulation model of the 42 m pump-truck boom, rigid or flexible, built on the design record.

Built from library components only (3D multibody, hydraulics, control), with the numbers of
:class:`~models.pump_truck.parameters.PumpTruckParameters`:

Mechanics (world ``y`` up, gravity ``9.81 m/s²`` along ``−y``):

* The boom moves in the vertical ``x``–``y`` plane; joint 1 sits ``turret.height`` above the slewing bearing;
  joints 1–5 turn about ``z``; relative joint angles ``q`` as in the record (``q = 0``: all sections in line,
  ``q1 = 0``: horizontal). **Slewing**: the whole boom stands on a revolute about the vertical world ``y`` axis
  (the slewing bearing) carrying the turret body (``turret.mass``, ``turret.J_slew`` about the axis), so slewing
  and the boom's motion are coupled in 3D (centrifugal and gyroscopic terms included); the boom's four-bar loops
  turn with it (their redundant rows are dropped in the cut frames: ``docs/engine.md``).
* Five sections as rigid ``Body`` with the record's mass properties: steel box + delivery pipe (filled or
  empty) from :func:`~models.pump_truck.statics.mass_properties`; the end hose a point mass at the tip pin
  (as in the hand statics), lumped into section 5's body. The sections are made by one function,
  :meth:`PumpTruck._section`, which returns the section's named frames (root, tip, pins); the flexible variant
  (below) returns the same frames from a FlexibleBody.
* Joint 1 driven by its direct cylinder (record ``joint1``: housing ``H`` on the turret, bracket ``c`` on
  section 1); joints 2–5 through the record's lever-and-link four-bars: lever (rocker) pivoted at ``P`` on
  section k−1, link from the lever tip ``T`` to the bracket ``c`` on section k, cylinder from ``H`` on section
  k−1 to ``T``. Each loop is closed by revolute joints and bodies (the engine removes the redundant planar loop
  constraints). Levers and links are steel bars (two plates of ``LINK_PLATE`` at the scale of the joint),
  light beside the sections (≤ 0.5 % of a joint's holding torque).
* Cylinders (``LineCylinder``) with the record's ISO 3320 bore, rod and stroke (:func:`sizing`) plus
  ``STOP_MARGIN`` at each end, so the transport fold sits just clear of the end stops.

Hydraulics (HLP46): a pressure-compensated pump (``PUMP_D`` at ``PUMP_SPEED``, compensator ``P_COMP``) into a
supply volume, a relief valve at the system pressure, a tank. Per cylinder:

* a closed-centre proportional ``DirectionalValve43`` (spool 20 Hz) with pressure-compensated meter-in edges
  (the individual compensators of the load-sensing valve blocks booms carry). The lowering flow is then set by the
  spool, and the pilot pressure rises only as far as the counterbalance valve must open to let the load follow.
  With plain edges at the 320 bar supply, any lowering command drove the pilot to supply pressure and the
  counterbalance valve wide open: a relay that held every joint loop in a limit cycle;
* a ``CounterbalanceValve`` on each cylinder line that holds the load somewhere in the joint's range (pilot from
  the other line, pilot ratio ``PILOT_RATIO`` = 3:1, setting 1.3 × that side's worst holding pressure over the
  record's sizing sweep, poppet lag ``CBV_T`` = the pilot damping orifice), each with a hose volume to the
  directional valve. Joints 2–5 fold through 180°, so their load changes chamber within their range: both lines
  carry one (the second named ``cbv{n}_over``); joint 1 always pushes: its cap side only. The
  openings have C1 corners over ``CBV_SMOOTHING`` of their ranges (Simscape's smoothing factor: a loop holding a
  load crosses them often);
* the cylinder-port cartridges of the valve block on both ports of every cylinder (``shock{n}A``, ``makeup{n}B``,
  ...): a shock relief valve to tank at ``SHOCK_FACTOR`` × the system pressure and an anti-cavitation make-up check
  valve from tank. They bound an emergency stop: without them a chamber trapped behind its counterbalance valve
  reached 430 bar and an expanding one −61 bar (pure oil); with them 374 bar and +0.09 bar;
* seal friction (``LineCylinder``): Coulomb ``CYL_FC`` × the force of the system pressure on the piston (3.5 bar
  of friction pressure: the breakaway pressure of standard cylinder seals, Rexroth data 3–5 bar), regularised
  below ``CYL_VREG``, plus viscous ``D_CYL``. Without it, counterbalance-metered lowering of the folding sections
  grew into a 2.6 Hz oscillation (the known counterbalance lowering instability); the seal friction damps it,
  as on the real machine.

The turret is slewed by a ``HydraulicMotor`` through an ``IdealGear`` (``SLEW_RATIO``) with its own valve and
hose volumes.

Control: per joint (``slew``, ``joint1`` … ``joint5``) a ``LimPID`` (PI by default, ``T_D > 0`` adds the D part;
output limited to ±1 = the valve command) whose output passes the valve amplifier's command filter (``T_CMD``,
first order: the ramp of mobile valve electronics; with the raw PI output the loops excited the boom's 5–6 Hz
oil-spring modes into limit cycles). A boom joint is controlled on its cylinder's pin-to-pin length, measured
along the cylinder: the joint's angle reference becomes a length reference through the record's kinematics
(:func:`length_reference`), so the crossover is ``OMEGA_C`` = 0.3 rad/s in every pose (on the angle it would
rise tenfold where the lever arm falls near the fold). The slewing joint is controlled on its angle. A joint
given in ``commands`` gets its valve command straight from a ``TimeTable`` (the operator's joystick).

Static-equilibrium start in any pose: the joints start at ``pose``, at rest and not accelerating (``phi``, ``w``
and ``a`` of each boom joint are initial conditions); the pressure of each cylinder's holding chamber is what the
initialisation solves for (its start value, ``p_tank + |F|/A`` with ``F`` the holding force by virtual work on this
model's own geometry, :func:`holding_forces`, is the guess), the other chamber and all lines start at tank pressure,
valves and counterbalance valves closed with their poppets at rest (``steady_start``), controller outputs zero, and
each length loop tared to the record's length in the start pose (``Tare``). With flexible sections the same
conditions give the deflected equilibrium: modal velocities and accelerations start at zero, the modal coordinates
are solved for.

Flexible variant (``flexible=True``): each section a ``FlexibleBody`` from its beam mesh and Craig–Bampton
reduction (:mod:`models.pump_truck.flexible`; pipe and hose as offset point masses), its in-plane modes chosen by
the modal participation factor method on the rigid boom's static loads (:func:`~models.pump_truck.flexible.mpf_modes`,
1 %, at most 8 per section). Each pin of the rigid model becomes a frame at the pin's beam node (off-axis pins
through a rigid bracket), so cylinders, levers and links attach as before and the hinge forces keep their names.

References
----------
Schwing / Putzmeister 42 m booms (five sections, lever-and-link joints 2–5, counterbalance valves 3:1 on the
boom cylinders). H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967 (valve–cylinder sizing).
Sun Hydraulics, *Counterbalance valves* (setting 1.3 × load, pilot ratio). Modelica Standard Library 4.0,
``Blocks.Continuous.LimPID``. J. L. Meriam, L. G. Kraige, *Engineering Mechanics: Statics*, ch. 7 (virtual work).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.components.control import Constant, FirstOrder, LimPID, Tare, TimeTable
from flexlib.components.hydraulics import (
    CheckValve,
    CounterbalanceValve,
    DirectionalValve43,
    HydraulicMotor,
    LineCylinder,
    PressureCompensatedPump,
    PressureReliefValve,
    Tank,
    Volume,
)
from flexlib.components.hydraulics.fluid import HLP46
from flexlib.components.mechanics import rotational, translational
from flexlib.components.mechanics.multibody import (
    Body,
    FixedTranslation,
    LineForce,
    RelativePosition,
    Revolute,
    World,
)
from flexlib.errors import ParameterError
from flexlib.models.boom.axis import (
    CBV_A_LEAK,
    CBV_DP_CHECK,
    CBV_DP_OPEN,
    CBV_SMOOTHING,
    CBV_T,
    CYL_FC,
    CYL_VREG,
    D_CYL,
    MAKEUP_AREA,
    MAKEUP_CRACK,
    MAKEUP_OPEN,
    PILOT_RATIO,
    SHOCK_FACTOR,
    SHOCK_LEAK,
    V_HOSE,
    VALVE_DP,
    VALVE_HZ,
)
from flexlib.models.boom.controller import OMEGA_C, T_CMD, T_I
from flexlib.models.boom.power import D_PUMP as PUMP_D
from flexlib.models.boom.power import DP_REG, P_COMP, V_SUPPLY
from flexlib.models.boom.power import SPEED as PUMP_SPEED
from flexlib.models.boom.slew import D_MOTOR as SLEW_D
from flexlib.models.boom.slew import J_ROTOR as SLEW_ROTOR_J
from flexlib.models.boom.slew import Q_VALVE as SLEW_Q
from flexlib.models.boom.slew import RATIO as SLEW_RATIO
from flexlib.models.boom.turret import SLEW_FRICTION, SLEW_W_REG
from flexlib.models.boom_proxy import link_body

from .arguments import JOINTS, check_modes, check_pose, check_sources, check_table, option
from .geometry import (
    LINK_PLATE,
    boom_pose,
    holding_forces,
    length_reference,
    linkage_masses,
    section_mass_properties,
    sizing,
)
from .parameters import PumpTruckParameters

__all__ = ["JOINTS", "TRANSPORT_POSE_DEG", "WORKING_POSE_DEG", "PumpTruck", "holding_forces", "linkage_masses",
           "section_mass_properties"]

#: Transport fold [deg] (slew, q1 … q5): boom resting on the truck, joints 2–5 folded to 2° before their ends.
TRANSPORT_POSE_DEG = (0.0, 0.0, 176.0, -176.0, 176.0, -176.0)
#: A working pose [deg]: boom raised 50°, sections opening downwards towards the pour.
WORKING_POSE_DEG = (0.0, 50.0, 10.0, -30.0, 20.0, -40.0)
#: Fully extended, horizontal [deg].
EXTENDED_POSE_DEG = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

P_TANK = HLP46.p_ref  # tank pressure [Pa] (atmospheric)
STOP_MARGIN = 0.03  # cylinder stroke beyond the record's range at each end [m]
W_MAX = 0.03  # joint speed at full valve command, 35 bar per edge, largest lever arm [rad/s] (valve sizing)
T_D = 0.0  # derivative time [s]; 0: PI (a D part excites the boom's hydraulic modes; docs/decisions/024-*)


class PumpTruck(fl.Model):
    """The pump-truck boom, rigid or with flexible sections (see the module docstring).

    Parameters
    ----------
    record : PumpTruckParameters, optional
        Design record (default ``PumpTruckParameters()``).
    pose : sequence of 6 float, optional
        Start angles [deg]: slew, then q1 … q5 (default :data:`TRANSPORT_POSE_DEG`). The boom starts at rest in
        static equilibrium there.
    targets : mapping, optional
        Joint reference trajectories as a time table in degrees: ``{"t": [s...], "joint2": [deg...], ...}``
        (linear between points, ends held). Joints not given hold their start angle.
    commands : mapping, optional
        Open-loop valve commands (−1…1) as a time table ``{"t": [...], "joint1": [...]}``; a joint given here has
        no controller (and must not be in ``targets``).
    filled : bool, optional
        Delivery pipe filled with concrete (default: the record's ``pipe.filled``).
    flexible : bool
        ``True``: each section a FlexibleBody (beam mesh, Craig–Bampton; :mod:`models.pump_truck.flexible`), its
        static deflection part of the start.
    modes : "mpf", int or mapping
        Modes of the flexible sections: ``"mpf"`` (default) the modal participation factor selection
        (:func:`~models.pump_truck.flexible.mpf_modes`: 1 % threshold, at most 8 per section), a count (the lowest
        in-plane modes) or ``{section: [mode indices]}``; only with ``flexible=True`` (a rigid boom given other
        modes than the default is refused, not run without them).
    slewing : bool
        ``True`` (default): the slewing bearing (a revolute about world ``y`` under the turret) and its drive
        (motor, gear, valve, control); ``False``: the turret fixed to the ground, no slewing drive.
    link_plate : float
        Cross-section of levers and links at joint scale 3 [m2] (default :data:`LINK_PLATE`).

    The options ``filled``, ``flexible``, ``modes``, ``slewing``, ``link_plate`` are declared (type, accepted
    values) in :data:`models.pump_truck.arguments.OPTIONS`; ``filled``, ``flexible`` and ``slewing`` take
    ``True``/``False`` only (``"no"`` is refused, not read as true).

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
        Start angles [rad] (slew, q1 … q5).
    F_hold : ndarray
        Holding forces of the five cylinders at the start [N] (positive pushes).
    cylinders : list of dict
        Per cylinder: ``bore``, ``rod``, ``stroke``, ``L0`` [m], ``hold`` (``"A"`` or ``"B"``: the chamber whose
        line carries the counterbalance valve), ``Q_nom`` [m3/s] of its valve.
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
        # the model options, each checked by its declaration (arguments.OPTIONS, also the registry's)
        filled, flexible, slewing = option("filled", filled), option("flexible", flexible), option("slewing", slewing)
        link_plate = option("link_plate", link_plate)
        modes = option("modes", modes)
        if not flexible and modes != "mpf":  # not ignored silently: the rigid boom has no modes to select
            raise ParameterError(f"PumpTruck: modes = {modes!r} selects the modes of the flexible sections, but the "
                                 "boom is rigid (flexible=False); give flexible=True as well, or leave modes out")
        if filled is not None:
            record = replace(record, pipe=replace(record.pipe, filled=filled))
        self.record = record
        q0 = check_pose(TRANSPORT_POSE_DEG if pose is None else pose, record)
        self._q0 = q0  # (underscore: the pose is a start value, not structure; one build serves every pose)
        self.flexible = flexible
        self.modes = check_modes(modes, record) if self.flexible else modes
        t_ref, ref_cols = check_table("targets", targets) if targets is not None else (np.zeros(1), {})
        t_cmd, cmd_cols = check_table("commands", commands) if commands is not None else (np.zeros(1), {})
        check_sources(ref_cols, cmd_cols)
        for name, col in cmd_cols.items():
            if np.any(np.abs(col) > 1.0):
                raise ParameterError(f"PumpTruck: commands[{name!r}] must stay within -1 ... 1 (valve command)")
        for name, col in ref_cols.items():
            k = JOINTS.index(name)
            if k > 0:
                drive = record.drive(k)
                lo, hi = math.degrees(drive.q_min), math.degrees(drive.q_max)
                if np.any(col < lo - 1e-9) or np.any(col > hi + 1e-9):
                    raise ParameterError(f"PumpTruck: targets[{name!r}] leaves the joint's range {lo:.1f} ... "
                                         f"{hi:.1f} deg")
        self.link_plate = link_plate
        q = q0[1:]
        geo = boom_pose(record, q, self.link_plate)
        F_hold, _ = holding_forces(record, q, self.link_plate)
        self._F_hold = F_hold
        rows = sizing(record)

        # ---- mechanics -------------------------------------------------------------------------------------
        self.world = World()
        tr = record.turret
        self.slewing = slewing
        self.turret_top = FixedTranslation(r=[0.0, tr.height, 0.0])
        if self.slewing:  # the slewing bearing: a revolute about world y under the whole boom, turret on it
            self.slew = Revolute(n=[0, 1, 0], use_axis_flange=True, use_friction=True, tau_c0=SLEW_FRICTION,
                                 w_reg=SLEW_W_REG, init={"phi": float(q0[0]), "w": 0.0})
            self.turret = Body(m=tr.mass, r_CM=[0.0, tr.height / 2, 0.0],
                               I=np.diag([tr.J_slew / 2, tr.J_slew, tr.J_slew / 2]))
            self.connect(self.world.frame_b, self.slew.frame_a)
            self.connect(self.slew.frame_b, self.turret_top.frame_a, self.turret.frame_a)
        else:
            self.connect(self.world.frame_b, self.turret_top.frame_a)
        parent = self.turret_top.frame_b  # joint 1 frame: x horizontal, y up, z the boom-joint axis
        self.joint1_housing = FixedTranslation(r=[*record.joint1.H, 0.0])
        self.connect(parent, self.joint1_housing.frame_a)

        frames: list[dict[str, Any]] = []
        for k in range(5):
            n = k + 1
            # at rest in equilibrium: angle, speed and acceleration fixed; the holding pressures follow
            joint = Revolute(use_axis_flange=True, init={"phi": float(q[k]), "w": 0.0, "a": 0.0})
            setattr(self, f"joint{n}", joint)
            self.connect(parent, joint.frame_a)
            fr = self._section(k, joint.frame_b)
            frames.append(fr)
            parent = fr["tip"]

        # ---- hydraulic supply ------------------------------------------------------------------------------
        self.tank = Tank()
        self.pump = PressureCompensatedPump(D_max=PUMP_D, p_set=P_COMP, dp_reg=DP_REG)
        self.pump_speed = Constant(k=PUMP_SPEED)
        self.supply = Volume(V=V_SUPPLY, p_start=P_TANK + P_COMP + DP_REG)
        self.relief = PressureReliefValve(p_crack=record.p_system, p_grad=1e10)
        self.connect(self.pump_speed.y, self.pump.w)
        tank_ports = [self.tank.port, self.pump.port_a, self.relief.port_b]
        supply_ports = [self.pump.port_b, self.supply.port, self.relief.port_a]

        def sources(name: str, k: int, kind: str) -> Any:
            """Reference (``kind="ref"``, rad) or valve command (``"cmd"``) of joint ``name`` as a TimeTable (a
            constant reference a ``Constant``: its value a parameter, so one build serves every start pose)."""
            if kind == "cmd":
                table = TimeTable(t=t_cmd, y=cmd_cols[name])
            elif name in ref_cols:
                table = TimeTable(t=t_ref, y=np.radians(ref_cols[name]))
            else:
                table = Constant(k=float(q0[k]))
            setattr(self, f"{kind}_{name}", table)
            return table.y

        def control(name: str, k: int, valve: DirectionalValve43, K_v: float, sign: float,
                    cylinder: LineCylinder | None = None, areas: tuple[float, float] = (1.0, 1.0)) -> None:
            """Valve command of joint ``name``: open loop, or a PID through the command filter.

            A boom joint (``cylinder`` given) is controlled on its cylinder's length: the angle reference becomes a
            length reference through the record's kinematics (:func:`length_reference`), the loop gain is
            ``OMEGA_C·A_p/Q_nom`` and the crossover ``OMEGA_C`` in every pose (on the angle, the lever arm, which
            falls to a tenth of its maximum near the fold, would raise the crossover onto the oil-spring modes). The
            slewing joint (``cylinder=None``, a constant gear) is controlled on its angle. ``K_v``: the valve's gain,
            rad/s per unit command for the slew, its ``Q_nom`` [m3/s] for a cylinder; ``sign`` +1 if u > 0 raises the
            angle. A cylinder loop gets the reference speed as feed-forward (``areas`` = piston and annulus area
            [m2]: the compensated valve's command for that speed, extending or retracting), so the PI only corrects.
            """
            if name in cmd_cols:
                self.connect(sources(name, k, "cmd"), valve.u)
                return
            kind = {"controller_type": "PID", "Td": T_D} if T_D > 0 else {"controller_type": "PI"}
            if cylinder is None:
                sensor = rotational.AngleSensor()
                setattr(self, f"angle_{name}", sensor)
                self.connect(getattr(self, name).axis, sensor.flange)
                measured, gain = sensor.phi, sign * OMEGA_C / K_v
            else:
                line = LineForce()  # the pin-to-pin line of the cylinder, carrying no force: a length sensor
                sensor = translational.RelativePositionSensor()
                setattr(self, f"stroke_line_{name}", line)
                setattr(self, f"stroke_{name}", sensor)
                self.connect(cylinder.frame_a, line.frame_a)
                self.connect(cylinder.frame_b, line.frame_b)
                self.connect(line.flange_a, sensor.flange_a)
                self.connect(line.flange_b, sensor.flange_b)
                # tared at the start to the record's length in the start pose: a flexible boom's sections start
                # deflected, and the loop must hold them there, not pull the pins to the rigid kinematics
                tare = Tare(y_start=float(record.drive(k).state(float(q0[k])).length))
                setattr(self, f"tare_{name}", tare)
                self.connect(sensor.s_rel, tare.u)
                measured, gain = tare.y, OMEGA_C * areas[0] / K_v
            pid = LimPID(init_type="initial_output", y_start=0.0, k=gain, Ti=T_I, y_max=1.0, y_min=-1.0,
                         use_feed_forward=cylinder is not None, **kind)
            setattr(self, f"pid_{name}", pid)
            if cylinder is None:
                self.connect(sources(name, k, "ref"), pid.u_s)
            else:
                t_L, L_ref = length_reference(record, k, t_ref, ref_cols.get(name), float(q0[k]))
                table = TimeTable(t=t_L, y=L_ref) if len(t_L) > 1 else Constant(k=float(L_ref[0]))
                setattr(self, f"ref_{name}", table)
                self.connect(table.y, pid.u_s)
                speed = np.append(np.diff(L_ref) / np.diff(t_L), 0.0) if len(t_L) > 1 else np.zeros(1)
                ff = (TimeTable(t=t_L, y=speed * np.where(speed > 0, areas[0], areas[1]) * K_v ** -1,
                                smoothness="constant") if len(t_L) > 1 else Constant(k=0.0))
                setattr(self, f"ff_{name}", ff)
                self.connect(ff.y, pid.u_ff)
            self.connect(measured, pid.u_m)
            ramp = FirstOrder(T=T_CMD)
            setattr(self, f"ramp_{name}", ramp)
            self.connect(pid.y, ramp.u)
            self.connect(ramp.y, valve.u)

        # ---- boom cylinders --------------------------------------------------------------------------------
        self.cylinders: list[dict[str, Any]] = []
        for k in range(5):
            n = k + 1
            row = rows[k]
            bore, rod = row["bore"], row["rod"]
            A_p, A_r = math.pi / 4 * bore**2, math.pi / 4 * (bore**2 - rod**2)
            stroke = row["stroke"] + 2 * STOP_MARGIN
            L0 = row["l_min"] - STOP_MARGIN
            F = float(F_hold[k])
            # F = (p_A − p_amb) A_p − (p_B − p_amb) A_r with the free chamber at tank (= ambient) pressure
            p_A, p_B = (P_TANK + F / A_p, P_TANK) if F >= 0 else (P_TANK, P_TANK - F / A_r)
            m_rod = record.steel.rho * math.pi / 4 * rod**2 * (row["l_max"] - row["l_min"])
            cyl = LineCylinder(d_bore=bore, d_rod=rod, stroke=stroke, L0=L0, m=m_rod, d=D_CYL,
                               F_c=CYL_FC * A_p * record.p_system, v_reg=CYL_VREG,
                               V_dead_A=0.1 * A_p * stroke + 1e-4, V_dead_B=0.1 * A_r * stroke + 1e-4,
                               p_fixed=False)
            # the free chamber at tank pressure (initial_equations); the holding chamber's pressure is what holds
            # the joint at rest (its start value the hand statics' guess). Which chamber is free is a parameter,
            # not a fixed start: the build (cache key) stays the same in every pose.
            cyl.cylinder.set_start("p_A", p_A, fixed=False)
            cyl.cylinder.set_start("p_B", p_B, fixed=False)
            setattr(self, f"free_A{n}", fl.Parameter(1.0 if F < 0 else 0.0, unit="1",
                                                      doc=f"1: cylinder {n}'s cap chamber (A) starts at tank "
                                                          "pressure; 0: its rod chamber (B) does"))
            setattr(self, f"cylinder{n}", cyl)
            if n == 1:
                self.connect(self.joint1_housing.frame_b, cyl.frame_a)
                self.connect(frames[0]["C"], cyl.frame_b)
            else:
                self._fourbar(n, frames[k - 1], frames[k], geo, cyl)
            # the chamber holding the extended boom carries the counterbalance valve
            hold = "A" if row["F"] >= 0 else "B"
            arms = [record.drive(n).state(float(qq)).lever_arm
                    for qq in np.linspace(record.drive(n).q_min, record.drive(n).q_max, 37)]
            arm = max(abs(a) for a in arms)
            Q_nom = A_p * arm * W_MAX
            valve = DirectionalValve43(Q_nom=Q_nom, dp_nom=VALVE_DP, omega=2 * math.pi * VALVE_HZ, zeta=0.7,
                                       A_leak=1e-10, compensated=True, dp_comp=VALVE_DP)
            setattr(self, f"valve{n}", valve)
            tank_ports.append(valve.port_T)
            # the cylinder-port cartridges of the valve block: a shock relief valve to tank and an anti-cavitation
            # make-up check valve from tank on each port (what limits the pressure peaks of an emergency stop)
            for side, port in (("A", cyl.port_A), ("B", cyl.port_B)):
                shock = PressureReliefValve(p_crack=SHOCK_FACTOR * record.p_system, p_grad=1e10, G_leak=SHOCK_LEAK)
                makeup = CheckValve(p_crack=MAKEUP_CRACK, p_open=MAKEUP_OPEN, A_max=MAKEUP_AREA)
                setattr(self, f"shock{n}{side}", shock)
                setattr(self, f"makeup{n}{side}", makeup)
                self.connect(port, shock.port_a, makeup.port_b)
                tank_ports += [shock.port_b, makeup.port_a]
            supply_ports.append(valve.port_P)
            # valve port A feeds the cap side: u > 0 extends the cylinder
            hold_port, free_port = (cyl.port_A, cyl.port_B) if hold == "A" else (cyl.port_B, cyl.port_A)
            v_hold, v_free = (valve.port_A, valve.port_B) if hold == "A" else (valve.port_B, valve.port_A)
            free = "B" if hold == "A" else "A"
            cbv, hose = self._counterbalance(1.3 * row[f"p_worst_{hold}"], Q_nom)
            setattr(self, f"cbv{n}", cbv)
            setattr(self, f"hose{n}", hose)
            self.connect(v_hold, hose.port, cbv.port_valve)
            self.connect(cbv.port_load, hold_port)
            if row[f"p_worst_{free}"] > 0:  # the other chamber holds the load once the joint is over centre
                over, over_hose = self._counterbalance(1.3 * row[f"p_worst_{free}"], Q_nom)
                setattr(self, f"cbv{n}_over", over)
                setattr(self, f"hose{n}_over", over_hose)
                self.connect(v_free, over_hose.port, over.port_valve, cbv.port_pilot)
                self.connect(over.port_load, free_port)
                self.connect(over.port_pilot, hose.port)
            else:
                self.connect(v_free, free_port, cbv.port_pilot)
            sign = 1.0 if arms[len(arms) // 2] > 0 else -1.0
            control(f"joint{n}", n, valve, Q_nom, sign, cyl, (A_p, A_r))
            self.cylinders.append({"bore": bore, "rod": rod, "stroke": stroke, "L0": L0, "hold": hold,
                                   "Q_nom": Q_nom})

        if self.slewing:
            self._slew_drive(tank_ports, supply_ports, control)
        self.connect(*tank_ports)
        self.connect(*supply_ports)

    @property
    def q0(self) -> np.ndarray:
        """Start angles [rad] (slew, q1 … q5)."""
        return self._q0.copy()

    @property
    def F_hold(self) -> np.ndarray:
        """Holding forces of the five cylinders at the start, by the hand statics [N] (positive pushes)."""
        return self._F_hold.copy()

    def initial_equations(self) -> list:
        """Each cylinder's free chamber at tank pressure: ``s (p_A − p_T) + (1 − s)(p_B − p_T) = 0``, ``s`` =
        ``free_A{n}`` (1 when the cylinder holds by pulling, its cap chamber free)."""
        out = []
        for n in range(1, 6):
            s, c = getattr(self, f"free_A{n}"), getattr(self, f"cylinder{n}").cylinder
            out.append(fl.eq(s * (c.p_A - P_TANK) + (1 - s) * (c.p_B - P_TANK), 0.0,
                             label=f"cylinder {n}: free chamber at tank pressure"))
        return out

    # ---- building blocks ------------------------------------------------------------------------------------
    @staticmethod
    def _counterbalance(p_crack: float, Q_nom: float) -> tuple[CounterbalanceValve, Volume]:
        """A counterbalance valve set at ``p_crack`` [Pa] for a line of valve rating ``Q_nom`` [m3/s], and the hose
        volume between it and the directional valve."""
        cbv = CounterbalanceValve(p_crack=p_crack, pilot_ratio=PILOT_RATIO, dp_open=CBV_DP_OPEN, dp_check=CBV_DP_CHECK,
                                  smoothing=CBV_SMOOTHING, Q_nom=2 * Q_nom, Q_nom_check=2 * Q_nom, dp_nom=VALVE_DP,
                                  use_dynamics=True, T=CBV_T, A_leak=CBV_A_LEAK, steady_start=True)
        return cbv, Volume(V=V_HOSE, p_start=P_TANK)

    def _slew_drive(self, tank_ports: list, supply_ports: list, control: Any) -> None:
        """Slewing motor, gear, valve and hose volumes driving the slewing revolute's axis; the slew angle under
        ``control``."""
        self.slew_motor = HydraulicMotor(D=SLEW_D)
        self.slew_rotor = rotational.Inertia(J=SLEW_ROTOR_J)
        self.slew_gear = rotational.IdealGear(ratio=SLEW_RATIO)
        self.slew_valve = DirectionalValve43(Q_nom=SLEW_Q, dp_nom=VALVE_DP, omega=2 * math.pi * VALVE_HZ, zeta=0.7,
                                             A_leak=1e-10, compensated=True, dp_comp=VALVE_DP)
        self.slew_line_a = Volume(V=V_HOSE, p_start=P_TANK)
        self.slew_line_b = Volume(V=V_HOSE, p_start=P_TANK)
        self.connect(self.slew_motor.flange, self.slew_rotor.flange_a)
        self.connect(self.slew_rotor.flange_b, self.slew_gear.flange_a)
        self.connect(self.slew_gear.flange_b, self.slew.axis)
        self.connect(self.slew_valve.port_A, self.slew_line_a.port, self.slew_motor.port_a)
        self.connect(self.slew_valve.port_B, self.slew_line_b.port, self.slew_motor.port_b)
        tank_ports.append(self.slew_valve.port_T)
        supply_ports.append(self.slew_valve.port_P)
        control("slew", 0, self.slew_valve, SLEW_Q / SLEW_D / SLEW_RATIO, 1.0)

    def _section(self, k: int, root: Any) -> dict:
        """Section ``k`` (0-based) on the frame ``root``: a rigid Body, or a FlexibleBody (``flexible``).

        Its pins (the record's attachment points in the section frame, independent of the pose: the drive bracket
        ``C`` and, on sections 1–4, the next joint's lever pivot ``P_next`` and cylinder housing ``H_next``) each
        get a frame. Returned: ``root``, ``tip`` and one frame per pin name, the same for both variants.
        """
        from .flexible import PIN_POINTS, attachment_points, flexible_section

        n = k + 1
        sec = self.record.sections[k]
        points = attachment_points(self.record, n)
        pins = {name: [*points[point], 0.0] for name, point in PIN_POINTS.items() if point in points}
        if self.flexible:
            modes = self.modes if isinstance(self.modes, int) else self.modes[n]
            frames = flexible_section(self, n, root, pins, self.record, modes)
            tip = FixedTranslation(r=[0.0, 0.0, 0.0])  # the tip pin under the rigid model's name
            setattr(self, f"section{n}_tip", tip)
            self.connect(frames["tip"], tip.frame_a)
            frames["tip"] = tip.frame_b
            # the tip pin seen from the root pin's frame: r_rel[1] is the section's deflection from its root tangent
            sensor = RelativePosition()
            setattr(self, f"deflection{n}", sensor)
            self.connect(root, sensor.frame_a)
            self.connect(tip.frame_b, sensor.frame_b)
            return frames
        mp = section_mass_properties(self.record, k)
        body = Body(m=mp["m"], r_CM=[float(v) for v in mp["com"]], I=mp["I"])
        setattr(self, f"section{n}", body)
        self.connect(root, body.frame_a)
        frames = {"root": root}
        tip = FixedTranslation(r=[sec.length, 0.0, 0.0])
        setattr(self, f"section{n}_tip", tip)
        self.connect(root, tip.frame_a)
        frames["tip"] = tip.frame_b
        for name, point in pins.items():
            pin = FixedTranslation(r=[float(v) for v in point])
            setattr(self, f"section{n}_{name}", pin)
            self.connect(root, pin.frame_a)
            frames[name] = pin.frame_b
        return frames

    def _fourbar(self, n: int, prev: dict, sec: dict, geo: dict, cyl: LineCylinder) -> None:
        """Lever and link of joint ``n`` (2–5) between section n−1 (``prev``) and n (``sec``); cylinder to T."""
        P, T, C = geo["pins"][f"P{n}"], geo["pins"][f"T{n}"], geo["pins"][f"C{n}"]
        th_prev, th_sec = geo["theta"][n - 2], geo["theta"][n - 1]
        th_lever = math.atan2(T[1] - P[1], T[0] - P[0])
        th_link = math.atan2(C[1] - T[1], C[0] - T[0])
        m_lever, m_link = linkage_masses(self.record, n, self.link_plate)
        r, s = self.record.drive(n).r, self.record.drive(n).s
        lever_joint = Revolute(guess={"phi": th_lever - th_prev})
        lever = link_body(m_lever, r)
        lever_tip = FixedTranslation(r=[r, 0.0, 0.0])
        link_joint = Revolute(guess={"phi": th_link - th_lever})
        link = link_body(m_link, s)
        link_tip = FixedTranslation(r=[s, 0.0, 0.0])
        link_pin = Revolute(guess={"phi": th_sec - th_link})
        for name, comp in (("lever_joint", lever_joint), ("lever", lever), ("lever_tip", lever_tip),
                           ("link_joint", link_joint), ("link", link), ("link_tip", link_tip),
                           ("link_pin", link_pin)):
            setattr(self, f"{name}{n}", comp)
        self.connect(prev["P_next"], lever_joint.frame_a)
        self.connect(lever_joint.frame_b, lever.frame_a, lever_tip.frame_a)
        self.connect(lever_tip.frame_b, link_joint.frame_a, cyl.frame_b)
        self.connect(link_joint.frame_b, link.frame_a, link_tip.frame_a)
        self.connect(link_tip.frame_b, link_pin.frame_a)
        self.connect(link_pin.frame_b, sec["C"])
        self.connect(prev["H_next"], cyl.frame_a)

