"""Substitution of unknowns that rows define explicitly (``v = f(others)``), in the simplified system.

:func:`explicit_definitions` finds, for a set of candidate unknowns, rows that give each one explicitly (linear in
it with a unit coefficient), one row per unknown by a maximum matching; :func:`eliminate` substitutes them
(definitions in a dependency cycle are kept as rows; derivatives of eliminated unknowns follow the chain rule;
results still report every eliminated unknown through its expression). The multibody pass uses them to tear the
frame kinematics along its tree (:mod:`flexlib.compile.passes.multibody.tearing`); :func:`eliminate_explicit`
applies them to every algebraic unknown.
"""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np
import scipy.sparse as sp

from flexlib.compile.simplify import SimpleSystem
from flexlib.compile.structure import matching, unit_coefficients
from flexlib.core.equations import der
from flexlib.core.variables import lookup

__all__ = ["acyclic", "eliminate", "eliminate_explicit", "explicit_definitions", "is_derivative"]


def explicit_definitions(simple: SimpleSystem, var_ids: list[int],
                         require_algebraic: bool = False) -> tuple[ca.SX, ca.SX, list[int]]:
    """Symbols, expressions ``v := f(...)`` and defining rows, from rows explicit in a frame variable
    (linear in it with a unit coefficient), chosen by a maximum matching."""
    eqs = simple.equations
    entries, coefs = [], {}
    syms = {k: simple.variables[k].sym for k in var_ids}
    position = {syms[k].element_hash(): j for j, k in enumerate(var_ids)}
    cand_rows, cand_js = [], []
    for r, e in enumerate(eqs):
        if e.origin == "loop closure":
            continue
        symbols = ca.symvar(e.expr)
        if require_algebraic and any(is_derivative(s) for s in symbols):
            continue  # a row with derivatives (a dynamic equation) stays: it defines a derivative
        # the candidates this row contains, in the order of var_ids (a lookup per symbol, not a scan of var_ids)
        js = sorted(j for j in (position.get(s.element_hash()) for s in symbols) if j is not None)
        if js:
            cand_rows.append(r)
            cand_js.append(js)
    found = unit_coefficients([eqs[r].expr for r in cand_rows], [[syms[var_ids[j]] for j in js] for js in cand_js])
    for r, js, units in zip(cand_rows, cand_js, found, strict=True):
        for k, c in units:
            entries.append((r, js[k]))
            coefs[(r, js[k])] = c
    if not entries:
        return ca.SX(0, 1), ca.SX(0, 1), []
    rr, cc = zip(*entries, strict=True)
    inc = sp.csr_matrix((np.ones(len(rr)), (rr, cc)), shape=(len(eqs), len(var_ids)))
    _, col_match = matching(inc)
    vs, defs, rows = [], [], []
    for j, r in enumerate(col_match):
        if r < 0:
            continue
        sym = syms[var_ids[j]]
        rest = ca.substitute(eqs[r].expr, sym, ca.SX(0.0))
        vs.append(sym)
        defs.append(-rest / coefs[(int(r), j)])
        rows.append(int(r))
    if not vs:
        return ca.SX(0, 1), ca.SX(0, 1), []
    return ca.vertcat(*vs), ca.vertcat(*defs), rows


def is_derivative(sym: ca.SX) -> bool:
    info = lookup(sym)
    return info is not None and info.kind == "der"


def eliminate_explicit(simple: SimpleSystem) -> SimpleSystem:
    """Substitute every algebraic unknown that one equation gives explicitly (``v = f(others)``).

    Candidates are unknowns whose derivative appears nowhere (cut forces and torques, angular
    velocities along a tree, sensor outputs); a maximum matching picks one defining equation per
    unknown, definitions in a cycle (an algebraic loop) are kept as equations.

    Not in the default pipeline: on a long chain it makes the residual and Jacobian deep and dense, and IDA with
    sparse LU is faster on the larger, local system (``docs/decisions/004-explicit-algebraics-eliminated.md``).
    """
    present: set[int] = set()
    for e in simple.equations:
        present.update(s.element_hash() for s in ca.symvar(e.expr))
    for rule in simple.der_rules.values():
        present.update(s.element_hash() for s in ca.symvar(rule))
    ids = [k for k, v in enumerate(simple.variables)
           if (v.info._der is None or v.info._der.sym.element_hash() not in present)
           and v.sym.element_hash() not in simple.der_rules]
    if not ids:
        return simple
    reduced = eliminate(simple, ids, require_algebraic=True)
    return reduced if reduced.variables else simple  # a fully explicit model still needs one unknown for IDA


def acyclic(vs: ca.SX, defs: ca.SX) -> list[int]:
    """Indices of definitions that are not part of a dependency cycle."""
    import numpy as np
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    n = vs.numel()
    spj = ca.jacobian_sparsity(defs, vs)
    colind, row = spj.get_ccs()
    cols = np.repeat(np.arange(n), np.diff(np.asarray(colind)))
    graph = sp.csr_matrix((np.ones(len(row)), (np.asarray(row), cols)), shape=(n, n))
    _, labels = connected_components(graph, directed=True, connection="strong")
    sizes = np.bincount(labels)
    self_loop = np.asarray(graph.diagonal()) != 0
    return [k for k in range(n) if sizes[labels[k]] == 1 and not self_loop[k]]


def eliminate(simple: SimpleSystem, ids: list[int], require_algebraic: bool = False,
               found: tuple[ca.SX, ca.SX, list[int]] | None = None) -> SimpleSystem:
    vs, defs, rows = found if found is not None else explicit_definitions(simple, ids, require_algebraic)
    if vs.numel() == 0:
        return simple
    keep = acyclic(vs, defs)
    if len(keep) < vs.numel():
        vs = ca.vertcat(*[vs[k] for k in keep]) if keep else ca.SX(0, 1)
        defs = ca.vertcat(*[defs[k] for k in keep]) if keep else ca.SX(0, 1)
        rows = [rows[k] for k in keep]
        if not keep:
            return simple
    # resolve definitions in terms of non-eliminated unknowns (tree depth substitutions at most)
    for _ in range(vs.numel() + 1):
        if not ca.depends_on(defs, vs):
            break
        defs = ca.substitute([defs], [vs], [defs])[0]
    else:  # a cycle of definitions: leave the system as it is
        return simple
    eliminated = {vs[k].element_hash(): k for k in range(vs.numel())}
    # derivatives of eliminated variables that appear anywhere: chain rule on the resolved definition
    olds, news = [vs], [defs]
    present = set()
    for e in simple.equations:
        present.update(s.element_hash() for s in ca.symvar(e.expr))
    for v in simple.variables:
        h = v.sym.element_hash()
        if h in eliminated and v.info._der is not None and v.info._der.sym.element_hash() in present:
            olds.append(v.info._der.sym)
            news.append(der(defs[eliminated[h]]))
    old, new = ca.vertcat(*olds), ca.vertcat(*news)

    def subst(exprs: list[ca.SX]) -> list[ca.SX]:
        if not exprs:
            return []
        out = ca.substitute([ca.vertcat(*exprs)], [old], [new])[0]
        return [out[k] for k in range(out.numel())]

    drop = set(rows)
    kept_eqs = [e for r, e in enumerate(simple.equations) if r not in drop]
    new_exprs = subst([e.expr for e in kept_eqs])
    equations = [dataclasses.replace(e, expr=x) for e, x in zip(kept_eqs, new_exprs, strict=True)]
    variables = [v for v in simple.variables if v.sym.element_hash() not in eliminated]
    signals = simple.substituted_signals(subst)
    rules = {h: e for h, e in simple.der_rules.items() if h not in eliminated}
    rule_keys = list(rules)
    rules = dict(zip(rule_keys, subst([rules[h] for h in rule_keys]), strict=True))
    return dataclasses.replace(simple, variables=variables, equations=equations, der_rules=rules, **signals)
