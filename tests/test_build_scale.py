"""The build-time fast paths (issue 9, deliverables 7 and 9) give what the paths they replace gave.

* ``matching(fast=True)`` (Karp–Sipser start, used by the balance checks) finds a maximum matching of the same
  size and the same Dulmage–Mendelsohn culprits as the greedy MC21 matching, on seeded random incidences and
  on the flat incidence of a mass chain; reference: the greedy matching, exact equality.
* ``render_many`` gives the strings of ``render`` one by one (exact equality), so the DAE's row labels are
  unchanged.
* Assembly reusing the dummy-derivative selection's Jacobian gives the level Jacobians a fresh
  ``casadi.jacobian`` gives (values at a random point, exact equality).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
import scipy.sparse as sp

from flexlib.compile import pipeline
from flexlib.compile.flat_checks import check_balance
from flexlib.compile.flatten import describe_all, flatten
from flexlib.compile.structure import culprits, matching
from flexlib.core.variables import render
from flexlib.models.n_mass_chain import NMassChain
from flexlib.models.planar_mechanisms import FourBarLinkage


def _assert_same_maximum(inc: sp.csr_matrix) -> None:
    rm, cm = matching(inc)
    rf, cf = matching(inc, fast=True)
    assert (rf >= 0).sum() == (rm >= 0).sum()
    for r, c in enumerate(rf):  # a valid matching: matched pairs are non-zeros, both arrays agree
        if c >= 0:
            assert inc[r, c] != 0 and cf[c] == r
    assert np.count_nonzero(cf >= 0) == np.count_nonzero(rf >= 0)
    assert culprits(inc, rf, cf) == culprits(inc, rm, cm)


@pytest.mark.parametrize("seed", range(40))
def test_fast_matching_random_incidence(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n, m = rng.integers(1, 40, size=2)
    inc = sp.random(n, m, density=float(rng.uniform(0.02, 0.3)), format="csr", random_state=seed)
    _assert_same_maximum(inc)


def test_fast_matching_flat_chain() -> None:
    flat = flatten(NMassChain(30), check=False)
    syms = ca.vertcat(*[v.sym for v in flat.variables])
    ders = [k for k, v in enumerate(flat.variables) if v.info._der is not None]
    exprs = ca.vertcat(*[e.expr for e in flat.equations])
    inc = sp.csr_matrix(np.asarray(ca.DM(ca.jacobian_sparsity(exprs, syms), 1).full()))
    dinc = np.asarray(ca.DM(ca.jacobian_sparsity(exprs, ca.vertcat(*[flat.variables[k].info._der.sym
                                                                      for k in ders])), 1).full())
    full = inc.toarray()
    full[:, ders] += dinc
    _assert_same_maximum(sp.csr_matrix(full))
    _assert_same_maximum(sp.csr_matrix(full[:-3]))  # unbalanced: culprits must agree too
    check_balance(flat.name, flat.variables, flat.equations)


def test_render_many_matches_render() -> None:
    for model in (NMassChain(5), FourBarLinkage()):
        eqs = flatten(model, check=False).equations
        assert describe_all(eqs) == [e.describe() for e in eqs]
        assert [f"{render(e.expr, 110)} = 0" for e in eqs if not e.label] == \
            [t for t, e in zip(describe_all(eqs), eqs, strict=True) if not e.label]


def test_level_jacobians_reused() -> None:
    _, _, dae, _ = pipeline.analyse(FourBarLinkage())
    assert dae.levels and all(lev.jacobian is not None for lev in dae.levels)
    dummies, levels = dae.structure.select()
    fresh = dae.structure.assemble(dummies, [type(lev)(lev.rows, lev.cands, lev.costs, lev.selected)
                                             for lev in levels])  # no stored Jacobian: casadi.jacobian again
    assert fresh.names == dae.names
    assert len(fresh.level_jacobians) == len(dae.level_jacobians)
    for a, b in zip(fresh.level_jacobians, dae.level_jacobians, strict=True):
        assert a.sparsity() == b.sparsity()
        assert str(a) == str(b)  # the same expression, term by term
