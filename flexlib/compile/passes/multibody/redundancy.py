"""Redundant loop-closure constraints: detect, drop, and report (the ADAMS approach, made explicit).

A kinematic loop closed by a connection that the orientation tree broke contributes six
equations — three on the positions of the two frames, three orientation residues. A planar
loop built in 3D (a four-bar with parallel axes) satisfies three of them identically: they are
redundant, the DAE is singular, and the matching reactions (axial force, two tilting moments)
are statically indeterminate.

Before index reduction, each loop's rows are written in joint coordinates (the frame
positions and orientations are replaced by their explicit tree equations — symbolic forward
kinematics), and the rank of their Jacobian (columns scaled by each coordinate's nominal value) is found by QR
with column pivoting — at the start configuration or at a slightly perturbed one, whichever has the higher
(generic) rank, so that a singular start (a fully stretched linkage) does not hide a real constraint. The
perturbed point is moved back onto the loop constraints (Gauss–Newton) before its rank counts: off the constraint
manifold, rows that only the loop geometry makes dependent (the extra links of a parallelogram) would look
independent. The perturbation moves large-motion coordinates only; small-motion ones (nominal below
``SMALL_MOTION_NOMINAL``, e.g. a flexible body's modal coordinates) stay at their start values. Each dependent row
is dropped and replaced by "the dual reaction component at the cut is zero": the
world-resolved force component for a position row, the frame-resolved
torque component for an orientation row. Reactions in the remaining (determinate) directions
are unaffected. The report names every dropped row and the reaction set to zero; a compliant
joint (bushing) resolves such reactions physically instead.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import casadi as ca
import numpy as np
import scipy.linalg as sla

from flexlib.compile.flatten import FlatEquation
from flexlib.compile.redundancy import BRANCH_SUFFIX, CHECK_PREFIX
from flexlib.compile.simplify import SimpleSystem
from flexlib.compile.tearing import explicit_definitions
from flexlib.core.component import Connector
from flexlib.core.variables import Kind
from flexlib.errors import ConnectError

__all__ = ["SMALL_MOTION_NOMINAL", "frame_variables", "lookup_sym", "onto_loops", "remove_redundant"]

_AXES = "xyz"

#: Coordinates with a smaller nominal value are small-motion ones (elastic deformation): the generic-rank test
#: does not perturb them (see :func:`remove_redundant`).
SMALL_MOTION_NOMINAL = 0.01


def frame_variables(simple: SimpleSystem) -> list[int]:
    """Indices of the remaining unknowns that are potentials of frame (over-determined) connectors."""
    out = []
    for k, v in enumerate(simple.variables):
        node = v.info.node
        if isinstance(node, Connector) and node.overdetermined and v.kind is Kind.potential:
            out.append(k)
    return out


def _branch_checks(simple: SimpleSystem) -> dict[str, ca.SX]:
    """A check row per orientation loop closure: ``min(cos θ, 0)`` with ``θ`` the relative rotation of the two cut
    frames, ``cos θ = (trace(T_b T_aᵀ) − 1)/2``.

    The closure's residue (:func:`~flexlib.components.mechanics.multibody.frames.equality_constraint`, the sine part
    of the relative rotation, as Modelica's ``equalityConstraint``) vanishes at a half-turn as well as at the
    identity, so a consistent start can close a loop in its mirrored branch, where the forces and torques across
    the cut act in reversed axes. The row is zero on the physical branch (``θ`` near zero) and about −1 on the
    mirrored one; :func:`flexlib.solve.build_checks.check_dropped_rows` evaluates it with the dropped rows, at the
    start and over the run."""
    out = simple.outputs
    checks: dict[str, ca.SX] = {}
    for e in simple.equations:
        if e.origin != "loop closure" or e.meta is None or e.meta[0] != "orientation" or e.meta[3] != 0:
            continue
        _, a, b, _ = e.meta
        try:
            Ta, Tb = _frame_T(out, a), _frame_T(out, b)
        except (KeyError, AttributeError):  # an over-determined record other than a frame orientation
            continue
        trace = sum(Tb[i][j] * Ta[i][j] for i in range(3) for j in range(3))  # trace(T_b T_aᵀ)
        label = e.label.rsplit(" [", 1)[0]
        checks[f"{CHECK_PREFIX}{e.owner + ': ' if e.owner else ''}{label}{BRANCH_SUFFIX}"] = ca.fmin(
            0.5 * (trace - 1.0), 0.0)
    return checks


def _frame_T(out: dict[str, ca.SX], frame: Any) -> list[list[ca.SX]]:
    """A frame's orientation matrix ``T`` (world → frame) as entries of ``simple.outputs``."""
    return [[out[f"{frame._label('T')}[{i},{j}]"] for j in range(3)] for i in range(3)]


def _reaction(simple: SimpleSystem, meta: tuple) -> tuple[ca.SX, str]:
    kind, a, _, k = meta
    out = simple.outputs
    if kind == "position":
        T = _frame_T(out, a)
        f = [out[f"{a._label('f')}[{i}]"] for i in range(3)]
        expr = sum(T[j][k] * f[j] for j in range(3))  # (Tᵀ f)_k: cut force along world axis k
        return expr, f"force along world {_AXES[k]} at {a.path}"
    if kind == "frame position":
        return out[f"{a._label('f')}[{k}]"], f"force along {a.path} axis {_AXES[k]}"
    return out[f"{a._label('t')}[{k}]"], f"torque about {a.path} axis {_AXES[k]}"


def _frame_resolved(simple: SimpleSystem) -> list[FlatEquation]:
    """The equations with each loop's three world-resolved position rows ``r_a − r_b`` replaced by the same
    difference resolved in the cut frame ``a``, ``T_a (r_a − r_b)`` (equivalent: ``T_a`` is orthogonal).

    A loop that is planar in a plane that turns — a four-bar on a slewing turret — has its redundant position
    row along the plane's normal, which is fixed in the cut frame but not in the world: a world-resolved row
    chosen for dropping at one slew angle is an independent constraint at another (and a random perturbation of
    the slew angle off the closure makes the world row look independent at the start). Resolved in the cut frame
    the redundancy is the same at every configuration, as the orientation rows' already is."""
    equations = list(simple.equations)
    triples: dict[tuple[int, int], list[int]] = {}
    for r, e in enumerate(equations):
        if e.origin == "loop closure" and e.meta is not None and e.meta[0] == "position":
            triples.setdefault((id(e.meta[1]), id(e.meta[2])), []).append(r)
    for rows in triples.values():
        if len(rows) != 3:
            continue
        first = equations[rows[0]]
        a, b = first.meta[1], first.meta[2]
        try:
            T = [[simple.outputs[f"{a._label('T')}[{i},{j}]"] for j in range(3)] for i in range(3)]
        except KeyError:
            continue
        world = [equations[r].expr for r in sorted(rows, key=lambda r: equations[r].meta[3])]
        for k in range(3):
            old = equations[rows[k]]
            expr = T[k][0] * world[0] + T[k][1] * world[1] + T[k][2] * world[2]
            label = f"loop closure {a.path} ~ {b.path} position along {a.path} axis {_AXES[k]}"
            equations[rows[k]] = FlatEquation(expr, old.owner, label, "loop closure", ("frame position", a, b, k))
    return equations


def remove_redundant(simple: SimpleSystem, param_values: dict[int, float]) -> SimpleSystem:
    """Drop numerically redundant loop-closure rows (replaced by zero indeterminate reactions).

    The rank test runs on the rows as built (world-resolved positions) and on the same rows with positions resolved
    in the cut frame (:func:`_frame_resolved`). Where the frame-resolved rows show more redundancy — a loop planar
    in a plane that turns relative to the world, e.g. on a slewing turret — they replace the world rows; otherwise
    the rows stay as built."""
    loop = [r for r, e in enumerate(simple.equations) if e.origin == "loop closure"]
    if not loop:
        return simple
    simple = dataclasses.replace(simple, outputs={**simple.outputs, **_branch_checks(simple)})
    # the frame variables' definitions come from the rows other than the loops', the same in both resolutions
    definitions = explicit_definitions(simple, frame_variables(simple))[:2]
    (rank_off, _), (rank, piv) = _loop_rank(simple, loop, param_values, definitions)
    framed = dataclasses.replace(simple, equations=_frame_resolved(simple))
    if any(e is not f for e, f in zip(simple.equations, framed.equations, strict=True)):
        (rank_f_off, _), (rank_f, piv_f) = _loop_rank(framed, loop, param_values, definitions)
        # which resolution: decided off the constraint manifold, where a world row that only the start pose made
        # redundant (the loop plane turned by a slew) shows as independent
        if rank_f_off < rank_off:
            simple, rank, piv = framed, rank_f, piv_f
    dropped = sorted(int(piv[k]) for k in range(rank, len(loop)))
    if not dropped:
        return simple
    equations = list(simple.equations)
    outputs = dict(simple.outputs)
    report = []
    for k in dropped:
        r = loop[k]
        old = equations[r]
        expr, what = _reaction(simple, old.meta)
        outputs[f"{CHECK_PREFIX}{old.owner + ': ' if old.owner else ''}{old.label} (dual to the {what})"] = old.expr
        equations[r] = FlatEquation(expr, old.owner, f"indeterminate reaction: {what} = 0", "redundant reaction",
                                    ("reaction", len(report)))  # its line in the report
        report.append(f"{old.owner or '(model)'}: dropped redundant constraint '{old.label}'; {what} is "
                      "statically indeterminate and set to 0")
    return dataclasses.replace(simple, equations=equations, outputs=outputs, redundant=report)


def _loop_rank(simple: SimpleSystem, loop: list[int], param_values: dict[int, float],
               definitions: tuple[ca.SX, ca.SX]) -> tuple[tuple[int, np.ndarray], tuple[int, np.ndarray]]:
    """Generic rank of the loop rows' Jacobian in joint coordinates and the QR pivots (independent rows first),
    ``(off, on)``: at perturbed points as perturbed (off the constraint manifold) and moved back onto the loop
    constraints (on it; the rows to drop). Without any perturbed point that closes the loops, both are the
    former. ``definitions``: the frame variables and their explicit definitions (:func:`explicit_definitions`,
    which leaves the loop rows out), substituted into the loop rows."""
    vs, defs = definitions
    L = ca.vertcat(*[simple.equations[r].expr for r in loop])
    for _ in range(len(simple.variables) + 1):
        if vs.numel() == 0 or not ca.depends_on(L, vs):
            break
        L = ca.substitute([L], [vs], [defs])[0]
    qs, qv, qn = [], [], []
    var_by_hash = {v.sym.element_hash(): v for v in simple.variables}
    for s in ca.symvar(L):
        v = var_by_hash.get(s.element_hash())
        if v is not None:
            qs.append(s)
            qv.append(v.start)
            qn.append(v.nominal)
    if not qs:  # rows of parameters only (two frames fixed in the world connected): rank 0 on and off the manifold
        psyms = [lookup_sym(h) for h in param_values]
        pairs = [(p, param_values[h]) for h, p in zip(param_values, psyms, strict=True) if p is not None]
        if pairs:
            L = ca.substitute([L], [ca.vertcat(*[p for p, _ in pairs])], [ca.DM([v for _, v in pairs])])[0]
        if L.is_constant():
            values = np.asarray(ca.evalf(L).full(), dtype=float).ravel()
            off = [(simple.equations[r], float(v)) for r, v in zip(loop, values, strict=True) if abs(v) > 1e-9]
            if off:
                rows = "; ".join(f"{e.owner + ': ' if e.owner else ''}{e.label or 'a connection row'} is off by {v:.6g}"
                                 for e, v in off[:4])
                raise ConnectError(f"frames fixed in the world are connected but do not coincide ({rows}); connect "
                                   "only one of them to the other part, or give them the same position and "
                                   "orientation")
        return (0, np.arange(len(loop))), (0, np.arange(len(loop)))
    q = ca.vertcat(*qs)
    psyms = [lookup_sym(h) for h in param_values]
    point_syms = ca.vertcat(q, *[p for p in psyms if p is not None])
    point_vals = np.concatenate([qv, [param_values[h] for h, p in zip(param_values, psyms, strict=True)
                                      if p is not None]])
    rel_syms = [rel.info.sym for rel, _ in simple.relations]
    jac = ca.jacobian(L, q)
    if rel_syms:
        jac = ca.substitute(jac, ca.vertcat(*rel_syms), ca.SX.zeros(len(rel_syms)))
    gfun = ca.Function("G", [point_syms], [jac])
    Lrel = ca.substitute(L, ca.vertcat(*rel_syms), ca.SX.zeros(len(rel_syms))) if rel_syms else L
    lfun = ca.Function("L", [point_syms], [Lrel])
    # generic rank: the start configuration may be singular (a stretched linkage); perturbed joint
    # coordinates keep a planar mechanism planar, so structural redundancy persists there
    # The rank is taken in coordinates scaled by their nominal values. Only large-motion coordinates
    # (nominal >= SMALL_MOTION_NOMINAL: joint angles, positions) are perturbed: a small-motion one (a flexible
    # body's modal coordinate, nominal ~1e-3 of the body) stays at its start, because a loop row that a
    # deformation affects only at second order (a link bent in two planes at once) is redundant for the
    # small deformations the coordinate stands for, not an independent constraint.
    nom = np.asarray(qn, dtype=float)
    moves = np.where(nom >= SMALL_MOTION_NOMINAL, 1.0, 0.0)
    rng = np.random.default_rng(12345)
    start = np.asarray(gfun(point_vals)) * nom
    off, on = [start], [start]
    for _ in range(2):
        pert = point_vals.copy()
        pert[:len(qv)] += 0.05 * rng.standard_normal(len(qv)) * (nom + np.abs(pert[:len(qv)])) * moves
        off.append(np.asarray(gfun(pert)) * nom)
        projected = onto_loops(lfun, gfun, pert, nom * moves)
        if projected is not None:
            on.append(np.asarray(gfun(projected)) * nom)
    if len(on) == 1:  # no perturbed point closes the loops (they cannot close near the start): the raw ranks
        on = off
    return _pivots(max(off, key=_rank)), _pivots(max(on, key=_rank))


def _pivots(G: np.ndarray) -> tuple[int, np.ndarray]:
    """Rank of the rows of ``G`` and the pivot order (independent rows first) of a pivoted QR of ``Gᵀ``."""
    scale = max(1.0, float(np.abs(G).max()))
    _, R, piv = sla.qr(G.T, mode="economic", pivoting=True)
    diag = np.abs(np.diag(R))
    return int(np.sum(diag > 1e-9 * scale)), piv


def onto_loops(lfun: ca.Function, gfun: ca.Function, point: np.ndarray, scale: np.ndarray,
                iterations: int = 30) -> np.ndarray | None:
    """``point`` (the loop rows' coordinates, then the parameters) moved onto the loop constraints (Gauss–Newton,
    minimum-norm steps in the coordinates ``scale`` > 0 scaled by it; the others held), or None if it does not
    converge; ``lfun`` and ``gfun`` give the rows and their Jacobian in the coordinates at a point.

    The rank must be the generic rank *on the constraint manifold*: off it, rows that are dependent only because
    of the geometry the loops enforce (the extra links of a parallelogram, parallel to the line of its disc axes)
    become independent, and a perturbed point left off the manifold would count them as constraints."""
    x = point.copy()
    n = len(scale)
    cols = np.flatnonzero(scale > 0)
    r0 = np.asarray(lfun(x), dtype=float).ravel()
    tol = 1e-12 * max(1.0, float(np.abs(r0).max(initial=0.0)), float(np.abs(x[:n]).max(initial=0.0)))
    for _ in range(iterations):
        r = np.asarray(lfun(x), dtype=float).ravel()
        if not np.all(np.isfinite(r)):
            return None
        if np.abs(r).max(initial=0.0) <= tol:
            return x
        J = np.asarray(gfun(x), dtype=float)[:, cols] * scale[cols]
        step = np.linalg.lstsq(J, r, rcond=None)[0]
        x[cols] -= scale[cols] * step
    return None


def _rank(G: np.ndarray) -> int:
    if G.size == 0:
        return 0
    sv = np.linalg.svd(G, compute_uv=False)
    return int(np.sum(sv > 1e-9 * max(1.0, float(np.abs(G).max()))))


def lookup_sym(h: int) -> ca.SX | None:
    """Parameter symbol by element hash."""
    from flexlib.core.variables import lookup_hash

    info = lookup_hash(h)
    return None if info is None else info.sym

