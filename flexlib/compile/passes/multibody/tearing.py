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

**Deep open trees keep their frames** (:func:`tear_or_keep_frames`, issue 9). Substituted along a
tree, link k's rows involve all k joint coordinates above it: the residual and its Jacobian grow as
N² along a chain of N joints, and CasADi's symbolic AD as ~N^2.5 (N-link chain, N = 50: 45 s of
build). A model without loop-closure rows whose deepest chain of frame definitions exceeds
:data:`KEEP_DEPTH` therefore keeps ``T`` and ``r_0`` as unknowns (Pantelides differentiates the tree
equations instead; every row stays local, the Jacobian O(N)). Their start values are the torn
definitions evaluated at the start values of the remaining unknowns, so ``T`` starts as the rotation of
the start angles. Models with loops are always torn (the loop rows must be in joint coordinates).
``BuildOptions(tree_frames="tear")`` / ``"keep"`` (or ``FLEXLIB_TREE_FRAMES``, its default) forces either choice,
passed to the multibody pass as the build's option; the choice is recorded in
``SimpleSystem.tree_frames`` and shown in ``Simulation.report``.

**Rows between frames are written relative to their common frame** before the tree is torn
(:func:`_localize_rows`): a loop closure, a line's length or force between two frames deep in a tree is
invariant under a rigid motion of the subtree they share, so it is written in the coordinates below their
lowest common frame instead of every coordinate from the root (checked numerically row by row).
"""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np

from flexlib.compile.environment import env_default
from flexlib.compile.passes.multibody.redundancy import frame_variables
from flexlib.compile.simplify import SimpleSystem
from flexlib.compile.tearing import eliminate, explicit_definitions, is_derivative

__all__ = ["KEEP_DEPTH", "eliminate_frame_kinematics", "tear_or_keep_frames"]

#: Depth (longest chain of frame definitions ``T``/``r_0`` that depend on each other) above which a model
#: without loops keeps its tree frames as unknowns. Measured on N-link chains (``benchmarks/multibody.py
#: --tree-frames-crossover``, see "Build time at scale" in ``benchmarks/README.md``).
KEEP_DEPTH = 12


def _frame_ids(simple: SimpleSystem) -> list[int]:
    return [k for k in frame_variables(simple) if simple.variables[k].info.name in ("T", "r_0")]


def eliminate_frame_kinematics(simple: SimpleSystem) -> SimpleSystem:
    """Substitute the explicit definitions of frame orientations ``T`` and origins ``r_0``."""
    ids = _frame_ids(simple)
    return eliminate(simple, ids) if ids else simple


def tear_or_keep_frames(simple: SimpleSystem, params: dict[int, float], mode: str | None = None) -> SimpleSystem:
    """Tear the frame kinematics (:func:`eliminate_frame_kinematics`) or keep them, by the rule in the module doc.

    Parameters
    ----------
    simple : SimpleSystem
        After alias elimination and redundant loop rows.
    params : dict of int to float
        Parameter values by symbol hash (for the start values of kept frames).
    mode : {"auto", "tear", "keep"} or None
        None: the environment default (``FLEXLIB_TREE_FRAMES``, :func:`flexlib.compile.environment.env_default`).
        ``"keep"`` still tears a model with loop-closure rows.

    Returns
    -------
    SimpleSystem
        With ``tree_frames`` saying what was chosen and why.
    """
    mode = env_default("tree_frames") if mode is None else mode
    ids = _frame_ids(simple)
    if not ids:
        return simple
    loops = any(e.origin == "loop closure" for e in simple.equations)
    found = explicit_definitions(simple, ids)
    vs, defs, _ = found
    depth = _depth(vs, defs) if vs.numel() else 0
    keep = not loops and (mode == "keep" or (mode == "auto" and depth > KEEP_DEPTH))
    why = (f"frame-definition depth {depth}" + ("; kinematic loops" if loops else "")
           + f"; rule: keep if no loops and depth > {KEEP_DEPTH}" + ("" if mode == "auto" else f" (forced: {mode})"))
    if not keep:
        if vs.numel():
            simple, n_local = _localize_rows(simple, vs, defs, params)
            why += f"; {n_local} rows written relative to their common base frame" if n_local else ""
        return dataclasses.replace(eliminate(simple, ids, found=found), tree_frames=f"torn ({why})")
    variables = _start_values(simple, vs, defs, params)
    kept = {s.element_hash() for s in ca.vertsplit(vs)}
    guesses = {v.name: v.start for v in variables if v.sym.element_hash() in kept and v.start != 0.0}
    return dataclasses.replace(simple, variables=variables, start_guesses={**simple.start_guesses, **guesses},
                               tree_frames=f"kept: {vs.numel()} frame unknowns T, r_0 ({why})")


#: A row written relative to its common frame must equal the torn original at random points to this relative
#: tolerance (:func:`_localize_rows`).
LOCAL_TOL = 1e-9


def _rewrites_agree(simple: SimpleSystem, vs: ca.SX, defs: ca.SX, params: dict[int, float],
                    rewrites: list[tuple[int, ca.SX]]) -> np.ndarray:
    """Which rewritten rows equal their torn originals at random points (relations false, then true)."""
    n = vs.numel()
    # check: torn original and torn rewrite agree at random points
    origs = ca.vertcat(*[simple.equations[r].expr for r, _ in rewrites])
    news = ca.vertcat(*[x for _, x in rewrites])
    both = ca.vertcat(origs, news)
    for _ in range(n + 1):
        if not ca.depends_on(both, vs):
            break
        both = ca.substitute(both, vs, defs)
    symbols = ca.symvar(both)
    f = ca.Function("loops", [ca.vertcat(*symbols) if symbols else ca.SX(0, 1)], [both])
    rng = np.random.default_rng(20261126)
    fixed = np.array([params.get(x.element_hash(), np.nan) for x in symbols], dtype=float)
    rel = {r.info.sym.element_hash() for r, _ in simple.relations}
    is_rel = np.array([x.element_hash() in rel for x in symbols], dtype=bool)
    ok = np.ones(len(rewrites), dtype=bool)
    m = len(rewrites)
    for switch in (0.0, 1.0):  # event relations false, then true: both branches of a piecewise row
        point = np.where(np.isfinite(fixed), fixed, rng.uniform(-1.0, 1.0, len(symbols)))
        point[is_rel] = switch
        with np.errstate(all="ignore"):
            val = np.asarray(f(point), dtype=float).ravel()
        a, b = val[:m], val[m:]
        ok &= np.isfinite(a) & (np.abs(a - b) <= LOCAL_TOL * (1.0 + np.abs(a) + np.abs(b)))
    return ok


def _localize_rows(simple: SimpleSystem, vs: ca.SX, defs: ca.SX,
                    params: dict[int, float]) -> tuple[SimpleSystem, int]:
    """Rows that span several frames written relative to their lowest common frame (the tree's common ancestor).

    Torn (:func:`eliminate_frame_kinematics`), a row that relates two frames far down a tree — a loop closure of a
    boom's fifth four-bar, the length of the cylinder that folds it — involves every joint and modal coordinate
    from the root down: 87 symbols per row of the flexible pump truck's last linkage, whose twice-differentiated
    rows then dominated the Jacobian. Most such rows are objective: invariant under a rigid motion of the whole
    subtree (the orientation residue depends on ``T_b T_aᵀ``, a frame-resolved loop row on ``T_a (r_a − r_b)``, a
    line's length and its force resolved in its end frames on ``r_b − r_a`` and ``T_a``, ``T_b``). With
    ``T_x = R_x T_F`` and ``r_x = r_F + T_Fᵀ ρ_x`` for the frames below a common frame ``F``, such a row equals the
    same row with ``T_F = I``, ``r_F = 0``: a function of the coordinates between ``F`` and the row's frames. The
    deepest frame symbols are expanded until those left belong to one frame, which is then set to the identity.

    Rows are not classified by kind: each rewrite is checked against the torn original at two random points
    (parameters at their values, event relations false and then true, every other symbol random, so the torn
    ``T_F`` is a product of rotations), and a row that does not match — a world-resolved loop row, a body's
    gravity, a base frame whose orientation is not a rotation of the coordinates — is kept as built. Rows with
    derivatives are left alone (their frame derivatives follow the chain rule of the torn definitions). Measured
    on the pump truck (``benchmarks/pump_truck.py``): the flexible boom's Jacobian 494 k → 320 k operations, the
    rigid one's 58 k → 31 k.

    Returns the system and the number of rows rewritten.
    """
    n = vs.numel()
    names = {v.sym.element_hash(): v.name for v in simple.variables}
    index = {vs[k].element_hash(): k for k in range(n)}
    entry: list[tuple[str, tuple[int, ...]]] = []  # ("T", (i, j)) or ("r", (k,)) of each frame symbol
    for k in range(n):
        leaf = names.get(vs[k].element_hash(), "").rsplit(".", 1)[-1]
        kind = "T" if leaf.startswith("T[") else "r"
        entry.append((kind, tuple(int(x) for x in leaf[leaf.index("[") + 1:-1].split(",")) if "[" in leaf else ()))
    level = _levels(vs, defs)

    def one_frame(ks: list[int]) -> bool:  # at most one symbol per entry of T and r_0: one frame's orientation/origin
        seen = [entry[k] for k in ks]
        return len(set(seen)) == len(seen) and all(len(x[1]) == (2 if x[0] == "T" else 1) for x in seen)

    rewrites: list[tuple[int, ca.SX]] = []
    for r, e in enumerate(simple.equations):
        symbols = ca.symvar(e.expr)
        ks = [k for k in (index.get(x.element_hash()) for x in symbols) if k is not None]
        if not ks or one_frame(ks) or any(is_derivative(x) for x in symbols):
            continue  # within one frame (a body's gravity, resolved in it, is not invariant), or a dynamic row
        # expand the deepest frame symbols until those left belong to one frame: the loop's base
        expr = e.expr
        for _ in range(max(level, default=0) + 2):
            ks = [k for k in (index.get(x.element_hash()) for x in ca.symvar(expr)) if k is not None]
            if not ks or one_frame(ks):
                break
            top = max(level[k] for k in ks)
            deep = [k for k in ks if level[k] == top]
            expr = ca.substitute(expr, ca.vertcat(*[vs[k] for k in deep]), ca.vertcat(*[defs[k] for k in deep]))
        if not ks or not one_frame(ks):
            continue  # torn to the root: nothing to gain
        base = [1.0 if entry[k][0] == "T" and entry[k][1][0] == entry[k][1][1] else 0.0 for k in ks]
        expr = ca.substitute(expr, ca.vertcat(*[vs[k] for k in ks]), ca.DM(base))
        rewrites.append((r, expr))
    if not rewrites:
        return simple, 0
    ok = _rewrites_agree(simple, vs, defs, params, rewrites)
    equations = list(simple.equations)
    for (r, expr), good in zip(rewrites, ok, strict=True):
        if good:
            equations[r] = dataclasses.replace(equations[r], expr=expr)
    return dataclasses.replace(simple, equations=equations), int(ok.sum())


def _depth(vs: ca.SX, defs: ca.SX) -> int:
    """Longest chain of definitions depending on each other (0 if none depends on another)."""
    return max(_levels(vs, defs), default=0)


def _levels(vs: ca.SX, defs: ca.SX) -> list[int]:
    """Per definition: 0 if it uses no other defined variable, else 1 + the largest level of those it uses."""
    n = vs.numel()
    colind, row = ca.jacobian_sparsity(defs, vs).get_ccs()
    deps: list[list[int]] = [[] for _ in range(n)]
    for j in range(n):
        for k in range(colind[j], colind[j + 1]):
            deps[row[k]].append(j)  # definition row[k] uses variable j
    level = [-1] * n
    for start in range(n):
        stack = [start]
        while stack:  # iterative depth-first evaluation of level[v] = 1 + max(level of its dependencies)
            v = stack[-1]
            if level[v] >= 0:
                stack.pop()
                continue
            todo = [d for d in deps[v] if level[d] < 0 and d != v]
            if todo and len(stack) <= n:
                stack.extend(todo)
                continue
            level[v] = 1 + max((level[d] for d in deps[v] if d != v), default=-1)
            stack.pop()
    return level


def _start_values(simple: SimpleSystem, vs: ca.SX, defs: ca.SX, params: dict[int, float]) -> list:
    """Variables with the kept frames' start values set from their definitions at the start point.

    The definitions are iterated numerically from the declared starts (``depth + 1`` sweeps resolve an acyclic
    tree exactly); parameters take their values, derivatives, event relations and time 0. Fixed starts stay.
    """
    start = {v.sym.element_hash(): v.start for v in simple.variables}
    own = {s.element_hash() for s in ca.vertsplit(vs)}
    others = [s for s in ca.symvar(defs) if s.element_hash() not in own]
    other_vals = [start.get(h, params.get(h, 0.0)) for h in (s.element_hash() for s in others)]
    f = ca.Function("frames", [vs, ca.vertcat(*others) if others else ca.SX(0, 1)], [defs])
    index = {s.element_hash(): k for k, s in enumerate(ca.vertsplit(vs))}
    x = np.array([start[h] for h in index], dtype=float)
    p = np.asarray(other_vals, dtype=float)
    for _ in range(vs.numel() + 1):
        new = np.asarray(f(x, p), dtype=float).ravel()
        if np.array_equal(new, x):
            break
        x = new
    out = []
    for v in simple.variables:
        k = index.get(v.sym.element_hash())
        if k is None or v.fixed or not np.isfinite(x[k]):
            out.append(v)
        else:
            out.append(dataclasses.replace(v, start=float(x[k])))
    return out
