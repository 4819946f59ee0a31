"""Stage 3c — explicit algebraic unknowns eliminated from the index-1 DAE.

After index reduction and :mod:`~flexlib.compile.post_simplify`, a component-built model still carries
many algebraic unknowns that one row gives explicitly: cut forces and torques (``f = m·(a − g) − …``),
velocities and accelerations of frames (``v_b = v_a + w × r``), joint rates and accelerations. Each such
row reads ``c·v + f(t, y, p) = 0`` with ``c`` a nonzero *constant*: solving it for ``v`` divides by no
variable or parameter, so the elimination is exact for every parameter value and every point of the run.
The row and ``v`` leave the DAE, ``v = −f/c`` is substituted into the other rows (and into every output,
event indicator, initial condition and dropped-row check, so results still report ``v`` by name), and
IDA sees fewer unknowns. This is one step of Gaussian elimination done symbolically, so the Jacobian of
the reduced DAE is the Schur complement of the original one: an index-1 DAE stays index-1.

**What is eliminated is chosen by sparsity, not by kind.** Substituting ``v`` from its row ``r`` into
the other rows of its column unites their patterns with that of ``r``: with ``r`` of ``R`` nonzeros and
column ``v`` in ``C`` other rows, the fill is at most ``(R − 1)·C`` (Markowitz 1957) and exactly
``Σ_k |pattern(r) \\ pattern(k) \\ {v}|`` over those rows; the row and column remove ``R + C`` entries.
Pairs are taken greedily, smallest net change first (a lazy heap re-evaluates a pair when it is popped),
and only while the net change of the Jacobian's nonzeros (the pattern of ``∂F/∂y + c_j ∂F/∂y'``) is
``≤ 0``: the Jacobian never becomes denser. On a long serial chain (``models/n_link_pendulum.py``) this
stops where eliminating everything would make the Jacobian dense (``tearing.eliminate_explicit``, the
older pre-index-reduction attempt).

**Definitions free of derivatives.** Only rows without ``y'`` define an unknown (``f(t, y, p)``), and a row
that can fail on finite values (``sqrt``, ``log``, ``pow``, ``exp``, ``acos``, a division by a variable: see
``_SAFE_OPS``) defines nothing and keeps its unknowns, so a fault still names that equation and its
variables. Substituting a definition that contains ``y'`` would put derivatives into rows that had none, which
collapses IDA's step size on stiff loops (``docs/decisions/004-explicit-algebraics-eliminated.md``).

**Dependency order.** A definition is read from the row as it stands (``v = −f/c``, other eliminated
unknowns still symbolic in ``f``) and the definitions are then resolved in dependency order; a pair is
refused if ``v`` already appears in the resolved definition of an eliminated unknown of row ``r`` (a
cycle), which also guarantees that ``c`` is the row's own coefficient of ``v``.

**Kept as they are:** states and every unknown whose derivative appears, dummy-derivative candidates
of every selection level (the state-selection monitor re-selects among them and reads them by name),
alias eliminations already made, and (unless ``explicit="all"``) every unknown inside IDA's error
test, so the test checks exactly what it checked before (``post_simplify`` passes that mask);
``derivative_level`` (IDA's error-test mask) is computed again on the reduced DAE by
:func:`flexlib.compile.codegen.compile_dae`.

**On by default** (``BuildOptions(explicit=False)`` or ``FLEXLIB_EXPLICIT=0`` turns it off; ``explicit="all"`` or
``FLEXLIB_EXPLICIT=all`` also eliminates unknowns inside IDA's error test, for measurements only: it costs
accuracy; the setting, :func:`explicit_mode`, is passed to :func:`flexlib.compile.post_simplify.post_simplify` and is
part of the cache key; why:
``docs/decisions/004-explicit-algebraics-eliminated.md``). Eliminated unknowns leave IDA's Newton iteration, so the
corrections, and with them the step sequence, differ at the level of the Newton tolerance.

References
----------
H. M. Markowitz, "The elimination form of the inverse and its application to linear programming",
*Management Science* 3(3), 1957, 255–269.
I. S. Duff, A. M. Erisman, J. K. Reid, *Direct Methods for Sparse Matrices*, 2nd ed., OUP 2017, §7.2
(local pivoting strategies: Markowitz cost and minimum fill-in).
"""

from __future__ import annotations

import heapq

import casadi as ca
import numpy as np

from flexlib.compile.environment import env_default
from flexlib.core.variables import time

__all__ = ["MAX_NET_FILL", "eliminate_explicit_algebraics", "explicit_mode"]

#: Largest accepted change of the Jacobian's number of structural nonzeros per elimination (0: never denser).
MAX_NET_FILL = 0


def explicit_mode(setting: bool | str | None = None) -> str:
    """The stage's mode for the option ``BuildOptions.explicit`` = ``setting``: ``"off"`` (False), ``"error-test"``
    (True: only unknowns already outside IDA's error test, the derivative level) or ``"all"`` (``"all"``, for
    measurements: any). None: the environment default (``FLEXLIB_EXPLICIT``; a value other than ``0``/``off``/
    ``false``/``no``, ``1``/``on``/``true``/``yes`` and ``all`` is a :class:`~flexlib.errors.RunArgumentError`,
    :func:`flexlib.compile.environment.env_switch`). Part of the cache key."""
    if setting is None:
        setting = env_default("explicit")
    return "all" if setting == "all" else "error-test" if setting else "off"


def _patterns(rows: list[ca.SX], y: ca.SX, yp: ca.SX) -> list[set[int]]:
    """Per row, the unknowns (entries of ``y``) whose value or derivative it contains."""
    F = ca.vertcat(ca.SX(0, 1), *rows)
    out: list[set[int]] = [set() for _ in rows]
    for v in (y, yp):
        colind, row = ca.jacobian_sparsity(F, v).get_ccs()
        for c in range(v.numel()):
            for r in row[colind[c]:colind[c + 1]]:
                out[r].add(c)
    return out


#: Operations allowed on values that vary during a run in a row used to eliminate an unknown: they give finite
#: values for finite arguments. A row that can fail (division by a variable, ``sqrt``, ``log``, ``pow``, ``exp``,
#: ``acos``, …) stays in the DAE, so a fault is reported by the integrator and the diagnosis names that
#: equation (``tests/robustness``); parameter-only subexpressions are not restricted (constant over a run).
_SAFE_OPS = frozenset(getattr(ca, f"OP_{name}") for name in (
    "ADD", "SUB", "MUL", "NEG", "SQ", "TWICE", "SIN", "COS", "FABS", "FMIN", "FMAX", "IF_ELSE_ZERO", "LT", "LE",
    "EQ", "NE", "NOT", "AND", "OR", "SIGN", "COPYSIGN", "ATAN", "TANH", "FLOOR", "CEIL", "CONST", "ASSIGN"))


def _safe_rows(rows: list[ca.SX], varying: ca.SX) -> np.ndarray:
    """Per row: True if every operation on a ``varying`` value is in ``_SAFE_OPS`` (division only by a
    parameter expression)."""
    F = ca.vertcat(ca.SX(0, 1), *rows)
    vary_h = {varying[k].element_hash() for k in range(varying.numel())}
    others = [s for s in ca.symvar(F) if s.element_hash() not in vary_h]
    fn = ca.Function("safe", [varying, ca.vertcat(ca.SX(0, 1), *others)], [F])
    n_work = fn.sz_w() + 1
    dep = np.zeros(n_work, dtype=bool)   # work entry depends on a varying value
    bad = np.zeros(n_work, dtype=bool)   # ... through an operation that can fail
    nonneg = np.zeros(n_work, dtype=bool)  # provably >= 0 (squares and their sums, products, positive constants)
    pos = np.zeros(n_work, dtype=bool)   # provably > 0
    safe = np.ones(F.numel(), dtype=bool)
    row_of = F.sparsity().row()
    op_in, op_out = ca.OP_INPUT, ca.OP_OUTPUT
    for k in range(fn.n_instructions()):
        op = fn.instruction_id(k)
        ins = fn.instruction_input(k)
        outs = fn.instruction_output(k)
        if op == op_in:
            dep[outs[0]] = ins[0] == 0
            bad[outs[0]] = False
        elif op == op_out:
            safe[row_of[outs[1]]] = not bad[ins[0]]
        else:
            d = any(dep[i] for i in ins)
            b = any(bad[i] for i in ins)
            if d and op not in _SAFE_OPS and not (op == ca.OP_DIV and (not dep[ins[1]] or pos[ins[1]])):
                b = True
            dep[outs[0]], bad[outs[0]] = d, b
            o = outs[0]
            if op == ca.OP_CONST:
                c = float(fn.instruction_constant(k))
                nonneg[o], pos[o] = c >= 0.0, c > 0.0
            elif op == ca.OP_SQ or (op == ca.OP_MUL and len(ins) == 2 and ins[0] == ins[1]):
                nonneg[o], pos[o] = True, False
            elif op == ca.OP_ADD:
                nonneg[o] = nonneg[ins[0]] and nonneg[ins[1]]
                pos[o] = nonneg[o] and (pos[ins[0]] or pos[ins[1]])
            elif op in (ca.OP_MUL, ca.OP_DIV):
                nonneg[o] = nonneg[ins[0]] and nonneg[ins[1]]
                pos[o] = pos[ins[0]] and pos[ins[1]]
            else:
                nonneg[o] = pos[o] = False
    return safe


def _pivots(rows: list[ca.SX], y: ca.SX, cands: list[int]) -> dict[tuple[int, int], float]:
    """Pairs (row, entry) where the row is affine in ``y[entry]`` with a nonzero constant coefficient."""
    if not cands or not rows:
        return {}
    J = ca.jacobian(ca.vertcat(*rows), ca.vertcat(*[y[i] for i in cands]))
    r_idx, c_idx = J.sparsity().get_triplet()
    out: dict[tuple[int, int], float] = {}
    for k, (r, c) in enumerate(zip(r_idx, c_idx, strict=True)):
        e = J.nz[k]
        if e.is_constant():
            val = float(ca.evalf(e))
            if val != 0.0 and np.isfinite(val):
                out[(r, cands[c])] = val
    return out


def _select(pattern: list[set[int]], pivots: dict[tuple[int, int], float],
            max_net: int) -> list[tuple[int, int]]:
    """Greedy minimum-net-fill choice of (row, entry) pairs, acyclic; in order of elimination."""
    rowpat = [set(p) for p in pattern]
    orig = [frozenset(p) for p in pattern]
    colpat: dict[int, set[int]] = {}
    for r, p in enumerate(rowpat):
        for c in p:
            colpat.setdefault(c, set()).add(r)
    row_done: set[int] = set()            # pivot rows (their pattern stays the resolved definition's)
    col_row: dict[int, int] = {}          # eliminated entry -> its pivot row

    def net(r: int, v: int) -> int | None:
        if r in row_done or v in col_row or v not in rowpat[r]:
            return None
        for j in orig[r]:
            if j in col_row and v in rowpat[col_row[j]]:
                return None  # v is in the definition of an eliminated unknown of row r: a cycle
        R = rowpat[r]
        others = [k for k in colpat[v] if k != r and k not in row_done]
        # entries of R missing from row k, without v (which leaves every row)
        fill = sum(len(R.difference(rowpat[k], (v,))) for k in others)
        return fill - len(R) - len(others)

    order: list[tuple[int, int]] = []
    while True:
        heap = []
        for (r, v) in pivots:
            c = net(r, v)
            if c is not None and c <= max_net:
                heap.append((c, len(rowpat[r]), r, v))
        if not heap:
            break
        heapq.heapify(heap)
        accepted = 0
        while heap:
            c0, _, r, v = heapq.heappop(heap)
            c = net(r, v)
            if c is None or c > max_net:
                continue
            if c != c0:
                heapq.heappush(heap, (c, len(rowpat[r]), r, v))
                continue
            R = rowpat[r] - {v}
            for k in list(colpat[v]):
                if k == r:
                    continue
                rowpat[k].discard(v)
                for u in R - rowpat[k]:
                    rowpat[k].add(u)
                    colpat[u].add(k)
            colpat[v] = {r}
            rowpat[r] = R
            row_done.add(r)
            col_row[v] = r
            order.append((r, v))
            accepted += 1
        if not accepted:
            break
    return order


def _resolve_definitions(defs: list[ca.SX], vs: ca.SX) -> ca.SX:
    """The definitions ``vs = defs`` resolved in dependency order: level by level, each substituting every definition
    resolved before it."""
    colind, dep_row = ca.jacobian_sparsity(ca.vertcat(*defs), vs).get_ccs()
    deps: list[list[int]] = [[] for _ in defs]
    for c in range(len(defs)):
        for r in dep_row[colind[c]:colind[c + 1]]:
            deps[r].append(c)
    level = [-1] * len(defs)

    def depth(k: int) -> int:
        stack = [k]
        while stack:
            j = stack[-1]
            pending = [d for d in deps[j] if level[d] < 0]
            if pending:
                stack.extend(pending)
                continue
            stack.pop()
            level[j] = 1 + max((level[d] for d in deps[j]), default=-1)
        return level[k]

    for k in range(len(defs)):
        if level[k] < 0:
            depth(k)
    resolved: list[ca.SX | None] = [None] * len(defs)
    done_syms: list[ca.SX] = []
    done_vals: list[ca.SX] = []
    for lev in range(max(level) + 1):
        ks = [k for k in range(len(defs)) if level[k] == lev]
        exprs = ca.vertcat(*[defs[k] for k in ks])
        if done_syms:
            exprs = ca.substitute([exprs], [ca.vertcat(*done_syms)], [ca.vertcat(*done_vals)])[0]
        for j, k in enumerate(ks):
            resolved[k] = exprs[j]
        done_syms += [vs[k] for k in ks]
        done_vals += [exprs[j] for j in range(len(ks))]
    return ca.vertcat(*resolved)


def eliminate_explicit_algebraics(rows: list[ca.SX], y: ca.SX, yp: ca.SX, differential: np.ndarray,
                                  protected: np.ndarray, max_net: int = MAX_NET_FILL
                                  ) -> tuple[list[int], list[int], ca.SX, ca.SX]:
    """Eliminate explicit algebraic unknowns of ``rows`` (``F(t, y, y', p) = 0``).

    Parameters
    ----------
    rows : list of casadi.SX
        The residual rows (one scalar each), over the entries of ``y`` that are still unknowns.
    y, yp : casadi.SX
        All entries and their derivatives (entries not in any row are ignored).
    differential : ndarray of bool
        States (never eliminated).
    protected : ndarray of bool
        Entries that must stay unknowns (dummy-derivative candidates, entries already eliminated).
    max_net : int
        Largest accepted change of the Jacobian's structural nonzeros per elimination.

    Returns
    -------
    kept_rows : list of int
        Indices of the rows that stay.
    eliminated : list of int
        Eliminated entries of ``y``.
    values : casadi.SX
        Their expressions in the kept entries (``y``, ``yp``), one per eliminated entry.
    new_rows : casadi.SX
        The kept rows with the eliminated entries substituted.
    """
    n_rows = len(rows)
    pattern = _patterns(rows, y, yp)
    present = set().union(*pattern) if pattern else set()
    cands = [i for i in sorted(present) if not differential[i] and not protected[i]]
    pivots = _pivots(rows, y, cands)
    if pivots:
        # only a row that holds a pivot's unknown can keep or forbid an elimination: the others count as safe
        pivot_entries = {v for _, v in pivots}
        relevant = [r for r, p in enumerate(pattern) if not pivot_entries.isdisjoint(p)]
        safe = np.ones(n_rows, dtype=bool)
        if relevant:
            safe[relevant] = _safe_rows([rows[r] for r in relevant], ca.vertcat(time, y, yp))
        # the unknowns of a row that can fail stay, so its diagnosis names them (and the row is not rewritten)
        in_unsafe = set().union(*[pattern[r] for r in np.flatnonzero(~safe)])
        # definitions free of y': rows without derivatives stay without them (see the module docstring)
        safe &= np.diff(np.asarray(ca.jacobian_sparsity(ca.vertcat(*rows), yp).T.colind())) == 0
        pivots = {rv: c for rv, c in pivots.items() if safe[rv[0]] and rv[1] not in in_unsafe}
    order = _select(pattern, pivots, max_net)
    if order and len(order) == n_rows:
        order.pop()  # a fully explicit model keeps one unknown: IDA steps it and finds its state events
    if not order:
        return list(range(n_rows)), [], ca.SX(0, 1), ca.vertcat(ca.SX(0, 1), *rows)
    # definitions v = -f/c read from the rows as they stand (other eliminated entries still symbolic)
    defs = []
    for r, v in order:
        c = pivots[(r, v)]
        defs.append(-ca.substitute(rows[r], y[v], ca.SX(0.0)) / c)
    elim = [v for _, v in order]
    vs = ca.vertcat(*[y[v] for v in elim])
    values = _resolve_definitions(defs, vs)
    pivot_rows = {r for r, _ in order}
    kept = [k for k in range(n_rows) if k not in pivot_rows]
    new_rows = ca.substitute([ca.vertcat(ca.SX(0, 1), *[rows[k] for k in kept])], [vs], [values])[0]
    return kept, elim, values, new_rows


def row_definitions(F: ca.SX, outputs: ca.SX, y: ca.SX, yp: ca.SX, differential: np.ndarray
                    ) -> tuple[np.ndarray, ca.SX]:
    """The algebraic unknowns that one row of the final residual ``F`` defines explicitly, and their definitions.

    What a result file derives instead of storing (:mod:`flexlib.results.stored`): the same elimination as the
    DAE's (:func:`eliminate_explicit_algebraics`: a row without derivatives, affine in the unknown with a nonzero
    constant coefficient, no operation that can fail, in dependency order), here without its limit on the
    Jacobian's fill (the DAE keeps such unknowns for IDA's sparse factorisation; a stored row needs none of them).
    States stay, and so does every unknown whose derivative ``outputs`` read.

    Returns
    -------
    given : ndarray of int
        The defined unknowns, in the order of ``values``.
    values : casadi.SX
        Their definitions in the other unknowns (a dense column; ``(0, 1)`` if none).
    """
    n = y.numel()
    protected = np.zeros(n, dtype=bool)
    protected[np.asarray(ca.jacobian_sparsity(outputs, yp).get_triplet()[1], dtype=np.int64)] = True
    if n == 0 or F.numel() == 0:
        return np.zeros(0, dtype=np.int64), ca.SX(0, 1)
    _, given, values, _ = eliminate_explicit_algebraics([F[i] for i in range(F.numel())], y, yp,
                                                        np.asarray(differential, dtype=bool), protected,
                                                        max_net=np.iinfo(np.int64).max)
    if not given:
        return np.zeros(0, dtype=np.int64), ca.SX(0, 1)
    return np.asarray(given, dtype=np.int64), ca.densify(values)
