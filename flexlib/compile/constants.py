"""Stage 2d — structurally constant unknowns, eliminated after tearing (the way aliases are).

After alias elimination and tearing (the frame orientations and origins are substituted), some unknowns are
fixed by the equations alone: a joint angle held by a rotational ``Fixed``, the motion of frames on fixed
pivots, the reactions that redundant loop rows set to zero, and whatever follows from them. They are found by
propagation to a fixpoint:

- a row left with a single unknown ``x``, linear in it with a coefficient built from parameters only and
  otherwise only parameters (``c(p)·x + d(p) = 0``: a sum of knowns, a product with a known zero), gives
  ``x = −d/c`` — a literal constant or a parameter expression, kept symbolic so ``run(params=...)`` changes it;
- a known ``x`` makes ``der(x) = 0`` (``v = der(constant)``), and its value is substituted everywhere, which
  can leave further rows with one unknown.

A row with one unknown must determine that unknown in any matching, so the remaining system is the original
one with a triangular block removed; a maximum matching checks that it is still structurally regular
(otherwise nothing is eliminated). Eliminated variables stay in results by name (their value expression).

**Planar mechanisms (default; opt out with ``assume_zero_geometry=False`` or ``FLEXLIB_ZERO_GEOMETRY=0``).**
A planar mechanism built from 3D components is planar only because some parameters are zero (in-plane
components of joint axes, out-of-plane components of rod vectors and centres of mass, products of inertia,
out-of-plane gravity), so its out-of-plane forces, torques, velocities and accelerations are zero numerically,
not structurally. When no row can be solved with the parameters symbolic, rows that become solvable with the
zero-valued parameters of frame components set to 0 are used, as few of those parameters as each row needs
are *assumed* zero (Modelica's ``Evaluate=true``) and substituted everywhere, and an axis ``n = (0, 0, n_z)``
normalised as ``n_z/|n_z|`` is made exact by assuming the sign of ``n_z``. The conditions are recorded
(``SimpleSystem.assumed``, ``CompiledModel.assumed``): a run whose parameters violate one fails with
:class:`~flexlib.errors.StructureChangedError` naming the parameter (:func:`check_assumed`; a ``params``
override never recompiles silently), and a cached build made under other values is rebuilt
(:func:`assumptions_hold`). Why, with the sizes it saves and the tests that moved when it became the default:
``docs/decisions/003-planar-geometry-assumed.md``.

Cost: one vectorised substitution and one sparsity pass screen the rows; a parameter is tried for release
symbolically only when a numeric sample does not already show that releasing it brings another unknown into
the row.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable

import casadi as ca
import numpy as np
import scipy.sparse as sp

from flexlib.compile.environment import env_default
from flexlib.compile.flatten import FlatVariable
from flexlib.compile.simplify import SimpleSystem
from flexlib.compile.structure import matching
from flexlib.core.component import Component
from flexlib.core.variables import lookup

__all__ = ["assumptions_hold", "check_assumed", "eliminate_constants", "zero_geometry"]


def _kinds(e: ca.SX, var_of: dict[int, int], der_of: dict[int, int]) -> tuple[list[int], list[int], bool]:
    """Unknowns, variables whose derivative appears, and whether time or a relation appears in ``e``."""
    unknowns, ders = [], []
    other = False
    for s in ca.symvar(e):
        h = s.element_hash()
        if h in var_of:
            unknowns.append(var_of[h])
        elif h in der_of:
            ders.append(der_of[h])
        else:
            info = lookup(s)
            if info is None or info.kind != "parameter":
                other = True
    return unknowns, ders, other


def _params_only(e: ca.SX) -> bool:
    return all((info := lookup(s)) is not None and info.kind == "parameter" for s in ca.symvar(e))


class _Solver:
    """Which unknown a row fixes to a constant, and to what value."""

    def __init__(self, simple: SimpleSystem, param_values: dict[int, float]) -> None:
        self.simple = simple
        self.var_of = {v.sym.element_hash(): k for k, v in enumerate(simple.variables)}
        self.der_of = {v.info._der.sym.element_hash(): k for k, v in enumerate(simple.variables)
                       if v.info._der is not None}
        self.ruled = {self.var_of[h] for h in simple.der_rules if h in self.var_of}
        syms = [lookup_param(h) for h in param_values]
        self.psyms = [s for s in syms if s is not None]
        self.pvals = np.array([param_values[s.element_hash()] for s in self.psyms])
        self.pvec = ca.vertcat(*self.psyms) if self.psyms else ca.SX(0, 1)
        self.xvec = ca.vertcat(*[v.sym for v in simple.variables])

    def single_unknown(self, exprs: list[ca.SX]) -> np.ndarray:
        """Mask of the rows that depend structurally on exactly one unknown: one sparsity pass over all of
        them instead of a ``symvar`` per row (a row :meth:`solve` can use is among them)."""
        if not exprs:
            return np.zeros(0, dtype=bool)
        rows, _ = ca.jacobian_sparsity(ca.vertcat(*exprs), self.xvec).get_triplet()
        return np.bincount(np.asarray(rows, dtype=int), minlength=len(exprs)) == 1

    def value_at(self, e: ca.SX) -> float:
        """Numeric value of a parameter expression at the build's parameter values."""
        f = ca.Function("v", [self.pvec], [e])
        return float(f(self.pvals))

    def solve(self, e: ca.SX) -> tuple[int, ca.SX] | None:
        unknowns, ders, other = _kinds(e, self.var_of, self.der_of)
        if not unknowns:
            return None
        if len(unknowns) == 1 and not ders and not other:
            k = unknowns[0]
            x = self.simple.variables[k].sym
            if k not in self.ruled and ca.is_linear(e, x):
                c = ca.jacobian(e, x)
                if not c.is_zero() and _params_only(c):
                    rest = ca.substitute(e, x, ca.SX(0.0))
                    if rest.is_zero():
                        return k, ca.SX(0.0)
                    if self.value_at(c) != 0.0:
                        return k, ca.simplify(-rest / c)
        return None


def eliminate_constants(simple: SimpleSystem, param_values: dict[int, float], *,
                        assume_zero_geometry: bool | None = None) -> SimpleSystem:
    """Eliminate the unknowns that the equations fix to constants or parameter expressions.

    Parameters
    ----------
    simple : SimpleSystem
        The system after alias elimination, redundant-constraint removal and tearing.
    param_values : dict
        Parameter values by symbol hash (the build's values; used to find the zero-valued parameters
        and to check that a parameter coefficient is not zero).
    assume_zero_geometry : bool or None
        Assume the zero-valued frame parameters zero (see the module doc); None: :func:`zero_geometry`
        (True unless ``FLEXLIB_ZERO_GEOMETRY=0``).

    Returns
    -------
    SimpleSystem
        Without the constant unknowns and their rows; ``outputs`` give every eliminated variable's value,
        ``assumed`` names the zero-valued parameters the elimination relies on.
    """
    if not simple.equations:
        return simple
    if assume_zero_geometry is None:
        assume_zero_geometry = zero_geometry()
    for use_zeros in ((True, False) if assume_zero_geometry else (False,)):
        found = _propagate(simple, param_values, use_zeros)
        if found is None:
            continue
        known, rows, assumed, signs = found
        if not known:
            return simple
        return _apply(simple, known, rows, assumed, signs)
    return simple


def _propagate(simple: SimpleSystem, param_values: dict[int, float],
               use_zeros: bool) -> tuple[dict[int, ca.SX], set[int], set[int], dict[int, float]] | None:
    """Known values by variable index, the rows used, the assumed zero parameters; None if the
    remaining system would not be structurally regular."""
    solver = _Solver(simple, param_values)
    geometric = geometric_parameters(simple)
    scalar = {q.sym.element_hash() for q in simple.flat.parameters if not q.index}
    zero_syms = {s.element_hash(): s for s, v in zip(solver.psyms, solver.pvals, strict=True)
                 if v == 0.0 and s.element_hash() in geometric}
    eqs = [e.expr for e in simple.equations]
    alive = list(range(len(eqs)))
    known: dict[int, ca.SX] = {}
    order: list[tuple[int, int]] = []  # (variable, row) in the order found
    assumed: set[int] = set()
    signs: dict[int, float] = {}  # parameter hash -> sign assumed (fabs(p) -> sign*... made exact)
    cand: dict[int, tuple[int, ca.SX] | None] = {}
    zero_cand: dict[int, tuple[int, ca.SX, list[int]] | None] = {}
    dirty = set(alive)
    users = _row_users(solver, eqs)
    new_old: list[ca.SX] = []
    new_val: list[ca.SX] = []
    values = dict(zip([q.element_hash() for q in solver.psyms], solver.pvals.tolist(), strict=True))
    while True:
        if new_old:
            _substitute_rows(eqs, alive, new_old, new_val, dirty, users)
            if any(h in assumed for h in (x.element_hash() for x in new_old)):
                sign_old, sign_new = _sign_rewrites(eqs, alive, geometric, values, signs)
                if sign_old:
                    _substitute_rows(eqs, alive, sign_old, sign_new, dirty)
            new_old, new_val = [], []
        rows = sorted(dirty)
        for r, one in zip(rows, solver.single_unknown([eqs[r] for r in rows]), strict=True):
            cand[r] = solver.solve(eqs[r]) if one else None
            zero_cand.pop(r, None)
        dirty = set()
        chosen = [(r, cand[r][0], cand[r][1], []) for r in alive if cand[r] is not None]
        if not chosen and use_zeros and zero_syms:
            rows = [r for r in alive if r not in zero_cand]
            zero_cand.update(zip(rows, _zero_solve(solver, [eqs[r] for r in rows], zero_syms, scalar), strict=True))
            chosen = [(r, *zero_cand[r]) for r in alive if zero_cand[r] is not None]
        if not chosen:
            break
        used = set()
        for r, k, val, zs in chosen:
            if k in known or k in used:
                continue
            used.add(k)
            known[k] = val
            order.append((k, r))
            alive.remove(r)
            _pin(simple.variables[k], val, new_old, new_val)
            for h in zs:
                if h not in assumed:
                    assumed.add(h)
                    new_old.append(zero_syms[h])
                    new_val.append(ca.SX(0.0))
    if not known:
        return {}, set(), set(), {}
    if len(known) == len(simple.variables):  # IDA needs one unknown: keep the last one found with its row
        k, r = order.pop()
        del known[k]
        alive.append(r)
        eqs[r] = simple.equations[r].expr
        osyms = [simple.variables[j].sym for j in known] + [lookup_param(h) for h in assumed]
        ovals = list(known.values()) + [ca.SX(0.0)] * len(assumed)
        osyms += [lookup_param(h) for h in signs]
        ovals += [sg * ca.fabs(lookup_param(h)) for h, sg in signs.items()]
        ders = [simple.variables[j].info._der.sym for j in known if simple.variables[j].info._der is not None]
        osyms += ders
        ovals += [ca.SX(0.0)] * len(ders)
        eqs[r] = ca.substitute([eqs[r]], [ca.vertcat(*osyms)], [ca.vertcat(*ovals)])[0]
    if not _regular(simple, [eqs[r] for r in alive], known):
        return None
    used_rows = set(range(len(eqs))) - set(alive)
    return known, used_rows, assumed, signs


def geometric_parameters(simple: SimpleSystem) -> set[int]:
    """Hashes of the parameters the domain passes of ``simple``'s model name as geometry: those that may be
    assumed zero where they are zero (:meth:`flexlib.compile.passes.Pass.geometric_parameters`)."""
    out: set[int] = set()
    for p in simple.flat.passes:
        out |= p.geometric_parameters(simple)
    return out


def zero_geometry() -> bool:
    """The default of ``assume_zero_geometry`` (``BuildOptions.zero_geometry``): True unless
    ``FLEXLIB_ZERO_GEOMETRY=0`` (or ``false``, ``no``, ``off``; see the module doc and
    :func:`flexlib.compile.environment.env_default`)."""
    return bool(env_default("zero_geometry"))


def _sign_rewrites(eqs: list[ca.SX], alive: list[int], geometric: set[int], values: dict[int, float],
                   signs: dict[int, float]) -> tuple[list[ca.SX], list[ca.SX]]:
    """``p → sign(p)·|p|`` for the non-zero frame parameters that appear as ``|p|`` (the norm of an axis
    with two components at zero): ``p/|p|`` becomes exactly ±1, so a planar rotation's out-of-plane
    entries become literal 0 and 1. Records the sign as an assumption."""
    rows = [eqs[r] for r in alive]
    if not rows:
        return [], []
    vec = ca.vertcat(*rows)
    syms = ca.symvar(vec)
    f = ca.Function("scan", [ca.vertcat(*syms)], [vec])
    holds: dict[int, int] = {}
    found: set[int] = set()
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        out = f.instruction_output(k)
        if op == ca.OP_FABS:
            j = holds.get(f.instruction_input(k)[0])
            if j is not None:
                found.add(j)
        for o in out:
            holds.pop(o, None)
        if op == ca.OP_INPUT:
            holds[out[0]] = f.instruction_input(k)[1]
    old, new = [], []
    for j in sorted(found):
        p = syms[j]
        h = p.element_hash()
        if h in signs or h not in geometric or values.get(h, 0.0) == 0.0:
            continue
        signs[h] = float(np.sign(values[h]))
        old.append(p)
        new.append(signs[h] * ca.fabs(p))
    return old, new


def _zero_solve(solver: _Solver, rows: list[ca.SX], zero_syms: dict[int, ca.SX],
                scalar: set[int]) -> list[tuple[int, ca.SX, list[int]] | None]:
    """Solve each row with the zero-valued frame parameters set to 0, assuming as few of them as needed
    (scalar parameters such as gravity or a mass are released first, then vector and tensor entries).

    All rows are substituted in one call and screened by one sparsity pass; only the rows that become
    solvable are examined one by one. There, releasing a parameter that brings another unknown into the row
    is recognised numerically (the row's derivative with respect to that unknown is non-zero at a sample
    point: the trial would fail), so the symbolic trial runs only for the parameters that may be released."""
    if not rows:
        return []
    zs = list(zero_syms.values())
    sub = ca.substitute([ca.vertcat(*rows)], [ca.vertcat(*zs)], [ca.SX.zeros(len(zs))])[0]
    subs = [sub[k] for k in range(len(rows))]
    out: list[tuple[int, ca.SX, list[int]] | None] = [None] * len(rows)
    rng = np.random.default_rng(0)
    for j in np.flatnonzero(solver.single_unknown(subs)):
        res = solver.solve(subs[j])
        if res is None:
            continue
        e = rows[j]
        syms = ca.symvar(e)
        hashes = [s.element_hash() for s in syms]
        present = [s for s, h in zip(syms, hashes, strict=True) if h in zero_syms]
        if not present:
            continue

        def attempt(zs: list[ca.SX], e: ca.SX = e) -> tuple[int, ca.SX] | None:
            return solver.solve(ca.substitute(e, ca.vertcat(*zs), ca.SX.zeros(len(zs)))) if zs else None

        res = attempt(present)  # the row's own zeros only: the same value as ``subs[j]``, built from ``e``
        if res is None:
            continue
        position = {h: i for i, h in enumerate(h for h in hashes if h in zero_syms)}  # index in ``present``
        need = sorted(position, key=lambda h: h not in scalar)  # hashes
        brings = _other_unknown_test(solver, e, syms, hashes, present, res[0], rng)
        for h in list(need):
            rest = [w for w in need if w != h]
            if not rest or brings([position[w] for w in rest]):
                continue
            trial = attempt([zero_syms[w] for w in rest])
            if trial is not None and trial[0] == res[0]:
                need, res = rest, trial
        out[j] = (res[0], res[1], need)
    return out


def _other_unknown_test(solver: _Solver, e: ca.SX, syms: list[ca.SX], hashes: list[int], present: list[ca.SX],
                        k: int, rng: np.random.Generator):
    """``brings(zeros)``: True if row ``e`` with only the ``present`` zero parameters at positions ``zeros`` set to
    0 (the others at sample values) certainly depends on an unknown other than ``k`` — its derivative with respect to
    one is finite and non-zero at a sample point (parameters at their values, other symbols random)."""
    other = [s for s, h in zip(syms, hashes, strict=True) if h in solver.var_of and solver.var_of[h] != k]
    if not other:
        return lambda zeros: False
    index = {z.element_hash(): i for i, z in enumerate(present)}
    rest = [s for s, h in zip(syms, hashes, strict=True) if h not in index]
    values = dict(zip([q.element_hash() for q in solver.psyms], solver.pvals.tolist(), strict=True))
    rest_val = np.array([values.get(s.element_hash(), rng.uniform(0.5, 1.5)) for s in rest])
    pres_val = rng.uniform(0.5, 1.5, len(present))
    jac = ca.Function("d", [ca.vertcat(*present), ca.vertcat(*rest)], [ca.jacobian(e, ca.vertcat(*other))])

    def brings(zeros: list[int]) -> bool:
        p = pres_val.copy()
        p[zeros] = 0.0
        d = np.asarray(jac(p, rest_val), dtype=float)
        return bool(np.any(np.isfinite(d) & (d != 0.0)))

    return brings


def _row_users(solver: _Solver, eqs: list[ca.SX]) -> dict[int, set[int]]:
    """Rows that depend on each unknown and derivative (by symbol hash), from one sparsity pass. Substituted
    values hold parameters only, so a row's set of unknowns can only shrink: the map stays a superset."""
    syms = [v.sym for v in solver.simple.variables] + [v.info._der.sym for v in solver.simple.variables
                                                       if v.info._der is not None]
    users: dict[int, set[int]] = {s.element_hash(): set() for s in syms}
    if eqs and syms:
        rows, cols = ca.jacobian_sparsity(ca.vertcat(*eqs), ca.vertcat(*syms)).get_triplet()
        for r, c in zip(rows, cols, strict=True):
            users[syms[c].element_hash()].add(r)
    return users


def _substitute_rows(eqs: list[ca.SX], alive: list[int], old: list[ca.SX], new: list[ca.SX], dirty: set[int],
                     users: dict[int, set[int]] | None = None) -> None:
    """Substitute ``old → new`` in the alive rows that depend on ``old``; mark them dirty. Rows that use an
    unknown or derivative in ``old`` are looked up in ``users`` (:func:`_row_users`), the others (parameters)
    found by a sparsity pass over the alive rows."""
    if not alive:
        return
    users = users or {}
    live = set(alive)
    touched_rows: set[int] = set()
    params = []
    for x in old:
        h = x.element_hash()
        if h in users:
            touched_rows |= users[h] & live
        else:
            params.append(x)
    if params:
        spj = ca.jacobian_sparsity(ca.vertcat(*[eqs[r] for r in alive]), ca.vertcat(*params))
        touched_rows |= {alive[j] for j in spj.get_triplet()[0]}
    touched = sorted(touched_rows)
    if not touched:
        return
    sub = ca.substitute([ca.vertcat(*[eqs[r] for r in touched])], [ca.vertcat(*old)], [ca.vertcat(*new)])[0]
    for i, r in enumerate(touched):
        eqs[r] = sub[i]
        dirty.add(r)


def _regular(simple: SimpleSystem, rows: list[ca.SX], known: dict[int, ca.SX]) -> bool:
    """True if the remaining rows match the remaining unknowns perfectly (derivatives count for their variable)."""
    rest = [k for k in range(len(simple.variables)) if k not in known]
    if len(rows) != len(rest):
        return False
    if not rows:
        return True
    cols, owner = [], []
    for j, k in enumerate(rest):
        v = simple.variables[k]
        cols.append(v.sym)
        owner.append(j)
        if v.info._der is not None:
            cols.append(v.info._der.sym)
            owner.append(j)
    spj = ca.jacobian_sparsity(ca.vertcat(*rows), ca.vertcat(*cols))
    r_idx, c_idx = spj.get_triplet()
    inc = sp.csr_matrix((np.ones(len(r_idx)), (np.asarray(r_idx, dtype=int),
                                                np.asarray(owner, dtype=int)[np.asarray(c_idx, dtype=int)])),
                        shape=(len(rows), len(rest)))
    row_match, _ = matching(inc)
    return bool(np.all(row_match >= 0))


def _pin(v: FlatVariable, val: ca.SX, old: list[ca.SX], new: list[ca.SX]) -> None:
    """Append the substitution of the constant ``val`` for the unknown ``v`` (and 0 for its derivative, if it has
    one) to ``old``/``new``."""
    old.append(v.sym)
    new.append(val)
    if v.info._der is not None:
        old.append(v.info._der.sym)
        new.append(ca.SX(0.0))


def _substituter(old: list[ca.SX], new: list[ca.SX]):
    o, n = ca.vertcat(*old), ca.vertcat(*new)

    def subst(exprs: list[ca.SX]) -> list[ca.SX]:
        if not exprs or not old:
            return list(exprs)
        out = ca.substitute([ca.vertcat(*exprs)], [o], [n])[0]
        return [out[k] for k in range(out.numel())]

    return subst


def _replace(simple: SimpleSystem, keep_rows: Iterable[int], drop_vars: set[int], old: list[ca.SX],
             new: list[ca.SX], **extra) -> SimpleSystem:
    subst = _substituter(old, new)
    kept = [simple.equations[r] for r in keep_rows]
    equations = [dataclasses.replace(e, expr=x) for e, x in zip(kept, subst([e.expr for e in kept]), strict=True)]
    variables = [v for k, v in enumerate(simple.variables) if k not in drop_vars]
    signals = simple.substituted_signals(subst)
    dropped = {simple.variables[k].sym.element_hash() for k in drop_vars}
    rk = [h for h in simple.der_rules if h not in dropped]
    rules = dict(zip(rk, subst([simple.der_rules[h] for h in rk]), strict=True))
    return dataclasses.replace(simple, variables=variables, equations=equations, der_rules=rules, **signals, **extra)


def _apply(simple: SimpleSystem, known: dict[int, ca.SX], rows: set[int], assumed: set[int],
           signs: dict[int, float]) -> SimpleSystem:
    old, new = [], []
    zero_old = [lookup_param(h) for h in assumed]
    sign_old = [lookup_param(h) for h in signs]
    sign_new = [sg * ca.fabs(p) for p, sg in zip(sign_old, signs.values(), strict=True)]
    for k, val in known.items():
        _pin(simple.variables[k], val, old, new)
    # values may contain assumed parameters only through rows solved before the assumption: set them to 0
    if zero_old:
        zsub = _substituter(zero_old, [ca.SX(0.0)] * len(zero_old))
        new = zsub(new)
        old += zero_old
        new += [ca.SX(0.0)] * len(zero_old)
    if sign_old:
        new = _substituter(sign_old, sign_new)(new)
        old += sign_old
        new += sign_new
    names = {q.sym.element_hash(): q.name for q in simple.flat.parameters}
    assumed_names = dict(simple.assumed)
    assumed_names.update({names[h]: "= 0" for h in assumed if h in names})
    assumed_names.update({names[h]: "> 0" if sg > 0 else "< 0" for h, sg in signs.items() if h in names})
    keep = [r for r in range(len(simple.equations)) if r not in rows]
    return _replace(simple, keep, set(known), old, new, assumed=dict(sorted(assumed_names.items())),
                    n_constants=simple.n_constants + len(known))


def lookup_param(h: int) -> ca.SX | None:
    """Parameter symbol by element hash (None if unknown)."""
    info = lookup_info(h)
    return None if info is None or info.kind != "parameter" else info.sym


def lookup_info(h: int):
    from flexlib.core.variables import lookup_hash

    return lookup_hash(h)


def _holds(condition: str, value: float) -> bool:
    return {"= 0": value == 0.0, "> 0": value > 0.0, "< 0": value < 0.0}[condition]


def assumptions_hold(assumed: dict[str, str], root: Component) -> bool:
    """True if every parameter condition a (cached) build assumed holds for the values of model ``root``."""
    if not assumed:
        return True
    values, _ = root.values()
    return all(_holds(cond, values[name]) for name, cond in assumed.items() if name in values)


def check_assumed(assumed: dict[str, str], names: list[str], vec: np.ndarray, model: str = "") -> None:
    """Raise :class:`~flexlib.errors.StructureChangedError` if a parameter violates a build assumption.

    Parameters
    ----------
    assumed : dict
        Parameter name → condition the build relied on (``"= 0"``, ``"> 0"``, ``"< 0"``).
    names : list of str
        Names of the entries of ``vec``.
    vec : ndarray
        The parameter values of a run.
    model : str
        Model name for the message.
    """
    if not assumed:
        return
    index = {n: k for k, n in enumerate(names)}
    bad = [(n, float(vec[index[n]]), c) for n, c in assumed.items() if n in index and not _holds(c, vec[index[n]])]
    if bad:
        from flexlib.errors import StructureChangedError

        what = ", ".join(f"{n} = {x:g} (the build assumed {n} {c})" for n, x, c in bad)
        raise StructureChangedError(
            f"model {model}: {what}: the build eliminated unknowns that this parameter fixes (e.g. the "
            "out-of-plane motion of a planar mechanism), so a run cannot change it; set the value on the "
            "model and create a new Simulation, or build with Simulation(model, assume_zero_geometry=False) "
            "to vary it in runs")
