"""Bench tests of :class:`flexlib.models.boom.JointController` and :class:`~flexlib.models.boom.AngleController`.

Plant: an ideal valve-controlled cylinder, an integrator — the valve command ``u`` sets the speed ``(Q_nom/A_p)·u``
of a prismatic joint (a translational ``Speed`` source on its axis) whose pins the controller measures (for the
angle loop: ``K_v·u`` into a rotational ``Speed`` source).

References:

* loop transfer function (closed form): ``L(s) = k·(1 + 1/(Ti s))·1/(1 + T_cmd s)·(Q_nom/A_p)/s`` with
  ``k = omega_c·A_p/Q_nom``, i.e. ``L(s) = omega_c (1 + 1/(Ti s))/(s (1 + T_cmd s))``: its proportional asymptote
  ``omega_c/ω`` crosses 1 at ``omega_c`` whatever ``A_p`` and ``Q_nom`` (for Ti = 2 s, T_cmd = 0.16 s the full
  ``|L|`` crosses 1 at 0.448 rad/s). Measured: the closed loop ``T = y/u_ref`` from :func:`flexlib.linearize` at
  rest, ``L = T/(1 − T)`` (unity feedback, set-point weight 1); tolerance 1e-6 relative at 0.05 … 3 rad/s
  (measured 1e-14).
* ramp with feed-forward: a reference with a long constant-speed part and the feed-forward ``A_p/Q_nom·dL/dt``;
  type-1 plant plus integral action plus exact feed-forward: the error and the PI part of the command
  (``pid.y − u_ff``) decay to zero during the cruise, with the closed loop's slowest poles (roots of
  ``T_cmd s³ + s² + omega_c s + omega_c/Ti``: −0.144 ± 0.369j). Tolerance: at the end of a 40 s cruise both below
  3× the envelope ``T_cmd·v·exp(Re(p)·t_cruise)`` (≈ 3e-3 of the lag ``T_cmd·v`` the filter alone would leave;
  measured 1.1× and 0.63× the envelope; largest error 0.87 × T_cmd·v during the acceleration).
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Gain
from flexlib.components.mechanics import rotational, translational
from flexlib.components.mechanics.multibody import Prismatic, World
from flexlib.errors import ParameterError
from flexlib.models.boom import AngleController, JointController, SmoothReference

A_P, Q_NOM, L0, OMEGA_C, TI, T_CMD = 0.02, 2e-3, 1.5, 0.3, 2.0, 0.16
TOL = {"rtol": 1e-9, "atol": 1e-11}


class CylinderBench(fl.Model):
    """JointController around an ideal valve-controlled cylinder; reference constant (``ref.k``) or a profile."""

    def __init__(self, reference: SmoothReference | None = None) -> None:
        super().__init__()
        self.world = World()
        self.pin = Prismatic(n=[1, 0, 0], use_axis_flange=True, init={"s": L0})
        self.speed = translational.Speed()
        self.valve = Gain(k=Q_NOM / A_P)
        self.loop = JointController(A_p=A_P, Q_nom=Q_NOM, L_start=L0, omega_c=OMEGA_C, Ti=TI, T_cmd=T_CMD)
        self.connect(self.world.frame_b, self.pin.frame_a, self.loop.frame_a)
        self.connect(self.pin.frame_b, self.loop.frame_b)
        self.connect(self.speed.flange, self.pin.axis)
        self.connect(self.loop.y, self.valve.u)
        self.connect(self.valve.y, self.speed.v_ref)
        if reference is None:
            self.ref, self.ff = Constant(k=L0), Constant(k=0.0)
            self.connect(self.ref.y, self.loop.u_ref)
            self.connect(self.ff.y, self.loop.u_ff)
        else:
            self.ref = reference
            self.connect(self.ref.y, self.loop.u_ref)
            self.connect(self.ref.ff, self.loop.u_ff)


class SlewBench(fl.Model):
    """AngleController around an ideal motor drive: joint speed ``K_v·u``."""

    def __init__(self, K_v: float) -> None:
        super().__init__()
        self.speed = rotational.Speed(init={"phi": 0.0})
        self.valve = Gain(k=K_v)
        self.loop = AngleController(K_v=K_v, omega_c=OMEGA_C, Ti=TI, T_cmd=T_CMD)
        self.ref, self.ff = Constant(k=0.0), Constant(k=0.0)
        self.connect(self.speed.flange, self.loop.flange)
        self.connect(self.loop.y, self.valve.u)
        self.connect(self.valve.y, self.speed.w_ref)
        self.connect(self.ref.y, self.loop.u_ref)
        self.connect(self.ff.y, self.loop.u_ff)


def loop_exact(w: np.ndarray) -> np.ndarray:
    s = 1j * w
    return OMEGA_C * (1 + 1 / (TI * s)) / (s * (1 + T_CMD * s))


W = np.array([0.05, 0.1, OMEGA_C, 1.0, 3.0])


@pytest.mark.parametrize(("bench", "output"), [(CylinderBench, "loop.tare.y"), (SlewBench, "loop.sensor.phi")])
def test_loop_transfer_function(bench, output):
    model = bench() if bench is CylinderBench else bench(K_v=0.175)
    lin = fl.linearize(model, inputs=["ref.k"], outputs=[output])
    T = lin.frequency_response(W / (2 * np.pi), "ref.k", output).ravel()
    L = T / (1 - T)
    assert np.max(np.abs(L / loop_exact(W) - 1)) < 1e-6
    assert abs(abs(OMEGA_C / (1j * OMEGA_C)) - 1) < 1e-15  # the proportional asymptote crosses 1 at omega_c


@pytest.fixture(scope="module")
def ramp_run():
    v, a = 0.01, 0.02
    ref = SmoothReference.from_moves(L0, [(1.0, L0 + 0.42, v, a)], ff_gain=(A_P / Q_NOM, A_P / Q_NOM))
    res = fl.Simulation(CylinderBench(ref), use_cache=False).run(45.0, dt_out=0.05, **TOL)
    return ref, res, v


def test_ramp_followed_with_feed_forward(ramp_run):
    ref, res, v = ramp_run
    t = res["time"]
    t_end_cruise = ref.knots[0][2]
    assert t_end_cruise > 40.0
    k = np.searchsorted(t, t_end_cruise - 0.01)
    error = res["loop.pid.control_error"]
    pi_part = res["loop.pid.y"] - res["loop.pid.u_ff"]
    lag = T_CMD * v  # the filter's lag alone
    sigma = max(np.roots([T_CMD, 1.0, OMEGA_C, OMEGA_C / TI]).real)
    envelope = lag * np.exp(sigma * (t_end_cruise - ref.knots[0][1]))
    assert envelope < 1e-2 * lag
    assert abs(error[k]) < 3 * envelope
    assert abs(pi_part[k]) < 3 * envelope * OMEGA_C * A_P / Q_NOM
    assert np.max(np.abs(error)) < 2 * lag  # the transient: never more than twice the open-loop lag


@pytest.mark.parametrize(("kw", "arg"), [({"A_p": 0.0}, "A_p"), ({"Q_nom": -1.0}, "Q_nom"), ({"Ti": 0.0}, "Ti"),
                                          ({"omega_c": float("inf")}, "omega_c"), ({"L_start": None}, "L_start"),
                                          ({"Td": -0.1}, "Td")])
def test_joint_controller_bad_arguments(kw, arg):
    with pytest.raises(ParameterError, match=rf"JointController: {arg} must"):
        JointController(**{"A_p": A_P, "Q_nom": Q_NOM, "L_start": L0, **kw})


@pytest.mark.parametrize(("kw", "arg"), [({"K_v": 0.0}, "K_v"), ({"sign": 0.5}, "sign"), ({"T_cmd": -1.0}, "T_cmd"),
                                          ({"use_feed_forward": "yes"}, "use_feed_forward")])
def test_angle_controller_bad_arguments(kw, arg):
    with pytest.raises(ParameterError, match=rf"AngleController: {arg} must"):
        AngleController(**{"K_v": 0.1, **kw})
