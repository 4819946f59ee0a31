"""Stick/slip friction (``SupportFriction``, ``Brake``, ``BearingFriction``, ``Clutch``) against closed-form motions.

A mass ``m`` on a support with a constant sliding force ``f0`` and breakaway force ``f0_max = peak f0`` under a force
``F(t)``: stuck while ``|F| ≤ f0_max`` (speed exactly zero: the path parameter holds the acceleration at zero), sliding
from the instant ``F = f0_max`` with ``m a = F − f0``, stuck again where the speed reaches zero. The MSL examples that
use these elements are compared with the Modelica Association's reference results in ``tests/msl``.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Ramp
from flexlib.components.mechanics.rotational import BearingFriction, Clutch, ConstantTorque, Inertia
from flexlib.components.mechanics.translational import Brake, ConstantForce, Force, Mass, SupportFriction

TOL = {"rtol": 1e-8, "atol": 1e-10}


class Block(fl.Model):
    """A 1 kg block on a support with 10 N sliding friction and 15 N breakaway, pushed by the input ``force``."""

    def __init__(self, force: fl.Component, v0: float = 0.0) -> None:
        super().__init__()
        self.source = force
        self.push = Force()
        self.block = Mass(m=1.0, init={"s": 0.0, "v": v0})
        self.friction = SupportFriction(f_pos=[[0.0, 10.0]], peak=1.5)
        self.connect(self.source.y, self.push.f)
        self.connect(self.push.flange, self.block.flange_a)
        self.connect(self.block.flange_b, self.friction.flange_a)


def test_sticking_is_exact_below_breakaway():
    """A 14 N push against 15 N breakaway for 10 s: the block moves less than 1e-12 m (issue 31), its speed stays
    exactly zero and the friction force is the push."""
    res = fl.Simulation(Block(Constant(k=14.0))).run(10.0, dt_out=0.5, progress=False, **TOL)
    assert np.max(np.abs(res["block.s"])) < 1e-12
    assert np.max(np.abs(res["block.v"])) == 0.0
    np.testing.assert_allclose(res["friction.f"], 14.0, rtol=1e-12)
    assert np.all(res["friction.mode"] == 0) and np.all(res["friction.locked"] == 1)


def test_breakaway_at_the_breakaway_force_then_sliding_as_closed_form():
    """A push rising 10 N/s from 0: stuck until it reaches 15 N at 1.5 s (the start-forward event within 1e-7 s),
    then ``a = F − 10 N``: ``v(t) = 5 (t² − 2.25) − 10 (t − 1.5)``, 18.75 m/s at 3 s (rtol 1e-6)."""
    res = fl.Simulation(Block(Ramp(height=30.0, duration=3.0))).run(3.0, dt_out=0.01, progress=False, **TOL)
    t_start = res.t[np.argmax(res["friction.start_forward"] > 0.5)]
    assert abs(t_start - 1.5) < 1e-7
    assert np.max(np.abs(res["block.v"][res.t < 1.5 - 1e-6])) == 0.0
    t = res.t[res.t > 1.6]
    np.testing.assert_allclose(res["block.v"][res.t > 1.6], 5 * (t**2 - 2.25) - 10 * (t - 1.5), rtol=1e-6)
    assert res["friction.mode"][-1] == 1


def test_sliding_block_stops_and_stays():
    """Started at 2 m/s with no push: ``a = −10 m/s²`` until it stops at 0.2 s after 0.2 m (within 1e-9 s and 1e-9 m),
    then stuck; the speed is held where the stop event left it (to round-off, below 1e-12 m/s)."""
    res = fl.Simulation(Block(Constant(k=0.0), v0=2.0)).run(1.0, dt_out=0.01, progress=False, **TOL)
    stuck = res.t > 0.2 + 1e-6
    t_stop = res.t[np.argmax(res["friction.mode"] == 0)]
    assert abs(t_stop - 0.2) < 1e-9
    np.testing.assert_allclose(res["block.s"][stuck], 0.2, atol=1e-9)
    assert np.ptp(res["block.v"][stuck]) == 0.0 and abs(res["block.v"][-1]) < 1e-12


def test_brake_released_is_free_and_engaged_stops():
    """A brake of zero normal force is free (mode 2, no force: the block keeps its speed); engaged at 20 N normal force
    and mu 0.5 it decelerates a 1 kg block at 10 m/s² from 1 m/s and stops it at 0.1 s."""

    class Braked(fl.Model):
        def __init__(self, f_normalized: float) -> None:
            super().__init__()
            self.block = Mass(m=1.0, init={"s": 0.0, "v": 1.0})
            self.brake = Brake(fn_max=20.0)
            self.pedal = Constant(k=f_normalized)
            self.connect(self.block.flange_b, self.brake.flange_a)
            self.connect(self.pedal.y, self.brake.f_normalized)

    free = fl.Simulation(Braked(0.0)).run(0.5, dt_out=0.05, progress=False, **TOL)
    np.testing.assert_allclose(free["block.v"], 1.0, rtol=1e-12)
    assert np.all(free["brake.mode"] == 2) and np.all(free["brake.f"] == 0.0)
    braked = fl.Simulation(Braked(1.0)).run(0.5, dt_out=0.01, progress=False, **TOL)
    t_stop = braked.t[np.argmax(braked["brake.mode"] == 0)]
    assert abs(t_stop - 0.1) < 1e-9
    np.testing.assert_allclose(braked["block.s"][-1], 0.05, atol=1e-9)


def test_bearing_friction_holds_a_torque_below_breakaway_and_clutch_couples():
    """Rotational: a bearing with 2 N m breakaway holds 1.9 N m exactly; a clutch (mu 0.5, 10 N, cgeo 1 m: 5 N m)
    between a spinning and a resting inertia (1 kg m² each) slips at ±5 N m until both turn at the mean speed, at
    ``t = J Δw / (2 · 5 N m)`` = 0.4 s for Δw = 4 rad/s, then sticks."""

    class Held(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.load = ConstantTorque(tau_constant=1.9)
            self.disc = Inertia(J=1.0, init={"phi": 0.0, "w": 0.0})
            self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]], peak=2.0)
            self.connect(self.load.flange, self.disc.flange_a)
            self.connect(self.disc.flange_b, self.bearing.flange_a)

    held = fl.Simulation(Held()).run(5.0, dt_out=0.5, progress=False, **TOL)
    assert np.max(np.abs(held["disc.phi"])) == 0.0
    np.testing.assert_allclose(held["bearing.tau"], 1.9, rtol=1e-12)

    class Coupled(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.a = Inertia(J=1.0, init={"phi": 0.0, "w": 4.0})
            self.b = Inertia(J=1.0, init={"phi": 0.0, "w": 0.0})
            self.clutch = Clutch(fn_max=10.0)
            self.pedal = Constant(k=1.0)
            self.connect(self.a.flange_b, self.clutch.flange_a)
            self.connect(self.clutch.flange_b, self.b.flange_a)
            self.connect(self.pedal.y, self.clutch.f_normalized)

    res = fl.Simulation(Coupled()).run(1.0, dt_out=0.01, progress=False, **TOL)
    t_stick = res.t[np.argmax(res["clutch.mode"] == 0)]
    assert abs(t_stick - 0.4) < 1e-9
    late = res.t > 0.41
    np.testing.assert_allclose(res["a.w"][late], 2.0, rtol=1e-9)
    np.testing.assert_allclose(res["b.w"][late], 2.0, rtol=1e-9)


@pytest.mark.parametrize("table, message", [
    ([[0.0, 1.0], [0.0, 2.0]], "strictly increasing"),
    ([[-1.0, 1.0], [1.0, 2.0]], "≥ 0"),
    ([1.0, 2.0, 3.0], "shape"),
    ([[0.0, "a"]], "SupportFriction: f_pos"),
])
def test_bad_friction_table_is_refused_naming_the_component(table, message):
    """A table whose speeds are not rising from zero, or not of rows [v, f], is refused with the component's class
    and the parameter named."""
    with pytest.raises(fl.ParameterError, match=message):
        SupportFriction(f_pos=table)


def test_constant_force_block_breaks_away_at_once():
    """A 20 N constant push (above the 15 N breakaway) from rest: sliding from the start with ``a = 10 m/s²``."""

    class Pushed(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.push = ConstantForce(f_constant=20.0)
            self.block = Mass(m=1.0, init={"s": 0.0, "v": 0.0})
            self.friction = SupportFriction(f_pos=[[0.0, 10.0]], peak=1.5)
            self.connect(self.push.flange, self.block.flange_a)
            self.connect(self.block.flange_b, self.friction.flange_a)

    res = fl.Simulation(Pushed()).run(1.0, dt_out=0.1, progress=False, **TOL)
    np.testing.assert_allclose(res["block.v"][-1], 10.0, rtol=1e-8)


class TwoSurfaces(fl.Model):
    """A 1 kg block sliding at 0.1 m/s on two friction surfaces (10 N and 6 N Coulomb, no breakaway peak), pushed by
    a force rising 8 N/s from 0: it stops, both surfaces stick at once, and which of them holds how much is not
    determined by the model."""

    def __init__(self) -> None:
        super().__init__()
        self.source = Ramp(height=24.0, duration=3.0)
        self.push = Force()
        self.block = Mass(m=1.0, init={"s": 0.0, "v": 0.1})
        self.surface1 = SupportFriction(f_pos=[[0.0, 10.0]])
        self.surface2 = SupportFriction(f_pos=[[0.0, 6.0]])
        self.connect(self.source.y, self.push.f)
        self.connect(self.push.flange, self.block.flange_a)
        self.connect(self.block.flange_b, self.surface1.flange_a)
        self.connect(self.surface1.flange_b, self.surface2.flange_a)


def test_two_surfaces_stuck_together_hold_until_the_push_exceeds_both():
    """``a = F − 16 N`` while sliding: the block stops where ``0.1 + 4 t² − 16 t = 0`` (t₁ = 6.2647e-3 s), both
    surfaces stick there and their split of the holding force is indeterminate (the integrator cannot step from the
    event: one surface is put at its sliding force, the other holds the rest). Whatever the split, the block stays
    exactly where it stopped until the push exceeds both surfaces together, ``F = 16 N`` at 2 s (within 1e-6 s), and
    then slides with ``v = 4 (t − 2)²``; each surface's force stays within its limit while stuck."""
    res = fl.Simulation(TwoSurfaces()).run(3.0, dt_out=0.01, progress=False, **TOL)
    t1 = (16.0 - np.sqrt(16.0**2 - 4 * 4.0 * 0.1)) / 8.0
    x1 = 0.1 * t1 + 4.0 / 3.0 * t1**3 - 8.0 * t1**2
    assert [text for _, text in res.events if text.startswith("indeterminate split")], res.events
    held = (res.t > t1 + 1e-6) & (res.t < 2.0 - 1e-6)
    assert np.max(np.abs(res["block.s"][held] - x1)) < 1e-9
    assert np.max(np.abs(res["block.v"][held])) < 1e-12
    assert np.all(np.abs(res["surface1.f"][held]) <= 10.0 + 1e-9)
    assert np.all(np.abs(res["surface2.f"][held]) <= 6.0 + 1e-9)
    # together they hold the push (1e-6 N: within the 2e-8 s between an element's breakaway and the other taking over)
    np.testing.assert_allclose(res["surface1.f"][held] + res["surface2.f"][held], 8.0 * res.t[held], rtol=0, atol=1e-6)
    moving = res.t > 2.0 + 1e-6
    starts = [t for t, text in res.events if t > 1.0]
    assert starts and abs(starts[0] - 2.0) < 1e-6, res.events
    t = res.t[moving]
    np.testing.assert_allclose(res["block.v"][moving], 4.0 * (t - 2.0) ** 2, rtol=1e-6, atol=1e-9)
    assert res.stats["state_events"] < 10, res.stats
