"""Statically indeterminate reactions: the variables that the dropped redundant loop rows leave undetermined.

:func:`~.redundancy.remove_redundant` replaces each dependent loop row by "the dual reaction component at the cut
is zero". The true value of that component is not fixed by the rigid model: any *self-stress* — internal forces
in equilibrium with zero external load, carried by the over-constrained loop — can be added to a solution and it
stays one. Every force, torque or other variable that changes along a self-stress is therefore indeterminate, and
its value in a result is one admissible split of the load (the one with the dropped components zero), not a
prediction; variables that no self-stress touches (the forces of a determinate sub-chain, a drive torque about its
joint axis in a planar loop, every motion variable) are determined.

The self-stress states are found numerically at the start configuration, once per build: the rows written in
the remaining unknowns are linearised with the states and all derivatives held (a self-stress changes no motion);
the zeroed reaction row ``k`` becomes ``reaction_k = λ_k`` and the response of every unknown to ``λ_k`` is the
least-squares solution of the linearised rows ``J δ = e_k`` (sparse augmented system
``[[I, J], [Jᵀ, 0]]``, rows and columns equilibrated, refined twice: round-off otherwise leaks into variables
that no self-stress reaches). A variable whose response, relative to its nominal value, exceeds
:data:`TOLERANCE` of the largest response to that ``λ_k`` is indeterminate; the rows ``k`` behind it are kept
for the messages. The configuration is the start moved onto the kept loop rows (Gauss–Newton, as the rank
test): a parallelogram's extra links are redundant only on the constraint manifold
(``docs/decisions/034-indeterminate-reactions-by-self-stress-response.md``).
"""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from flexlib.compile.passes.multibody.redundancy import SMALL_MOTION_NOMINAL, lookup_sym, onto_loops
from flexlib.compile.redundancy import CHECK_PREFIX
from flexlib.compile.simplify import SimpleSystem

__all__ = ["TOLERANCE", "indeterminate_reactions"]

#: A variable responds to a self-stress if its response (over its nominal value) exceeds this fraction of the
#: largest response to the same zeroed reaction (the separation measured:
#: ``docs/decisions/034-indeterminate-reactions-by-self-stress-response.md``).
TOLERANCE = 1e-8


def indeterminate_reactions(simple: SimpleSystem, params: dict[int, float]) -> SimpleSystem:
    """``simple`` with :attr:`~flexlib.compile.simplify.SimpleSystem.indeterminate` filled: every named variable
    (``simple.outputs``) that a self-stress of the over-constrained loops changes, with the indices in
    ``simple.redundant`` of the dropped rows behind it (module docstring). Unchanged without dropped rows.

    Parameters
    ----------
    simple : SimpleSystem
        After the redundant loop rows are dropped (their reaction rows tagged ``("reaction", i)``) and the frame
        kinematics torn, before constant unknowns are eliminated (the zeroed reactions are still rows).
    params : dict of int to float
        Parameter values by symbol hash.
    """
    eqs = simple.equations
    reactions = [(r, e.meta[1]) for r, e in enumerate(eqs) if e.origin == "redundant reaction"
                 and e.meta is not None and e.meta[0] == "reaction"]
    if not reactions:
        return simple
    R = ca.vertcat(*[e.expr for e in eqs])
    D, held = _derivatives(simple, R)
    free = [v for v in simple.variables if v.sym.element_hash() not in held]
    psyms = [(lookup_sym(h), x) for h, x in params.items()]
    psyms = [(p, x) for p, x in psyms if p is not None]
    P = ca.vertcat(*[p for p, _ in psyms]) if psyms else ca.SX(0, 1)
    pv = np.array([x for _, x in psyms], dtype=float)
    rel = [rel.info.sym for rel, _ in simple.relations]  # relations at their false side, as in the rank test
    X = ca.vertcat(*[v.sym for v in simple.variables])
    Z = ca.vertcat(*rel) if rel else ca.SX(0, 1)
    A = ca.vertcat(*[v.sym for v in free])
    x = _closed_start(simple, P, pv, Z)
    J = _evaluate(ca.jacobian(R, A), [X, D, P, Z], [x, np.zeros(D.numel()), pv, np.zeros(Z.numel())])
    used = np.flatnonzero(np.diff(J.indptr))  # rows in the free unknowns
    J = J[used]
    position = {int(r): i for i, r in enumerate(used)}
    E = np.zeros((len(used), len(simple.redundant)))
    for r, k in reactions:
        if r in position:
            E[position[r], k] = 1.0
    delta = _least_squares(J, E)
    names = [n for n in simple.outputs if not n.startswith(CHECK_PREFIX)]
    out = _evaluate(ca.jacobian(ca.vertcat(*[simple.outputs[n] for n in names]), A), [X, D, P, Z],
                    [x, np.zeros(D.numel()), pv, np.zeros(Z.numel())])
    nominal = {v.name: v.nominal for v in simple.flat.variables}
    response = np.abs(out @ delta) / np.array([nominal.get(n, 1.0) for n in names])[:, None]
    largest = response.max(axis=0)
    hit = response > TOLERANCE * np.where(largest > 0, largest, np.inf)
    found = {names[i]: [int(k) for k in np.flatnonzero(hit[i])] for i in np.flatnonzero(hit.any(axis=1))}
    return dataclasses.replace(simple, indeterminate=found)


def _derivatives(simple: SimpleSystem, R: ca.SX) -> tuple[ca.SX, set[int]]:
    """The derivative symbols the rows ``R`` may contain (every order of every remaining unknown that has one) and
    the unknowns whose derivatives they do contain (the states, by symbol hash): ``which_depends`` on the
    candidates, a small fraction of the time ``symvar`` takes on a machine's rows."""
    chains: list[tuple[int, ca.SX]] = []
    for v in simple.variables:
        info = v.info._der
        while info is not None:
            chains.append((v.sym.element_hash(), info.sym))
            info = info._der
    if not chains:
        return ca.SX(0, 1), set()
    D = ca.vertcat(*[d for _, d in chains])
    appear = ca.which_depends(R, D, 1, False)
    return D, {h for (h, _), a in zip(chains, appear, strict=True) if a}


def _evaluate(expr: ca.SX, syms: list[ca.SX], values: list[np.ndarray]) -> sp.csr_matrix:
    """A sparse SX matrix evaluated at ``values`` of ``syms``, as a CSR matrix."""
    return sp.csr_matrix(ca.Function("flexlib_indeterminate", syms, [expr])(*values).sparse())


def _closed_start(simple: SimpleSystem, P: ca.SX, pv: np.ndarray, Z: ca.SX) -> np.ndarray:
    """The remaining unknowns' start values, the joint coordinates of the kept loop rows moved onto them (large
    motions only, as the rank test; the start as it is where the move does not converge)."""
    x = np.array([v.start for v in simple.variables], dtype=float)
    loop = [e.expr for e in simple.equations if e.origin == "loop closure"]
    if not loop:
        return x
    L = ca.vertcat(*loop)
    index = {v.sym.element_hash(): k for k, v in enumerate(simple.variables)}
    cols = [index[s.element_hash()] for s in ca.symvar(L) if s.element_hash() in index]
    if not cols:
        return x
    q = ca.vertcat(*[simple.variables[k].sym for k in cols])
    if Z.numel():
        L = ca.substitute(L, Z, ca.SX.zeros(Z.numel()))
    point = ca.vertcat(q, P)
    lfun = ca.Function("L", [point], [L])
    gfun = ca.Function("G", [point], [ca.jacobian(L, q)])
    nom = np.array([simple.variables[k].nominal for k in cols], dtype=float)
    closed = onto_loops(lfun, gfun, np.concatenate([x[cols], pv]), nom * (nom >= SMALL_MOTION_NOMINAL))
    if closed is not None:
        x[cols] = closed[:len(cols)]
    return x


def _least_squares(J: sp.csr_matrix, E: np.ndarray) -> np.ndarray:
    """``δ`` minimising ``‖J δ − E‖`` column by column: the augmented system ``[[I, J], [Jᵀ, 0]] [r; δ] = [E; 0]``
    of the row- and column-equilibrated ``J``, by sparse LU with two steps of iterative refinement (a slightly
    regularised system where ``J`` has dependent columns)."""
    m, n = J.shape
    rows = 1.0 / np.maximum(abs(J).max(axis=1).toarray().ravel(), 1e-300)
    Js = sp.diags(rows) @ J
    cols = 1.0 / np.maximum(abs(Js).max(axis=0).toarray().ravel(), 1e-300)
    Js = sp.csc_matrix(Js @ sp.diags(cols))
    rhs = np.vstack([rows[:, None] * E, np.zeros((n, E.shape[1]))])
    for eps in (0.0, 1e-10):
        K = sp.bmat([[sp.identity(m), Js], [Js.T, -eps * sp.identity(n) if eps else None]], format="csc")
        try:
            lu = spl.splu(K)
        except RuntimeError:  # exactly singular: unknowns the held motion leaves free (a minimum-norm answer)
            continue
        sol = lu.solve(rhs)
        for _ in range(2):
            sol = sol + lu.solve(rhs - K @ sol)
        if np.all(np.isfinite(sol)):
            return cols[:, None] * sol[m:]
    return np.zeros((n, E.shape[1]))
