"""Event-generating functions: ``if_else`` and the discontinuous functions built on it.

Modelica semantics: a relation such as ``x > 0`` inside an ``if`` is evaluated only at
events. Between events its value is frozen, so the integrator sees a smooth residual;
the zero crossing of ``x - 0`` is located by root finding, and the integration is
restarted with the new value. :func:`if_else` turns each relation of its condition into
a discrete symbol (a run-time input of the compiled model) plus an event indicator.
Relations that depend on time and parameters only, affinely in time (``time >= t_on``),
become time events, which the integrator hits exactly.

Use :func:`no_event` to write a condition that is evaluated continuously (no events;
only for expressions that are continuous across the switch).
"""

from __future__ import annotations

from contextvars import ContextVar
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from flexlib.core.equations import as_sx
from flexlib.core.variables import SymInfo
from flexlib.errors import ModelError

__all__ = ["abs_", "assert_", "if_else", "latch", "max_", "min_", "no_event", "sign"]

#: Relations created while a component's equations() runs are recorded here by the flattener.
CURRENT_RELATIONS: ContextVar[list | None] = ContextVar("flexlib_relations", default=None)


@dataclass(eq=False)
class Relation:
    """A relation ``lhs < rhs`` / ``lhs <= rhs`` frozen between events.

    Attributes
    ----------
    info : SymInfo
        The discrete symbol (1.0 = true, 0.0 = false).
    indicator : casadi.SX
        ``rhs - lhs``: the relation is true when it is > 0 (``<``) or >= 0 (``<=``).
    strict : bool
        True for ``<``, False for ``<=``.
    text : str
        Printable form for diagnostics.
    """

    info: SymInfo
    indicator: ca.SX
    strict: bool
    text: str
    lhs: ca.SX | None = None
    rhs: ca.SX | None = None
    owner: str = ""
    assertion: str = ""  # set by assert_(): the relation must stay true; message if it becomes false

    def describe(self) -> str:
        """``owner: lhs < rhs`` with hierarchical names."""
        from flexlib.core.variables import render

        if self.lhs is None or self.rhs is None:
            return self.text
        body = f"{render(self.lhs, 60)} {'<' if self.strict else '<='} {render(self.rhs, 60)}"
        return f"{self.owner}: {body}" if self.owner else body

    def value(self, z: float) -> bool:
        """Relation value for indicator value ``z`` (away from an event)."""
        return z > 0.0 if self.strict else z >= 0.0


def _register(text: str, indicator: Any, strict: bool, where: str, lhs: ca.SX | None = None,
              rhs: ca.SX | None = None) -> ca.SX:
    """A relation's discrete symbol, recorded for the flattener; ``indicator`` is an expression or a function of the
    symbol (a latch's indicator depends on its own value)."""
    sym = ca.SX.sym(f"rel({text[:40]})")
    info = SymInfo(sym, "relation", name=text)
    rel = Relation(info, indicator(sym) if callable(indicator) else indicator, strict, text, lhs, rhs)
    info.extra["relation"] = rel
    sink = CURRENT_RELATIONS.get()
    if sink is None:
        raise ModelError(f"{where} may only be used inside equations()")
    sink.append(rel)
    return sym


def _relation(lhs: ca.SX, rhs: ca.SX, strict: bool) -> ca.SX:
    text = f"{lhs} {'<' if strict else '<='} {rhs}"
    return _register(text, rhs - lhs, strict, "if_else() with an event-generating condition", lhs=lhs, rhs=rhs)


def _discretize(cond: ca.SX) -> ca.SX:
    """Replace the relations of a scalar boolean expression by discrete symbols."""
    if cond.is_constant():
        return cond
    op = cond.op()
    if op == ca.OP_LT:
        return _relation(cond.dep(0), cond.dep(1), True)
    if op == ca.OP_LE:
        return _relation(cond.dep(0), cond.dep(1), False)
    if op == ca.OP_NOT:
        return ca.logic_not(_discretize(cond.dep(0)))
    if op == ca.OP_AND:
        return ca.logic_and(_discretize(cond.dep(0)), _discretize(cond.dep(1)))
    if op == ca.OP_OR:
        return ca.logic_or(_discretize(cond.dep(0)), _discretize(cond.dep(1)))
    if op in (ca.OP_EQ, ca.OP_NE):
        raise ModelError(f"if_else(): equality test on real numbers ({cond}) cannot generate an event")
    raise ModelError(f"if_else(): condition {cond} is not a relation (<, <=, >, >=) or a logical combination")


def _condition(cond: Any, where: str) -> ca.SX:
    """A condition as SX: a relation or logical expression, or a plain bool (a structural choice)."""
    if isinstance(cond, (bool, np.bool_)):
        return ca.SX(float(cond))
    return as_sx(cond, f"{where}: condition")


def if_else(cond: Any, if_true: Any, if_false: Any) -> ca.SX:
    """``if cond then if_true else if_false`` with event semantics.

    Parameters
    ----------
    cond : casadi.SX
        Scalar relation (``x > 0``, ``time >= t0``) or a logical combination of relations
        (``ca.logic_and``, ``ca.logic_or``, ``ca.logic_not``).
    if_true, if_false : casadi.SX or float
        The two branches (scalars or arrays of equal shape).
    """
    c = _condition(cond, "if_else()")
    if not c.is_scalar():
        raise ModelError("if_else(): the condition must be a scalar")
    return ca.if_else(_discretize(c), as_sx(if_true, "if_else(): if_true"), as_sx(if_false, "if_else(): if_false"))


def assert_(cond: Any, message: str) -> None:
    """Modelica ``assert(cond, message)``: the run stops with an error when ``cond`` becomes false.

    Call it inside :meth:`Component.equations` (it adds no equation). ``cond`` is one relation
    (``u <= u_max``); it becomes an event indicator, so the violation is located in time, and the
    :class:`~flexlib.SolverError` names the component, the relation and ``message``, keeping the
    result up to the violation. A condition false at the start fails the run at once.

    Parameters
    ----------
    cond : casadi.SX
        A single relation (``<``, ``<=``, ``>``, ``>=``) that must hold during the whole run.
    message : str
        What is wrong, for the user (units and limits help).
    """
    if not isinstance(message, str):
        raise ModelError(f"assert_(): message must be a string, got {type(message).__name__} {message!r:.60}")
    c = as_sx(cond, "assert_(): condition")
    if not c.is_scalar() or c.is_constant() or c.op() not in (ca.OP_LT, ca.OP_LE):
        raise ModelError(f"assert_(): the condition must be one relation (<, <=, >, >=), got {c}")
    _discretize(c)
    sink = CURRENT_RELATIONS.get()
    assert sink is not None  # _discretize raised otherwise
    sink[-1].assertion = message


def _margin(cond: Any, where: str) -> tuple[ca.SX, bool]:
    """``rhs − lhs`` and the strictness of one relation ``lhs < rhs`` / ``lhs <= rhs`` (``>``, ``>=`` turned round)."""
    c = as_sx(cond, where)
    if not c.is_scalar() or c.is_constant() or c.op() not in (ca.OP_LT, ca.OP_LE):
        raise ModelError(f"{where} must be one relation (<, <=, >, >=), got {c}")
    return c.dep(1) - c.dep(0), c.op() == ca.OP_LT


def latch(set_when: Any, hold_while: Any) -> ca.SX:
    """A discrete value with memory (Modelica's ``pre()``): 1 from the event where ``set_when`` becomes true, for as
    long as ``hold_while`` holds; 0 from the event where ``hold_while`` fails, until ``set_when`` holds again.

    Modelica writes it ``y = not pre(y) and set_when or pre(y) and hold_while``: which condition is watched depends on
    the value before the event. Here the value is one relation whose indicator is ``set_when``'s while it is 0 and
    ``hold_while``'s while it is 1 (a discrete selection by the value itself, constant between events): a crossing of
    the watched indicator switches it, and the event iteration re-evaluates it with the new value, as it does every
    relation. It starts at 0 (Modelica's ``pre(y) = false`` at the start): it is 1 at the start where ``set_when``
    holds there.

    Parameters
    ----------
    set_when : casadi.SX
        One relation (``u > u_high``) that switches the value to 1 when it becomes true.
    hold_while : casadi.SX
        One relation (``u > u_low``) that keeps the value 1 while it holds. Both are taken as their indicators'
        sign: at exactly zero a strict relation counts as false (``set_when``'s strictness is used for both).

    Returns
    -------
    casadi.SX
        The value, 1.0 or 0.0, frozen between events.
    """
    set_margin, strict = _margin(set_when, "latch(): set_when")
    hold_margin, _ = _margin(hold_while, "latch(): hold_while")
    return _register(f"latch(set {set_when}, hold {hold_while})",
                     lambda own: ca.if_else(own, hold_margin, set_margin), strict, "latch()")


def no_event(cond: Any, if_true: Any, if_false: Any) -> ca.SX:
    """``if cond then if_true else if_false`` evaluated continuously, without events."""
    return ca.if_else(_condition(cond, "no_event()"), as_sx(if_true, "no_event(): if_true"),
                      as_sx(if_false, "no_event(): if_false"))


def abs_(x: Any) -> ca.SX:
    """``|x|`` with an event at ``x = 0``."""
    x = as_sx(x, "abs_()")
    return if_else(x >= 0, x, -x)


def sign(x: Any) -> ca.SX:
    """Sign of ``x`` (-1, 0 only at the event instant, +1) with events at ``x = 0``."""
    x = as_sx(x, "sign()")
    return if_else(x > 0, 1.0, if_else(x < 0, -1.0, 0.0))


def max_(a: Any, b: Any) -> ca.SX:
    """``max(a, b)`` with an event where ``a = b``."""
    a, b = as_sx(a, "max_()"), as_sx(b, "max_()")
    return if_else(a >= b, a, b)


def min_(a: Any, b: Any) -> ca.SX:
    """``min(a, b)`` with an event where ``a = b``."""
    a, b = as_sx(a, "min_()"), as_sx(b, "min_()")
    return if_else(a <= b, a, b)
