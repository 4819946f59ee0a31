"""Stage 1 — flatten: instance tree → one list of scalar variables, parameters and equations.

Connection semantics follow the Modelica specification §9.2: for every connection set,
potential variables are equal and flow variables sum to zero, with a + sign for inside
connectors (connectors of sub-components) and a − sign for outside connectors (the
model's own connectors); a connector whose flow is connected nowhere gets ``flow = 0``.
The model is checked for balance: each leaf component locally (Modelica's local balance
rule) and the whole model by maximum matching, naming the culprits (the checks are in
:mod:`flexlib.compile.flat_checks`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np

from flexlib.compile.flat_checks import (
    check_balance,
    check_finite,
    check_inputs,
    check_local_balance,
    check_symbols,
    warn_unconnected,
)
from flexlib.compile.scaling import apply_marks, instance_nominals
from flexlib.core.component import Component, Connector, Node
from flexlib.core.functions import CURRENT_RELATIONS, Relation
from flexlib.core.tables import CURRENT_TABLES, SegmentTable
from flexlib.core.variables import Kind, Parameter, StateSelect, SymInfo, full_name, lookup, render, render_many
from flexlib.errors import FlexlibError, ModelError

if TYPE_CHECKING:
    from flexlib.compile.build_options import BuildOptions

__all__ = ["FlatEquation", "FlatParameter", "FlatSystem", "FlatVariable", "flatten"]


@dataclass(eq=False)
class FlatVariable:
    """One scalar unknown of the flat model."""

    name: str
    sym: ca.SX
    info: SymInfo
    unit: str
    doc: str
    start: float
    fixed: bool
    nominal: float
    state_select: StateSelect
    kind: Kind
    owner: str
    der_rule: ca.SX | None = None
    #: False for a variable declared at the derivative level (``Variable(error_test=False)``)
    error_test: bool = True
    #: True for a kinematic intermediate (``Variable(intermediate=True)``): eliminated where a row gives it
    intermediate: bool = False


@dataclass(eq=False)
class FlatParameter:
    """One scalar parameter of the flat model."""

    name: str
    sym: ca.SX
    value: float
    unit: str
    doc: str
    owner: str
    decl: Parameter
    node: Node
    decl_name: str
    index: tuple


@dataclass(eq=False)
class FlatEquation:
    """One scalar equation ``expr = 0``."""

    expr: ca.SX
    owner: str
    label: str
    origin: str = "equation"  # "equation" | "connect" | "unconnected flow" | "loop closure" | "initial"
    meta: tuple | None = None  # loop closure: ("position" | "orientation", frame_a, frame_b, component)

    def describe(self) -> str:
        """Short printable form for diagnostics (symbols by hierarchical name)."""
        if self.label:
            return self.label
        return f"{render(self.expr, 110)} = 0"


def describe_all(equations: list[FlatEquation]) -> list[str]:
    """``[e.describe() for e in equations]``, with the symbols of all unlabelled rows named in one pass."""
    unlabelled = [k for k, e in enumerate(equations) if not e.label]
    texts = [e.label for e in equations]
    for k, text in zip(unlabelled, render_many([equations[k].expr for k in unlabelled], 110), strict=True):
        texts[k] = f"{text} = 0"
    return texts


@dataclass(eq=False)
class FlatSystem:
    """Output of stage 1."""

    name: str
    variables: list[FlatVariable]
    parameters: list[FlatParameter]
    equations: list[FlatEquation]
    relations: list[Relation]
    by_hash: dict[int, int] = field(default_factory=dict)
    initial: list[FlatEquation] = field(default_factory=list)
    """Initial equations (hold at the start time only; they count as initial conditions)."""
    passes: list[Any] = field(default_factory=list)
    """The domain passes that apply to the model (:mod:`flexlib.compile.passes`); stage 2 runs them on."""
    tables: list[SegmentTable] = field(default_factory=list)
    """Tables looked up by time (:func:`flexlib.segment_row`): their symbols become lookups at compile."""

    def variable(self, sym: ca.SX) -> FlatVariable | None:
        """The flat variable of a scalar symbol, if any."""
        k = self.by_hash.get(sym.element_hash())
        return None if k is None else self.variables[k]


def _scalars(node: Node, name: str) -> list[tuple[str, ca.SX]]:
    decl = node._decls[name]
    sym = node._symbol(name)
    if not decl.shape:  # a scalar declaration: its symbol is its only element
        return [(node._label(name), sym)]
    return [(label, sym.nz[k]) for k, (label, _) in enumerate(decl.element_names(node._label(name)))]


def _elements(expr: ca.SX) -> list[ca.SX]:
    """The scalar elements ``expr.nz[k]`` of a dense column (``[expr]`` itself for a dense scalar)."""
    if expr.is_scalar() and expr.is_dense():
        return [expr]
    return [expr.nz[k] for k in range(expr.numel())]


def _declarations(nodes: list[Node]) -> tuple[list[FlatVariable], list[FlatParameter], dict[int, int]]:
    """The scalar variables and parameters the nodes declare (each node validated first), and the variables' index by
    symbol hash."""
    variables: list[FlatVariable] = []
    parameters: list[FlatParameter] = []
    by_hash: dict[int, int] = {}
    nominals = instance_nominals(nodes)  # the components' nominals() at the build's values (scaling stage)
    for node in nodes:
        node.validate()  # cross-parameter rules, now with the instance path known
        for name, decl in node._decls.items():
            if node._parent is None and decl.kind is Kind.input and not isinstance(node, Connector):
                decl = decl.as_parameter()  # a top-level input: a run-time parameter (an FMU's input)
                value = node.start_of(name)[0]
                flat_vals = np.asarray(value, dtype=float).flatten(order="F")
                for k, (label, sym) in enumerate(_scalars(node, name)):
                    parameters.append(FlatParameter(label, sym, float(flat_vals[k]), decl.unit, decl.doc, node.path,
                                                    decl, node, name, ()))
                continue
            if isinstance(decl, Parameter):
                value = node.parameter_value(name)
                if value is None:
                    raise ModelError(f"parameter {node._label(name)} [{decl.unit}] has no value and no default")
                if not decl.shape:  # a scalar: its symbol is its only element
                    parameters.append(FlatParameter(node._label(name), node._symbol(name), float(value), decl.unit,
                                                    decl.doc, node.path, decl, node, name, ()))
                    continue
                flat_vals = np.asarray(value, dtype=float).flatten(order="F")
                for k, (label, index) in enumerate(decl.element_names(node._label(name))):
                    parameters.append(FlatParameter(label, node._symbol(name).nz[k], float(flat_vals[k]), decl.unit,
                                                    decl.doc, node.path, decl, node, name, index))
                continue
            start, fixed = node.start_of(name)
            fixed = fixed is True  # a "default" start is no initial condition of the structure (the initialiser
            starts = np.asarray(start, dtype=float).flatten(order="F")  # adds it where one is missing)
            kind = decl.kind
            rule = None
            if getattr(decl, "derivative", None) is not None:
                rule = ca.vec(ca.SX(decl.derivative(node)))
                if rule.numel() != decl.size:
                    raise ModelError(f"{node._label(name)}: derivative rule has {rule.numel()} entries, "
                                     f"the variable {decl.size}")
            for k, (label, sym) in enumerate(_scalars(node, name)):
                by_hash[sym.element_hash()] = len(variables)
                variables.append(FlatVariable(label, sym, lookup(sym), decl.unit, decl.doc, float(starts[k]), fixed,
                                              nominals.get((id(node), name), decl.nominal),
                                              node.state_select_of(name), kind, node.path,
                                              None if rule is None else rule[k],
                                              bool(getattr(decl, "error_test", True)),
                                              bool(getattr(decl, "intermediate", False))))
    return variables, parameters, by_hash


def _component_equations(nodes: list[Node]) -> tuple[list[FlatEquation], list[Relation], list[FlatEquation],
                                                      list[SegmentTable]]:
    """The scalar equations, event relations, initial equations and time tables of the components."""
    equations: list[FlatEquation] = []
    relations: list[Relation] = []
    initial: list[FlatEquation] = []
    tables: list[SegmentTable] = []
    for node in nodes:
        if not isinstance(node, Component):
            continue
        path = node.path
        sink: list[Relation] = []
        own_tables: list[SegmentTable] = []
        token, token_t = CURRENT_RELATIONS.set(sink), CURRENT_TABLES.set(own_tables)
        try:
            own = _call(node, "equations")
        finally:
            CURRENT_RELATIONS.reset(token)
            CURRENT_TABLES.reset(token_t)
        tables.extend(own_tables)
        for rel in sink:
            if rel.indicator is None:
                raise ModelError(f"{node.path or type(node).__name__}: a latch declared by latch() has no conditions "
                                 "(give them with define_latch() in the same equations())")
            rel.reinit = [_reinit_names(node, x, v) for x, v in rel.reinit]
            rel.owner = node.path or type(node).__name__
            rel.text = rel.describe()
            rel.info.name = f"rel({rel.text})"
        relations.extend(sink)
        for equ in _equation_list(node, "initial_equations", _call(node, "initial_equations")):
            for k in range(equ.residual.numel()):
                initial.append(FlatEquation(equ.residual[k], node.path, equ.label or "initial equation", "initial"))
        for equ in _equation_list(node, "equations", own):
            res = equ.residual
            if res.is_scalar() and res.is_dense():
                equations.append(FlatEquation(res, path, equ.label, "equation"))
                continue
            for k in range(res.numel()):
                equations.append(FlatEquation(res[k], path, equ.label, "equation"))
    return equations, relations, initial, tables


def _reinit_names(node: Component, x: ca.SX, value: Any) -> list:
    """A reinit action ``[state name, value]`` (the value a number or a variable's name), from its symbols."""
    names = []
    for what, sym in (("reinitialised variable", x), ("value", value)):
        if not isinstance(sym, ca.SX):
            names.append(sym)
            continue
        info = lookup(sym)
        if info is None or info.kind != "variable":
            raise ModelError(f"{node.path or type(node).__name__}: reinit(): the {what} {sym} is not a variable")
        names.append(full_name(info))
    return names


def flatten(root: Component, check: bool = True, options: BuildOptions | None = None) -> FlatSystem:
    """Flatten the instance tree below ``root`` and check its balance (``options``: the build's, which the domain
    passes read; None: the environment defaults).

    Raises
    ------
    ModelError
        Missing parameter values, unconnected inputs, bad equations.
    BalanceError
        Too many or too few equations (names the components involved).
    StructuralSingularityError
        As many equations as unknowns, but no perfect matching.

    Warns
    -----
    ModelWarning
        A component connected to nothing that has no effect on the model
        (:func:`~flexlib.compile.flat_checks.unconnected_components`).
    """
    if root._parent is not None:
        raise ModelError(f"{root.path}: flatten the top-level model, not a sub-component")
    nodes = root.walk()

    # -- domain passes (the multibody orientation tree): components may then declare dependent quantities
    from flexlib.compile.passes import active_passes  # here: the passes' modules build on this one

    passes = active_passes(nodes, options)
    for p in passes:
        p.structure(nodes)
    for node in nodes:
        if isinstance(node, Component):
            _call(node, "on_structure")

    variables, parameters, by_hash = _declarations(nodes)
    equations, relations, initial, tables = _component_equations(nodes)
    check_finite(nodes, equations, initial)
    _connection_equations(nodes, equations, set().union(*(p.broken_connections() for p in passes)))
    for p in passes:
        p.connection_equations(equations)
    for p in passes:
        apply_marks(variables, by_hash, *p.marks(nodes, equations))
    check_inputs(root, nodes)
    check_local_balance(nodes, equations)
    flat = FlatSystem(type(root).__name__, variables, parameters, equations, relations, by_hash, initial, passes,
                      tables)
    check_symbols(flat)
    if check:
        check_balance(flat.name, flat.variables, flat.equations)
    warn_unconnected(root, nodes, equations + initial)
    return flat


_SX_FLOAT = ca.SX.__float__


def _symbolic_float(self: ca.SX) -> float:
    """``float(SX)`` while equations are collected: CasADi returns NaN for a symbolic expression, which is how
    ``math.sin(x)`` silently turns into a NaN constant; refuse it instead."""
    if not self.is_constant():
        raise ModelError(
            f"float() of the symbolic expression {render(self, 60)}: a function of Python's 'math' module "
            "(math.sin, math.sqrt, math.exp, ...) or float()/int() was applied to a symbol; use the casadi "
            "(ca.sin, ca.sqrt) or numpy (np.sin) functions on symbols")
    return _SX_FLOAT(self)


def _call(node: Component, method: str) -> list:
    """``node.equations()`` / ``node.initial_equations()``, with any error naming the component."""
    where = f"{node.path or '(model)'} ({type(node).__name__}).{method}()"
    ca.SX.__float__ = _symbolic_float
    try:
        return getattr(node, method)()
    except FlexlibError as exc:  # keep the class (and its attributes); put the component in front
        if node.path and str(exc).startswith(node.path):
            raise
        try:
            named = type(exc)(f"{where}: {exc}")
            named.__dict__.update(exc.__dict__)
        except Exception:  # an error class with another constructor: keep it as it is
            raise exc from None
        raise named from exc
    except Exception as exc:
        text = str(exc)
        if "Cannot compute the truth value" in text:
            raise ModelError(
                f"{where}: a Python 'if', 'and', 'or', 'not' or comparison chain was applied to a symbolic "
                "expression, which has no truth value while the model is built; write the condition with "
                "fl.if_else(cond, a, b) (events) or fl.no_event(...), and combine relations with "
                "casadi.logic_and / logic_or / logic_not") from exc
        raise ModelError(f"{where} failed: {type(exc).__name__}: {text}") from exc
    finally:
        ca.SX.__float__ = _SX_FLOAT


def _equation_list(node: Component, method: str, got: Any) -> list:
    """What ``node.equations()`` / ``node.initial_equations()`` returned, as a list of equations: None is none; one
    equation (a missing ``[...]``: Python's "not iterable"), a string (iterated letter by letter), an expression or a
    non-equation entry is refused naming the component and the method."""
    if got is None:
        return []
    where = f"{node.path or type(node).__name__}.{method}()"
    if hasattr(got, "residual"):
        raise ModelError(f"{where} returned one equation, not a list; return [eq(...), ...]")
    if isinstance(got, (str, bytes, ca.SX, ca.MX, ca.DM, Mapping)) or not hasattr(got, "__iter__"):
        raise ModelError(f"{where} returned {type(got).__name__} {got!r:.80}; return a list of equations "
                         "[eq(lhs, rhs), ...]")
    items = list(got)
    for equ in items:
        if not hasattr(equ, "residual"):
            raise ModelError(f"{where} returned {equ!r:.80} in its list; write each equation as eq(lhs, rhs)")
    return items


# ---------------------------------------------------------------------------------------------
# Connections
# ---------------------------------------------------------------------------------------------
def _flow_sum(name: str, elems: list[tuple[Connector, str]], owner: str, equations: list[FlatEquation]) -> None:
    """The flow balance of ``name`` over one connection set (inside connectors +, outside −), or ``flow = 0`` for a
    connector connected nowhere."""
    conns = [c for c, _ in elems]
    first = conns[0]
    terms = []
    for conn, side in elems:
        s = conn._symbol(name)
        terms.append(s if side == "inside" else -s)
    total = terms[0]
    for t in terms[1:]:
        total = total + t
    origin = "connect" if len(elems) > 1 else "unconnected flow"
    if len(elems) > 1:
        label = f"sum of {name} over ({', '.join(c.path for c in conns)}) = 0"
    else:
        label = f"{first._label(name)} = 0 (unconnected)"
    row_owner = owner or first.path.rpartition(".")[0]
    for expr in _elements(total):
        equations.append(FlatEquation(expr, row_owner, label, origin))


def _potential_equalities(name: str, conns: list[Connector],
                          edges: list[tuple[tuple[int, str], Connector, Connector, str]], owner: str,
                          broken: set[frozenset] | None, equations: list[FlatEquation]) -> None:
    """Equality of the potential variable ``name`` along one set's connections (broken ones last, as loop
    closures)."""
    first = conns[0]
    set_edges = list(edges)
    set_edges.sort(key=lambda e: frozenset((id(e[1]), id(e[2]))) in (broken or set()))
    group = {id(c): id(c) for c in conns}

    def gfind(x: int, group: dict[int, int] = group) -> int:
        while group[x] != x:
            x = group[x]
        return x

    for _, ca_, cb_, edge_owner in set_edges:
        ra_, rb_ = gfind(id(ca_)), gfind(id(cb_))
        if ra_ == rb_:
            continue
        group[ra_] = rb_
        diff = ca_._symbol(name) - cb_._symbol(name)
        is_loop = frozenset((id(ca_), id(cb_))) in (broken or set())
        label = f"{ca_._label(name)} = {cb_._label(name)}"
        for k, expr in enumerate(_elements(diff)):
            meta = ("position", ca_, cb_, k) if is_loop else None
            equations.append(FlatEquation(expr, edge_owner or owner, label,
                                          "loop closure" if is_loop else "connect", meta))
    for conn in conns[1:]:  # members not joined by edges (should not happen): chain equality
        if gfind(id(conn)) != gfind(id(first)):
            diff = first._symbol(name) - conn._symbol(name)
            group[gfind(id(conn))] = gfind(id(first))
            for k in range(diff.numel()):
                equations.append(FlatEquation(diff.nz[k], owner, f"{first._label(name)} = "
                                              f"{conn._label(name)}", "connect"))


def _connection_equations(nodes: list[Node], equations: list[FlatEquation],
                          broken: set[frozenset] | None = None) -> None:
    parent: dict[tuple[int, str], tuple[int, str]] = {}
    members: dict[tuple[int, str], tuple[Connector, str]] = {}

    def find(x: tuple[int, str]) -> tuple[int, str]:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    def element(conn: Connector, side: str) -> tuple[int, str]:
        key = (id(conn), side)
        if key not in parent:
            parent[key] = key
            members[key] = (conn, side)
        return key

    for node in nodes:
        if isinstance(node, Connector):
            element(node, "inside")
    where: dict[tuple[int, str], str] = {}
    edges: list[tuple[tuple[int, str], Connector, Connector, str]] = []
    for node in nodes:
        if not isinstance(node, Component):
            continue
        for a, b in node._connections:
            if a[0] == "signal":
                for (la, sa), (lb, sb) in zip(_scalars(a[1].node, a[1].name),
                                              _scalars(b[1].node, b[1].name), strict=True):
                    equations.append(FlatEquation(sa - sb, node.path, f"connect({la}, {lb})", "connect"))
                continue
            ka = element(a[1], "outside" if a[1]._parent is node else "inside")
            kb = element(b[1], "outside" if b[1]._parent is node else "inside")
            where[ka] = where[kb] = node.path
            edges.append((ka, a[1], b[1], node.path))
            ra, rb = find(ka), find(kb)
            if ra != rb:
                parent[ra] = rb
    sets: dict[tuple[int, str], list[tuple[Connector, str]]] = {}
    for key in parent:
        sets.setdefault(find(key), []).append(members[key])
    edges_of: dict[tuple[int, str], list] = {}  # each set's edges in connection order (one pass, not one per set)
    for e in edges:
        edges_of.setdefault(find(e[0]), []).append(e)
    for root_key, elems in sets.items():
        owner = where.get(root_key, "")
        conns = [c for c, _ in elems]
        first = conns[0]
        if len(conns) > 1:
            first.check_connection(conns)
        for name, decl in first._decls.items():
            if decl.kind is Kind.flow:
                _flow_sum(name, elems, owner, equations)
            elif getattr(decl, "overdetermined", False):
                continue  # equated by the pass that handles the connector (flexlib.compile.passes)
            else:  # equal along the set's connections; a broken (loop-closing) one gives loop-closure rows
                _potential_equalities(name, conns, edges_of.get(root_key, []), owner, broken, equations)
