"""Stage 2 — simplify: alias elimination.

Equations of the form ``a = b``, ``a = -b``, ``a = constant`` and ``a = parameter``
(most connection equations and the ``phi = flange_a.phi`` lines of every component)
are removed; each alias class keeps one representative, chosen by state-selection
preference, then internal variables before connector variables, then initial
conditions. Every eliminated variable keeps an expression in the representatives, so
results still report it and initial conditions on it still apply.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import casadi as ca

from flexlib.compile.flatten import FlatEquation, FlatSystem, FlatVariable
from flexlib.core.component import Connector
from flexlib.core.functions import Relation
from flexlib.core.variables import render_many
from flexlib.errors import InitializationError

__all__ = ["Condition", "SimpleSystem", "simplify"]


@dataclass(eq=False)
class Condition:
    """An initial condition ``expr = value`` coming from a fixed start value of variable ``name``."""

    name: str
    expr: ca.SX
    value: float


@dataclass(eq=False)
class SimpleSystem:
    """Output of stage 2.

    Attributes
    ----------
    variables : list of FlatVariable
        Remaining unknowns (alias representatives and non-aliased variables).
    equations : list of FlatEquation
        Remaining equations, written in the remaining unknowns.
    outputs : dict of str to casadi.SX
        Every variable of the flat model (eliminated or not) as an expression of the
        remaining unknowns and the parameters.
    conditions : list of Condition
        Initial conditions (fixed start values), in the remaining unknowns.
    relations : list of tuple(Relation, casadi.SX)
        Event relations and their indicators in the remaining unknowns.
    n_eliminated : int
        Number of alias equations removed.
    """

    flat: FlatSystem
    variables: list[FlatVariable]
    equations: list[FlatEquation]
    outputs: dict[str, ca.SX]
    conditions: list[Condition]
    relations: list[tuple[Relation, ca.SX]]
    n_eliminated: int
    der_rules: dict[int, ca.SX] = dataclasses.field(default_factory=dict)
    """Derivative rules of remaining unknowns (by symbol hash), written in the remaining unknowns."""
    redundant: list[str] = dataclasses.field(default_factory=list)
    """Redundant loop-closure constraints that were dropped (filled by ``redundancy.remove_redundant``)."""
    indeterminate: dict[str, list[int]] = dataclasses.field(default_factory=dict)
    """Variables (by name) that the dropped rows leave statically indeterminate, each with the indices in
    ``redundant`` of the rows that do (filled by ``passes.multibody.indeterminate``)."""
    assumed: dict[str, str] = dataclasses.field(default_factory=dict)
    """Conditions on parameters (name → ``"= 0"``, ``"> 0"``, ``"< 0"``) that the elimination of constants
    relies on (``constants.py``); a run violating one is refused."""
    n_constants: int = 0
    """Number of unknowns found constant (``constants.eliminate_constants``)."""
    tree_frames: str = ""
    start_guesses: dict[str, float] = dataclasses.field(default_factory=dict)
    """Build-time start guesses of unknowns that have no start of their own (kept tree frames), by name."""
    """Whether the tree's frame kinematics were torn or kept as unknowns, and why (``tearing.tear_or_keep_frames``)."""

    def substituted_signals(self, subst: Callable[[list[ca.SX]], list[ca.SX]]) -> dict[str, Any]:
        """``outputs``, ``conditions`` and ``relations`` with ``subst`` applied to their expressions (one call per
        kind, in that order), as keywords for :func:`dataclasses.replace`."""
        names = list(self.outputs)
        outputs = dict(zip(names, subst([self.outputs[n] for n in names]), strict=True))
        cond_exprs = subst([c.expr for c in self.conditions])
        conditions = [dataclasses.replace(c, expr=x) for c, x in zip(self.conditions, cond_exprs, strict=True)]
        rel_exprs = subst([i for _, i in self.relations])
        relations = [(rel, x) for (rel, _), x in zip(self.relations, rel_exprs, strict=True)]
        return {"outputs": outputs, "conditions": conditions, "relations": relations}


def _classify(flat: FlatSystem, e: ca.SX) -> tuple | None:
    """``(a, b, sign)`` for ``a = sign*b``, ``(a, value_expr)`` for ``a = const/param``, else None."""

    def var(x: ca.SX) -> int | None:
        if x.is_symbolic():
            return flat.by_hash.get(x.element_hash())
        return None

    def known(x: ca.SX) -> bool:
        if x.is_constant():
            return True
        if x.is_symbolic():
            from flexlib.core.variables import lookup

            info = lookup(x)
            return info is not None and info.kind == "parameter"
        return False

    if e.is_symbolic():
        a = var(e)
        return None if a is None else (a, ca.SX(0.0))
    op = e.op()
    if op == ca.OP_NEG:
        a = var(e.dep(0))
        return None if a is None else (a, ca.SX(0.0))
    if op not in (ca.OP_SUB, ca.OP_ADD):
        return None
    d0, d1 = e.dep(0), e.dep(1)
    s = 1.0 if op == ca.OP_SUB else -1.0
    a, b = var(d0), var(d1)
    if a is not None and b is not None:
        return (a, b, s)
    if a is not None and d1.is_op(ca.OP_NEG):
        b = var(d1.dep(0))
        if b is not None:
            return (a, b, -s)
    if a is not None and known(d1):
        return (a, d1 if s == 1.0 else -d1)
    if b is not None and known(d0):
        return (b, s * d0) if op == ca.OP_SUB else (b, -d0)
    return None


def _priority(v: FlatVariable, index: int) -> tuple:
    internal = not isinstance(v.info.node, Connector)
    return (int(v.state_select), internal, v.fixed, -v.name.count("."), -len(v.name), -index)


def _alias_classes(flat: FlatSystem) -> tuple[dict[int, list[tuple[int, float]]], dict[int, ca.SX],
                                               list[FlatEquation], int]:
    """Alias classes (root → members with their signs) of the alias and binding equations, the value bound to a class,
    the equations kept, and the number eliminated."""
    n = len(flat.variables)
    parent = list(range(n))
    sign = [1.0] * n
    binding: dict[int, ca.SX] = {}
    kept_eqs: list[FlatEquation] = []

    def find(i: int) -> tuple[int, float]:
        """Root of ``i`` and the sign ``s`` with ``value_i = s * value_root`` (path compression)."""
        path = []
        while parent[i] != i:
            path.append(i)
            i = parent[i]
        acc = 1.0
        for j in reversed(path):
            acc *= sign[j]
            sign[j], parent[j] = acc, i
        return i, (sign[path[0]] if path else 1.0)

    n_elim = 0
    for equ in flat.equations:
        cls = None if equ.origin == "loop closure" else _classify(flat, equ.expr)
        if cls is None:
            kept_eqs.append(equ)
            continue
        if len(cls) == 3:
            a, b, s = cls
            ra, sa = find(a)
            rb, sb = find(b)
            if ra == rb or (ra in binding and rb in binding):
                kept_eqs.append(equ)
                continue
            # a = s*b, a = sa*ra, b = sb*rb  ->  ra = s*sa*sb * rb
            parent[ra], sign[ra] = rb, s * sa * sb
            if ra in binding:
                binding[rb] = sign[ra] * binding.pop(ra)
        else:
            a, value = cls
            ra, sa = find(a)
            if ra in binding:
                kept_eqs.append(equ)
                continue
            binding[ra] = sa * value
        n_elim += 1

    classes: dict[int, list[tuple[int, float]]] = {}
    for i in range(n):
        r, s = find(i)
        classes.setdefault(r, []).append((i, s))
    return classes, binding, kept_eqs, n_elim


def _representatives(flat: FlatSystem, classes: dict[int, list[tuple[int, float]]], binding: dict[int, ca.SX]
                     ) -> tuple[list[FlatVariable], dict[int, ca.SX]]:
    """One variable per unbound class (declarations merged over its members) and the value of every variable."""
    kept_vars: list[FlatVariable] = []
    value_of: dict[int, ca.SX] = {}
    for root, members in classes.items():
        if root in binding:
            bound = binding[root]
            negated = None
            for i, s in members:
                if s == 1.0:
                    value_of[i] = bound
                else:
                    negated = -bound if negated is None else negated  # one node per class and sign
                    value_of[i] = negated
            continue
        rep, s_rep = max(members, key=lambda m: _priority(flat.variables[m[0]], m[0]))
        rv = flat.variables[rep]
        merged = dataclasses.replace(
            rv,
            state_select=max(flat.variables[i].state_select for i, _ in members),
            nominal=max(flat.variables[i].nominal for i, _ in members),
            # an alias of a derivative-level variable (a joint's acceleration, say) is one too
            error_test=all(flat.variables[i].error_test for i, _ in members),
            intermediate=any(flat.variables[i].intermediate for i, _ in members),
        )
        if merged.start == 0.0:
            for i, s in members:
                if flat.variables[i].start != 0.0:
                    merged.start = s * s_rep * flat.variables[i].start
                    break
        kept_vars.append(merged)
        negated = None
        for i, s in members:
            if s * s_rep == 1.0:
                value_of[i] = rv.sym
            else:
                negated = -rv.sym if negated is None else negated  # one node per class and sign
                value_of[i] = negated
    return kept_vars, value_of


def _substitution(flat: FlatSystem, value_of: dict[int, ca.SX]) -> tuple[list[ca.SX], list[ca.SX]]:
    """Symbols of the eliminated variables (and their derivatives) and the expressions that replace them."""
    old_syms: list[ca.SX] = []
    new_exprs: list[ca.SX] = []
    for i, v in enumerate(flat.variables):
        val = value_of[i]
        if val.is_symbolic() and val.element_hash() == v.sym.element_hash():
            continue
        old_syms.append(v.sym)
        new_exprs.append(val)
        if v.info._der is not None:
            from flexlib.core.equations import der

            old_syms.append(v.info._der.sym)
            negated_var = (val.is_op(ca.OP_NEG) and val.dep(0).is_symbolic()
                           and val.dep(0).element_hash() in flat.by_hash)
            new_exprs.append(-der(val.dep(0)) if negated_var else der(val))  # der(-x) = -der(x)
    return old_syms, new_exprs


def _class_rules(flat: FlatSystem, classes: dict[int, list[tuple[int, float]]], binding: dict[int, ca.SX],
                 value_of: dict[int, ca.SX]) -> dict[int, ca.SX]:
    """Derivative rules: each alias class takes the rule of a member, rescaled by the member's sign."""
    rule_owner: dict[int, ca.SX] = {}
    for root, members in classes.items():
        if root in binding:
            continue
        rep_sym = value_of[members[0][0]]
        rep_sym = rep_sym if rep_sym.is_symbolic() else rep_sym.dep(0)
        for i, _ in members:
            v = flat.variables[i]
            if v.der_rule is not None:
                sgn = 1.0 if value_of[i].is_symbolic() else -1.0  # v = ±rep
                rule_owner[rep_sym.element_hash()] = sgn * v.der_rule
                break
    return rule_owner


def simplify(flat: FlatSystem) -> SimpleSystem:
    """Eliminate alias variables from a flat system."""
    classes, binding, kept_eqs, n_elim = _alias_classes(flat)
    kept_vars, value_of = _representatives(flat, classes, binding)
    old_syms, new_exprs = _substitution(flat, value_of)

    def subst(exprs: list[ca.SX]) -> list[ca.SX]:
        if not exprs or not old_syms:
            return exprs
        out = ca.substitute([ca.vertcat(*exprs)], [ca.vertcat(*old_syms)], [ca.vertcat(*new_exprs)])[0]
        return [out[k] for k in range(out.numel())]

    rule_owner = _class_rules(flat, classes, binding, value_of)
    rule_hashes = list(rule_owner)
    rule_exprs = subst([rule_owner[h] for h in rule_hashes])
    der_rules = dict(zip(rule_hashes, rule_exprs, strict=True))
    new_eq_exprs = subst([e.expr for e in kept_eqs])
    equations = [dataclasses.replace(e, expr=x) for e, x in zip(kept_eqs, new_eq_exprs, strict=True)]
    rel_ind = subst([r.indicator for r in flat.relations])
    relations = list(zip(flat.relations, rel_ind, strict=True))
    outputs = {v.name: value_of[i] for i, v in enumerate(flat.variables)}
    conditions = _conditions(flat, value_of)
    initial_exprs = subst([e.expr for e in flat.initial])
    # an initial equation without a label of its own is named by its text (der(spring.w_rel) = 0)
    plain = [k for k, e in enumerate(flat.initial) if e.label == "initial equation"]
    texts = dict(zip(plain, render_many([flat.initial[k].expr for k in plain], 110), strict=True))
    for k, (e, expr) in enumerate(zip(flat.initial, initial_exprs, strict=True)):
        label = f"{texts[k]} = 0" if k in texts else e.label
        conditions.append(Condition(f"{e.owner or '(model)'}: {label} #{k}", expr, 0.0))
    return SimpleSystem(flat, kept_vars, equations, outputs, conditions, relations, n_elim, der_rules)


def _conditions(flat: FlatSystem, value_of: dict[int, ca.SX]) -> list[Condition]:
    """Initial conditions from fixed start values, with duplicates on one alias class merged."""
    seen: dict[int, tuple[str, float]] = {}
    out: list[Condition] = []
    var_hashes = {w.sym.element_hash() for w in flat.variables}  # a set lookup per symbol, not depends_on on all
    for i, v in enumerate(flat.variables):
        if not v.fixed:
            continue
        expr = value_of[i]
        if not any(s.element_hash() in var_hashes for s in ca.symvar(expr)):
            # bound to a constant/parameter: the condition is checked at initialisation time
            out.append(Condition(v.name, expr, v.start))
            continue
        if expr.is_symbolic():
            key, sgn = expr.element_hash(), 1.0
        elif expr.op() == ca.OP_NEG and expr.dep(0).is_symbolic():
            key, sgn = expr.dep(0).element_hash(), -1.0
        else:
            out.append(Condition(v.name, expr, v.start))
            continue
        if key in seen:
            other, val = seen[key]
            if abs(sgn * v.start - val) > 1e-12 * max(1.0, abs(val)):
                raise InitializationError(
                    f"conflicting initial conditions: {other} and {v.name} = {v.start:g} are connected "
                    "(aliases) but have different values")
            continue
        seen[key] = (v.name, sgn * v.start)
        out.append(Condition(v.name, expr, v.start))
    return out
