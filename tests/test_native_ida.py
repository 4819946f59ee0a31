"""The C-driven IDA backend (``solver="ida-native"``, ``flexlib.solve.backends.ida_c``) against closed-form
solutions and against IDA stepped from Python (``solver="ida-sksundae"``, the same SUNDIALS IDA) at tight
tolerances."""

import math
from pathlib import Path

import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq
from flexlib.compile.cache import cache_dir
from flexlib.models.n_mass_chain import NMassChain
from flexlib.models.reference.blow_up import BlowUp
from flexlib.models.reference.events import BouncingContact, FallingBall, SaturatedRamp, StepForce, Thermostat
from flexlib.models.reference.mass_spring_damper import DampedOscillator
from flexlib.solve import native
from flexlib.solve.backends.base import DENSE_MAX

HERE = Path(__file__).resolve().parent
STATS_KEYS = {"steps", "nfev", "njev", "state_events", "time_events", "restarts", "wall_model", "wall_ida",
              "wall_python"}


def both(sim: fl.Simulation, t_end: float, **kw) -> dict[str, fl.Result]:
    """``"ida"``: IDA stepped from Python (scikit-sundae, the default before the C driver and its fallback);
    ``"ida-native"``: the C driver (the default when available)."""
    kw.setdefault("progress", False)
    return {"ida": sim.run(t_end, solver="ida-sksundae", **kw), "ida-native": sim.run(t_end, solver="ida-native", **kw)}


def test_oscillator_matches_analytic_and_default_backend():
    """x(t) of the underdamped oscillator to 1e-6 on a 101-point grid (rtol 1e-8). It is the same IDA with the
    same Jacobian: step counts equal the default backend's, values agree to 1e-10."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 10.0, 101)
    res = both(sim, 10.0, output_times=grid, rtol=1e-8, atol=1e-10)
    r = res["ida-native"]
    np.testing.assert_array_equal(r.t, grid)
    np.testing.assert_allclose(r["x"], DampedOscillator.exact(grid), atol=1e-6)
    np.testing.assert_allclose(r["x"], res["ida"]["x"], atol=1e-10)
    assert STATS_KEYS <= set(r.stats)
    assert r.stats["steps"] == res["ida"].stats["steps"] and r.stats["nfev"] > 0 and r.stats["njev"] > 0


def test_every_step_recorded_without_grid():
    """No output grid: one row per internal step, as in the default backend (same times to 1e-12)."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    res = both(sim, 5.0, rtol=1e-8, atol=1e-10)
    assert len(res["ida-native"].t) == res["ida-native"].stats["steps"] + 1
    np.testing.assert_allclose(res["ida-native"].t, res["ida"].t, atol=1e-12)
    np.testing.assert_allclose(res["ida-native"]["x"], DampedOscillator.exact(res["ida-native"].t), atol=1e-6)


def test_row_buffer_refills(monkeypatch):
    """More output rows than the C buffer holds: rows are copied in chunks, none lost or repeated."""
    from flexlib.solve.backends import ida_c

    monkeypatch.setattr(ida_c, "ROW_BUFFER_VALUES", 7 * 2)  # 16 rows (the minimum) per chunk
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    grid = np.linspace(0.0, 10.0, 1001)
    r = sim.run(10.0, output_times=grid, rtol=1e-8, atol=1e-10, solver="ida-native", progress=False)
    np.testing.assert_array_equal(r.t, grid)
    np.testing.assert_allclose(r["x"], DampedOscillator.exact(grid), atol=1e-6)
    r2 = sim.run(10.0, rtol=1e-8, atol=1e-10, solver="ida-native", progress=False)
    assert len(r2.t) == r2.stats["steps"] + 1 and np.all(np.diff(r2.t) > 0)


class UnitCartesianPendulum(fl.Model):
    """Planar pendulum in Cartesian coordinates (index 3), m = L = 1, started at 45° at rest."""

    g = Parameter(9.81, unit="m/s2")
    x = Variable(unit="m")
    y = Variable(unit="m")
    u = Variable(unit="m/s")
    v = Variable(unit="m/s")
    lam = Variable(unit="N/m")

    def equations(self):
        return [eq(der(self.x), self.u), eq(der(self.y), self.v), eq(der(self.u), -self.lam * self.x),
                eq(der(self.v), -self.lam * self.y - self.g), eq(self.x**2 + self.y**2, 1.0)]


def test_index3_pendulum_constraint_and_energy():
    """Index-3 pendulum, 10 s at rtol 1e-8 on a 0.01 s grid. References: g = x²+y²−1 = 0, g' = x·u+y·v = 0 and
    E conserved. Tolerances: |g| < 1e-7, |g'| < 1e-6 (interpolated rows; measured 1.3e-8 and 6.1e-7), |ΔE| < 2e-5
    (measured 1.1e-5); the same IDA as the default backend: values agree to 1e-12."""
    th = math.pi / 4
    sim = fl.Simulation(UnitCartesianPendulum(init={"x": math.sin(th), "u": 0.0}, guess={"y": -math.cos(th)}),
                        use_cache=False)
    res = both(sim, 10.0, dt_out=0.01, rtol=1e-8, atol=1e-10, dynamic_states=False)
    r = res["ida-native"]
    x, y, u, v = r["x"], r["y"], r["u"], r["v"]
    assert np.abs(x**2 + y**2 - 1.0).max() < 1e-7
    assert np.abs(x * u + y * v).max() < 1e-6
    energy = 0.5 * (u**2 + v**2) + 9.81 * y
    assert np.abs(energy - energy[0]).max() < 2e-5
    for k in ("x", "y", "lam"):
        np.testing.assert_allclose(r[k], res["ida"][k], atol=1e-12, err_msg=k)


def test_pendulum_over_the_top_with_state_selection():
    """Started at the bottom with 8 m/s (E = 32 J/kg > 2·g) the pendulum loops over the top: the dynamic
    state-selection monitor switches states in ida-native as in the default backend; constraint held to 1e-6."""
    sim = fl.Simulation(UnitCartesianPendulum(init={"x": 0.0, "u": 8.0}, guess={"y": -1.0}), use_cache=False)
    if not sim.compiled.has_state_choice:
        pytest.skip("this build has no state choice")
    res = both(sim, 2.0, dt_out=0.01, rtol=1e-8, atol=1e-10)
    r = res["ida-native"]
    assert r.stats["state_switches"] >= 1 and r.stats["state_switches"] == res["ida"].stats["state_switches"]
    assert np.abs(r["x"] ** 2 + r["y"] ** 2 - 1.0).max() < 1e-6
    assert r["y"].max() > 0.9  # over the top
    np.testing.assert_allclose(r["y"], res["ida"]["y"], atol=1e-4)


def test_time_event_rows_as_default_backend():
    """StepForce: event at 0.55 s off the grid; the rows (times, values to 1e-9) equal the default backend's."""
    sim = fl.Simulation(StepForce(init={"x": 0.0, "v": 0.0}), use_cache=False)
    res = both(sim, 1.0, output_times=np.linspace(0.0, 1.0, 11), params={"t_on": 0.55}, rtol=1e-9, atol=1e-11)
    np.testing.assert_array_equal(res["ida-native"].t, res["ida"].t)
    assert res["ida-native"].events == res["ida"].events
    r = res["ida-native"]
    np.testing.assert_allclose(r["v"], np.where(r.t > 0.55, 1.0 - np.exp(-(r.t - 0.55)), 0.0), atol=1e-8)
    np.testing.assert_allclose(r["x"], res["ida"]["x"], atol=1e-9)


@pytest.mark.parametrize("rtol", [1e-6, 1e-10])
def test_state_event_located(rtol):
    """Falling ball: first contact at sqrt(2·h0/g) to 1e-8, lift-off found, states continuous across the event,
    the event times equal the default backend's to 1e-10."""
    sim = fl.Simulation(FallingBall(init={"h": 1.0, "v": 0.0}), use_cache=False)
    res = both(sim, 1.0, output_times=np.linspace(0.0, 1.0, 101), rtol=rtol, atol=rtol * 1e-2)
    r = res["ida-native"]
    assert abs(r.events[0][0] - math.sqrt(2 / 9.81)) <= 1e-8
    assert r.events[0][1].startswith("state event:") and r.events[0][1].endswith("h < 0")
    assert r.stats["state_events"] >= 2
    k = np.flatnonzero(r.t == r.events[0][0])
    assert len(k) == 2 and r["h"][k[0]] == r["h"][k[1]]
    assert np.all(r["fc"][r["h"] > 1e-9] == 0.0)
    np.testing.assert_allclose([e[0] for e in r.events], [e[0] for e in res["ida"].events], atol=1e-10)


def test_bouncing_contact_and_grid_kept():
    """BouncingContact at rtol 1e-10: first contact to 1e-8, bounces back above 4 m/s, every grid point kept
    in order (tests/test_engine_events.py)."""
    res = fl.Simulation(BouncingContact(init={"h": 1.0, "v": 0.0}), use_cache=False).run(
        1.0, dt_out=0.01, rtol=1e-10, atol=1e-12, solver="ida-native", progress=False)
    first = res.events[0][0]
    assert abs(first - math.sqrt(2 / 9.81)) <= 1e-8
    assert res.stats["state_events"] >= 2
    assert res["h"].min() < 0 and res["v"][res.t > first].max() > 4.0
    assert np.all(np.diff(res.t) >= 0)
    assert set(np.round(np.linspace(0, 1, 101), 12)) <= set(np.round(res.t, 12))


def test_chattering_stops_with_the_result():
    """Thermostat sliding mode: first switch at 2·ln 2 (1e-8), then a chattering SolverError naming the relation,
    with the result attached (the sign check after a restart works in C-driven runs too)."""
    sim = fl.Simulation(Thermostat(init={"T": 290.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"event chattering at t = 1\.386.*Thermostat: T < 295") as err:
        sim.run(3.0, dt_out=0.1, rtol=1e-12, atol=1e-10, solver="ida-native", progress=False)
    res = err.value.result
    assert abs(res.events[0][0] - 2 * math.log(2)) <= 1e-8


def test_state_event_coinciding_with_time_event():
    """SaturatedRamp: x(1) to 1e-7 of the closed form of der(x) = u − x."""
    res = fl.Simulation(SaturatedRamp(), use_cache=False).run(1.0, dt_out=0.05, rtol=1e-10, atol=1e-12,
                                                               solver="ida-native", progress=False)
    x1 = 20.0 * (0.05 - 1.0 + math.exp(-0.05))
    assert abs(res["x"][-1] - (1.0 - (1.0 - x1) * math.exp(-0.45))) < 1e-7
    assert any(abs(t - 0.55) < 1e-12 for t, _ in res.events)


def test_hydraulic_cylinder_end_stops():
    """Cylinder driven into both end stops (the catalogue's ``PressureDriven``): the resting penetration equals
    F_hyd / c_stop to 1e-6 relative, and the run agrees with the default backend (positions to 1e-9 m)."""
    from flexlib.models.reference.hydraulic_cylinder import A_P, A_R, BAR, P_ATM, STROKE, PressureDriven

    p_s = 100 * BAR
    sim = fl.Simulation(PressureDriven(p_s, t_switch=2.0))
    res = both(sim, 4.0, dt_out=0.001, rtol=1e-7, atol=1e-9)
    r = res["ida-native"]
    x = r["cylinder.x"]
    out, back = (r.t > 1.5) & (r.t < 2.0), r.t > 3.5
    f_out = p_s * A_P - P_ATM * A_R - P_ATM * (A_P - A_R)
    f_back = -(P_ATM * A_P - p_s * A_R - P_ATM * (A_P - A_R))
    np.testing.assert_allclose(x[out] - STROKE, f_out / 1e9, rtol=1e-6)
    np.testing.assert_allclose(-x[back], f_back / 1e9, rtol=1e-6)
    assert [e[1] for e in r.events] == [e[1] for e in res["ida"].events]
    grid_rows = np.isin(r.t, res["ida"].t)
    assert grid_rows.sum() >= 4001
    np.testing.assert_allclose(x[np.isin(r.t, np.linspace(0, 4, 4001))],
                               res["ida"]["cylinder.x"][np.isin(res["ida"].t, np.linspace(0, 4, 4001))], atol=1e-9)


@pytest.mark.parametrize("n", [10, 100])
def test_n_mass_chain_matches_default_backend(n, monkeypatch):
    """N-mass chain (dense LU at n = 10 masses / 31 unknowns, SuperLU_MT at 100 / 301, on both routes): positions
    equal the default backend's to 1e-9 m on the 0.1 s grid at rtol 1e-8."""
    sim = fl.Simulation(NMassChain(n), use_cache=False, codegen=False)
    if sim.compiled.n > DENSE_MAX:  # the scikit-sundae route's linear solver (the C driver's default is KLU)
        monkeypatch.setenv("FLEXLIB_LINSOL", "superlumt")
    assert sim.compiled.library is None
    res = both(sim, 10.0, dt_out=0.1, rtol=1e-8, atol=1e-10)
    for i in (0, n // 2, n - 1):
        np.testing.assert_allclose(res["ida-native"][f"mass{i}.s"], res["ida"][f"mass{i}.s"], atol=1e-9)
    assert abs(res["ida-native"].stats["steps"] - res["ida"].stats["steps"]) <= 0.02 * res["ida"].stats["steps"]


def test_generated_c_is_called_directly():
    """With generated C (codegen=True) the driver calls flexlib_res / flexlib_jac by address; results equal the
    SX virtual machine's to 1e-12 (same arithmetic up to compiler reordering)."""
    vm = fl.Simulation(NMassChain(5), use_cache=False, codegen=False)
    cg = fl.Simulation(NMassChain(5), use_cache=False, codegen=True)
    assert cg.compiled.library is not None
    r_vm = vm.run(10.0, dt_out=0.1, rtol=1e-8, atol=1e-10, solver="ida-native", progress=False)
    r_cg = cg.run(10.0, dt_out=0.1, rtol=1e-8, atol=1e-10, solver="ida-native", progress=False)
    ev = cg.compiled._functions["ida_native"]["ev"]
    assert ev["res"].symbol is not None and ev["jac"].symbol is not None
    np.testing.assert_allclose(r_cg["mass4.s"], r_vm["mass4.s"], atol=1e-12)


def test_failure_keeps_rows_and_names_the_variable():
    """The blow-up stops just before t = 1 (step size underflow, as in the default backend): SolverError with the
    rows so far (the same 20 grid rows as the default backend, x = 1/(1−t) to 1e-3 relative at the default rtol 1e-6,
    measured 3.1e-4 at t = 0.95; then the point where IDA stopped, at the time the message names, which is not
    compared with the closed form: the step size underflows there because IDA no longer resolves the blow-up,
    x = 1.3e15 against 6.1e4), and the message names x as dominating IDA's weighted local error estimate."""
    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"underflow at t = 0\.99.*local error estimates: x \(") as exc:
        sim.run(2.0, dt_out=0.05, solver="ida-native", progress=False)
    r = exc.value.result
    assert r.status == "failed" and 0.9 < r.t[-1] < 1.0 and len(r.t) == 21  # 20 grid rows and the failure point
    assert f"at t = {r.t[-1]:.10g} s" in str(exc.value)
    np.testing.assert_allclose(r["x"][:-1], 1.0 / (1.0 - r.t[:-1]), rtol=1e-3)


def test_ida_flags_are_named():
    """IDA's return flags are reported by IDA's own names (IDAGetReturnFlagName)."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    from flexlib.solve.backends.ida_c import make_driver

    m = sim.compiled
    p = np.concatenate([sim.parameter_vector(), np.zeros(m.n_relations)])
    drv, _ = make_driver(m, p, 1e-6, 1e-8, 0.0, 0.0, np.array([1.0, 0.0]), np.array([0.0, -4.0]))
    assert drv.flag_name(-4) == "IDA_CONV_FAIL" and drv.flag_name(-3) == "IDA_ERR_FAIL"


def test_max_steps_and_max_step():
    """``max_steps`` stops the run with the result so far; ``max_step`` bounds the step (≥ 1000 steps in 10 s)."""
    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"maximum number of steps \(20\)") as exc:
        sim.run(10.0, dt_out=1.0, max_steps=20, solver="ida-native", progress=False)
    assert exc.value.result.stats["steps"] == 20
    r = sim.run(10.0, dt_out=1.0, max_step=0.01, solver="ida-native", progress=False)
    assert r.stats["steps"] >= 1000
    np.testing.assert_allclose(r["x"], DampedOscillator.exact(r.t), atol=1e-5)


def test_driver_compiled_once_into_the_cache():
    """The driver library lives in cache_dir()/native, named by its source hash; a second lookup reuses it."""
    path = native.driver_library()
    assert path.parent == cache_dir() / "native" and path.exists()
    mtime = path.stat().st_mtime_ns
    assert native.driver_library() == path and path.stat().st_mtime_ns == mtime
    assert not list(path.parent.glob("*.tmp"))


def test_sigterm_while_in_the_c_loop_keeps_the_result(tmp_path):
    """SIGTERM sent from another thread while IDA steps in C: the C loop returns to Python within CHUNK_STEPS
    steps, the run raises SimulationInterrupted, and the rows so far (every 1 s grid point; x = cos t to 1e-4 over
    the first 100 s) are written to the file."""
    import os
    import signal
    import threading

    sim = fl.Simulation(DampedOscillator(init={"x": 1.0, "v": 0.0}, k=1.0, d=0.0), use_cache=False)
    sim.run(1.0, solver="ida-native", progress=False)  # driver set up: the signal comes during the steps
    path = tmp_path / "run.h5"
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGTERM))
    timer.start()
    try:
        with pytest.raises(fl.SimulationInterrupted, match=r"interrupted by SIGTERM at t = ") as err:
            sim.run(1e5, dt_out=1.0, solver="ida-native", result_file=path, progress=False)
    finally:
        timer.cancel()
    res = err.value.result
    assert res.status == "interrupted" and 100 < res.t[-1] < 1e5
    # the 1 s grid, no row lost or repeated, then the point where the run stopped
    np.testing.assert_array_equal(res.t[:-1], np.arange(len(res.t) - 1))
    assert res.t[-2] < res.t[-1] < res.t[-2] + 1.0
    np.testing.assert_allclose(res["x"][:100], np.cos(res.t[:100]), atol=1e-4)  # phase error grows with t
    assert fl.load_result(path).status == "interrupted"
