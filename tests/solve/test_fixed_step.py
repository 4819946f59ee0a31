"""The fixed-step integrator (``solver=fl.FixedStep(h=...)``, issue 32) against closed forms and IDA.

References and tolerances: the harmonic oscillator ``x'' = −4x`` (``x = cos 2t``): BDF2 halving the step divides the
error by 4 (3.6 … 4.4), implicit Euler by 2 (1.8 … 2.2); the index-reduced four-bar loop against IDA at rtol 1e-10:
second order (3.5 … 4.5) and 2e-5 of the crank angle's range at h = 1 ms; a bouncing ball's impacts found at the
first step boundary after the exact instant (the first within ``h``, the next within ``3h``: the first delay carries
over); a time event hit exactly; identical runs bitwise equal.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import Variable, der, eq
from flexlib.models.reference.drive_trains import CoupledClutches
from tests.msl.test_msl_multibody_examples import Fourbar1
from tests.test_engine_events import BouncingBall


class Oscillator(fl.Model):
    x = Variable(unit="m", start=1.0, fixed=True)
    v = Variable(unit="m/s", start=0.0, fixed=True)

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), -4.0 * self.x)]


class SteepRate(fl.Model):
    """``x' = −k(t) x`` with the rate ``k`` rising from 1 to 10⁴ 1/s over 1 ms at 0.5 s (no event): across it the
    iteration matrix of an earlier step makes Newton's corrections grow tenfold each (a linear problem, so a fresh
    matrix converges at its second correction)."""

    x = Variable(unit="1", start=1.0, fixed=True)

    def equations(self):
        k = 1.0 + 0.5e4 * (1.0 + ca.tanh((fl.time - 0.5) / 2e-4))
        return [eq(der(self.x), -k * self.x)]


@pytest.fixture(scope="module")
def oscillator():
    return fl.Simulation(Oscillator())


@pytest.mark.parametrize("method, order", [("bdf2", 2), ("euler", 1)])
def test_order_of_accuracy_on_the_oscillator(oscillator, method, order):
    """The global error of ``x = cos 2t`` over 2 s falls as ``h^order`` (the ratio of two halvings)."""
    errors = []
    for h in (1e-2, 5e-3):
        res = oscillator.run(2.0, dt_out=0.1, progress=False, solver=fl.FixedStep(h=h, method=method))
        errors.append(np.max(np.abs(res["x"] - np.cos(2 * res.t))))
        assert res.stats["steps"] == round(2.0 / h) and res.stats["solver"] == "fixed-step"
    assert 2**order * 0.9 < errors[0] / errors[1] < 2**order * 1.1
    if method == "bdf2":
        assert errors[0] < 5e-4


def test_index_reduced_loop_converges_at_second_order():
    """MSL's Fourbar1 (a spatial loop, index reduction and dummy derivatives) against IDA at rtol 1e-10 over 2 s."""
    sim = fl.Simulation(Fourbar1())
    ref = sim.run(2.0, dt_out=0.01, progress=False, rtol=1e-10, atol=1e-12)
    errors = []
    for h in (2e-3, 1e-3):
        res = sim.run(2.0, dt_out=0.01, progress=False, solver=fl.FixedStep(h=h))
        errors.append(np.max(np.abs(res["j1.phi"] - ref["j1.phi"])) / np.ptp(ref["j1.phi"]))
    assert 3.5 < errors[0] / errors[1] < 4.5
    assert errors[1] < 2e-5


def test_state_events_at_step_boundaries_and_time_events_exact():
    """Bouncing ball (``fl.reinit``): each impact at the first step boundary after it (the first within h); the coupled
    clutches' steps at 0.4 s and 0.9 s hit exactly, with the reference's 11 state events; two runs bitwise equal."""
    h = 1e-3
    res = fl.Simulation(BouncingBall()).run(1.2, dt_out=0.01, progress=False, solver=fl.FixedStep(h=h))
    g, e = 9.81, 0.8
    t1 = np.sqrt(2.0 / g)
    exact = [t1, t1 + 2 * e * g * t1 / g]
    impacts = [t for t, text in res.events if "h < 0" in text]
    assert len(impacts) == 2
    assert 0.0 <= impacts[0] - exact[0] < h
    # the first impact's delay δ < h lengthens the next flight (rebound from −v1 − gδ, from below the floor): < 3 h
    assert 0.0 <= impacts[1] - exact[1] < 3 * h
    sim = fl.Simulation(CoupledClutches())
    a = sim.run(1.5, dt_out=0.01, progress=False, solver=fl.FixedStep(h=h))
    times = [t for t, text in a.events if text.startswith("time event")]
    assert times == [0.4, 0.9]
    assert a.stats["state_events"] == 11
    b = sim.run(1.5, dt_out=0.01, progress=False, solver=fl.FixedStep(h=h))
    np.testing.assert_array_equal(a["J1.w"], b["J1.w"])


@pytest.mark.parametrize("native", [True, False])
def test_newton_divergence_names_the_time_and_keeps_the_result(native):
    """Steps of 0.3 s on the four-bar (a crank turn is 1.2 s) that may not be halved: the corrections grow, and the
    run fails, saying so and suggesting a smaller step, with the result up to there (C and Python alike)."""
    with pytest.raises(fl.SolverError, match=r"diverged at t = 0.6 s in 4 iterations") as failure:
        fl.Simulation(Fourbar1()).run(1.0, dt_out=0.01, progress=False,
                                      solver=fl.FixedStep(h=0.3, max_halvings=0, native=native))
    assert failure.value.result is not None and failure.value.result.t[-1] == pytest.approx(0.6)


def test_steps_that_do_not_converge_are_halved_and_unconverged_ones_are_reported():
    """The same steps with halving: the run goes through on halves; steps still unconverged at the smallest size
    are taken and reported as an AccuracyWarning naming the first."""
    with pytest.warns(fl.AccuracyWarning, match=r"had not converged, the first ending at t = 0.1125 s"):
        res = fl.Simulation(Fourbar1()).run(1.2, dt_out=0.3, progress=False,
                                            solver=fl.FixedStep(h=0.3, max_halvings=3))
    assert res.stats["halved_steps"] == 28 and res.stats["unconverged_steps"] == 15


def test_c_and_python_take_the_same_steps():
    """The C stepper and the Python one: the same steps, events and values (to round-off of their LU solvers)."""
    sim = fl.Simulation(CoupledClutches())
    a, b = (sim.run(1.5, dt_out=0.01, progress=False, solver=fl.FixedStep(h=1e-3, native=native))
            for native in (True, False))
    assert a.stats["solver"] == b.stats["solver"] == "fixed-step"
    assert [t for t, _ in a.events] == [t for t, _ in b.events] and len(a.events) == 13
    for name in ("J1.w", "J2.w", "J3.w", "J4.w"):
        np.testing.assert_allclose(a[name], b[name], rtol=0, atol=1e-12)


@pytest.mark.parametrize("native", [True, False])
def test_the_costliest_step_says_what_it_did(native):
    """``stats["worst_step_work"]``: the Newton corrections, matrix evaluations and full LU factorisations of the step
    that cost most (which step that is depends on the machine; what any step did is bounded by the totals and the
    method: at least one correction, at most ``newton_iters`` per solution of a step, a full factorisation only
    with a matrix evaluation)."""
    sim = fl.Simulation(CoupledClutches())
    res = sim.run(1.5, dt_out=0.01, progress=False, solver=fl.FixedStep(h=1e-3, native=native))
    corrections, matrices, full = res.stats["worst_step_work"]
    limit = 2 ** (fl.FixedStep().max_halvings + 1) - 1  # step solutions of a step halved to the end
    assert 1 <= corrections <= 2 * limit * fl.FixedStep().newton_iters and corrections <= res.stats["newton_iters"]
    assert 0 <= full <= matrices <= limit and matrices <= res.stats["njev"]
    # every step counted once by its work; the totals are the run's
    work = {(c, m, f): n for c, m, f, n in res.stats["step_work"]}
    assert sum(work.values()) == res.stats["steps"]
    assert sum(k[0] * n for k, n in work.items()) == res.stats["newton_iters"]
    assert sum(k[1] * n for k, n in work.items()) == res.stats["njev"]
    assert tuple(res.stats["worst_step_work"]) in work
    # the costliest by work at the run's mean costs of a correction, a matrix and a full factorisation
    assert tuple(res.stats["worst_work"]) in work and res.stats["worst_step_by_work"] > 0.0
    assert max(c for c, _, _ in work) <= 2 * limit * fl.FixedStep().newton_iters


@pytest.mark.parametrize("native", [True, False])
def test_an_old_matrix_that_cannot_converge_is_given_up_at_once(native):
    """Where the rate jumps (SteepRate), the step's old matrix diverges: it is given up at its second correction (its
    rate of contraction cannot meet the test within the corrections left), not after all ``newton_iters``; the fresh
    one converges at its second, so no step takes more than four corrections and one matrix (ten without the rule at
    ``newton_iters=8``); before the jump ``x = exp(−t)`` within 1e-3, after it the solution has decayed."""
    sim = fl.Simulation(SteepRate())
    res = sim.run(1.0, dt_out=0.1, progress=False,
                  solver=fl.FixedStep(h=1e-2, newton_iters=8, max_halvings=0, native=native))
    work = {(c, m, f): n for c, m, f, n in res.stats["step_work"]}
    assert max(c for c, m, _ in work if m >= 1) <= 4 and any(c >= 3 and m == 1 for c, m, _ in work)
    assert res.stats["unconverged_steps"] == 0
    assert abs(res["x"][-1]) < 1e-6 and res["x"][4] == pytest.approx(np.exp(-0.4), rel=1e-3)  # t = 0.4 s: k = 1/s


@pytest.mark.parametrize("kwargs, message", [
    ({"h": 0.0}, "positive number of seconds"),
    ({"h": float("nan")}, "positive number of seconds"),
    ({"h": "1e-3"}, "positive number of seconds"),
    ({"h": 1e-3, "method": "rk4"}, "must be one of euler, bdf2"),
    ({"h": 1e-3, "newton_iters": 0}, "integer 1"),
    ({"h": 1e-3, "max_halvings": 9}, "integer 0"),
    ({"h": 1e-3, "max_halvings": 1.5}, "integer 0"),
    ({"h": 1e-3, "realtime": "yes"}, "True or False"),
    ({"h": 1e-3, "native": "c"}, "True, False or None"),
])
def test_bad_arguments_are_refused(kwargs, message):
    with pytest.raises(fl.RunArgumentError, match=message):
        fl.FixedStep(**kwargs)


@pytest.mark.parametrize("native", [True, False])
def test_realtime_pacing_keeps_the_run_behind_the_wall_clock(oscillator, native):
    """``realtime=True``: a step never ends before its simulated time on the wall clock (sleeping cannot end early,
    so this holds on a loaded machine too); the values are those of the unpaced run; overruns are counted."""
    import time

    plain = oscillator.run(0.3, dt_out=0.05, progress=False, solver=fl.FixedStep(h=0.01, native=native))
    w0 = time.monotonic()
    paced = oscillator.run(0.3, dt_out=0.05, progress=False,
                           solver=fl.FixedStep(h=0.01, realtime=True, native=native))
    assert time.monotonic() - w0 >= 0.3 - 0.01  # the clock starts after the first step
    np.testing.assert_array_equal(paced["x"], plain["x"])
    assert paced.stats["overruns"] >= 0 and paced.stats["worst_late"] >= 0.0
    assert paced.stats["worst_step_wall"] >= paced.stats["mean_step_wall"] > 0.0


def test_solver_records_round_trip_and_run():
    """A solver as a JSON-ready record (scenario files, run records, the CLI): the object it stands for, and back."""
    from flexlib.solve.solvers import as_solver

    assert as_solver({"kind": "fixed-step", "h": 0.002}) == fl.FixedStep(h=0.002)
    assert fl.FixedStep(h=0.002, realtime=True).record() == {"kind": "fixed-step", "h": 0.002, "realtime": True}
    assert fl.IDA(max_order=2).record() == {"kind": "ida", "max_order": 2}
    for solver in (fl.FixedStep(h=5e-4, method="euler", max_halvings=0), fl.IDA(linear_solver="dense"),
                   fl.CasadiIDAS(max_order=3)):
        assert as_solver(solver.record()) == solver
    with pytest.raises(fl.RunArgumentError, match="'kind' must be one of"):
        as_solver({"h": 0.001})
    with pytest.raises(fl.RunArgumentError, match="fixed-step has no option 'step'"):
        as_solver({"kind": "fixed-step", "step": 0.001})
    with pytest.raises(fl.RunArgumentError, match="positive number of seconds"):
        as_solver({"kind": "fixed-step", "h": -1.0})


def test_cli_runs_a_registered_scenario_with_fixed_steps_and_records_them(tmp_path):
    """``flexlib run MODEL --solver fixed-step --step H``: every step H, the step costs in the summary, the solver
    record in the result file, repeated by ``--from``."""
    from click.testing import CliRunner

    from flexlib import registry
    from flexlib.cli import cli

    out = tmp_path / "fourbar.h5"
    res = CliRunner().invoke(cli, ["run", "fourbar", "--t-end", "0.2", "--solver", "fixed-step", "--step", "0.002",
                                   "--out", str(out), "--no-progress"], env={"COLUMNS": "200"},
                             catch_exceptions=False)
    assert res.exit_code == 0, res.output
    assert "step cost, mean / worst [ms]" in res.output and "halved / unconverged steps" in res.output
    assert "worst step: corrections / matrices / full LU" in res.output
    done = fl.load_result(out)
    assert done.stats["solver"] == "fixed-step" and done.stats["h"] == 0.002 and done.stats["steps"] == 100
    assert registry.run_settings(done).run["solver"] == {"kind": "fixed-step", "h": 0.002}
    again = tmp_path / "again.h5"
    res = CliRunner().invoke(cli, ["run", "--from", str(out), "--out", str(again), "--no-progress"],
                             catch_exceptions=False)
    assert res.exit_code == 0, res.output
    np.testing.assert_array_equal(fl.load_result(again).values, done.values)
    bad = CliRunner().invoke(cli, ["run", "fourbar", "--step", "0.002"], catch_exceptions=False)
    assert bad.exit_code != 0 and "--step is an option of --solver fixed-step" in bad.output
    # the bounded configuration: no halvings, recorded with the solver
    bounded = tmp_path / "bounded.h5"
    res = CliRunner().invoke(cli, ["run", "fourbar", "--t-end", "0.2", "--solver", "fixed-step", "--max-halvings", "0",
                                   "--out", str(bounded), "--no-progress"], catch_exceptions=False)
    assert res.exit_code == 0, res.output
    done = fl.load_result(bounded)
    assert registry.run_settings(done).run["solver"] == {"kind": "fixed-step", "max_halvings": 0}
    assert done.stats["halved_steps"] == 0 and done.stats["steps"] == 200
    bad = CliRunner().invoke(cli, ["run", "fourbar", "--max-halvings", "0"], catch_exceptions=False)
    assert bad.exit_code != 0 and "--max-halvings is an option of --solver fixed-step" in bad.output
    bad = CliRunner().invoke(cli, ["run", "fourbar", "--solver", "fixed-step", "--max-halvings", "9"],
                             catch_exceptions=False)
    assert bad.exit_code != 0 and "--max-halvings" in bad.output
