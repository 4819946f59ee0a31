"""Dummy-derivative selection of the index reduction (Mattsson–Söderlind).

The columns and rows of the differentiated system (:class:`Col`, :class:`Row`), the numeric point the selection
pivots at, and the choice, level by level, of the derivatives that become dummies (algebraic unknowns) so that
the remaining states are independent.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import scipy.linalg as sla

from flexlib.compile.flatten import FlatVariable
from flexlib.compile.simplify import SimpleSystem
from flexlib.compile.structure import row_jacobian
from flexlib.core.variables import StateSelect, SymInfo, time
from flexlib.errors import StructuralSingularityError

__all__ = ["Col", "Level", "Row", "col_name", "dummy_cost", "lookup_hash", "numeric_point", "pick_columns",
           "select_dummies", "structural_pick"]

log = logging.getLogger("flexlib.compile.index_reduction")


@dataclass(eq=False)
class Col:
    var: int          # index into SimpleSystem.variables
    order: int
    info: SymInfo
    der: int = -1     # column of the derivative, -1 if none


@dataclass(eq=False)
class Row:
    source: int       # original equation index
    order: int        # times differentiated
    inc: set[int]
    expr: ca.SX | None = None
    der: int = -1     # row of the derivative, -1 if none
    pred: int = -1    # row this one is the derivative of



@dataclass(eq=False)
class Level:
    """One level of the dummy-derivative selection (Mattsson–Söderlind): ``need`` of the candidate
    derivatives ``cands`` are made dummies so that the block of ``rows`` over them is regular."""

    rows: list[int]
    cands: list[int]
    costs: list[int]
    selected: list[int]
    jacobian: ca.SX | None = field(default=None, repr=False)
    """d(rows)/d(cands), symbolic, as the selection built it (assembly reuses it instead of a second jacobian)."""


def numeric_point(simple: SimpleSystem, cols: list[Col], param_values: dict[int, float]) -> tuple[ca.SX, np.ndarray]:
    syms, vals = [time], [0.0]
    for c in cols:
        syms.append(c.info.sym)
        vals.append(simple.variables[c.var].start if c.order == 0 else 0.0)
    for h, val in param_values.items():
        info = lookup_hash(h)
        if info is not None:
            syms.append(info.sym)
            vals.append(val)
    return ca.vertcat(*syms), np.array(vals)


def lookup_hash(h: int) -> SymInfo | None:
    """Registry entry by element hash."""
    from flexlib.core.variables import lookup_hash as registry_entry

    return registry_entry(h)


def dummy_cost(col: Col, cols: list[Col], variables: list[FlatVariable]) -> int:
    """Cost of making ``col`` a dummy derivative (= removing its antiderivative from the states)."""
    if col.order >= 2:
        return -1  # the antiderivative is itself a generated derivative
    return int(variables[col.var].state_select)


def select_dummies(rows: list[Row], cols: list[Col], variables: list[FlatVariable],
                    simple: SimpleSystem, param_values: dict[int, float],
                    point: tuple[ca.SX, np.ndarray] | None = None) -> tuple[set[int], list[Level]]:
    g = [k for k, r in enumerate(rows) if r.der < 0]
    z = [k for k, c in enumerate(cols) if c.der < 0]
    anti = {c.der: k for k, c in enumerate(cols) if c.der >= 0}
    dummies: set[int] = set()
    levels: list[Level] = []
    if not any(rows[k].order > 0 for k in g):
        return dummies, levels
    if point is None:
        point_syms, point_vals = numeric_point(simple, cols, param_values)
        # relations: freeze at their start values
        rel_syms = [rel.info.sym for rel, _ in simple.relations]
        if rel_syms:  # (a latch's indicator reads discrete values: iterated from 0 as the start's iteration is)
            rel_vec = ca.vertcat(*rel_syms)
            ind = ca.Function("ind", [point_syms, rel_vec], [ca.vertcat(*[i for _, i in simple.relations])])
            values = np.zeros(len(rel_syms))
            for _ in range(len(rel_syms) + 1):
                zval = np.asarray(ind(point_vals, values)).ravel()
                new = np.array([float(rel.value(z)) for (rel, _), z in zip(simple.relations, zval, strict=True)])
                if np.array_equal(new, values):
                    break
                values = new
            point_syms = ca.vertcat(point_syms, rel_vec)
            point_vals = np.concatenate([point_vals, values])
    else:
        point_syms, point_vals = point
    level = 1
    while True:
        g_diff = [r for r in g if rows[r].order > 0]
        if not g_diff:
            break
        cand = [c for c in z if cols[c].order > 0]
        need = len(g_diff)
        if len(cand) < need:
            raise StructuralSingularityError(
                f"dummy derivative selection failed at level {level}: {need} differentiated equations but only "
                f"{len(cand)} candidate derivatives")
        jexpr = row_jacobian(ca.vertcat(*[rows[r].expr for r in g_diff]), ca.vertcat(*[cols[c].info.sym for c in cand]))
        jfun = ca.Function("jsel", [point_syms], [jexpr])
        J = np.asarray(jfun(point_vals))
        costs = [dummy_cost(cols[c], cols, variables) for c in cand]
        selected = pick_columns(J, cand, costs, need)
        if selected is None:
            log.warning("dummy derivative selection is numerically singular at the start values "
                        "(level %d); using a structural selection", level)
            selected = structural_pick(J != 0, cand, need, jexpr)
        dummies.update(selected)
        levels.append(Level(list(g_diff), list(cand), costs, list(selected), jexpr))
        always = [cols[anti[c]] for c in selected if cols[anti[c]].order == 0
                  and variables[cols[anti[c]].var].state_select is StateSelect.always]
        for col in always:
            log.warning("%s has state_select='always' but cannot be a state", variables[col.var].name)
        g = [rows[r].pred for r in g_diff]
        z = [anti[c] for c in selected]
        level += 1
    return dummies, levels


def pick_columns(J: np.ndarray, cand: list[int], cost: list[int], need: int) -> list[int] | None:
    """Choose ``need`` columns of ``J`` forming a well-conditioned square block, cheapest cost classes first."""
    scale = max(1.0, float(np.abs(J).max()) if J.size else 1.0)
    tol = 1e-9 * scale
    chosen: list[int] = []
    Q = np.zeros((J.shape[0], 0))
    for level in sorted(set(cost)):
        if len(chosen) == need:
            break
        idx = [k for k in range(len(cand)) if cost[k] == level]
        A = J[:, idx]
        A = A - Q @ (Q.T @ A)
        if not np.any(np.abs(A) > tol):
            continue
        _, R, piv = sla.qr(A, mode="economic", pivoting=True)
        diag = np.abs(np.diag(R))
        for k in range(len(diag)):
            if len(chosen) == need or diag[k] <= tol:
                break
            chosen.append(idx[piv[k]])
        Q, _ = np.linalg.qr(J[:, chosen]) if chosen else (Q, None)
    if len(chosen) < need:
        return None
    return [cand[k] for k in chosen]


def structural_pick(mask: np.ndarray, cand: list[int], need: int, jexpr: ca.SX) -> list[int]:
    from flexlib.compile.structure import matching

    spj = jexpr.sparsity()
    colind, row = spj.get_ccs()
    import scipy.sparse as sp

    inc = sp.csc_matrix((np.ones(len(row)), np.asarray(row), np.asarray(colind)), shape=spj.shape).tocsr()
    row_match, _ = matching(inc)
    if np.any(row_match < 0):
        raise StructuralSingularityError(
            "dummy derivative selection: differentiated equations are structurally singular")
    return [cand[c] for c in row_match]


def col_name(col: Col, variables: list[FlatVariable]) -> str:
    name = variables[col.var].name
    for _ in range(col.order):
        name = f"der({name})"
    return name

