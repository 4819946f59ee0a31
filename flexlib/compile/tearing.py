"""Elimination of explicit frame kinematics (the tree of a multibody model), before index reduction.

Along the spanning tree every frame's orientation matrix and origin are given explicitly by the
equation of the component that computes them (``T_b = T_rel(φ)·T_a``, ``r_b = r_a + T_aᵀ r``,
``T = T(Q)``). Substituting these definitions (in tree order) leaves a system in joint
coordinates and body variables — the recursive minimal-coordinate form — where a loop closure
is an ordinary constraint on joint angles that Pantelides' algorithm and dummy derivatives
handle directly. Derivatives of eliminated variables are replaced by the chain rule; results
still report every eliminated variable through its expression.

Angular velocities stay unknowns (they are integrated quantities of bodies); their tree
equations remain and are differentiated where needed.
"""

from __future__ import annotations

import dataclasses

import casadi as ca

from flexlib.compile.redundancy import explicit_definitions, frame_variables
from flexlib.compile.simplify import SimpleSystem
from flexlib.core.variables import der

__all__ = ["eliminate_explicit", "eliminate_frame_kinematics"]


def eliminate_frame_kinematics(simple: SimpleSystem) -> SimpleSystem:
    """Substitute the explicit definitions of frame orientations ``T`` and origins ``r_0``."""
    ids = [k for k in frame_variables(simple) if simple.variables[k].info.name in ("T", "r_0")]
    return _eliminate(simple, ids) if ids else simple


def eliminate_explicit(simple: SimpleSystem) -> SimpleSystem:
    """Substitute every algebraic unknown that one equation gives explicitly (``v = f(others)``).

    Candidates are unknowns whose derivative appears nowhere (cut forces and torques, angular
    velocities along a tree, sensor outputs); a maximum matching picks one defining equation per
    unknown, definitions in a cycle (an algebraic loop) are kept as equations.

    Not in the default pipeline: measured on an N-link chain (benchmarks/multibody.py) it cuts the
    unknowns 2.5× but makes the residual and Jacobian deep and dense (N = 10: 350 k Jacobian
    instructions, 1.1 ms per evaluation), so IDA with sparse LU is faster on the larger, local system.
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
    reduced = _eliminate(simple, ids, require_algebraic=True)
    return reduced if reduced.variables else simple  # a fully explicit model still needs one unknown for IDA


def _acyclic(vs: ca.SX, defs: ca.SX) -> list[int]:
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


def _eliminate(simple: SimpleSystem, ids: list[int], require_algebraic: bool = False) -> SimpleSystem:
    vs, defs, rows = explicit_definitions(simple, ids, require_algebraic)
    if vs.numel() == 0:
        return simple
    keep = _acyclic(vs, defs)
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
    names = list(simple.outputs)
    outputs = dict(zip(names, subst([simple.outputs[n] for n in names]), strict=True))
    cond_exprs = subst([c.expr for c in simple.conditions])
    conditions = [dataclasses.replace(c, expr=x) for c, x in zip(simple.conditions, cond_exprs, strict=True)]
    rel_exprs = subst([i for _, i in simple.relations])
    relations = [(rel, x) for (rel, _), x in zip(simple.relations, rel_exprs, strict=True)]
    rules = {h: e for h, e in simple.der_rules.items() if h not in eliminated}
    rule_keys = list(rules)
    rules = dict(zip(rule_keys, subst([rules[h] for h in rule_keys]), strict=True))
    return dataclasses.replace(simple, variables=variables, equations=equations, outputs=outputs,
                               conditions=conditions, relations=relations, der_rules=rules)
