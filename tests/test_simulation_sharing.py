"""``Simulation.initialize`` (the consistent start alone), ``Simulation.with_model`` (one build for instances that
differ only in values), and the symbolic helpers behind faster builds (``row_jacobian``, batched
``unit_coefficients``)."""

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib.compile.structure import DENSE_ROW_NNZ, row_jacobian, unit_coefficients
from tests.test_engine_api import Orbit, Tank, TwoLags


def _orbit(t, r0, v0, c, m=1.0):
    """r(t) = r0 cos(ωt) + v0/ω sin(ωt), ω = sqrt(c/m): the isotropic oscillator's closed form."""
    w = np.sqrt(c / m)
    return np.outer(np.cos(w * t), r0) + np.outer(np.sin(w * t), np.asarray(v0) / w)


def test_initialize_is_the_first_row_of_a_run(tmp_path, monkeypatch):
    """initialize() gives one row at t_start, equal to the first row of run() (1e-12), with no steps; the start
    itself is the model's: r = (1, 0, 0), v = (0, 0.5, 0.1)."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    sim = fl.Simulation(Orbit())
    start = sim.initialize()
    assert start.t.tolist() == [0.0] and start.stats["steps"] == 0
    np.testing.assert_allclose(start["mass.port.r"][0], [1.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(start["mass.v"][0], [0.0, 0.5, 0.1], atol=1e-12)
    run = sim.run(0.5, dt_out=0.25)
    np.testing.assert_allclose(start.values[0], run.values[0], rtol=1e-12, atol=1e-12)
    assert sim.initialize(t_start=2.0).t.tolist() == [2.0]
    with pytest.raises(fl.RunArgumentError, match="t_start"):
        sim.initialize(t_start="soon")
    with pytest.raises(fl.InitializationError, match=r"under-specified[\s\S]*\bp\b"):
        fl.Simulation(Tank()).initialize()


def test_with_model_shares_the_build_of_an_instance_with_other_values(tmp_path, monkeypatch):
    """Another start value and another stiffness are values: the build is shared (the same compiled model), and
    each instance runs its own oscillation (closed form, 1e-5); the first Simulation is unchanged."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    sim = fl.Simulation(Orbit())
    other = Orbit(c=9.0)
    other.mass.port.set_start("r", [2.0, 0.0, -1.0], fixed=True)
    sim2 = sim.with_model(other)
    assert sim2.compiled is sim.compiled and sim2.model is other and sim.model is not other
    t = np.linspace(0.0, 2.0, 41)
    res2 = sim2.run(2.0, output_times=t, rtol=1e-9, atol=1e-11)
    np.testing.assert_allclose(res2["mass.port.r"], _orbit(t, [2.0, 0.0, -1.0], [0.0, 0.5, 0.1], 9.0), atol=1e-5)
    res = sim.run(2.0, output_times=t, rtol=1e-9, atol=1e-11)
    np.testing.assert_allclose(res["mass.port.r"], _orbit(t, [1.0, 0.0, 0.0], [0.0, 0.5, 0.1], 4.0), atol=1e-5)


def test_with_model_builds_another_structure(tmp_path, monkeypatch):
    """An instance of another structure gets its own build (checked, not assumed), with or without the cache."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    for use_cache in (True, False):
        sim = fl.Simulation(Orbit(), use_cache=use_cache)
        lags = sim.with_model(TwoLags())
        assert lags.compiled is not sim.compiled and sorted(lags.states) == ["x", "z"]
        assert lags.initialize(steady_state=True)["z"][0] == pytest.approx(2.0, rel=1e-12)
        with pytest.raises(TypeError, match="Component"):
            sim.with_model("Orbit")


def test_row_jacobian_matches_casadi_with_fewer_operations():
    """40 coordinates act through 3 shared numbers (as a flexible section's modal coordinates act on the frames
    below it through its tip frame), and each of 30 rows works on those 3 through a long expression of its own:
    the row-by-row Jacobian equals CasADi's (same pattern, values to 1e-13) with fewer operations (CasADi's
    all-rows-at-once forward mode runs every row's expression once per coordinate); sparse rows alone give
    CasADi's own Jacobian."""
    x = ca.SX.sym("x", 40)
    rng = np.random.default_rng(3)
    u = ca.mtimes(ca.DM(rng.standard_normal((3, 40))), x)
    dense = []
    for i in range(30):
        v = (i + 1) * u[0]
        for _ in range(20):
            v = ca.sin(v) * u[1] + ca.cos(v) * u[2]
        dense.append(v)
    sparse = [x[i] * x[i + 1] for i in range(10)]
    F = ca.vertcat(*dense[:15], *sparse, *dense[15:])
    J_ref, J = ca.jacobian(F, x), row_jacobian(F, x)
    assert J.sparsity() == J_ref.sparsity()
    v0 = 0.1 * rng.standard_normal(40)
    a = ca.Function("a", [x], [J_ref])(v0).full()
    b = ca.Function("b", [x], [J])(v0).full()
    np.testing.assert_allclose(b, a, rtol=1e-13, atol=1e-13)
    assert ca.Function("b", [x], [J]).n_instructions() < 0.5 * ca.Function("a", [x], [J_ref]).n_instructions()
    S = ca.vertcat(*sparse)
    assert max(np.diff(np.asarray(ca.jacobian_sparsity(S, x).T.colind()))) <= DENSE_ROW_NNZ
    assert row_jacobian(S, x).sparsity() == ca.jacobian(S, x).sparsity()


def test_unit_coefficients_of_many_rows():
    """Per row, the listed symbols with a constant coefficient ±1: not 2, not a variable coefficient, not a
    nonlinear occurrence; a symbol shared between rows is judged in each row on its own."""
    x, y, z, w = (ca.SX.sym(n) for n in "xyzw")
    rows = [x + 2 * y, -z + x * y, 3 * w - x, ca.sin(y) + w, x]
    syms = [[x, y], [z, x, y], [w, x], [y, w], []]
    assert unit_coefficients(rows, syms) == [[(0, 1.0)], [(0, -1.0)], [(1, -1.0)], [(1, 1.0)], []]
    assert unit_coefficients([], []) == []
