"""Structural analysis: incidence matrices, maximum matching and Dulmage–Mendelsohn culprits.

Used by the balance check (stage 1), by Pantelides' algorithm (stage 3) and by the
initialisation check (stage 4). Matching is MC21 (DFS augmenting paths with lookahead).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence

import casadi as ca
import numpy as np
import scipy.sparse as sp

__all__ = ["culprits", "derivative_level", "incidence", "matching", "unit_coefficients"]


def incidence(exprs: ca.SX, syms: ca.SX) -> sp.csr_matrix:
    """Structural incidence ``A[i, j] = 1`` if equation ``i`` depends on symbol ``j``."""
    if exprs.numel() == 0 or syms.numel() == 0:
        return sp.csr_matrix((exprs.numel(), syms.numel()))
    spj = ca.jacobian_sparsity(exprs, syms)
    colind, row = spj.get_ccs()
    data = np.ones(len(row))
    return sp.csc_matrix((data, np.asarray(row), np.asarray(colind)), shape=spj.shape).tocsr()


def _karp_sipser(indptr: list[int], indices: list[int], n: int, m: int) -> tuple[list[int], list[int]]:
    """Initial matching by the Karp–Sipser rule: a column (row) with one free neighbour is matched to it.

    Degree-one vertices are matched first (optimal for them), so the long alias and connection chains of a
    flat model are matched end to end; only when none is left is a free row matched greedily to its first
    free column. O(non-zeros). Karp & Sipser, FOCS 1981; Duff, Kaya & Uçar, ACM TOMS 38(3), 2011.
    """
    row_match, col_match = [-1] * n, [-1] * m
    col_rows: list[list[int]] = [[] for _ in range(m)]
    for r in range(n):
        for k in range(indptr[r], indptr[r + 1]):
            col_rows[indices[k]].append(r)
    row_deg = [indptr[r + 1] - indptr[r] for r in range(n)]
    col_deg = [len(rs) for rs in col_rows]
    cols1 = [c for c in range(m) if col_deg[c] == 1]
    rows1 = [r for r in range(n) if row_deg[r] == 1]
    next_row = 0

    def take(r: int, c: int) -> None:
        row_match[r], col_match[c] = c, r
        for k in range(indptr[r], indptr[r + 1]):  # row r leaves: its free columns lose a neighbour
            c2 = indices[k]
            if col_match[c2] < 0:
                col_deg[c2] -= 1
                if col_deg[c2] == 1:
                    cols1.append(c2)
        for r2 in col_rows[c]:  # column c leaves: its free rows lose a neighbour
            if row_match[r2] < 0:
                row_deg[r2] -= 1
                if row_deg[r2] == 1:
                    rows1.append(r2)

    while True:
        if cols1:
            c = cols1.pop()
            if col_match[c] < 0 and col_deg[c] == 1:
                take(next(r for r in col_rows[c] if row_match[r] < 0), c)
            continue
        if rows1:
            r = rows1.pop()
            if row_match[r] < 0 and row_deg[r] == 1:
                take(r, next(indices[k] for k in range(indptr[r], indptr[r + 1]) if col_match[indices[k]] < 0))
            continue
        while next_row < n and (row_match[next_row] >= 0 or row_deg[next_row] == 0):
            next_row += 1
        if next_row == n:
            break
        r = next_row
        take(r, next(indices[k] for k in range(indptr[r], indptr[r + 1]) if col_match[indices[k]] < 0))
    return row_match, col_match


def matching(inc: sp.spmatrix, in_order: bool = False, fast: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Maximum bipartite matching of rows (equations) to columns (unknowns).

    A greedy pass followed by depth-first augmenting paths with one-step lookahead (Duff's
    MC21, Duff, Kaya & Uçar, ACM TOMS 38(3), 2011): the long alternating chains of multibody models are
    what the depth-first search handles well (``docs/decisions/001-mc21-matching.md``).

    With ``in_order`` the rows are matched strictly one after the other (no greedy pass ahead);
    an augmenting path never unmatches a row, so every row left unmatched depends on earlier
    rows only: the earlier rows have priority (the greedy basis of the transversal matroid).

    With ``fast`` the initial matching is Karp–Sipser's instead of the greedy pass: some maximum matching,
    found in near-linear time on the flat system of a large model, where the greedy pass leaves hundreds of
    rows whose augmenting paths run along whole alias chains. For callers that need only the matching's size or the
    Dulmage–Mendelsohn culprits (balance checks); the other callers keep the greedy pass, whose particular
    matching fixes the DAE they build.

    Returns
    -------
    row_match : ndarray
        Column matched to each row, -1 if unmatched.
    col_match : ndarray
        Row matched to each column, -1 if unmatched.
    """
    csr = sp.csr_matrix(inc)
    n, m = csr.shape
    row_match = [-1] * n
    col_match = [-1] * m
    if n == 0 or m == 0:
        return np.asarray(row_match, dtype=int), np.asarray(col_match, dtype=int)
    indptr = csr.indptr.tolist()
    indices = csr.indices.tolist()
    if fast and not in_order:
        row_match, col_match = _karp_sipser(indptr, indices, n, m)
    for r in range(0 if in_order or fast else n):  # cheap greedy pass
        for k in range(indptr[r], indptr[r + 1]):
            c = indices[k]
            if col_match[c] < 0:
                row_match[r], col_match[c] = c, r
                break
    visited = [0] * m
    look = indptr[:-1]  # lookahead pointers: columns before look[r] are known to be matched
    for stamp, root in enumerate((r for r in range(n) if row_match[r] < 0), start=1):
        rows, cols, ptrs = [root], [], [indptr[root]]
        while rows:
            row = rows[-1]
            free = -1
            for k in range(look[row], indptr[row + 1]):
                if col_match[indices[k]] < 0:
                    free = indices[k]
                    break
            look[row] = indptr[row + 1] if free < 0 else k
            if free >= 0:
                cols.append(free)
                for r, c in zip(rows, cols):
                    row_match[r], col_match[c] = c, r
                break
            p, end = ptrs[-1], indptr[row + 1]
            while p < end and visited[indices[p]] == stamp:
                p += 1
            if p == end:
                rows.pop()
                ptrs.pop()
                if cols:
                    cols.pop()
                continue
            c = indices[p]
            visited[c] = stamp
            ptrs[-1] = p + 1
            cols.append(c)
            rows.append(col_match[c])
            ptrs.append(indptr[col_match[c]])
    return np.asarray(row_match, dtype=int), np.asarray(col_match, dtype=int)


def culprits(inc: sp.spmatrix, row_match: np.ndarray, col_match: np.ndarray) -> tuple[list[int], list[int]]:
    """Rows of the over-determined part and columns of the under-determined part.

    The over-determined part is every equation reachable from an unmatched equation by an
    alternating path (equation → its variable → the equation matched to that variable → …);
    the under-determined part likewise from unmatched variables. These are the coarse
    Dulmage–Mendelsohn blocks, independent of which maximum matching was found.
    """
    csr = sp.csr_matrix(inc)
    over_rows = _alternating_reach(csr, row_match, col_match)
    under_cols = _alternating_reach(csr.tocsc(), col_match, row_match)
    return sorted(over_rows), sorted(under_cols)


def _alternating_reach(compressed: sp.spmatrix, own_match: np.ndarray, other_match: np.ndarray) -> set[int]:
    """The rows (of a CSR ``compressed``; columns of a CSC one) reachable from the unmatched ones
    (``own_match < 0``) by alternating paths: a row, one of its entries' columns, the row matched to that column
    (``other_match``), and so on."""
    reached: set[int] = set()
    queue = deque(int(i) for i in np.flatnonzero(own_match < 0))
    reached.update(queue)
    while queue:
        i = queue.popleft()
        for j in compressed.indices[compressed.indptr[i]:compressed.indptr[i + 1]]:
            i2 = other_match[j]
            if i2 >= 0 and i2 not in reached:
                reached.add(int(i2))
                queue.append(int(i2))
    return reached


def group_by_owner(items: Sequence[tuple[str, str]], limit: int = 12) -> str:
    """Format ``[(owner, text)]`` as ``"owner: text; text"`` lines, at most ``limit`` lines."""
    groups: dict[str, list[str]] = {}
    for owner, text in items:
        groups.setdefault(owner or "(model)", []).append(text)
    lines = [f"  {owner}: {'; '.join(texts[:6])}{' …' if len(texts) > 6 else ''}"
             for owner, texts in list(groups.items())[:limit]]
    if len(groups) > limit:
        lines.append(f"  … and {len(groups) - limit} more components")
    return "\n".join(lines)


def derivative_level(F: ca.SX, y: ca.SX, yp: ca.SX, differential: np.ndarray,
                     untested: np.ndarray | None = None) -> np.ndarray:
    """Mask of the algebraic unknowns kept out of IDA's local error test.

    Derivative-level unknowns are the algebraic unknowns whose value depends on an acceleration: joint and body
    accelerations, the cut forces and reactions they determine, and whatever is computed from those. Their local
    error behaves like that of the index-2 variables of a Hessenberg DAE, one order lower than BDF's estimate
    assumes, and the error test on them can collapse the step size
    (``docs/decisions/008-error-test-excludes-derivative-level-unknowns.md``). They are excluded by an infinite
    absolute tolerance, which is what SUNDIALS' ``IDASetSuppressAlg`` does for all algebraic variables (it is not
    exposed by scikit-sundae); positions and velocities stay in the test. The infinite tolerance also leaves them out
    of IDA's Newton convergence test, so constraints are held to the requested tolerance rather than below it.
    Computed once at compile time (``CompiledModel.derivative_level``); the solvers apply it unless
    ``FLEXLIB_ERROR_TEST_ALL=1``.

    Found structurally. The equations free of ``yp`` are matched to the algebraic unknowns (Dulmage–Mendelsohn);
    the columns left in the under-determined part are those only ``yp`` determines: accelerations that are
    derivatives of velocities, reactions of constraints that index reduction differentiated. Recursive kinematics
    (a multibody frame carries its acceleration ``Frame.a`` and angular acceleration ``Frame.z`` along the tree, a
    joint its relative acceleration) computes accelerations with no ``yp`` in sight, so those variables are
    declared ``Variable(error_test=False)`` (``untested``). A declared unknown counts as a derivative: it is
    excluded, a row containing it is not free of ``yp``, and the cut forces it determines fall into the
    under-determined part with it — unless positions and velocities alone determine it
    (:func:`_kinematically_known`: gravity carried out from the World, a rod's centripetal terms), which are tested
    like any algebraic unknown.
    """
    n = len(differential)
    differential = np.asarray(differential, dtype=bool)
    dyp = incidence(F, yp)
    inc_y = incidence(F, y)
    declared = np.zeros(n, dtype=bool) if untested is None else np.asarray(untested, dtype=bool) & ~differential
    if declared.any():
        declared &= ~_kinematically_known(F, y, dyp, inc_y, declared)
    alg = np.flatnonzero(~differential & ~declared)
    # a row containing a declared unknown is not free of derivatives
    uses_declared = np.asarray(inc_y[:, np.flatnonzero(declared)].sum(axis=1)).ravel() > 0
    free_rows = np.flatnonzero((np.diff(dyp.indptr) == 0) & ~uses_declared)
    mask = declared.copy()
    if len(alg):
        inc = inc_y[free_rows][:, alg]
        row_match, col_match = matching(inc, fast=True)
        _, under = culprits(inc, row_match, col_match)
        mask[alg[under]] = True
    return mask


def _kinematically_known(F: ca.SX, y: ca.SX, inc_yp: sp.csr_matrix, inc_y: sp.csr_matrix,
                         declared: np.ndarray) -> np.ndarray:
    """The declared unknowns (frame accelerations) that positions and velocities alone determine.

    A declared unknown ``u`` is defined by a row that gives it explicitly (coefficient ±1, as a joint's
    ``b.a = T_rel a.a`` or a body's ``a_0 = Tᵀ a + g``). It is known without accelerations when such a row contains
    no ``yp`` (no joint acceleration) and every other declared unknown in it is known so: gravity carried out from the
    World through the tree, or the centripetal terms of a rod, are tested like any algebraic unknown; what a joint's
    acceleration reaches is not. Fixed point from "nothing known".
    """
    rows = np.flatnonzero(np.asarray(inc_y[:, np.flatnonzero(declared)].sum(axis=1)).ravel() > 0)
    has_yp = np.diff(inc_yp.indptr) > 0
    row_cands = [[int(c) for c in inc_y.indices[inc_y.indptr[r]:inc_y.indptr[r + 1]] if declared[c]] for r in rows]
    unit = unit_coefficients([F[int(r)] for r in rows], [[y[c] for c in cs] for cs in row_cands])
    # defining rows per candidate: (the other candidates in the row)
    defs: dict[int, list[list[int]]] = {}
    for r, cs, u in zip(rows, row_cands, unit, strict=True):
        if has_yp[r]:
            continue
        for k, _ in u:
            defs.setdefault(cs[k], []).append([c for c in cs if c != cs[k]])
    known = np.zeros(len(declared), dtype=bool)
    changed = True
    while changed:
        changed = False
        for c, alternatives in defs.items():
            if not known[c] and any(all(known[o] for o in others) for others in alternatives):
                known[c] = changed = True
    return known


def unit_coefficients(exprs: Sequence[ca.SX], syms: Sequence[Sequence[ca.SX]]) -> list[list[tuple[int, float]]]:
    """For each scalar row ``exprs[r]``, the symbols of ``syms[r]`` it gives explicitly: ``(k, c)`` for each
    ``syms[r][k]`` whose coefficient ``c`` in the row is the constant ±1 (a constant partial derivative means the
    row is linear in it). One Jacobian for all rows, with respect to the union of their symbols."""
    out: list[list[tuple[int, float]]] = [[] for _ in exprs]
    rows = [r for r, ss in enumerate(syms) if len(ss)]
    if not rows:
        return out
    # d(row r)/d(syms[r]) for every r at once: each row reads its own candidates' entries of one Jacobian
    by_hash = {s.element_hash(): s for r in rows for s in syms[r]}
    column = {h: k for k, h in enumerate(by_hash)}
    J = ca.jacobian(ca.vertcat(*[exprs[r] for r in rows]), ca.vertcat(*by_hash.values()))
    colind, row_of = J.sparsity().get_ccs()
    nz = J.nz[:] if J.nnz() else ca.SX(0, 1)
    free = ca.symvar(nz) if nz.numel() else []
    depends = (np.diff(np.asarray(ca.jacobian_sparsity(nz, ca.vertcat(*free)).T.colind())) if free
               else np.zeros(nz.numel(), dtype=int))
    const = np.flatnonzero(depends == 0)
    values = np.asarray(ca.evalf(nz[const.tolist()])).ravel() if len(const) else np.zeros(0)
    entry = {}
    for k, v in zip(const, values, strict=True):
        if abs(v) == 1.0:
            col = int(np.searchsorted(colind, k, side="right") - 1)
            entry[(int(row_of[k]), col)] = float(v)
    for i, r in enumerate(rows):
        for k, s in enumerate(syms[r]):
            c = entry.get((i, column[s.element_hash()]))
            if c is not None:
                out[r].append((k, c))
    return out


#: Rows with more than this many structural nonzeros are differentiated one by one (:func:`row_jacobian`).
DENSE_ROW_NNZ = 16


def row_jacobian(expr: ca.SX, x: ca.SX) -> ca.SX:
    """``d expr / d x`` with its dense rows differentiated one by one, the others together.

    One scalar row is differentiated in reverse mode: one adjoint sweep over the row's own expression, at most a
    few times its operations. CasADi's Jacobian of many rows at once picks one mode for all, with column colouring
    in forward mode, which sweeps a shared expression once per column: where a row deep in a torn tree depends on
    many coordinates through shared kinematics (a flexible section's modal coordinates all move the frames
    downstream through its tip frame), that is many sweeps
    (``docs/decisions/007-dense-rows-differentiated-row-by-row.md``). Rows with at most :data:`DENSE_ROW_NNZ`
    nonzeros stay together, where the colouring compresses well.
    """
    if expr.numel() == 0 or x.numel() == 0:
        return ca.jacobian(expr, x)
    row_nnz = np.diff(np.asarray(ca.jacobian_sparsity(expr, x).T.colind()))
    dense = np.flatnonzero(row_nnz > DENSE_ROW_NNZ)
    if not len(dense):
        return ca.jacobian(expr, x)
    sparse = np.flatnonzero(row_nnz <= DENSE_ROW_NNZ)
    parts = [ca.jacobian(expr[int(i)], x) for i in dense]
    if len(sparse):
        parts.append(ca.jacobian(expr[sparse.tolist()], x))
    return ca.vertcat(*parts)[np.argsort(np.concatenate([dense, sparse])).tolist(), :]
