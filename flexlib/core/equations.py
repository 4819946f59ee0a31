"""Equations: ``eq(lhs, rhs)``, the :class:`Equation` it returns, and ``der`` (the time derivative).

A component's :meth:`~flexlib.Component.equations` returns a list of ``eq(...)``; ``der(x)`` of a declared variable
is its derivative symbol, ``der`` of an expression its derivative by the chain rule.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from flexlib.core.values import not_a_number
from flexlib.core.variables import lookup
from flexlib.errors import ModelError

__all__ = ["Equation", "as_sx", "der", "eq"]


def as_sx(x: Any, what: str = "an expression") -> ca.SX:
    """``x`` as an SX expression: an SX, a DM or a real number / array of them.

    A string (``eq(x, "b")``), None (``eq(None)`` became the constant NaN), a bool, a dict or another object is
    refused with a :class:`~flexlib.ModelError` naming ``what`` (``"eq(): right side"``) and the value.
    """
    if isinstance(x, ca.SX):
        return x
    if isinstance(x, (ca.MX,)):
        raise ModelError("flexlib equations are SX expressions; got an MX expression")
    if isinstance(x, ca.DM):
        return ca.SX(x)
    if type(x) is float or (type(x) is int and abs(x) < 2**1000):  # the usual constant (eq(x) has rhs 0.0)
        return ca.SX(float(x))
    why = not_a_number(x)
    if why is None:
        try:
            return ca.SX(np.asarray(x, dtype=float))
        except (TypeError, ValueError, OverflowError) as exc:  # 10**400; a ragged list
            why = f"not numeric ({exc})"
    if isinstance(x, (list, tuple)) or (isinstance(x, np.ndarray) and x.dtype == object and x.ndim in (1, 2)):
        # numbers and symbols mixed ([x, 0.0], [[a, b], [c, d]]): a column, or a matrix of rows; a bad entry is
        # named by itself
        items = list(x)
        try:
            if items and all(isinstance(r, (list, tuple, np.ndarray)) for r in items):
                return ca.vertcat(*[ca.horzcat(*[as_sx(v, what) for v in r]) for r in items])
            return ca.vertcat(*[as_sx(v, what) for v in items]) if items else ca.SX(0, 1)
        except RuntimeError as exc:  # CasADi: rows of different lengths
            raise ModelError(f"{what}: {x!r:.80} is not a regular array (rows of different lengths)") from exc
    shown = "got None" if x is None else f"{x!r:.80} is {why}"
    raise ModelError(f"{what}: {shown}; give a symbolic expression (a variable, a parameter, an expression of them) "
                     "or a real number")


def der(expr: Any) -> ca.SX:
    """Time derivative of a variable or of an expression of variables (chain rule).

    Parameters
    ----------
    expr : casadi.SX
        A variable symbol (scalar or array) or an expression of variables, parameters and time.

    Returns
    -------
    casadi.SX
        ``der(x)`` symbols for variables; ``dexpr/dt`` by forward differentiation otherwise.
    """
    e = as_sx(expr, "der()")
    if e.is_scalar() and e.is_symbolic():  # one scalar symbol (the usual case): its der symbol
        info = lookup(e)
        if info is not None and info.kind not in ("time", "parameter", "relation", "table"):
            return info.der_info.sym
    if e.is_valid_input():  # a (matrix of) plain symbols
        out = []
        for k in range(e.nnz()):
            s = e.nz[k]
            info = lookup(s)
            if info is None:
                raise ModelError(f"der({s}): {s} is not a flexlib variable")
            if info.kind == "time":
                out.append(ca.SX(1.0))
            elif info.kind in ("parameter", "relation", "table"):
                out.append(ca.SX(0.0))
            else:
                out.append(info.der_info.sym)
        res = ca.SX(e.sparsity(), ca.vertcat(*out)) if out else ca.SX(e.shape)
        return res
    syms = ca.symvar(e)
    if not syms:
        return ca.SX.zeros(*e.shape)
    v, d = [], []
    for s in syms:
        info = lookup(s)
        if info is None:
            raise ModelError(f"der(): symbol {s} in {e} is not a flexlib variable")
        if info.kind in ("parameter", "relation", "table"):
            continue
        v.append(s)
        d.append(ca.SX(1.0) if info.kind == "time" else info.der_info.sym)
    if not v:
        return ca.SX.zeros(*e.shape)
    if e.is_scalar():  # no reshaping around the directional derivative
        return ca.jtimes(e, ca.vertcat(*v), ca.vertcat(*d))
    flat = ca.vec(e)
    dflat = ca.jtimes(flat, ca.vertcat(*v), ca.vertcat(*d))
    return ca.reshape(dflat, e.shape[0], e.shape[1])


@dataclass(eq=False)
class Equation:
    """One (possibly array-valued) equation ``lhs = rhs`` stored as the residual ``lhs - rhs``.

    Attributes
    ----------
    residual : casadi.SX
        Column of scalar residuals.
    label : str
        Optional description shown in diagnostics.
    owner : str
        Hierarchical path of the component that declared it (set by the flattener).
    """

    residual: ca.SX
    label: str = ""
    owner: str = ""


def eq(lhs: Any, rhs: Any = 0.0, label: str = "") -> Equation:
    """The equation ``lhs = rhs`` (CasADi overloads ``==``, so equations use this function).

    Parameters
    ----------
    lhs, rhs : casadi.SX or array_like
        Both sides, of equal shape (a scalar side is broadcast).
    label : str
        Optional short description used in diagnostics.
    """
    if type(label) is not str:
        raise ModelError(f"eq(): label must be a string, got {type(label).__name__} {label!r:.60}")
    a = lhs if type(lhs) is ca.SX else as_sx(lhs, f"eq({label!r}): left side" if label else "eq(): left side")
    b = rhs if type(rhs) is ca.SX else as_sx(rhs, f"eq({label!r}): right side" if label else "eq(): right side")
    if a.is_scalar() and b.is_scalar():  # the usual scalar equation: a - b is already a column
        return Equation(a - b, label=label)
    if a.shape != b.shape:
        if b.is_scalar():
            b = ca.repmat(b, a.shape[0], a.shape[1])
        elif a.is_scalar():
            a = ca.repmat(a, b.shape[0], b.shape[1])
        else:
            raise ModelError(f"eq(): left side has shape {a.shape}, right side {b.shape} ({label or 'equation'})")
    return Equation(ca.vec(a - b), label=label)
