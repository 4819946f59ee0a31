"""Stage 3b — simplification after index reduction.

Known state derivatives are substituted (where ``c·yp_s + f(y) = 0`` defines ``yp_s`` explicitly, it
replaces ``yp_s`` in the other rows; ``docs/decisions/005-known-derivatives-substituted.md``), and trivial algebraic
aliases left by the differentiation (``der(y) = v``) are eliminated. Then algebraic unknowns that
one row gives explicitly with a constant coefficient are eliminated where that does not make the
Jacobian denser (:mod:`flexlib.compile.explicit`).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from flexlib.compile.explicit import eliminate_explicit_algebraics
from flexlib.compile.structure import derivative_level

__all__ = ["post_simplify"]


def _linear_single(e: ca.SX, sym: ca.SX) -> bool:
    return bool(ca.is_linear(e, sym)) and ca.jacobian(e, sym).is_constant()


def _substitute_known_derivatives(rows: list[ca.SX], yp: ca.SX, differential: np.ndarray,
                                  inc_yp: list[list[int]]) -> None:
    """Replace, in place, each state derivative that a row defines explicitly by its definition in the other rows."""
    n = len(rows)
    # (a) known derivatives: row = c*yp_s + f(y), f without yp
    defined: dict[int, tuple[int, ca.SX]] = {}
    for r in range(n):
        if len(inc_yp[r]) != 1:
            continue
        i = inc_yp[r][0]
        if not differential[i] or i in defined:
            continue
        e = rows[r]
        if not _linear_single(e, yp[i]):
            continue
        coef = float(ca.evalf(ca.jacobian(e, yp[i])))
        if coef == 0.0:
            continue
        f = ca.substitute(e, yp[i], ca.SX(0.0))
        defined[i] = (r, -f / coef)
    if defined:
        dsyms = ca.vertcat(*[yp[i] for i in defined])
        dvals = ca.vertcat(*[v for _, v in defined.values()])
        def_rows = {r for r, _ in defined.values()}
        others = [k for k in range(n) if k not in def_rows]
        if others:
            new = ca.substitute([ca.vertcat(*[rows[k] for k in others])], [dsyms], [dvals])[0]
            for j, k in enumerate(others):
                rows[k] = new[j]


def _eliminate_aliases(rows: list[ca.SX], y: ca.SX, y_hash: dict[int, int], differential: np.ndarray,
                       untested: np.ndarray | None) -> tuple[list[ca.SX], dict[int, tuple[float, ca.SX]], ca.SX,
                                                             ca.SX, list[int]]:
    """Drop the rows that make an algebraic entry an alias (``a = ±b``) and substitute it: the rows left, the aliases,
    their substitution (symbols → values) and the kept row indices."""
    n = len(rows)
    # (b) algebraic aliases: row = a - b or a + b with a algebraic y entry, b any y/yp entry
    alias: dict[int, tuple[float, ca.SX]] = {}
    dropped_rows: set[int] = set()

    def resolve(sym: ca.SX) -> tuple[float, ca.SX]:
        s = 1.0
        while sym.element_hash() in y_hash and y_hash[sym.element_hash()] in alias:
            s2, sym = alias[y_hash[sym.element_hash()]]
            s *= s2
        return s, sym

    for r in range(n):
        e = rows[r]
        if e.is_symbolic() or e.op() not in (ca.OP_SUB, ca.OP_ADD):
            continue
        d0, d1 = e.dep(0), e.dep(1)
        if not (d0.is_symbolic() and d1.is_symbolic()):
            continue
        # d0 = sgn*d1 with d0 = s0*a, d1 = s1*b  ->  a = k*b and b = k*a, k = sgn*s0*s1
        sgn = 1.0 if e.op() == ca.OP_SUB else -1.0
        s0, a = resolve(d0)
        s1, b = resolve(d1)
        ha, hb = a.element_hash(), b.element_hash()
        if ha == hb:
            continue
        k = sgn * s0 * s1
        if ha in y_hash and not differential[y_hash[ha]]:
            gone, target = y_hash[ha], b
        elif hb in y_hash and not differential[y_hash[hb]]:
            gone, target = y_hash[hb], a
        else:
            continue
        alias[gone] = (k, target)
        if untested is not None and untested[gone] and target.element_hash() in y_hash:
            untested[y_hash[target.element_hash()]] = True  # the derivative-level mark goes with the value
        dropped_rows.add(r)
    if alias:
        asyms, avals = [], []
        for i in alias:
            s, target = resolve(y[i])
            asyms.append(y[i])
            avals.append(s * target)
        subs_syms, subs_vals = ca.vertcat(*asyms), ca.vertcat(*avals)
        kept_rows = [k for k in range(n) if k not in dropped_rows]
        new = ca.substitute([ca.vertcat(*[rows[k] for k in kept_rows])], [subs_syms], [subs_vals])[0]
        rows = [new[j] for j in range(len(kept_rows))]
    else:
        subs_syms, subs_vals = ca.SX(0, 1), ca.SX(0, 1)
        kept_rows = list(range(n))
    return rows, alias, subs_syms, subs_vals, kept_rows


def post_simplify(F: ca.SX, y: ca.SX, yp: ca.SX, differential: np.ndarray,
                  protected: np.ndarray | None = None, explicit_mode: str = "error-test",
                  untested: np.ndarray | None = None, intermediate: np.ndarray | None = None):
    """Substitute known state derivatives, eliminate trivial algebraic aliases and explicit algebraics.

    ``protected`` marks entries that must stay unknowns (dummy-derivative candidates); ``explicit_mode`` is the
    explicit algebraics' mode (:func:`flexlib.compile.explicit.explicit_mode`: ``"off"`` skips them). Returns the new
    residual, the kept entry indices, the substitution (symbols → values) that expresses eliminated
    entries in kept ones, the kept row indices, and the entries eliminated as explicit algebraics.
    """
    n = F.numel()
    rows = [F[k] for k in range(n)]
    y_hash = {y[i].element_hash(): i for i in range(n)}
    inc_yp = _incidence_lists(F, yp)
    _substitute_known_derivatives(rows, yp, differential, inc_yp)
    rows, alias, subs_syms, subs_vals, kept_rows = _eliminate_aliases(rows, y, y_hash, differential, untested)
    keep = [i for i in range(n) if i not in alias]
    # (c) explicit algebraics: row = c*v + f(others), c a nonzero constant (sparsity-guarded, see explicit.py)
    explicit: list[int] = []
    if explicit_mode != "off" and rows:
        fixed = np.zeros(n, dtype=bool) if protected is None else np.array(protected, dtype=bool)
        fixed[list(alias)] = True
        if explicit_mode == "error-test":
            # only unknowns already outside IDA's error test (derivative level): the test keeps what it checked
            # ... and kinematic intermediates (``Variable(intermediate=True)``: a frame's velocity along the tree)
            free = derivative_level(ca.vertcat(*rows), y, yp, differential, untested)
            if intermediate is not None:
                free |= intermediate
            fixed |= ~free
        kept2, explicit, values, new = eliminate_explicit_algebraics(rows, y, yp, differential, fixed)
        if explicit and _states_kept(new, yp, differential, set(explicit) | set(alias)):
            esyms = ca.vertcat(*[y[i] for i in explicit])
            if subs_syms.numel():
                subs_vals = ca.substitute([subs_vals], [esyms], [values])[0]
            subs_syms, subs_vals = ca.vertcat(subs_syms, esyms), ca.vertcat(subs_vals, values)
            rows = [new[j] for j in range(new.numel())]
            kept_rows = [kept_rows[k] for k in kept2]
            gone = set(explicit)
            keep = [i for i in keep if i not in gone]
        else:
            explicit = []
    return ca.vertcat(*rows), keep, subs_syms, subs_vals, kept_rows, explicit


def _states_kept(F: ca.SX, yp: ca.SX, differential: np.ndarray, gone: set[int]) -> bool:
    """True if the derivative of every remaining state still appears in ``F`` (no state lost by cancellation)."""
    colind, _ = ca.jacobian_sparsity(F, yp).get_ccs()
    has = np.diff(np.asarray(colind)) > 0
    return all(has[i] for i in np.flatnonzero(differential) if i not in gone)


def _incidence_lists(F: ca.SX, v: ca.SX) -> list[list[int]]:
    spj = ca.jacobian_sparsity(F, v)
    colind, row = spj.get_ccs()
    out: list[list[int]] = [[] for _ in range(F.numel())]
    for c in range(v.numel()):
        for r in row[colind[c]:colind[c + 1]]:
            out[r].append(c)
    return out
