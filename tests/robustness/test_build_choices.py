"""Build-time numeric choices are re-checked at every run (issue 8, "never silently wrong").

The redundancy analysis drops the loop-closure rows that are dependent at the build's parameter
values (3 for a planar four-bar). A run whose parameters make the loop spatial must not report
success with a gap in the loop; a cached entry built at other values must not be reused blindly.
Reference for the planar runs: Norton's closed-form four-bar position analysis
(``flexlib.models.reference.closed_form``).
"""


import warnings

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.reference import closed_form as ref
from flexlib.models.reference.four_bar import A, B, C, D, FourBar

TH2 = 0.3
TH3, TH4 = ref.fourbar_angles(A, B, C, D, TH2, "open")


class AxisFourBar(FourBar):
    """The planar four-bar with the rocker's joint axis as a constructor argument."""

    def __init__(self, rocker_axis: tuple[float, float, float] = (0.0, 0.0, 1.0)) -> None:
        super().__init__(TH2, TH3, TH4, w2=1.0)
        self.rev4.n = np.array(rocker_axis, dtype=float)


def test_params_override_that_makes_the_loop_spatial_is_refused():
    """Without the zero-geometry assumption the axis is a run-time parameter: the dropped-row check refuses it
    (with the default assumption the parameter check refuses it first, tests/robustness/test_constants_assumed.py)."""
    sim = fl.Simulation(AxisFourBar(), use_cache=False, assume_zero_geometry=False)
    with pytest.raises(fl.StructureChangedError) as info:
        sim.run(0.1, dt_out=0.01, params={"rev4.n": [0.0, 0.3, 1.0]})
    msg = str(info.value)
    assert "rev3.frame_b" in msg and "rev4.n" in msg and "dropped as redundant" in msg


def test_same_simulation_still_runs_after_a_refused_override():
    sim = fl.Simulation(AxisFourBar(), use_cache=False)
    with pytest.raises(fl.StructureChangedError):
        sim.run(0.05, params={"rev4.n": [0.0, 0.3, 1.0]})
    res = sim.run(0.2, dt_out=0.01, rtol=1e-8, atol=1e-10)
    ref3, ref4 = ref.fourbar_angles(A, B, C, D, res["rev1.phi"], "open")
    np.testing.assert_allclose(res["rev4.phi"], ref4, atol=1e-7)
    np.testing.assert_allclose(res["rev1.phi"] + res["rev2.phi"], ref3, atol=1e-7)


def test_cached_planar_entry_is_not_reused_for_a_spatial_loop():
    """Same structure key (the axis is a parameter value): the cached build's dropped rows do not hold, so
    the model is rebuilt at its own values and gives the same answer as an uncached build (0 states)."""
    sim = fl.Simulation(AxisFourBar())
    assert sim.run(0.05).status == "success"
    tilted = fl.Simulation(AxisFourBar((0.0, 0.3, 1.0)))
    with pytest.raises(fl.InitializationError) as cached_err:
        tilted.run(0.1, dt_out=0.01)
    with pytest.raises(fl.InitializationError) as fresh_err:
        fl.Simulation(AxisFourBar((0.0, 0.3, 1.0)), use_cache=False).run(0.1, dt_out=0.01)
    assert "0 states" in str(cached_err.value)
    assert str(cached_err.value) == str(fresh_err.value)
    assert tilted.build_info["cached"] is False  # rebuilt, not the planar entry


def test_override_that_keeps_the_loop_planar_runs_and_matches_closed_form():
    """A longer crank through ``params`` keeps the loop planar: the dropped rows still hold, no false alarm,
    and the angles follow the closed form for the new crank length to 1e-7 rad."""
    a2 = 0.25
    th3, th4 = ref.fourbar_angles(a2, B, C, D, TH2, "open")
    sim = fl.Simulation(FourBar(TH2, th3, th4, w2=2.0), use_cache=False)
    res = sim.run(0.5, dt_out=0.01, rtol=1e-8, atol=1e-10, params={"crank.r": [a2, 0.0, 0.0]})
    ref3, ref4 = ref.fourbar_angles(a2, B, C, D, res["rev1.phi"], "open")
    np.testing.assert_allclose(res["rev4.phi"], ref4, atol=1e-7)
    np.testing.assert_allclose(res["rev1.phi"] + res["rev2.phi"], ref3, atol=1e-7)


class Constant2(fl.Model):
    """Every variable fixed by an equation: no unknowns are left after simplification."""

    k = fl.Parameter(2.0, unit="m")
    x = fl.Variable(unit="m")
    y = fl.Variable(unit="m")

    def equations(self):
        return [fl.eq(self.x, self.k), fl.eq(self.y, self.x * fl.time)]


def test_model_without_unknowns_runs():
    """No unknowns left (was a raw CasADi "'substitute' not defined for DM"): the results are the expressions
    themselves, exactly, and follow a run-time parameter."""
    sim = fl.Simulation(Constant2(), use_cache=False)
    res = sim.run(1.0, dt_out=0.25)
    np.testing.assert_allclose(res["y"], 2.0 * res.t, rtol=1e-15, atol=0)
    res = sim.run(1.0, dt_out=0.5, params={"k": 3.0})
    np.testing.assert_array_equal(res["x"], [3.0, 3.0, 3.0])


def test_model_without_unknowns_switches_at_time_events():
    """A step source feeding a gain, nothing to integrate: the output switches exactly at the step time."""
    from flexlib.components.control import Gain, Step

    class Stepped(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.step = Step(height=2.0, start_time=0.3)
            self.gain = Gain(k=1.5)
            self.connect(self.step.y, self.gain.u)

    res = fl.Simulation(Stepped(), use_cache=False).run(1.0, dt_out=0.1)
    assert res.stats["time_events"] == 1 and abs(res.events[0][0] - 0.3) < 1e-12
    np.testing.assert_allclose(res.value("gain.y", 0.2), 0.0)
    np.testing.assert_allclose(res.value("gain.y", 0.5), 3.0)


def test_dropped_rows_over_many_rows_match_pointwise_evaluation():
    """The run-time check evaluates the dropped rows row by row through a buffer; reference: the same ``chk``
    function called point by point (DM), at perturbed points and with a spatial rocker axis so the rows are
    nonzero. Agreement to 1e-12 relative (same operations; only the evaluation path differs)."""
    from flexlib.solve.build_checks import dropped_row_values

    sim = fl.Simulation(AxisFourBar(), use_cache=False, assume_zero_geometry=False)  # the axis stays a parameter
    m = sim.compiled
    assert m.check_labels
    rng = np.random.default_rng(1)
    n_rows = 7
    res = sim.run(0.1, dt_out=0.01)
    with warnings.catch_warnings():  # the unknowns as a vector, the indeterminate reactions among them
        warnings.simplefilter("ignore", fl.IndeterminateReactionWarning)
        y0 = np.array([res[name][-1] for name in m.y_names])
    Y = y0[:, None] + 0.1 * rng.standard_normal((m.n, n_rows))
    YP = rng.standard_normal((m.n, n_rows))
    pvec = sim.parameter_vector({"rev4.n": [0.0, 0.3, 1.0]})
    P = np.repeat(np.concatenate([pvec, np.zeros(m.n_relations)])[:, None], n_rows, axis=1)
    T = np.linspace(0.0, 0.1, n_rows)
    got = dropped_row_values(m, T, Y, YP, P)
    fn = m.function("chk")
    want = np.column_stack([np.asarray(fn(T[i], Y[:, i], YP[:, i], P[:, i])).ravel() for i in range(n_rows)])
    assert got.shape == (len(m.check_labels), n_rows)
    assert np.abs(want).max() > 1e-3  # the rows are really violated here: the comparison is not 0 == 0
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15)
