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
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from flexlib.core.equations import as_sx
from flexlib.core.variables import SymInfo
from flexlib.errors import ModelError

__all__ = ["abs_", "assert_", "define_latch", "if_else", "initial", "latch", "max_", "min_", "no_event", "reinit",
           "sign"]

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
    indicator: ca.SX | None  # None: a latch declared by latch() whose conditions define_latch() has still to give
    strict: bool
    text: str
    lhs: ca.SX | None = None
    rhs: ca.SX | None = None
    owner: str = ""
    assertion: str = ""  # set by assert_(): the relation must stay true; message if it becomes false
    initial: bool = False  # initial(): 1 while the start is found, 0 afterwards (set by the start, never watched)
    #: reinit(): (state symbol, value: a number or a variable's symbol) set at the event where the relation becomes true
    reinit: list = field(default_factory=list)

    def describe(self) -> str:
        """``owner: lhs < rhs`` with hierarchical names."""
        from flexlib.core.variables import render

        if self.lhs is None or self.rhs is None:
            return f"{self.owner}: {self.text}" if self.owner else self.text
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
    """A continuous margin whose sign is the value of ``cond`` (a relation, a discrete value, or a logical
    combination of them), and the strictness of its first relation.

    ``lhs < rhs`` gives ``rhs − lhs``; a discrete value ``d`` (a relation's, a latch's or :func:`initial`'s symbol,
    frozen between events) gives ``±1``; ``and`` is the smaller margin, ``or`` the larger, ``not`` the negated one.
    Only the sign matters: the margin crosses zero where the condition switches, and a discrete operand changes
    only at events.
    """
    c = as_sx(cond, where)
    if not c.is_scalar():
        raise ModelError(f"{where} must be a scalar condition, got shape {c.shape}")
    sink = CURRENT_RELATIONS.get()
    discrete = {r.info.sym.element_hash() for r in sink} if sink else set()
    strictness: list[bool] = []

    def walk(e: ca.SX) -> ca.SX:
        if e.is_symbolic() and e.element_hash() in discrete:
            return ca.if_else(e, 1.0, -1.0)
        if e.is_constant():  # a structural choice (an element that is never free)
            return ca.SX(1.0 if float(e) else -1.0)
        op = None if e.is_constant() or e.is_symbolic() else e.op()
        if op in (ca.OP_LT, ca.OP_LE):
            strictness.append(op == ca.OP_LT)
            return e.dep(1) - e.dep(0)
        if op == ca.OP_AND:
            return ca.fmin(walk(e.dep(0)), walk(e.dep(1)))
        if op == ca.OP_OR:
            return ca.fmax(walk(e.dep(0)), walk(e.dep(1)))
        if op == ca.OP_NOT:
            return -walk(e.dep(0))
        raise ModelError(f"{where} must be a relation (<, <=, >, >=), a discrete value (a relation's, latch()'s or "
                         f"initial()'s) or a logical combination of them, got {e}")

    margin = walk(c)
    if not strictness:
        raise ModelError(f"{where} must contain a relation of continuous values, got {c}")
    return margin, strictness[0]


#: the text of a latch declared without a name, until define_latch() gives its conditions
_DECLARED = "latch(declared)"


def latch(set_when: Any = None, hold_while: Any = None, name: str = "") -> ca.SX:
    """A discrete value with memory (Modelica's ``pre()``): 1 from the event where ``set_when`` becomes true, for as
    long as ``hold_while`` holds; 0 from the event where ``hold_while`` fails, until ``set_when`` holds again.

    Modelica writes it ``y = not pre(y) and set_when or pre(y) and hold_while``: which condition is watched depends on
    the value before the event. Here the value is one relation whose indicator is ``set_when``'s while it is 0 and
    ``hold_while``'s while it is 1 (a discrete selection by the value itself, constant between events): a crossing of
    the watched indicator switches it, and the event iteration re-evaluates it with the new value, as it does every
    relation. It starts at 0 (Modelica's ``pre(y) = false`` at the start): it is 1 at the start where ``set_when``
    holds there.

    The conditions may combine relations with other discrete values (relations, latches of the same component,
    :func:`initial`) by ``ca.logic_and``/``logic_or``/``logic_not``: a state machine of several latches (MSL's friction
    modes) reads the others' values as Modelica reads ``pre()`` in an event iteration — each pass of the iteration
    evaluates every latch with the values of the pass before, until none changes. Latches whose conditions refer to
    each other are declared first, ``latch()`` without conditions, and given their conditions by
    :func:`define_latch`.

    Parameters
    ----------
    set_when : casadi.SX
        A relation (``u > u_high``), or a logical combination of relations and discrete values, that switches the
        value to 1 when it becomes true.
    hold_while : casadi.SX
        Likewise, the condition that keeps the value 1 while it holds. Both are taken as their margins' sign: at
        exactly zero a strict relation counts as false (the strictness of ``set_when``'s first relation is used for
        both).
    name : str
        What the value means (``"forward sliding"``), for event logs and diagnostics; default the conditions.

    Returns
    -------
    casadi.SX
        The value, 1.0 or 0.0, frozen between events.
    """
    if not isinstance(name, str):
        raise ModelError(f"latch(): name must be a string, got {type(name).__name__}")
    if set_when is None and hold_while is None:
        return _register(name or _DECLARED, lambda own: None, True, "latch()")
    if set_when is None or hold_while is None:
        raise ModelError("latch(): give both set_when and hold_while, or neither (then define_latch() gives them)")
    value = latch(name=name or _DECLARED)
    define_latch(value, set_when, hold_while)
    return value


def define_latch(value: ca.SX, set_when: Any, hold_while: Any) -> None:
    """Give a latch declared by :func:`latch` (without conditions) its conditions; see :func:`latch`.

    Parameters
    ----------
    value : casadi.SX
        The latch's value, as ``latch()`` returned it in the same ``equations()``.
    set_when, hold_while : casadi.SX
        The conditions, as for :func:`latch`.
    """
    sink = CURRENT_RELATIONS.get()
    if sink is None:
        raise ModelError("define_latch() may only be used inside equations()")
    h = value.element_hash() if isinstance(value, ca.SX) and value.is_symbolic() else None
    rel = next((r for r in sink if r.info.sym.element_hash() == h), None)
    if rel is None or rel.indicator is not None:
        raise ModelError(f"define_latch(): {value} is not a latch declared by latch() in this equations(), or it has "
                         "its conditions already")
    set_margin, strict = _margin(set_when, "latch(): set_when")
    hold_margin, _ = _margin(hold_while, "latch(): hold_while")
    rel.indicator = ca.if_else(value, hold_margin, set_margin)
    rel.strict = strict
    if rel.text == _DECLARED:
        rel.text = f"latch(set {set_when}, hold {hold_while})"


def initial() -> ca.SX:
    """Modelica's ``initial()``: a discrete value that is 1 while the start is found and 0 afterwards.

    Use it in a :func:`latch`'s condition (MSL's friction starts sliding where the relative speed is not zero at the
    start: ``initial() and w_rel > 0``). The run's start sets it to 1 for the whole iteration that makes the start
    consistent, and to 0 before the integration begins; the latches keep the values they had at the start until
    their next event, as Modelica's discrete variables do.

    Returns
    -------
    casadi.SX
        The discrete value (1.0 during the start, 0.0 afterwards).
    """
    sym = _register("initial()", ca.SX(-1.0), True, "initial()")
    sink = CURRENT_RELATIONS.get()
    assert sink is not None  # _register raised otherwise
    sink[-1].initial = True
    return sym


def reinit(when: Any, *values: tuple[Any, Any]) -> ca.SX:
    """Modelica's ``when when then reinit(x, value); ... end when``: at the event where the relation ``when`` becomes
    true, each state ``x`` is set to its ``value``; the event iteration then goes on from the new state.

    Call it inside :meth:`Component.equations` (it adds no equation). A hard stop is the typical use: when the
    position reaches the stop, the position is put on it and the speed to zero (MSL's ``MassWithStopAndFriction``).

    Parameters
    ----------
    when : casadi.SX
        One relation (``<``, ``<=``, ``>``, ``>=``); its rising edge (false → true, at an event after the start)
        fires the reinitialisation.
    *values : (casadi.SX, float or casadi.SX)
        Pairs ``(x, value)``: ``x`` a variable of the component that the compiled model keeps as a state (give it
        ``state_select="always"``), ``value`` a number or a variable (declare a variable for an expression: its
        value just before the reinitialisation is taken).

    Returns
    -------
    casadi.SX
        The relation's discrete value (1.0 while ``when`` holds).
    """
    margin, strict = _margin(when, "reinit(): when")
    c = as_sx(when, "reinit(): when")
    if c.op() not in (ca.OP_LT, ca.OP_LE):
        raise ModelError(f"reinit(): when must be one relation (<, <=, >, >=), got {c}")
    if not values:
        raise ModelError("reinit(): give at least one pair (state, value)")
    actions = []
    for pair in values:
        if not isinstance(pair, tuple) or len(pair) != 2:
            raise ModelError(f"reinit(): each value is a pair (state, value), got {pair!r:.80}")
        x, v = pair
        if not (isinstance(x, ca.SX) and x.is_scalar() and x.is_symbolic()):
            raise ModelError(f"reinit(): the reinitialised {x!r:.60} must be a scalar variable of the component")
        if isinstance(v, ca.SX) and not v.is_constant():
            if not (v.is_scalar() and v.is_symbolic()):
                raise ModelError(f"reinit(): the value {v!r:.60} must be a number or a scalar variable (declare a "
                                 "variable for an expression)")
        else:
            v = float(ca.evalf(v)) if isinstance(v, ca.SX) else float(v)
            if not np.isfinite(v):
                raise ModelError(f"reinit(): the value for {x} must be finite, got {v}")
        actions.append((x, v))
    sym = _register(f"{c.dep(0)} {'<' if strict else '<='} {c.dep(1)}", margin, strict, "reinit()",
                    lhs=c.dep(0), rhs=c.dep(1))
    sink = CURRENT_RELATIONS.get()
    assert sink is not None  # _register raised otherwise
    sink[-1].reinit = actions
    return sym


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
