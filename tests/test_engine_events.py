"""Time and state events (Modelica event semantics), checked against closed-form solutions."""

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import Variable, der, eq, if_else
from flexlib.models.reference.events import BangBang, BouncingContact, SaturatedRamp, Thermostat


@pytest.mark.parametrize("solver", [None, "ida-native"], ids=["default", "ida-native"])
def test_time_events_hit_exactly(solver):
    """Event times equal the switching parameters to 1e-12; w(t) piecewise linear (exact to 1e-9): with the
    default solver and with the C driver (``solver="ida-native"``) named."""
    named = {} if solver is None else {"solver": solver, "progress": False}
    res = fl.Simulation(BangBang(init={"w": 0.0}), use_cache=False).run(4.0, dt_out=0.5, rtol=1e-8, atol=1e-10,
                                                                        **named)
    times = [t for t, text in res.events if text.startswith("time event")]
    np.testing.assert_allclose(times, [1.0, 2.5], atol=1e-12)
    assert res.stats["time_events"] == 2
    w_exact = np.piecewise(res.t, [res.t < 1.0, (res.t >= 1.0) & (res.t < 2.5), res.t >= 2.5],
                           [lambda t: t / 2, lambda t: 0.5 - (t - 1) / 2, lambda t: -0.25 + (t - 2.5) / 2])
    np.testing.assert_allclose(res["w"], w_exact, atol=1e-9)
    # left and right values are both stored at an event
    k = np.flatnonzero(res.t == 1.0)
    assert len(k) >= 2 and set(np.round(res["tau"][k], 12)) == {1.0, -1.0}


def test_time_event_parameter_change_moves_event():
    """The switching time is a run-time parameter: a new value moves the event without recompiling."""
    sim = fl.Simulation(BangBang(init={"w": 0.0}), use_cache=False)
    res = sim.run(4.0, dt_out=1.0, params={"t1": 0.75})
    times = [t for t, _ in res.events]
    np.testing.assert_allclose(times, [0.75, 2.5], atol=1e-12)


def test_state_event_located():
    """First contact at t = sqrt(2 h0 / g) (free fall) located to 1e-8; the ball bounces back up."""
    h0 = 1.0
    res = fl.Simulation(BouncingContact(init={"h": h0, "v": 0.0}), use_cache=False).run(
        1.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    first = res.events[0][0]
    assert abs(first - np.sqrt(2 * h0 / 9.81)) <= 1e-8
    assert res.stats["state_events"] >= 2  # contact and lift-off
    assert res["h"].min() < 0 and res["v"][res.t > first].max() > 4.0  # in contact, then bouncing up again
    # contact force is zero in flight and positive in contact (the branch is frozen between events)
    assert np.all(res["fc"][res["h"] > 1e-9] == 0.0)


def test_event_reinitialisation_and_chattering():
    """First switch at t = 2 ln 2 (T = 300 − 10·exp(−t/2) reaches 295), 1e-8; states continuous across it.
    Afterwards the relation re-crosses at once (a sliding mode, dT/dt < 0 when off, > 0 when on): the
    run stops with a clear chattering error that names the relation and keeps the result."""
    sim = fl.Simulation(Thermostat(init={"T": 290.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"event chattering at t = 1\.386.*Thermostat: T < 295") as err:
        sim.run(3.0, dt_out=0.1, rtol=1e-12, atol=1e-10)
    res = err.value.result
    t_event = res.events[0][0]
    assert abs(t_event - 2 * np.log(2)) <= 1e-8
    k = np.flatnonzero(res.t == t_event)
    assert len(k) >= 2 and np.ptp(res["T"][k]) == 0.0
    assert set(res["q"][k]) == {0.0, 10.0}


def test_output_grid_kept_after_state_event():
    """A state event inside a long step does not drop or reorder grid points."""
    res = fl.Simulation(BouncingContact(init={"h": 1.0, "v": 0.0}), use_cache=False).run(1.0, dt_out=0.01)
    assert np.all(np.diff(res.t) >= 0)
    grid = np.round(np.linspace(0, 1, 101), 12)
    assert set(grid) <= set(np.round(res.t, 12))


def test_state_event_coinciding_with_time_event():
    """A state event found exactly at a time event does not hide the time event (it used to leave the next
    stop time equal to the current time and IDA refused to start). x(1) matches the closed form of
    der(x) = u - x (1e-7)."""
    res = fl.Simulation(SaturatedRamp(), use_cache=False).run(1.0, dt_out=0.05, rtol=1e-10, atol=1e-12)
    # closed form: on [0.5, 0.55] x' = 20(t-0.5) - x, x(0.5) = 0; on [0.55, 1] x' = 1 - x
    a, t1 = 20.0, 0.05
    x1 = a * (t1 - 1.0 + np.exp(-t1))
    expected = 1.0 - (1.0 - x1) * np.exp(-(1.0 - 0.55))
    assert abs(res["x"][-1] - expected) < 1e-7
    assert any(abs(t - 0.55) < 1e-12 for t, _ in res.events)


class AssertBounded(fl.Model):
    """x grows at 1 m/s; an assertion requires x <= 0.5 m."""

    x = Variable(unit="m", start=0.0, fixed=True)

    def equations(self):
        fl.assert_(self.x <= 0.5, "x must stay below 0.5 m")
        return [eq(der(self.x), 1.0)]


@pytest.mark.parametrize("solver", ["ida", "casadi-idas"])
def test_assertion_stops_the_run_at_the_violation(solver):
    """assert_: the run stops where x crosses 0.5 (t = 0.5 s to 1e-9), the error names the component, the
    relation and the message, and the result up to the violation is kept; false at the start fails at once."""
    with pytest.raises(fl.SolverError,
                       match=r"assertion failed at t = 0.5 s:\n  AssertBounded: x <= 0.5: x must stay") as e:
        fl.Simulation(AssertBounded(), use_cache=False).run(1.0, dt_out=0.1, solver=solver, progress=False)
    assert abs(e.value.result.t[-1] - 0.5) < 1e-9
    assert abs(e.value.result["x"][-1] - 0.5) < 1e-9
    model = AssertBounded()
    model.set_start("x", 0.7)
    with pytest.raises(fl.SolverError, match=r"assertion failed at t = 0 s"):
        fl.Simulation(model, use_cache=False).run(1.0, solver=solver, progress=False)
    with pytest.raises(fl.ModelError, match=r"assert_\(\): the condition must be one relation"):
        class NotARelation(AssertBounded):
            def equations(self):
                fl.assert_(self.x + 1.0, "not a relation")
                return []
        fl.Simulation(NotARelation(), use_cache=False)


class Saturating(fl.Model):
    """der(x) = 1 below x = 1 and 2 - x above: the only steady state is x = 2, on the far side of the relation
    from the start guess x = 0."""

    x = Variable()

    def equations(self):
        return [eq(der(self.x), if_else(self.x > 1.0, 2.0 - self.x, 1.0))]


def test_initialisation_switches_a_relation_when_its_branch_has_no_solution():
    """steady_state=True from a start guess on the branch without a steady state: initialisation switches the
    relation and finds x = 2 (exact, 1e-12), instead of failing with the guess's branch."""
    res = fl.Simulation(Saturating(), use_cache=False).run(1.0, dt_out=0.5, steady_state=True, progress=False)
    np.testing.assert_allclose(res["x"], 2.0, atol=1e-12)


class FallingLevel(fl.Model):
    """``x = x0 − t`` [m]; ``on`` is set at the start where ``x > 0`` (``initial()``) and held while ``x > 0``;
    ``seen`` (declared, then defined) is set when ``on`` is 1 and x falls below 0.5 m, and held while ``on`` is."""

    x = Variable(unit="m")
    on = Variable(unit="1")
    seen = Variable(unit="1")

    def __init__(self, x0: float) -> None:
        super().__init__()
        self.x0 = fl.Parameter(unit="m")
        self.x0 = x0

    def equations(self):
        on = fl.latch(ca.logic_and(fl.initial(), self.x > 0), self.x > 0, name="on")
        seen = fl.latch(name="seen")
        fl.define_latch(seen, ca.logic_and(on, self.x < 0.5), on > 0.5)
        return [eq(self.x, self.x0 - fl.time), eq(self.on, on), eq(self.seen, seen)]


def test_latches_read_each_other_and_initial():
    """``initial()`` is 1 only while the start is found: ``on`` starts at 1 for x0 = 1 m, drops where x reaches 0
    (t = 1 s, within 1e-9 s) and is never set again; for x0 = −1 m it stays 0 although nothing else sets it. ``seen``
    reads ``on``: set at t = 0.5 s, dropped with ``on`` at 1 s. The events are logged by the latches' names."""
    res = fl.Simulation(FallingLevel(1.0)).run(2.0, dt_out=0.01, progress=False)
    t_off = res.t[np.argmax(res["on"] < 0.5)]
    assert res["on"][0] == 1.0 and abs(t_off - 1.0) < 1e-9 and np.all(res["on"][res.t > 1.0 + 1e-6] == 0.0)
    t_seen = res.t[np.argmax(res["seen"] > 0.5)]
    assert abs(t_seen - 0.5) < 1e-9 and np.all(res["seen"][res.t > 1.0 + 1e-6] == 0.0)
    assert any("FallingLevel: seen" in text or ": seen" in text for _, text in res.events)
    low = fl.Simulation(FallingLevel(-1.0)).run(1.0, dt_out=0.1, progress=False)
    assert np.all(low["on"] == 0.0) and np.all(low["seen"] == 0.0)


class _LatchMisuse(fl.Model):
    x = Variable(unit="m")

    def __init__(self, how: str) -> None:
        super().__init__()
        self.how = how

    def equations(self):
        if self.how == "undefined":
            fl.latch()
        elif self.how == "half":
            fl.latch(self.x > 0)
        elif self.how == "not a latch":
            fl.define_latch(self.x, self.x > 0, self.x > 0)
        elif self.how == "twice":
            y = fl.latch(self.x > 0, self.x > 0)
            fl.define_latch(y, self.x > 0, self.x > 0)
        elif self.how == "no relation":
            fl.latch(self.x + 1.0, self.x > 0)
        return [eq(der(self.x), 1.0)]


@pytest.mark.parametrize("how, message", [
    ("undefined", "latch declared by latch\\(\\) has no conditions"),
    ("half", "give both set_when and hold_while"),
    ("not a latch", "is not a latch declared"),
    ("twice", "has its conditions already"),
    ("no relation", "must be a relation"),
])
def test_latch_misuse_is_a_model_error(how, message):
    """A latch without conditions, with one condition, defined twice, a define_latch() of another symbol, or a
    condition that is not a relation: a ModelError that says so (naming the component where the flattener sees it)."""
    with pytest.raises(fl.ModelError, match=message):
        fl.build(_LatchMisuse(how))


class BouncingBall(fl.Model):
    """A ball dropped from 1 m; where it reaches the floor its height is put to 0 and its speed to ``-e v`` (fl.reinit,
    Modelica's ``when h < 0 then reinit(v, -e*pre(v))``)."""

    h = Variable(unit="m", start=1.0, fixed=True, state_select="always")
    v = Variable(unit="m/s", start=0.0, fixed=True, state_select="always")
    v_rebound = Variable(unit="m/s")

    def __init__(self, e: float = 0.8) -> None:
        super().__init__()
        self.e = fl.Parameter(unit="1")
        self.e = e

    def equations(self):
        fl.reinit(self.h < 0, (self.v, self.v_rebound), (self.h, 0.0))
        return [eq(der(self.h), self.v), eq(der(self.v), -9.81), eq(self.v_rebound, -self.e * self.v)]


def test_reinit_bounces_a_ball_at_the_closed_form_instants():
    """Impacts at ``t1 = sqrt(2 h0/g)`` and ``t1 + 2 e v1/g``, ``t1 + 2 e v1/g + 2 e² v1/g`` (1e-9 s), the
    rebound speed ``e v1`` (1e-9 relative), one event per impact (the reinitialised state re-evaluates the
    relation: no second event for the same impact)."""
    res = fl.Simulation(BouncingBall()).run(2.0, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False)
    g, e = 9.81, 0.8
    t1 = np.sqrt(2.0 / g)
    v1 = g * t1
    expected = [t1, t1 + 2 * e * v1 / g, t1 + 2 * e * v1 / g + 2 * e**2 * v1 / g]
    impacts = [t for t, text in res.events if "h < 0" in text]
    np.testing.assert_allclose(impacts, expected, atol=1e-9)
    np.testing.assert_allclose(res.value("v", [impacts[0]], side="right"), e * v1, rtol=1e-9)
    np.testing.assert_allclose(res.value("v", [impacts[0]], side="left"), -v1, rtol=1e-9)
    assert np.all(res["h"] >= -1e-9)


class _ReinitMisuse(fl.Model):
    x = Variable(unit="m", start=1.0, fixed=True)
    v = Variable(unit="m/s", start=0.0, fixed=True)

    def __init__(self, how: str) -> None:
        super().__init__()
        self.how = how

    def equations(self):
        if self.how == "expression":
            fl.reinit(self.x < 0, (self.v, -0.5 * self.v))
        elif self.how == "no pair":
            fl.reinit(self.x < 0)
        elif self.how == "not a relation":
            fl.reinit(ca.logic_and(self.x < 0, self.v < 0), (self.v, 0.0))
        elif self.how == "algebraic":
            fl.reinit(self.x < 0, (self.v, 0.0))
            return [eq(der(self.x), -1.0), eq(self.v, 2.0 * self.x)]
        return [eq(der(self.x), self.v), eq(der(self.v), -1.0)]


@pytest.mark.parametrize("how, message", [
    ("expression", "must be a number or a scalar variable"),
    ("no pair", "at least one pair"),
    ("not a relation", "must be one relation"),
    ("algebraic", "is not a state of the compiled model"),
])
def test_reinit_misuse_is_a_model_error(how, message):
    """A value that is an expression, no pair, a condition that is not one relation, a reinitialised variable the
    model does not keep as a state: a ModelError that says so."""
    with pytest.raises(fl.ModelError, match=message):
        fl.build(_ReinitMisuse(how))
