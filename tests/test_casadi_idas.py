"""The CasADi-IDAS backend (``flexlib.solve.backends.casadi``) against closed-form solutions and the default backend."""

from functools import partial

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq, if_else, time
from flexlib.models.reference.blow_up import BlowUp
from flexlib.models.reference.events import FallingBall, StepForce
from flexlib.models.reference.mass_spring_damper import DampedOscillator
from flexlib.solve import casadi_dae, casadi_runner
from flexlib.solve.solvers import integrate

BACKENDS = {"ida": partial(integrate, "ida-sksundae"), "casadi": partial(integrate, "casadi-idas")}
STATS_KEYS = {"steps", "nfev", "njev", "state_events", "time_events", "restarts"}


def _run(sim: fl.Simulation, backend: str, t_end: float, grid, params=None, **kw) -> fl.Result:
    """What ``Simulation.run`` does, with the integrator chosen explicitly."""
    m = sim.compiled
    pvec = sim.parameter_vector(params)
    p = np.concatenate([pvec, np.zeros(m.n_relations)])
    _, starts = sim.model.values()
    y0, yp0 = sim._initialize(0.0, p, starts, False)
    try:
        traj = BACKENDS[backend](m, sim.initializer, p, y0, yp0, 0.0, t_end, grid, **kw)
    except fl.SolverError as err:
        err.result = sim._result(err.result, pvec, 0.0, kw.get("rtol", 1e-6), kw.get("atol", 1e-8))
        raise
    return sim._result(traj, pvec, 0.0, kw.get("rtol", 1e-6), kw.get("atol", 1e-8))


# -- (a) damped oscillator ---------------------------------------------------------------------------------------
def test_oscillator_matches_analytic_and_default_backend():
    """x(t) of the underdamped oscillator to 1e-6 on a 101-point grid (rtol 1e-8); both backends agree."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 10.0, 101)
    res = {b: _run(sim, b, 10.0, grid, rtol=1e-8, atol=1e-10) for b in BACKENDS}
    for b, r in res.items():
        np.testing.assert_array_equal(r.t, grid)
        np.testing.assert_allclose(r["x"], DampedOscillator.exact(grid), atol=1e-6, err_msg=b)
        assert STATS_KEYS <= set(r.stats), b
    np.testing.assert_allclose(res["casadi"]["x"], res["ida"]["x"], atol=2e-7)
    np.testing.assert_allclose(res["casadi"]["v"], res["ida"]["v"], atol=5e-7)
    assert res["casadi"].stats["steps"] > 0 and res["casadi"].stats["nfev"] >= res["casadi"].stats["steps"]
    assert res["casadi"].stats["restarts"] == 0


def test_parameters_are_runtime_inputs_and_integrators_are_cached():
    """A second run with another stiffness reuses the built CasADi integrator (no rebuild)."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 5.0, 51)
    _run(sim, "casadi", 5.0, grid, rtol=1e-8, atol=1e-10)
    backend = sim.compiled._functions["casadi_idas"]
    built = dict(backend.integrators)
    build_time = backend.build_time
    r = _run(sim, "casadi", 5.0, grid, params={"k": 9.0}, rtol=1e-8, atol=1e-10)
    assert sim.compiled._functions["casadi_idas"] is backend
    assert backend.integrators.keys() >= built.keys()
    assert all(backend.integrators[k] is f for k, f in built.items())
    assert backend.build_time == build_time  # same grid size and options: nothing new was built
    np.testing.assert_allclose(r["x"], DampedOscillator.exact(grid, k=9.0), atol=1e-6)


def test_dense_output_when_no_grid():
    """t_out=None (every step in the default backend) gives a uniform grid of DENSE_POINTS intervals."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    r = _run(sim, "casadi", 2.0, None)
    assert len(r.t) == casadi_runner.DENSE_POINTS + 1
    np.testing.assert_allclose(np.diff(r.t), 2.0 / casadi_runner.DENSE_POINTS, rtol=1e-9)
    np.testing.assert_allclose(r["x"], DampedOscillator.exact(r.t), atol=1e-5)


# -- (b) time event ----------------------------------------------------------------------------------------------
def test_time_event_hit_exactly():
    """The event is at t = 0.5 exactly, left and right rows are stored, v(t) = 1 − exp(−(t − 0.5)) after it."""
    sim = fl.Simulation(StepForce(init={"x": 0.0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 2.0, 21)
    res = {b: _run(sim, b, 2.0, grid) for b in BACKENDS}
    for b, r in res.items():
        assert [e[0] for e in r.events] == [0.5], b
        assert r.stats["time_events"] == 1 and r.stats["state_events"] == 0, b
        k = np.flatnonzero(r.t == 0.5)
        assert len(k) == 3 and list(r["f"][k]) == [0.0, 0.0, 1.0], b
        tt = r.t
        v_exact = np.where(tt >= 0.5, 1.0 - np.exp(-(tt - 0.5)), 0.0)
        v_exact[k[:2]] = 0.0
        np.testing.assert_allclose(r["v"], v_exact, atol=1e-6, err_msg=b)
    np.testing.assert_array_equal(res["casadi"].t, res["ida"].t)
    assert res["casadi"].events == res["ida"].events
    np.testing.assert_allclose(res["casadi"]["x"], res["ida"]["x"], atol=1e-6)


def test_time_event_between_output_points():
    """An event at 0.55 s (off the 0.1 s grid, set at run time) is hit exactly; rows as in the default backend."""
    sim = fl.Simulation(StepForce(init={"x": 0.0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 1.0, 11)
    res = {b: _run(sim, b, 1.0, grid, params={"t_on": 0.55}, rtol=1e-9, atol=1e-11) for b in BACKENDS}
    for b, r in res.items():
        assert [e[0] for e in r.events] == [0.55], b
        assert len(r.t) == len(grid) + 2, b
        np.testing.assert_allclose(r["v"], np.where(r.t > 0.55, 1.0 - np.exp(-(r.t - 0.55)), 0.0), atol=1e-8)
    np.testing.assert_array_equal(res["casadi"].t, res["ida"].t)
    np.testing.assert_allclose(res["casadi"]["x"], res["ida"]["x"], atol=1e-8)


# -- (c) state event ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rtol", [1e-6, 1e-10])
def test_state_event_located(rtol):
    """First contact at t = sqrt(2·h0/g) to 1e-8; lift-off found too; both backends agree."""
    h0 = 1.0
    sim = fl.Simulation(FallingBall(init={"h": h0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 1.0, 101)
    res = {b: _run(sim, b, 1.0, grid, rtol=rtol, atol=rtol * 1e-2) for b in BACKENDS}
    t_hit = np.sqrt(2 * h0 / 9.81)
    for b, r in res.items():
        assert abs(r.events[0][0] - t_hit) <= 1e-8, b
        assert r.events[0][1].startswith("state event:") and r.events[0][1].endswith("h < 0"), b
        assert r.stats["state_events"] >= 2, b  # contact and lift-off
        k = np.flatnonzero(r.t == r.events[0][0])
        assert len(k) == 2 and r["h"][k[0]] == r["h"][k[1]], b  # states continuous across the event
        assert np.all(r["fc"][r["h"] > 1e-9] == 0.0), b
    ev_c, ev_i = [e[0] for e in res["casadi"].events], [e[0] for e in res["ida"].events]
    assert len(ev_c) == len(ev_i)
    np.testing.assert_allclose(ev_c, ev_i, atol=1e4 * rtol)
    # the casadi backend returns every grid point; compare where both have one
    np.testing.assert_array_equal(np.unique(res["casadi"].t[np.isin(res["casadi"].t, grid)]), grid)
    common = np.intersect1d(np.intersect1d(res["casadi"].t, res["ida"].t), grid)
    assert len(common) >= len(grid) - 2
    first = {b: {float(t): i for i, t in reversed(list(enumerate(r.t)))} for b, r in res.items()}
    h = {b: r["h"][[first[b][float(t)] for t in common]] for b, r in res.items()}
    np.testing.assert_allclose(h["casadi"], h["ida"], atol=1e3 * rtol)


def test_branch_undefined_past_the_event():
    """``if_else(x < 1, sqrt(1 - x), 0)``: integrating past x = 1 with the relation frozen gives NaN;
    the failing calls are retried shorter and the event is found where IDAS gets stuck."""

    class SqrtBranch(fl.Model):
        x = Variable()

        def equations(self):
            return [eq(der(self.x), 1.0 + if_else(self.x < 1, ca.sqrt(1 - self.x), 0.0))]

    sim = fl.Simulation(SqrtBranch(init={"x": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 2.0, 5)
    res = {b: _run(sim, b, 2.0, grid) for b in BACKENDS}
    # x' = 1 + sqrt(1 - x) from 0 reaches x = 1 at t = 2·(1 − ln 2) (with s = sqrt(1 − x):
    # dt = −2s/(1 + s) ds); afterwards x' = 1. The sqrt singularity limits the accuracy of both.
    t_hit = 2 * (1 - np.log(2))
    for b, r in res.items():
        assert len(r.events) == 1 and abs(r.events[0][0] - t_hit) < 5e-5, b
        np.testing.assert_allclose(r["x"][-1], 1.0 + 2.0 - t_hit, atol=5e-5, err_msg=b)


def test_max_step_option():
    """``max_step`` bounds the step size (at least t_end / max_step steps) without changing the result."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    r = _run(sim, "casadi", 10.0, np.linspace(0.0, 10.0, 11), max_step=0.01)
    assert r.stats["steps"] >= 1000
    np.testing.assert_allclose(r["x"], DampedOscillator.exact(r.t), atol=1e-5)


def test_failure_raises_solver_error_with_partial_result():
    """A finite-time blow-up (x' = x², x(0) = 1) raises SolverError carrying the trajectory so far."""

    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.SolverError) as exc:
        _run(sim, "casadi", 2.0, np.linspace(0.0, 2.0, 41))
    result = exc.value.result
    assert result.status == "failed" and "CasADi IDAS failed" in result.message
    assert 0.0 < len(result.t) and result.t[-1] < 1.0
    early = result.t <= 0.8  # rows now reach t = 0.95 s, where the global error (~x²) exceeds 1e-4
    np.testing.assert_allclose(result["x"][early], 1.0 / (1.0 - result.t[early]), rtol=1e-4)


def test_max_steps():
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match="maximum number of steps"):
        _run(sim, "casadi", 10.0, np.linspace(0.0, 10.0, 11), max_steps=20)


# -- (f) compiled model evaluation, mechanisms and the hydraulic servo against the default backend -----------------
def test_compiled_residual_jacobian_matches_symbolic():
    """With generated C the backend evaluates the library: the Jacobian CasADi's IDAS uses (``jac_flexlib_res``
    of the companion library, from ``flexlib_jac`` at cj = 0 and 1) equals the SX Jacobian to 1e-12 relative,
    and a run at rtol 1e-8 gives the SX route's link angles to 1e-5 rad (measured 1.4e-6 rad over 1 s, the
    crank turning by 10 rad: the Newton iterations differ in round-off and in the ∂F/∂t column, which the C
    Jacobian leaves out, so the step sequences differ within the tolerance)."""
    from flexlib.models.planar_mechanisms import FourBarLinkage

    sim = fl.Simulation(FourBarLinkage(), use_cache=False, codegen=True)
    m = sim.compiled
    assert m.library is not None
    res_c = casadi_dae.compiled_residual(m)
    assert res_c is not None
    rng = np.random.default_rng(1)
    p = np.concatenate([m.param_defaults, np.zeros(m.n_relations)])
    args = [0.3, rng.standard_normal(m.n), rng.standard_normal(m.n), p, np.zeros(m.n)]
    jc, js = res_c.jacobian()(*args), m.sx_function("res").jacobian()(*args)
    for k in (1, 2):  # d/dy, d/dy'
        a, b = np.array(ca.DM(jc[k])), np.array(ca.DM(js[k]))
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())
    np.testing.assert_allclose(np.array(res_c(*args[:4])), np.array(m.sx_function("res")(*args[:4])), rtol=1e-14,
                               atol=1e-12)
    runs = {}
    for use in (True, False):
        casadi_runner.USE_LIBRARY = use
        try:
            runs[use] = sim.run(1.0, dt_out=0.01, rtol=1e-8, atol=1e-10, solver="casadi-idas", progress=False)
            assert sim.compiled._functions["casadi_idas"].compiled is use
        finally:
            casadi_runner.USE_LIBRARY = True
    for name in ("rev_crank.phi", "rev_coupler.phi", "rev_rocker.phi"):
        np.testing.assert_allclose(runs[True][name], runs[False][name], atol=1e-5, err_msg=name)


def test_four_bar_matches_default_backend():
    """Crank-rocker four-bar (3 loops closed by a cut revolute), 10 s at rtol 1e-9: absolute link angles of the
    two backends agree to 5e-5 rad (measured 1.5e-5; each is this close to the minimal-coordinate reference at
    this tolerance, see benchmarks/README.md, work–precision)."""
    from flexlib.models.planar_mechanisms import FourBarLinkage

    sim = fl.Simulation(FourBarLinkage(), use_cache=False, codegen=True)
    out = {s: sim.model.absolute_angles(sim.run(10.0, dt_out=0.01, rtol=1e-9, atol=1e-11, solver=s, progress=False))
           for s in ("ida", "casadi-idas")}
    assert sim.compiled._functions["casadi_idas"].compiled  # the library was evaluated
    for name, angle in out["ida"].items():
        np.testing.assert_allclose(out["casadi-idas"][name], angle, atol=5e-5, err_msg=name)


def _on_grid(r: fl.Result, name: str, dt: float) -> np.ndarray:
    """Values at the output grid (event rows, which repeat their time, dropped)."""
    keep = np.abs(r.t / dt - np.round(r.t / dt)) < 1e-7
    _, first = np.unique(r.t[keep], return_index=True)
    return r[name][keep][first]


def test_hydraulic_servo_through_end_stops_matches_default_backend():
    """The catalogue's hydraulic servo (flexlib.models.reference.hydraulic_servo: pump, relief valve, 4/3 valve,
    cylinder into both end stops twice, PID) over 20 s at rtol 1e-6, atol 1e-8: casadi-idas runs through the end-stop
    contacts (it failed at 5.79 s with IDA_ERR_FAIL before the start fall-backs) and its piston position agrees with
    the default backend's to 2e-5 m on the 10 ms grid (measured 6.7e-6 m; 0.005 % of the stroke), the end-stop
    penetrations to 1e-9 m."""
    from flexlib.models.reference.hydraulic_servo import STROKE, HydraulicServo

    sim = fl.Simulation(HydraulicServo(), use_cache=False)
    r = {s: sim.run(20.0, dt_out=0.01, rtol=1e-6, atol=1e-8, solver=s, progress=False)
         for s in ("ida", "casadi-idas")}
    x = {s: _on_grid(rr, "cylinder.x", 0.01) for s, rr in r.items()}
    assert len(x["ida"]) == len(x["casadi-idas"]) == 2001
    np.testing.assert_allclose(x["casadi-idas"], x["ida"], atol=2e-5)
    assert x["ida"].max() > STROKE and x["ida"].min() < 0.0  # both stops reached
    assert abs(x["casadi-idas"].max() - x["ida"].max()) < 1e-9
    assert abs(x["casadi-idas"].min() - x["ida"].min()) < 1e-9
    assert r["casadi-idas"].stats["state_events"] >= 8  # contact and release at both stops, twice each


class ThrustBall(FallingBall):
    """The falling ball of :class:`FallingBall`, with an upward thrust of ``a_up`` [m/s²] from ``t_on`` on."""

    t_on = Parameter(0.62, unit="s")
    a_up = Parameter(25.0, unit="m/s2")
    a = Variable(unit="m/s2")

    def equations(self):
        return [
            eq(der(self.h), self.v),
            eq(der(self.v), -self.g + self.fc + self.a),
            eq(self.fc, if_else(self.h < 0, -self.k * self.h - self.d * self.v, 0.0)),
            eq(self.a, if_else(time >= self.t_on, self.a_up, 0.0)),
        ]


def test_time_and_state_events_match_default_backend():
    """Contact (state event, t = 0.4515 s), lift-off (state event, 0.4836 s), thrust switched on in flight
    (time event, 0.62 s; the ball rises to 7.9 m by 1.5 s): the same events in the same order as the default
    backend, times to 1e-9 s (measured 4e-12 s), and h on the 10 ms grid to 1e-7 m at rtol 1e-9 (measured
    1.5e-8 m)."""
    sim = fl.Simulation(ThrustBall(init={"h": 1.0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 1.5, 151)
    res = {b: _run(sim, b, 1.5, grid, rtol=1e-9, atol=1e-11) for b in BACKENDS}
    kinds = {b: [e[1].split(":")[0] for e in r.events] for b, r in res.items()}
    assert kinds["casadi"] == kinds["ida"]
    assert "time event" in kinds["ida"] and kinds["ida"].count("state event") >= 2
    np.testing.assert_allclose([e[0] for e in res["casadi"].events], [e[0] for e in res["ida"].events], atol=1e-9)
    h = {b: _on_grid(r, "h", 0.01) for b, r in res.items()}
    assert len(h["ida"]) == len(h["casadi"]) == len(grid)
    np.testing.assert_allclose(h["casadi"], h["ida"], atol=1e-7)
