"""Faults on the ``solver="casadi-idas"`` backend: a run that fails mid-way keeps its rows.

CasADi's integrator raises without partial results, so the backend halves a failing call and retries
until one output interval fails (``flexlib/solve/backends/casadi.py``). Each test asserts the error class,
that the message names the culprit (time of the failure and the solver), and what survives in
``err.result``.
"""

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import Variable, der, eq, if_else
from flexlib.models.reference.blow_up import BlowUp


class SqrtWall(fl.Model):
    """x' = −1 from x(0) = 0.5 crosses zero at t = 0.5 s; y with y² = x (algebraic) has no real value past it."""

    x = Variable()
    y = Variable()

    def equations(self):
        return [eq(der(self.x), -1.0), eq(self.y**2, self.x)]


@pytest.mark.parametrize("n_out", [11, 101, 1001])
def test_blow_up_keeps_rows_up_to_one_interval_before_the_failure(n_out):
    """x = 1/(1 − t) on [0, 2] s with n_out outputs: the rows up to within one output interval (plus
    the solver's last accepted steps) of t = 1 s survive in ``err.result`` and follow the exact
    solution (rtol 1e-4); today's single failing call kept only t = 0."""
    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False)
    grid = np.linspace(0.0, 2.0, n_out)
    dt = grid[1] - grid[0]
    with pytest.raises(fl.SolverError, match="CasADi IDAS failed between t = ") as exc:
        sim.run(2.0, output_times=grid, solver="casadi-idas", progress=False)
    res = exc.value.result
    assert res.status == "failed" and "CasADi IDAS failed" in res.message
    assert res.t[-1] < 1.0 and res.t[-1] >= 1.0 - 2 * dt - 1e-12
    early = res.t <= 0.8
    np.testing.assert_allclose(res["x"][early], 1.0 / (1.0 - res.t[early]), rtol=1e-4)
    exact = 1.0 / (1.0 - res.t)
    assert np.all(np.abs(res["x"] - exact) <= 2e-5 * exact**2)
    # the message brackets the failure by one output interval
    msg = str(exc.value)
    a, b = (float(v) for v in msg.split("between t = ")[1].split(" s (")[0].split(" s and t = "))
    assert a <= 1.0 + 1e-9 and b - a <= dt + 1e-12


def test_every_step_mode_keeps_rows_before_a_nan():
    """y = sqrt(x) with x = 0.5 − t: no real solution after t = 0.5 s. Without output times
    (uniform grid of DENSE_POINTS intervals) the rows up to t ≥ 0.49 s survive; on them x = 0.5 − t
    (1e-9: x' is constant) and y² = x to 5e-6 (the algebraic equation holds to the Newton tolerance,
    about rtol·|y| in y)."""
    sim = fl.Simulation(SqrtWall(init={"x": 0.5}, guess={"y": 0.7}), use_cache=False)
    with pytest.raises(fl.SolverError) as exc:
        sim.run(1.0, solver="casadi-idas", progress=False)
    res = exc.value.result
    assert res.status == "failed"
    assert 0.49 <= res.t[-1] <= 0.5 + 1e-9
    np.testing.assert_allclose(res["x"], 0.5 - res.t, atol=1e-9)
    np.testing.assert_allclose(res["y"] ** 2, res["x"], atol=5e-6)


class SwitchToBlowUp(fl.Model):
    """x' = 1 while x < 2, then x' = x²: x = 2 at t = 1 s, then x = 1/(1/2 − (t − 1)) blows up at t = 1.5 s."""

    x = Variable()

    def equations(self):
        return [eq(der(self.x), if_else(self.x < 2, 1.0, self.x**2))]


def test_blow_up_after_a_state_event_keeps_rows():
    """With a state relation (event at t = 1 s) the failure at t = 1.5 s still keeps every output up to one
    interval (0.1 s) before it; the message brackets the failure time; the rows after the event follow the
    exact solution to 2e-5·x² (the error equation e' = 2x·e, rtol 1e-6)."""
    sim = fl.Simulation(SwitchToBlowUp(init={"x": 1.0}), use_cache=False)
    grid = np.linspace(0.0, 3.0, 31)
    with pytest.raises(fl.SolverError, match="CasADi IDAS failed between t = ") as exc:
        sim.run(3.0, output_times=grid, solver="casadi-idas", progress=False)
    res = exc.value.result
    assert res.status == "failed" and len(res.events) == 1
    assert 1.4 - 1e-12 <= res.t[-1] < 1.5
    a, b = (float(v) for v in str(exc.value).split("between t = ")[1].split(" s (")[0].split(" s and t = "))
    assert a <= 1.5 <= b
    late = res.t > 1.0 + 1e-9
    exact = 1.0 / (0.5 - (res.t[late] - 1.0))
    assert np.all(np.abs(res["x"][late] - exact) <= 2e-5 * exact**2)


def test_jacobian_companion_that_does_not_compile_falls_back_to_the_symbolic_residual(monkeypatch):
    """The companion library (``jac_flexlib_res``) is compiled by gcc at the first casadi-idas run of a model
    with generated C; if gcc fails there, a ``CacheWarning`` names the model's library and gcc's message, and
    the run goes on with CasADi's symbolic residual (x = 1/(1 − t) to 1e-6 relative up to 0.9 s)."""
    import subprocess

    from flexlib.solve import casadi_dae

    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False, codegen=True)
    lib = sim.compiled.library
    assert lib is not None

    def failing_gcc(cmd, **kw):
        return subprocess.CompletedProcess(cmd, 1, "", "cc1: fatal error: no space left on device")

    monkeypatch.setattr(casadi_dae.subprocess, "run", failing_gcc)  # the companion is compiled there
    with pytest.warns(fl.CacheWarning, match="no space left on device") as rec:
        res = sim.run(0.9, dt_out=0.1, rtol=1e-9, atol=1e-11, solver="casadi-idas", progress=False)
    assert any(lib in str(w.message) for w in rec)
    assert not sim.compiled._functions["casadi_idas"].compiled
    np.testing.assert_allclose(res["x"], 1.0 / (1.0 - res.t), rtol=1e-6)


class NegativeRoot(fl.Model):
    """x' = −1 from 1, y = sqrt(x): square root of a negative number after t = 1 s."""

    x = Variable(unit="m")
    y = Variable(unit="m0.5")

    def equations(self):
        return [eq(der(self.x), -1.0), eq(self.y, ca.sqrt(self.x), label="square root")]


def test_sqrt_of_a_negative_names_the_equation_as_the_default_backend_does():
    """Issue 26: the run ended as "CasADi IDAS failed ... (IDA_LSETUP_FAIL)" without naming the equation; now the
    message carries the default backend's diagnosis at the last accepted point."""
    sim = fl.Simulation(NegativeRoot(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"(?s)CasADi IDAS failed between t = 1 s.*equation \(model\): square "
                                             r"root evaluates to nan.*x = -") as err:
        sim.run(2.0, solver="casadi-idas", progress=False)
    res = err.value.result
    assert res.status == "failed" and 0.99 < res.t[-1] <= 1.0
