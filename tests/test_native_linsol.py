"""The C driver's linear solvers (``flexlib.solve.backends.ida_c.linear_solver``): dense LU up to ``KLU_MIN`` unknowns,
KLU (kvxopt's SuiteSparse: BTF + AMD ordering once, a numeric factorisation per setup) above, SuperLU_MT when KLU
is not installed. The choice must not change the answer: on a model on each side of the size rule, every linear
solver gives the same trajectory to 1e-6 of each variable's range at rtol 1e-9 / atol 1e-11 (reference: the dense LU,
which factorises afresh with partial pivoting at every setup) where the trajectory is smooth, and against a run at
rtol 1e-11 / atol 1e-13 where it is sensitive (a three-link pendulum)."""

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.n_link_pendulum import NLinkPendulum
from flexlib.models.n_mass_chain import NMassChain
from flexlib.solve import native
from flexlib.solve.backends import ida_c

needs_klu = pytest.mark.skipif(not (native.native_available() and native.klu_available()),
                               reason="C driver or kvxopt's KLU unavailable")


def _runs(sim: fl.Simulation, t_end: float, monkeypatch: pytest.MonkeyPatch) -> dict[str, fl.Result]:
    out = {}
    for ls in ("dense", "superlumt", "klu"):
        monkeypatch.setenv("FLEXLIB_LINSOL", ls)
        out[ls] = sim.run(t_end, dt_out=0.01, rtol=1e-9, atol=1e-11, progress=False)
        assert out[ls].stats["linear_solver"] == ls
    return out


def _max_rel_dev(a: fl.Result, b: fl.Result) -> float:
    """Largest difference on the common grid relative to each variable's range in ``b`` (at least 1e-6)."""
    np.testing.assert_array_equal(a.t, b.t)
    va, vb = np.asarray(a.values), np.asarray(b.values)
    scale = np.maximum(vb.max(axis=0) - vb.min(axis=0), 1e-6)
    return float(np.max(np.abs(va - vb) / scale))


@needs_klu
def test_small_model_is_dense_and_all_solvers_agree(monkeypatch):
    """A chain of six masses (19 unknowns, below ``KLU_MIN``): the rule picks dense LU; SuperLU_MT and KLU give the
    same trajectory over 20 s to 1e-6 of each variable's range."""
    sim = fl.Simulation(NMassChain(6))
    assert sim.compiled.n <= ida_c.KLU_MIN
    monkeypatch.delenv("FLEXLIB_LINSOL", raising=False)
    assert ida_c.linear_solver(sim.compiled) == "dense"
    res = _runs(sim, 20.0, monkeypatch)
    for ls in ("superlumt", "klu"):
        assert res[ls].success
        assert _max_rel_dev(res[ls], res["dense"]) < 1e-6, ls


@needs_klu
def test_large_model_is_klu_refactorised_and_all_solvers_agree(monkeypatch):
    """A three-link pendulum of 3D bodies (99 unknowns, above ``KLU_MIN``): the rule picks KLU, which factorises
    once per setup (one setup per Jacobian). The motion is sensitive (the three solvers differ by 3e-6..1e-5 of a
    variable's range after 3 s at rtol 1e-9), so each is compared with a run at rtol 1e-11: every solver within 2e-5
    of each variable's range (measured 2e-6 KLU, 5e-6 dense, 1e-5 SuperLU_MT), and KLU's error at most twice the
    dense LU's."""
    monkeypatch.setenv("FLEXLIB_EXPLICIT", "0")  # the DAE as measured (99 unknowns); the stage would leave 32
    sim = fl.Simulation(NLinkPendulum(3), assume_zero_geometry=False)
    assert sim.compiled.n > ida_c.KLU_MIN
    monkeypatch.delenv("FLEXLIB_LINSOL", raising=False)
    assert ida_c.linear_solver(sim.compiled) == "klu"
    ref = sim.run(3.0, dt_out=0.01, rtol=1e-11, atol=1e-13, progress=False)
    res = _runs(sim, 3.0, monkeypatch)
    st = res["klu"].stats
    assert 1 <= st["n_factor_full"] == st["n_lsetup"] == st["njev"]
    assert st["n_lsolve"] >= st["nfev"] - st["steps"]  # one solve per Newton iteration
    err = {ls: _max_rel_dev(r, ref) for ls, r in res.items()}
    assert all(r.success for r in res.values())
    assert max(err.values()) < 2e-5, err
    assert err["klu"] <= 2.0 * err["dense"], err


@needs_klu
def test_without_klu_the_rule_falls_back(monkeypatch):
    """Without KLU: dense LU up to ``DENSE_MAX`` unknowns (as on the scikit-sundae route), SuperLU_MT above."""
    monkeypatch.delenv("FLEXLIB_LINSOL", raising=False)
    monkeypatch.setattr(ida_c, "klu_available", lambda: False)

    class Sized:
        def __init__(self, n: int) -> None:
            self.n = n

    from flexlib.solve.backends.base import DENSE_MAX

    assert ida_c.linear_solver(Sized(DENSE_MAX)) == "dense"
    assert ida_c.linear_solver(Sized(DENSE_MAX + 1)) == "superlumt"
