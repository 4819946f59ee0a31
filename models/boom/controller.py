"""Joint controllers of a boom: a measurement, a PI(D) with limited output and the valve amplifier's command filter.

Diagram (:class:`JointController`; :class:`AngleController` measures an angle instead, without the tare)::

    frame_a ── line (LineForce, no force) ── frame_b
                 │ flange_a, flange_b
               sensor (RelativePositionSensor) ── tare (Tare) ──> pid.u_m
    u_ref ────────────────────────────────────────────────────────> pid.u_s     pid (LimPID, ±1) ── ramp ──> y
    u_ff ─────────────────────────────────────────────────────────> pid.u_ff                  (FirstOrder T_cmd)
"""

from __future__ import annotations

from typing import Any

import flexlib as fl
from flexlib import Input, Output
from flexlib.components.control import FirstOrder, LimPID, Tare
from flexlib.components.mechanics import rotational, translational
from flexlib.components.mechanics.multibody import LineForce
from flexlib.components.mechanics.multibody.interfaces import Frame
from flexlib.errors import ParameterError

from ._checks import positive, positives

__all__ = ["AngleController", "JointController"]

# defaults: the joint loops of models/pump_truck/model.py (OMEGA_C, T_I, T_CMD)
OMEGA_C = 0.3  # crossover [rad/s]: below the boom's 5-6 Hz oil-spring modes
T_I = 2.0  # integral time [s]
T_CMD = 0.16  # valve amplifier command filter [s]


class _Loop(fl.Model):
    """The shared loop: ``pid`` (:class:`~flexlib.components.control.LimPID`, PI or PID, output ±1, started at
    output 0) and ``ramp`` (:class:`~flexlib.components.control.FirstOrder`) between ``u_ref``/``u_ff`` and ``y``;
    a subclass provides the measurement."""

    def _close(self, part: str, measured: Any, k: float, Ti: float, Td: float, T_cmd: float, unit: str,
               feed_forward: bool) -> None:
        Ti, T_cmd = positives(part, Ti=(Ti, "s"), T_cmd=(T_cmd, "s"))
        Td = positive(part, "Td", Td, "s", allow_zero=True)
        kind = {"controller_type": "PID", "Td": Td} if Td > 0 else {"controller_type": "PI"}
        self.u_ref = Input(unit=unit, doc="Reference")
        self.y = Output(unit="1", doc="Valve command, -1 ... 1")
        self.pid = LimPID(init_type="initial_output", y_start=0.0, k=k, Ti=Ti, y_max=1.0, y_min=-1.0,
                          use_feed_forward=feed_forward, **kind)
        self.ramp = FirstOrder(T=T_cmd)
        self.connect(self.u_ref, self.pid.u_s)
        self.connect(measured, self.pid.u_m)
        self.connect(self.pid.y, self.ramp.u)
        self.connect(self.ramp.y, self.y)
        if feed_forward:
            self.u_ff = Input(unit="1", doc="Feed-forward valve command (added before the limiter)")
            self.connect(self.u_ff, self.pid.u_ff)


class JointController(_Loop):
    """Length loop of one cylinder-driven boom joint: pin-to-pin length sensor, tare, PI, command filter.

    Contains ``line`` (a :class:`~flexlib.components.mechanics.multibody.LineForce` between the cylinder's pins,
    carrying no force) with ``sensor`` (:class:`~flexlib.components.mechanics.translational.RelativePositionSensor`)
    on its flanges: the pin-to-pin length; ``tare`` (:class:`~flexlib.components.control.Tare`) re-zeroing it to
    ``L_start`` at the start (a deflected flexible boom is held where it starts, not pulled to the rigid kinematics);
    ``pid`` (:class:`~flexlib.components.control.LimPID`: PI, or PID with ``Td > 0``; output limited to ±1; started at
    output 0) with the feed-forward input; ``ramp`` (:class:`~flexlib.components.control.FirstOrder`, ``T_cmd``: the
    valve amplifier's command ramp, which keeps the loop off the boom's oil-spring modes).

    Gain ``k = omega_c·A_p/Q_nom``: with a compensated valve the cylinder speed is ``(Q_nom/A_p)·u`` (extending), so
    the loop ``L(s) = omega_c·(1 + 1/(Ti·s))/(s·(1 + T_cmd·s))`` has its proportional asymptote ``omega_c/ω`` cross 1
    at ``omega_c`` in every pose (on the joint angle the lever arm would move it tenfold).

    Parameters
    ----------
    omega_c : float
        Crossover of the proportional part [rad/s] (default 0.3).
    A_p : float
        Piston area [m2].
    Q_nom : float
        Valve rating [m3/s]: the flow at full command.
    L_start : float
        Pin-to-pin length read at the start [m] (the design record's length in the start pose).
    Ti : float
        Integral time [s] (default 2).
    T_cmd : float
        Command filter time constant [s] (default 0.16).
    Td : float
        Derivative time [s] (default 0: PI).

    Connectors
    ----------
    frame_a, frame_b : multibody Frame
        The cylinder's pins (housing, rod end).
    u_ref : Input [m]
        Length reference.
    u_ff : Input [1]
        Feed-forward valve command (e.g. ``A·dL_ref/dt / Q_nom``; 0 for none).
    y : Output [1]
        Valve command.

    References
    ----------
    Modelica Standard Library 4.0, ``Blocks.Continuous.LimPID``; K. J. Åström, T. Hägglund, *PID Controllers*,
    ISA 1995; H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §8 (valve-controlled cylinder as an
    integrator). Values: :mod:`models.pump_truck.model` (its joint loops).
    """

    def __init__(self, A_p: float, Q_nom: float, L_start: float, omega_c: float = OMEGA_C, Ti: float = T_I,
                 T_cmd: float = T_CMD, Td: float = 0.0, **kw: Any) -> None:
        super().__init__(**kw)
        part = "JointController"
        A_p, Q_nom, omega_c, L_start = positives(part, A_p=(A_p, "m2"), Q_nom=(Q_nom, "m3/s"),
                                                 omega_c=(omega_c, "rad/s"), L_start=(L_start, "m"))
        self.frame_a = Frame(doc="Cylinder housing pin")
        self.frame_b = Frame(doc="Cylinder rod-end pin")
        self.line = LineForce()  # the pin-to-pin line, carrying no force: a length sensor
        self.sensor = translational.RelativePositionSensor()
        self.tare = Tare(y_start=L_start)
        self.connect(self.frame_a, self.line.frame_a)
        self.connect(self.frame_b, self.line.frame_b)
        self.connect(self.line.flange_a, self.sensor.flange_a)
        self.connect(self.line.flange_b, self.sensor.flange_b)
        self.connect(self.sensor.s_rel, self.tare.u)
        self._close(part, self.tare.y, omega_c * A_p / Q_nom, Ti, Td, T_cmd, "m", True)


class AngleController(_Loop):
    """Angle loop of a motor-driven joint (the slew): angle sensor, PI, command filter.

    Contains ``sensor`` (:class:`~flexlib.components.mechanics.rotational.AngleSensor` on ``flange``) and the same
    ``pid`` and ``ramp`` as :class:`JointController`. Gain ``k = sign·omega_c/K_v``: ``K_v`` is the joint speed at
    full command (a compensated valve and a constant gear make it a constant), so the proportional asymptote of the
    loop crosses 1 at ``omega_c``.

    Parameters
    ----------
    K_v : float
        Joint speed at full valve command [rad/s].
    omega_c : float
        Crossover of the proportional part [rad/s] (default 0.3).
    sign : float
        +1 if a positive command turns the joint positively, −1 otherwise.
    Ti, T_cmd, Td : float
        Integral time, command filter, derivative time [s] (defaults 2, 0.16, 0).
    use_feed_forward : bool
        True (default) for the input ``u_ff``.

    Connectors
    ----------
    flange : rotational Flange
        The joint's axis (measured, no torque).
    u_ref : Input [rad]
        Angle reference.
    u_ff : Input [1]
        Feed-forward valve command (``dq_ref/dt / K_v``; only with ``use_feed_forward``).
    y : Output [1]
        Valve command.
    """

    def __init__(self, K_v: float, omega_c: float = OMEGA_C, sign: float = 1.0, Ti: float = T_I,
                 T_cmd: float = T_CMD, Td: float = 0.0, use_feed_forward: bool = True, **kw: Any) -> None:
        super().__init__(**kw)
        part = "AngleController"
        K_v, omega_c = positives(part, K_v=(K_v, "rad/s"), omega_c=(omega_c, "rad/s"))
        if sign not in (1, -1):
            raise ParameterError(f"{part}: sign must be +1 or -1, got {sign!r}")
        if not isinstance(use_feed_forward, bool):
            raise ParameterError(f"{part}: use_feed_forward must be True or False, got {use_feed_forward!r}")
        self.flange = rotational.Flange(doc="Joint axis (measured)")
        self.sensor = rotational.AngleSensor()
        self.connect(self.flange, self.sensor.flange)
        self._close(part, self.sensor.phi, float(sign) * omega_c / K_v, Ti, Td, T_cmd, "rad", use_feed_forward)
