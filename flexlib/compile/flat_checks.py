"""Checks of the flat model: balance, structural singularity and the errors and warnings that name the culprit.

Each check takes the flattened equations (and, where it needs them, the component tree) and raises a
:class:`~flexlib.errors.FlexlibError` subclass, or warns, with the components and equations at fault.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np
import scipy.sparse as sp

from flexlib.compile.structure import culprits, group_by_owner, incidence, matching
from flexlib.core.component import Component, Connector, Node
from flexlib.core.variables import Kind, Parameter, Variable, lookup, render
from flexlib.errors import BalanceError, ModelError, ModelWarning, StructuralSingularityError

if TYPE_CHECKING:
    from flexlib.compile.flatten import FlatEquation, FlatSystem, FlatVariable

__all__ = ["check_balance", "check_finite", "check_inputs", "check_local_balance", "check_symbols",
           "nonfinite_constant", "unconnected_components", "warn_unconnected"]


def nonfinite_constant(expr: ca.SX) -> float | None:
    """A NaN or infinite numeric constant in the expression graph of ``expr``, if any."""
    syms = ca.symvar(expr)
    if not syms:
        vals = np.asarray(ca.DM(expr)).ravel()
        bad = vals[~np.isfinite(vals)]
        return float(bad[0]) if bad.size else None
    f = ca.Function("f", [ca.vertcat(*syms)], [expr])  # one input: no max_io warning for large models
    for k in range(f.n_instructions()):
        if f.instruction_id(k) == ca.OP_CONST:
            c = float(f.instruction_constant(k))
            if not np.isfinite(c):
                return c
    return None


def check_finite(nodes: list[Node], equations: list[FlatEquation], initial: list[FlatEquation]) -> None:
    """Reject NaN/inf constants in the equations, naming the component and the equation (``math.sin(symbol)``
    silently gives a NaN constant: the ``math`` module converts the symbol to a float, which is NaN)."""
    rows = equations + initial
    if not rows or nonfinite_constant(ca.vertcat(*[e.expr for e in rows])) is None:
        return  # the usual case: one pass over the whole graph
    types = {node.path: type(node).__name__ for node in nodes}
    for e in rows:
        c = nonfinite_constant(e.expr)
        if c is not None:
            raise ModelError(
                f"{e.owner or '(model)'} ({types.get(e.owner, 'model')}): equation {e.describe()!r} contains the "
                f"constant {c}. A NaN usually comes from a function of Python's 'math' module (math.sin, "
                "math.sqrt, math.exp, ...) applied to a symbol, which turns the symbol into float('nan'): use "
                "the casadi (ca.sin, ca.sqrt) or numpy (np.sin) functions on symbols")



def check_inputs(root: Component, nodes: list[Node]) -> None:
    fed: set[int] = set()
    for node in nodes:
        if not isinstance(node, Component):
            continue
        for a, b in node._connections:
            for item in (a, b):
                if item[0] == "signal" and item[1].node is not node:
                    fed.add(id(item[1]))
    for node in nodes:
        for name, decl in node._decls.items():
            if decl.kind is Kind.input and not isinstance(node, Connector) and node is not root:
                info = lookup(node._symbol(name).nz[0])
                if id(info) not in fed:
                    raise ModelError(f"input {node._label(name)} [{decl.unit}] is not connected "
                                     "(connect it to a signal source)")


def unconnected_components(root: Component, nodes: list[Node], rows: list[FlatEquation]) -> list[Component]:
    """The components that are connected to nothing and have no effect on the rest of the model.

    The rule (Modelica tools check unconnected components; an unconnected flow is zero, so an open connector is
    legal): a component below the root that has connectors of its own (:class:`Connector` children) is reported
    when

    - no connection made outside it reaches it: none of its connectors, signal inputs/outputs or those of its
      sub-components is connected by an enclosing model;
    - it has no dynamics of its own: no ``der()`` in its equations (a mass, an inertia or a free body left
      unconnected is a free motion, which is a legitimate model);
    - nothing else uses it: no equation outside it contains one of its parameters or variables (a World that
      gives the bodies of its model their gravity is used even with its frame unconnected).

    A component without connectors (a block of equations, a signal source whose output is recorded) is never
    reported; neither is a component with a connector left open while another one is connected. Only the
    outermost such component is reported, not its parts.
    """
    reached: set[int] = set()
    for node in nodes:
        if not isinstance(node, Component):
            continue
        for pair in node._connections:
            for kind, item in pair:
                holder = item if kind == "connector" else item.node
                while holder is not None and holder is not node:
                    reached.add(id(holder))
                    holder = holder._parent
    found: list[Component] = []
    for node in nodes:
        if (node is root or not isinstance(node, Component) or id(node) in reached
                or not any(isinstance(c, Connector) for c in node._children.values())):
            continue
        if any(node.path.startswith(f.path + ".") for f in found):
            continue
        prefix = node.path + "."
        own = [e.expr for e in rows if e.owner == node.path or e.owner.startswith(prefix)]
        if own and any((info := lookup(sym)) is not None and info.kind == "der"
                       for sym in ca.symvar(ca.vertcat(*own))):
            continue  # a free motion of its own
        syms = [info.sym for part in node.walk() for info in part._infos]
        syms += [info._der.sym for part in node.walk() for info in part._infos if info._der is not None]
        others = [e.expr for e in rows if not (e.owner == node.path or e.owner.startswith(prefix))]
        if syms and others and ca.depends_on(ca.vertcat(*others), ca.vertcat(*syms)):
            continue  # used by other components (World's gravity)
        found.append(node)
    return found


def warn_unconnected(root: Component, nodes: list[Node], rows: list[FlatEquation]) -> None:
    """A :class:`~flexlib.errors.ModelWarning` naming each component connected to nothing
    (:func:`unconnected_components`)."""
    for node in unconnected_components(root, nodes, rows):
        ports = [name for name, c in node._children.items() if isinstance(c, Connector)]
        warnings.warn(
            f"{node.path} ({type(node).__name__}) is connected to nothing: none of its connectors "
            f"({', '.join(ports)}) is connected and nothing else in {type(root).__name__} uses it, so it has no "
            f"effect on the model. Connect it (self.connect(self.{node.path}.{ports[0]}, ...)) or remove it",
            ModelWarning, stacklevel=2)


def check_local_balance(nodes: list[Node], equations: list[FlatEquation]) -> None:
    counts: dict[str, int] = {}
    for e in equations:
        if e.origin == "equation":
            counts[e.owner] = counts.get(e.owner, 0) + 1
    for node in nodes:
        if not isinstance(node, Component) or not getattr(node, "check_local_balance", True) or node._parent is None:
            continue  # the root model is checked globally, with culprits named
        if any(isinstance(c, Connector) and c.overdetermined for c in node._children.values()):
            continue  # over-determined records are counted by the spanning tree (global check)
        if any(not isinstance(c, Connector) for c in node._children.values()):
            continue  # a composite: checked globally
        unknowns, flows = [], 0
        for holder in [node, *node._children.values()]:
            for name, decl in holder._decls.items():
                if isinstance(decl, Parameter) or decl.kind is Kind.input:
                    continue
                if isinstance(holder, Connector) and decl.kind is Kind.flow:
                    flows += decl.size
                unknowns.append(holder._label(name) if decl.size == 1 else f"{holder._label(name)}{list(decl.shape)}")
        n_unknown = sum(holder._decls[n].size for holder in [node, *node._children.values()]
                        for n in holder._decls if isinstance(holder._decls[n], Variable)
                        and holder._decls[n].kind is not Kind.input)
        need = n_unknown - flows
        have = counts.get(node.path, 0)
        if have != need:
            raise BalanceError(
                f"component {node.path or '(model)'} ({type(node).__name__}) has {have} equations but needs {need}: "
                f"{n_unknown} unknowns ({', '.join(unknowns)}) minus {flows} connector flow variables, "
                "which get their equations from connections")


def check_symbols(flat: FlatSystem) -> None:
    """Every symbol of the equations and initial equations is a variable, parameter, derivative or relation of this
    model; the error names the equation that uses a foreign one (a ``ca.SX.sym``, a variable of a component that is
    not part of the model) and its component (an initial equation's free symbol was CasADi's "variables are free"
    error at run time)."""
    rows = flat.equations + flat.initial
    if not rows:
        return
    exprs = ca.vertcat(*[e.expr for e in rows])

    def where(s: ca.SX) -> str:  # the first row using s (only on the error path)
        for e in rows:
            if ca.depends_on(e.expr, s):
                kind = "initial equation" if e.origin == "initial" else "equation"
                label = f" ({e.label})" if e.label and e.label != "initial equation" else ""
                return f"{e.owner or '(model)'}: {kind} '{render(e.expr, 110)} = 0'{label} uses"
        return "an equation uses"

    inputs = {q.sym.element_hash() for q in flat.parameters if q.decl_name in q.node._decls
               and q.node._decls[q.decl_name].kind is Kind.input}  # top-level inputs: parameters of the flat model
    for s in ca.symvar(exprs):
        info = lookup(s)
        if info is not None and s.element_hash() in inputs:
            continue
        if info is None:
            raise ModelError(f"{where(s)} symbol {s}, which is not a flexlib variable or parameter (a casadi "
                             "symbol made with ca.SX.sym? declare it with Variable() or Parameter())")
        if info.kind == "variable" and s.element_hash() not in flat.by_hash:
            raise ModelError(f"{where(s)} {info.node._label(info.name)} of {type(info.node).__name__} "
                             f"{info.node.path or '(unnamed)'}, which is not part of this model")
        if info.kind == "der" and info.root.sym.element_hash() not in flat.by_hash:
            raise ModelError(f"{where(s)} {s}, a derivative of a variable that is not part of this model")
    for s in ca.symvar(ca.vertcat(*[e.expr for e in flat.equations])) if flat.equations else []:
        info = lookup(s)
        if info is not None and info.kind == "der" and info.order > 1:
            raise ModelError(f"{s}: der(der(x)) is not supported; introduce a velocity variable")


def check_balance(name: str, variables: list[FlatVariable], equations: list[FlatEquation]) -> None:
    """Raise if the system is unbalanced or structurally singular, naming the culprits.

    Run on the flat model, or after alias elimination and redundant-constraint removal (a planar
    loop built in 3D is structurally singular until its redundant rows are dropped).
    """
    n_eq, n_var = len(equations), len(variables)
    if n_eq == 0 and n_var == 0:
        raise ModelError(f"model {name} has no variables and no equations")
    syms = ca.vertcat(*[v.sym for v in variables]) if variables else ca.SX(0, 1)
    exprs = ca.vertcat(*[e.expr for e in equations]) if equations else ca.SX(0, 1)
    inc = incidence(exprs, syms)
    with_der = [k for k, v in enumerate(variables) if v.info._der is not None]
    if with_der:
        dinc = incidence(exprs, ca.vertcat(*[variables[k].info._der.sym for k in with_der])).tocoo()
        inc = inc + sp.csr_matrix((dinc.data, (dinc.row, np.asarray(with_der)[dinc.col])), shape=inc.shape)
    row_match, col_match = matching(inc, fast=True)
    if n_eq == n_var and np.all(row_match >= 0):
        return
    rows, cols = culprits(inc, row_match, col_match)
    eq_items = [(equations[r].owner, equations[r].describe()) for r in rows]
    var_items = [(variables[c].owner, variables[c].name) for c in cols]
    parts = []
    if rows:
        parts.append("Equations in the over-determined part (too many equations for their variables):\n"
                     + group_by_owner(eq_items))
    if cols:
        parts.append("Variables in the under-determined part (not determined by any equation):\n"
                     + group_by_owner(var_items))
    if n_eq != n_var:
        msg = f"model {name} is unbalanced: {n_eq} equations for {n_var} unknowns.\n" + "\n".join(parts)
        raise BalanceError(msg, [t for _, t in eq_items], [t for _, t in var_items])
    msg = (f"model {name} is structurally singular: {n_eq} equations and {n_var} unknowns, but the "
           "equations cannot be solved for the unknowns.\n" + "\n".join(parts))
    raise StructuralSingularityError(msg, [t for _, t in eq_items], [t for _, t in var_items])
