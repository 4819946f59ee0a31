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

__all__ = ["eliminate_frame_kinematics"]


def eliminate_frame_kinematics(simple: SimpleSystem) -> SimpleSystem:
    """Substitute the explicit definitions of frame orientations ``T`` and origins ``r_0``."""
    ids = [k for k in frame_variables(simple) if simple.variables[k].info.name in ("T", "r_0")]
    if not ids:
        return simple
    vs, defs, rows = explicit_definitions(simple, ids)
    if vs.numel() == 0:
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
