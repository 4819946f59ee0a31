"""Tests of the math blocks (``Gain``, ``Add``, ``Feedback``) against their defining equations.

Reference: ``Modelica.Blocks.Math`` (MSL 4.0): y = k u, y = k1 u1 + k2 u2, y = u1 − u2.
Block outputs are algebraic unknowns of the DAE, which IDA interpolates between its steps, so
they match their formulas to the integration tolerance: 1e-7 absolute at rtol = 1e-8.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Add, Constant, Feedback, Gain, Sine


class Chain(fl.Model):
    """sine → gain → add(+ constant) → feedback(− sine)."""

    def __init__(self) -> None:
        super().__init__()
        self.sine = Sine(amplitude=2.0, f=1.0)
        self.constant = Constant(k=0.7)
        self.gain = Gain(k=-3.0)
        self.add = Add(k1=0.5, k2=4.0)
        self.feedback = Feedback()
        self.connect(self.sine.y, self.gain.u, self.feedback.u2)
        self.connect(self.gain.y, self.add.u1)
        self.connect(self.constant.y, self.add.u2)
        self.connect(self.add.y, self.feedback.u1)


def test_gain_add_feedback():
    """Each block output equals its formula applied to the upstream signals."""
    res = fl.Simulation(Chain(), use_cache=False).run(1.0, dt_out=0.05, rtol=1e-8, atol=1e-10)
    u = 2.0 * np.sin(2 * np.pi * res.t)
    np.testing.assert_allclose(res["sine.y"], u, rtol=0, atol=1e-7)
    np.testing.assert_allclose(res["gain.y"], -3.0 * u, rtol=0, atol=1e-7)
    np.testing.assert_allclose(res["add.y"], 0.5 * (-3.0 * u) + 4.0 * 0.7, rtol=0, atol=1e-7)
    np.testing.assert_allclose(res["feedback.y"], 0.5 * (-3.0 * u) + 2.8 - u, rtol=0, atol=1e-7)


def test_unconnected_input_is_reported():
    """Bad input: an unconnected block input is an error naming the input."""

    class Open(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.constant = Constant(k=1.0)
            self.feedback = Feedback()
            self.connect(self.constant.y, self.feedback.u1)

    with pytest.raises(fl.ModelError, match=r"feedback\.u2"):
        fl.Simulation(Open(), use_cache=False)


def test_two_outputs_cannot_be_connected():
    """Bad input: connecting two outputs is a ConnectError naming both."""
    model = fl.Model()
    model.a = Constant(k=1.0)
    model.b = Constant(k=2.0)
    with pytest.raises(fl.ConnectError, match=r"a\.y.*b\.y"):
        model.connect(model.a.y, model.b.y)


def test_tare_rezeroes_its_input_at_the_start():
    """Tare: y = u − u(t0) + y_start with u = 0.7 + 2 sin(2π t) from t0 = 0.3 s: y(t) = 2 (sin 2πt − sin 0.6π) + 5.
    The start value is held by a state (der(u0) = 0), so it also holds for a start the initialisation computes."""
    from flexlib.components.control import Tare

    class Tared(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.sine = Sine(amplitude=2.0, f=1.0, offset=0.7)
            self.tare = Tare(y_start=5.0)
            self.connect(self.sine.y, self.tare.u)

    res = fl.Simulation(Tared()).run(2.0, t_start=0.3, dt_out=0.01, rtol=1e-8, atol=1e-10, progress=False)
    expected = 2.0 * (np.sin(2 * np.pi * res.t) - np.sin(2 * np.pi * 0.3)) + 5.0
    np.testing.assert_allclose(res["tare.y"], expected, atol=1e-7)
    assert res["tare.y"][0] == pytest.approx(5.0, abs=1e-12)


def test_trim_finds_the_holding_torque_at_the_start():
    """Trim: y = u + b, b constant and found by the initialisation. An inertia J = 0.5 kg.m2 loaded by −3 N.m,
    driven by a torque source fed by Trim(u = step of 1 N.m at 0.5 s), starts at rest and not accelerating: the
    trim is the holding torque b = 3 N.m (the guess 2 N.m is corrected), and after the step the inertia
    accelerates at 1/J = 2 rad/s2: φ(t) = (t − 0.5)² for t > 0.5 s."""
    from flexlib.components.control import Step, Trim
    from flexlib.components.mechanics.rotational import Inertia, Torque

    class Held(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.load = Torque()
            self.load_value = Constant(k=-3.0)
            self.motor = Torque()
            self.step = Step(height=1.0, start_time=0.5)
            self.trim = Trim(guess={"b": 2.0})
            self.inertia = Inertia(J=0.5, init={"phi": 0.0, "w": 0.0, "a": 0.0})
            self.connect(self.load_value.y, self.load.tau)
            self.connect(self.step.y, self.trim.u)
            self.connect(self.trim.y, self.motor.tau)
            self.connect(self.load.flange, self.motor.flange, self.inertia.flange_a)

    res = fl.Simulation(Held()).run(1.0, dt_out=0.01, rtol=1e-9, atol=1e-11, progress=False)
    assert res["trim.b"][0] == pytest.approx(3.0, abs=1e-9)
    assert np.ptp(res["trim.b"]) < 1e-12
    t = res.t
    np.testing.assert_allclose(res["inertia.phi"], np.where(t > 0.5, (t - 0.5) ** 2, 0.0), atol=1e-7)
