"""The frames' kinematics carried along the spanning tree, and their error-test marks: the multibody pass's part of
the error-test policy (:mod:`flexlib.compile.scaling`).

A component relates its frames with MSL's rows only (``r_0``, ``T``, ``w``, ``f``, ``t``). The pass gives every
frame its velocity ``v``, acceleration less gravity ``a`` and angular acceleration ``z``, resolved in the frame
(:func:`declare_frame_kinematics`), and writes their rows (recursive kinematics, as in Featherstone's algorithms):

- at each tree root from its component's rows and the World's gravity (:func:`root_kinematics`);
- along each branch from the rows that place one frame relative to the other with the component's own coordinates
  (:func:`branch_kinematics`), so accelerations are computed by rows free of derivatives, and a body reads its
  frame's ``a`` and ``z`` instead of the second time derivative of its position, which depends on every joint
  coordinate between it and the root.

Where the compile-time derivative level (``structure.derivative_level``) cannot see that these are accelerations,
this module marks them:

- a frame's ``v``, ``a``, ``z`` are kinematic intermediates (eliminated where a row gives them explicitly), and
  ``a``, ``z`` are kept out of IDA's local error test;
- in a component with frames, an unknown ``y`` that a row defines as the derivative of a velocity the component
  prefers as a state, ``der(w) = y`` with ``w`` itself not the coordinate but its rate (``y`` not declared
  ``state_select="prefer"``), is the joint's acceleration and kept out of the error test (a revolute's ``a``, a
  free motion's ``a_rel_a`` and ``z_rel_b``, a flexible body's modal accelerations ``qdd``).

An acceleration in the error test forces steps the positions and velocities do not need: measured, a point mass on
a universal joint took 22 000 steps instead of 1 040 when one of its accelerations was tested.
"""

from __future__ import annotations

from collections.abc import Callable

import casadi as ca
import numpy as np

from flexlib.compile.flatten import FlatEquation
from flexlib.core.component import Component, Connector, Node
from flexlib.core.equations import der
from flexlib.core.variables import Potential, StateSelect, SymInfo, lookup
from flexlib.errors import ModelError

__all__ = ["FRAME_KINEMATICS", "FRAME_MARKS", "acceleration_marks", "branch_kinematics", "declare_frame_kinematics",
           "frame_kinematics_declaration", "root_kinematics", "tree_kinematics"]

#: The kinematic quantities of a frame the pass carries along the tree: (unit, meaning), all resolved in the frame.
FRAME_KINEMATICS = {
    "v": ("m/s", "Velocity of the origin, resolved in frame (multibody pass)"),
    "a": ("m/s2", "Acceleration of the origin less gravity, T (d²r_0/dt² − g), resolved in frame (multibody pass)"),
    "z": ("rad/s2", "Angular acceleration, resolved in frame (multibody pass)"),
}

#: Per kinematic quantity of a frame carried along the tree: (kept in the error test, kinematic intermediate).
FRAME_MARKS = {"v": (True, True), "a": (False, True), "z": (False, True)}


def _hashes(node: Node, name: str) -> list[int]:
    return [s.element_hash() for s in ca.symvar(node._symbol(name))]


def _symbol_pair(expr: ca.SX) -> tuple[SymInfo, SymInfo] | None:
    """``(p, q)`` of a row ``p − q`` of two flexlib symbols, else None (no graph walk)."""
    if expr.n_dep() != 2 or expr.op() != ca.OP_SUB or not (expr.dep(0).is_symbolic() and expr.dep(1).is_symbolic()):
        return None
    p, q = lookup(expr.dep(0)), lookup(expr.dep(1))
    return None if p is None or q is None else (p, q)


def _difference(expr: ca.SX) -> tuple[SymInfo, SymInfo] | None:
    """``(der(x), y)`` of a row ``der(x) − y`` or ``y − der(x)`` of two symbols, else None (no graph walk)."""
    pair = _symbol_pair(expr)
    if pair is None:
        return None
    p, q = pair
    if p.kind == "der" and q.kind == "variable" and p.base is not None:
        return p, q
    if q.kind == "der" and p.kind == "variable" and q.base is not None:
        return q, p
    return None


def _acceleration(expr: ca.SX, owners: set[int]) -> int | None:
    """The symbol hash of ``y`` if ``expr`` is ``±(der(w) − y)`` with ``w`` and ``y`` unknowns of one component in
    ``owners`` (by ``id``), ``w`` preferred as a state and ``y`` not; else None."""
    pair = _difference(expr)
    if pair is None:
        return None
    d, y = pair
    w = d.base
    if w.node is not y.node or id(y.node) not in owners:
        return None
    decls = y.node._decls
    if decls[w.name].state_select is not StateSelect.prefer or decls[y.name].state_select is StateSelect.prefer:
        return None
    return y.sym.element_hash()


def acceleration_marks(nodes: list[Node], equations: list[FlatEquation],
                       is_frame: Callable[[type], bool]) -> tuple[set[int], set[int]]:
    """Symbol hashes of the unknowns to keep out of the error test and of the kinematic intermediates (module doc);
    ``is_frame`` tells a frame connector class."""
    untested: set[int] = set()
    intermediate: set[int] = set()
    owners: dict[str, int] = {}
    for node in nodes:
        if not (isinstance(node, Connector) and is_frame(type(node))):
            continue
        for name, (tested, inter) in FRAME_MARKS.items():
            if name in node._decls:
                hashes = _hashes(node, name)
                if not tested:
                    untested.update(hashes)
                if inter:
                    intermediate.update(hashes)
        parent = node._parent
        if isinstance(parent, Component):
            owners[parent.path] = id(parent)
    ids = set(owners.values())
    for e in equations:
        if e.origin == "equation" and e.owner in owners:
            h = _acceleration(e.expr, ids)
            if h is not None:
                untested.add(h)
    return untested, intermediate


# -- the recursion introduced for a joint written with MSL's rows only ------------------------------------------


def _rates(rows: list[ca.SX]) -> dict[int, ca.SX]:
    """``{hash(x): y}`` for the rows ``±(der(x) − y)`` of one component (``w = der(phi)``, ``a = der(w)``)."""
    out: dict[int, ca.SX] = {}
    for expr in rows:
        pair = _difference(expr)
        if pair is not None:
            out[pair[0].base.sym.element_hash()] = pair[1].sym
    return out


def _aliased(rows: list[ca.SX], rates: dict[int, ca.SX]) -> dict[int, ca.SX]:
    """``rates`` with the rate of ``x`` given to ``p`` too for each row ``p − x`` of two unknowns (``r_0 =
    frame_a.r_0`` beside ``v_0 = der(r_0)``)."""
    out = dict(rates)
    for expr in rows:
        pair = _symbol_pair(expr)
        if pair is None or pair[0].kind != "variable" or pair[1].kind != "variable":
            continue
        p, q = pair
        hp, hq = p.sym.element_hash(), q.sym.element_hash()
        if hq in out and hp not in out:
            out[hp] = out[hq]
        elif hp in out and hq not in out:
            out[hq] = out[hp]
    return out


def _rate(expr: ca.SX, rates: dict[int, ca.SX]) -> ca.SX:
    """``d expr/dt``: a symbol's rate from ``rates`` where a row gives it, else its ``der()`` symbol."""
    if expr.is_constant():
        return ca.SX.zeros(expr.shape)
    syms, dots = [], []
    for s in ca.symvar(expr):
        info = lookup(s)
        if info is None or info.kind in ("parameter", "relation", "table"):
            continue
        syms.append(s)
        dots.append(rates.get(s.element_hash(), der(s)))
    if not syms:
        return ca.SX.zeros(expr.shape)
    return ca.jtimes(expr, ca.vertcat(*syms), ca.vertcat(*dots))


def _coefficient(expr: ca.SX, t: ca.SX) -> float:
    """The constant coefficient of ``t`` in ``expr`` (0 if it is not a nonzero constant)."""
    coef = ca.jacobian(expr, t)
    if coef.is_one():
        return 1.0
    if coef.is_minus_one():
        return -1.0
    return float(ca.evalf(coef)) if coef.is_constant() else 0.0


def _definitions(rows: list[ca.SX], hashes: list[set[int]], targets: list[ca.SX],
                 exclude: list[ca.SX] = ()) -> list[ca.SX] | None:
    """Per target symbol, the expression a row gives it explicitly (linear with a constant coefficient), from rows
    with one target and none of ``exclude`` (``hashes``: the symbols of each row); None if a target has none."""
    index = {t.element_hash(): k for k, t in enumerate(targets)}
    skip = {t.element_hash() for t in exclude}
    found: list[ca.SX | None] = [None] * len(targets)
    for expr, present in zip(rows, hashes, strict=True):
        hits = [index[h] for h in present if h in index]
        if len(hits) != 1 or found[hits[0]] is not None or not skip.isdisjoint(present):
            continue
        t = targets[hits[0]]
        if expr.op() == ca.OP_SUB and ca.is_equal(expr.dep(0), t):  # t − f (eq(t, f)): f, no substitution
            found[hits[0]] = expr.dep(1)
            continue
        c = _coefficient(expr, t)
        if c != 0.0:
            found[hits[0]] = -ca.substitute(expr, t, ca.SX(0.0)) / c
    return None if any(f is None for f in found) else found  # type: ignore[return-value]


def _elements(node: Node, name: str) -> list[ca.SX]:
    sym = node._symbol(name)
    return [sym.nz[k] for k in range(sym.numel())]


def _check_relative(owner: Component, exprs: list[ca.SX], relative: list[ca.SX], src_T: ca.SX) -> None:
    """The definitions must be the relative ones moved by the source frame's rigid motion (written as MSL writes
    a joint); checked at a random point with a random source orientation."""
    rng = np.random.default_rng(20261127)
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    both = ca.vertcat(*[ca.vec(x) for x in exprs]) - ca.vertcat(*[ca.vec(x) for x in relative])
    both = ca.substitute(both, ca.vec(src_T), ca.vec(ca.DM(q)))
    syms = ca.symvar(both)
    f = ca.Function("rel", [ca.vertcat(*syms) if syms else ca.SX(0, 1)], [both])
    with np.errstate(all="ignore"):
        gap = np.asarray(f(rng.uniform(-1.0, 1.0, len(syms))), dtype=float).ravel()
    if not np.all(np.abs(gap) <= 1e-9):
        raise ModelError(f"{owner.path}: the rows relating its frames are not a relative motion of one frame from the "
                         "other (r_0,b = r_0,a + T_aᵀ r_rel, T_b = T_rel T_a, w_b = T_rel w_a + w_rel): the multibody "
                         "pass cannot introduce the frames' velocities and accelerations")


def _source(owner: Component, src: Connector, dst: Connector, T_def: ca.SX) -> Connector:
    """The frame of ``owner`` that the rows compute ``dst`` from: the one whose ``T`` the orientation rows read (a
    flexible body writes all its frames from the one the tree enters by, not from frame_a of each branch), else
    ``src``."""
    read = [c for c in owner._children.values() if isinstance(c, Connector) and c is not dst and "T" in c._decls
            and ca.depends_on(ca.vec(T_def), ca.vec(c._symbol("T")))]
    return read[0] if len(read) == 1 else src


def _expanded(owner: Component, rows: list[ca.SX], rates: dict[int, ca.SX], *defs: ca.SX) -> list[ca.SX]:
    """``defs`` with the component's intermediate unknowns replaced by what its rows define them as: an unknown
    ``u`` of ``owner`` itself with a row ``u − f`` (``f`` free of ``u`` and of derivatives) and no rate in ``rates``
    (:func:`_rates` of ``rows``), such as a flexible body's angular velocity in body axes in
    ``w_frame = T_k w + w_k``."""
    known: dict[int, tuple[ca.SX, ca.SX]] = {}
    for expr in rows:
        if expr.n_dep() != 2 or expr.op() != ca.OP_SUB or not expr.dep(0).is_symbolic():
            continue
        info = lookup(expr.dep(0))
        if info is None or info.kind != "variable" or info.node is not owner:
            continue
        h = info.sym.element_hash()
        f = expr.dep(1)
        if h in rates or h in known or ca.depends_on(f, info.sym):
            continue
        if any((lookup(x) is not None and lookup(x).kind == "der") for x in ca.symvar(f)):
            continue
        known[h] = (info.sym, f)
    out = list(defs)
    for _ in range(3):
        both = ca.vertcat(*out)
        used = [known[s.element_hash()] for s in ca.symvar(both) if s.element_hash() in known]
        if not used:
            break
        syms, values = ca.vertcat(*[u for u, _ in used]), ca.vertcat(*[f for _, f in used])
        out = [ca.substitute(x, syms, values) for x in out]
    return out


def branch_kinematics(owner: Component, src: Connector, dst: Connector, rows: list[ca.SX],
                      checked: set | None = None, hashes: list[set[int]] | None = None) -> list[ca.SX] | None:
    """Rows for ``dst``'s ``v``, ``a``, ``z`` from ``src``'s, for a component that relates its frames with MSL's rows
    only (``r_0``, ``T``, ``w`` of ``dst`` defined from ``src`` and its coordinates). None where the component's
    own rows do not define ``dst``'s ``r_0``, ``T`` and ``w`` (a composite whose parts relate the frames).
    ``checked``: the (class, source, destination, row count) already checked to be a relative motion in this build;
    ``hashes``: the symbols of each row, if known.

    With ``r_0,dst = r_0,src + T_srcᵀ r_rel``, ``T_dst = T_rel T_src`` and ``w_dst = T_rel w_src + w_rel`` (checked),
    and ``˙`` the rate along the component's own rows::

        v_dst = T_rel (v_src + w_src × r_rel + ṙ_rel)
        a_dst = T_rel (a_src + z_src × r_rel + w_src × (w_src × r_rel) + 2 w_src × ṙ_rel + r̈_rel)
        z_dst = T_rel z_src + ẇ_rel + (T_rel w_src) × w_rel
    """
    T_dst, r_dst, w_dst = (_elements(dst, n) for n in ("T", "r_0", "w"))
    if hashes is None:
        hashes = [{s.element_hash() for s in ca.symvar(x)} for x in rows]
    T_defs = _definitions(rows, hashes, T_dst, exclude=r_dst + w_dst)  # the orientation first: others may use it
    rw_defs = _definitions(rows, hashes, r_dst + w_dst) if T_defs is not None else None
    if T_defs is None or rw_defs is None:
        return None
    T_def = ca.reshape(ca.vertcat(*T_defs), 3, 3)
    src = _source(owner, src, dst, T_def)
    T_syms = dst._symbol("T")
    rates = _rates(rows)
    r_own, w_own = _expanded(owner, rows, rates, ca.vertcat(*rw_defs[:3]), ca.vertcat(*rw_defs[3:]))
    r_def = ca.substitute(r_own, ca.vec(T_syms), ca.vec(T_def))
    w_def = ca.substitute(w_own, ca.vec(T_syms), ca.vec(T_def))
    T_src, r_src, w_src = src._symbol("T"), src._symbol("r_0"), src._symbol("w")
    eye = ca.DM(np.eye(3).reshape(-1, order="F"))
    zero = ca.DM(np.zeros(3))
    T_rel = ca.reshape(ca.substitute(ca.vec(T_def), ca.vec(T_src), eye), 3, 3)
    r_rel = ca.substitute(r_def, ca.vertcat(r_src, ca.vec(T_src)), ca.vertcat(zero, eye))
    w_rel = ca.substitute(w_def, ca.vertcat(w_src, ca.vec(T_src)), ca.vertcat(zero, eye))
    key = (type(owner), src._name, dst._name, len(rows))
    if checked is None or key not in checked:
        _check_relative(owner, [T_def, r_def, w_def],
                        [ca.mtimes(T_rel, T_src), r_src + ca.mtimes(T_src.T, r_rel), ca.mtimes(T_rel, w_src) + w_rel],
                        T_src)
        if checked is not None:
            checked.add(key)
    relative = ca.depends_on(ca.vertcat(r_own, w_own), ca.vec(T_syms))
    if relative:  # the rows give r_0 or w from dst's own T (a joint written from frame_b, rooted there): with
        # T_src = I that T stands for T_rel, whose rate is −[w_rel×] T_rel; no derivative of the coordinates T_rel is
        # made of (a quaternion's der(der(Q)))
        at_src = (ca.vertcat(r_src, w_src, ca.vec(T_src)), ca.vertcat(zero, zero, eye))
        r_rel, w_rel = ca.substitute(r_own, *at_src), ca.substitute(w_own, *at_src)
        T_rate = -ca.mtimes(ca.skew(w_rel), T_syms)
        rates.update({ca.vec(T_syms)[k].element_hash(): ca.vec(T_rate)[k] for k in range(9)})
    v_s, a_s, z_s = src._symbol("v"), src._symbol("a"), src._symbol("z")
    v_in, a_in = v_s, a_s
    if not r_rel.is_zero():
        rd = _rate(r_rel, rates)
        v_in = v_s + ca.cross(w_src, r_rel) + rd
        a_in = (a_s + ca.cross(z_s, r_rel) + ca.cross(w_src, ca.cross(w_src, r_rel)) + 2 * ca.cross(w_src, rd)
                + _rate(rd, rates))
    z = ca.mtimes(T_rel, z_s)
    if not w_rel.is_zero():
        z = z + _rate(w_rel, rates) + ca.cross(ca.mtimes(T_rel, w_src), w_rel)
    found = [dst._symbol("v") - ca.mtimes(T_rel, v_in), dst._symbol("a") - ca.mtimes(T_rel, a_in),
             dst._symbol("z") - z]
    if relative:
        found = [ca.substitute(x, ca.vec(T_syms), ca.vec(T_rel)) for x in found]
    return found


def _gravity(owner: Component, nodes: list[Node]) -> ca.SX:
    """The gravity acceleration resolved in world [m/s2] at a tree root: the root's component's ``gravity()`` if it
    has one (the World), else that of the model's World (the one definite root whose component has ``gravity()``)."""
    if callable(getattr(type(owner), "gravity", None)):
        return owner.gravity()
    worlds = [n for n in nodes if isinstance(n, Component) and n.__dict__.get("_od_roots")
              and callable(getattr(type(n), "gravity", None))]
    if len(worlds) != 1:
        raise ModelError(f"{owner.path}: computes the root of an orientation tree, and the multibody pass needs the "
                         f"gravity acceleration there; the model has {len(worlds)} World components (one gives "
                         "gravity to all frames)")
    return worlds[0].gravity()


def root_kinematics(owner: Component, root: Connector, rows: list[ca.SX], hashes: list[set[int]],
                    gravity: Callable[[], ca.SX]) -> list[ca.SX]:
    """Rows for the ``v``, ``a``, ``z`` of a tree's root frame from its component's rows (a World, a fixed frame or
    a free body that computes ``r_0``, ``T``, ``w`` of the frame): with ``˙`` the rate along those rows and ``g``
    the gravity acceleration::

        v = T ṙ_0,  a = T (r̈_0 − g),  z = ẇ

    ``r_0``, ``w`` and a constant ``T`` are taken as the rows define them (rows free of derivatives; where a row
    gives a rate, as a free body's ``v_0 = der(r_0)``, that rate), so a frame fixed in the world gets the constant
    rows ``v = 0``, ``a = −T g``, ``z = 0``. A varying ``T`` changes at ``−[w×] T`` (no derivative of the
    coordinates it is made of)."""
    T_sym, r_sym, w_sym = (_elements(root, n) for n in ("T", "r_0", "w"))
    plain = [k for k, x in enumerate(rows) if not any(_is_der(y) for y in ca.symvar(x))]
    rows_p, hashes_p = [rows[k] for k in plain], [hashes[k] for k in plain]
    T_defs = _definitions(rows_p, hashes_p, T_sym, exclude=r_sym + w_sym)
    rw_defs = _definitions(rows_p, hashes_p, r_sym + w_sym)
    T = root._symbol("T")
    rates = _aliased(rows, _rates(rows))
    r, w = root._symbol("r_0"), root._symbol("w")
    if rw_defs is not None:
        if not all(x.element_hash() in rates for x in r_sym):
            r = ca.vertcat(*rw_defs[:3])
        if not all(x.element_hash() in rates for x in w_sym):
            w = ca.vertcat(*rw_defs[3:])
    z = _rate(w, rates)
    if T_defs is not None and all(x.is_constant() for x in T_defs):
        T = ca.reshape(ca.vertcat(*T_defs), 3, 3)
    else:
        w_frame = root._symbol("w")
        T_rate = -ca.mtimes(ca.skew(w_frame), T)
        rates.update({ca.vec(T)[k].element_hash(): ca.vec(T_rate)[k] for k in range(9)})
        rates.update({w_frame[k].element_hash(): z[k] for k in range(3) if w_frame[k].element_hash() not in rates})
    rd = _rate(r, rates)
    return [root._symbol("v") - ca.mtimes(T, rd), root._symbol("a") - ca.mtimes(T, _rate(rd, rates) - gravity()),
            root._symbol("z") - z]


def _is_der(s: ca.SX) -> bool:
    info = lookup(s)
    return info is not None and info.kind == "der"


def frame_kinematics_declaration(node: Node, name: str, is_frame: Callable[[type], bool]
                                 ) -> tuple[Potential, str] | None:
    """The declaration of a frame's ``v``, ``a`` or ``z`` (:data:`FRAME_KINEMATICS`) and the name it follows, for a
    frame ``node`` (a connector with ``r_0``, ``T``, ``w``); None for another name or node."""
    if name not in FRAME_KINEMATICS or not (isinstance(node, Connector) and is_frame(type(node))):
        return None
    if not all(n in node._decls for n in ("r_0", "T", "w")):
        return None
    unit, doc = FRAME_KINEMATICS[name]
    before = ["w", *FRAME_KINEMATICS][:list(FRAME_KINEMATICS).index(name) + 1]
    after = next(n for n in reversed(before) if n in node._decls)  # the same order whichever is declared first
    return Potential(unit=unit, shape=3, overdetermined=True, doc=doc), after


def declare_frame_kinematics(nodes: list[Node], is_frame: Callable[[type], bool]) -> None:
    """Give every frame (a connector with ``r_0``, ``T``, ``w``) the kinematic quantities the pass carries along the
    tree, ``v``, ``a`` and ``z`` (:data:`FRAME_KINEMATICS`), as declarations of the pass
    (:meth:`~flexlib.core.component.Node.add_pass_declaration`)."""
    for node in nodes:
        for name in FRAME_KINEMATICS:
            found = frame_kinematics_declaration(node, name, is_frame)
            if found is not None:
                node.add_pass_declaration(name, *found)


class _Rows:
    """The rows of each component (indices into the flat equations, and the symbols of each), gathered once."""

    def __init__(self, equations: list[FlatEquation]) -> None:
        self.equations = equations
        self.own: dict[str, list[int]] = {}
        for r, e in enumerate(equations):
            if e.origin == "equation":
                self.own.setdefault(e.owner, []).append(r)
        self.symbols: dict[str, list[set[int]]] = {}

    def of(self, node: Component) -> tuple[list[int], list[ca.SX], list[set[int]]]:
        at = self.own.get(node.path, [])
        if node.path not in self.symbols:
            self.symbols[node.path] = [{s.element_hash() for s in ca.symvar(self.equations[r].expr)} for r in at]
        return at, [self.equations[r].expr for r in at], self.symbols[node.path]


def _writes(frame: Connector, rows: list[ca.SX], hashes: list[set[int]]) -> bool:
    """True if one of the rows defines an element of the frame's ``v``, ``a`` or ``z`` (names exactly one, with a
    constant coefficient: ``v_b = R v_a`` does, a body's ``f = m (a + ...)`` that reads ``a`` does not)."""
    elements = {s.element_hash(): s for n in FRAME_KINEMATICS for s in _elements(frame, n)}
    for expr, present in zip(rows, hashes, strict=True):
        hits = [h for h in present if h in elements]
        if len(hits) == 1 and _coefficient(expr, elements[hits[0]]) != 0.0:
            return True
    return False


def tree_kinematics(nodes: list[Node], depth: dict[int, int], roots: set[int], equations: list[FlatEquation]) -> None:
    """Insert rows for the ``v``, ``a``, ``z`` of every frame that a branch computes with MSL's rows only
    (:func:`branch_kinematics`) into ``equations``, before the component's row for that frame's ``T`` (where a
    library joint writes them), and of every tree root (:func:`root_kinematics`), after its component's rows for the
    root's ``r_0``, ``T``, ``w``; a component that writes a frame's ``v``, ``a``, ``z`` itself is left as it is."""
    rows = _Rows(equations)
    inserts: dict[int, list[FlatEquation]] = {}
    checked: set = set()

    def insert(where: int, node: Component, frame: Connector, found: list[ca.SX], source: str) -> None:
        for name, vec in zip(FRAME_KINEMATICS, found, strict=True):
            label = f"{frame._label(name)} from {source} (multibody kinematics pass)"
            inserts.setdefault(where, []).extend(FlatEquation(vec[k], node.path, label, "equation") for k in range(3))

    for node in nodes:
        if isinstance(node, Connector) and id(node) in roots and isinstance(node._parent, Component):
            owner = node._parent
            at, exprs, hashes = rows.of(owner)
            if FRAME_KINEMATICS.keys() <= node._decls.keys() and not _writes(node, exprs, hashes):
                found = root_kinematics(owner, node, exprs, hashes, lambda owner=owner: _gravity(owner, nodes))
                frame = {h for n in ("r_0", "T", "w") for h in _hashes(node, n)}
                last = max((r for r, h in zip(at, hashes, strict=True) if not frame.isdisjoint(h)), default=None)
                insert(len(equations) if last is None else last + 1, owner, node, found, "the world")
        branches = node.__dict__.get("_od_branches", []) if isinstance(node, Component) else []
        for a, b in branches:
            src, dst = (a, b) if depth[id(a)] < depth[id(b)] else (b, a)
            if not FRAME_KINEMATICS.keys() <= dst._decls.keys():
                continue
            at, exprs, hashes = rows.of(node)
            if _writes(dst, exprs, hashes):
                continue  # the component writes the recursion itself
            found = branch_kinematics(node, src, dst, exprs, checked, hashes)
            if found is None:
                if any(isinstance(c, Component) for c in node._children.values()):
                    continue  # a composite: its parts relate the frames
                raise ModelError(f"{node.path}: declares branch({a.path}, {b.path}) but its rows do not give "
                                 f"{dst.path}'s r_0, T and w explicitly from {src.path} (one row each, as MSL's "
                                 "joints write them), so the multibody pass cannot carry the frames' velocities and "
                                 f"accelerations; write them so, or write {dst.path}'s v, a and z rows too")
            orientation = set(_hashes(dst, "T"))
            where = next((r for r, h in zip(at, hashes, strict=True) if not orientation.isdisjoint(h)), len(equations))
            insert(where, node, dst, found, src.path)
    if inserts:
        merged: list[FlatEquation] = []
        for r, e in enumerate(equations):
            merged += inserts.get(r, [])
            merged.append(e)
        merged += inserts.get(len(equations), [])
        equations[:] = merged
