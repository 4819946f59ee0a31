"""Scaling stage: the nominal value of every unknown and which unknowns IDA's local error test leaves out.

The nominal of an unknown sets its error weight (``rtol·|y| + atol·nominal``) and the column scale of the rank
tests. It comes from, in this order:

1. the component's ``nominals()`` method, if it has one: a mapping from variable names (``"x"``, or
   ``"port_A.m_flow"`` for a variable of one of its connectors) to values, evaluated by this stage at the
   parameter values the model is built with (a hydraulic cylinder's piston position weighted by its stroke, its
   chamber masses by what 100 bar adds to them). A value that is not a positive finite number keeps the
   declaration's;
2. the declaration, ``Variable(nominal=...)`` (default 1).

Alias elimination then takes the largest nominal of each alias class (:mod:`flexlib.compile.simplify`). The
evaluated values of 1 are part of the cache key (:func:`key_nominals`), so an instance with another stroke is
built again instead of reusing another instance's weights.

Error-test policy: an unknown is left out of IDA's local error test where it is an algebraic unknown at the
derivative level (``structure.derivative_level``, found at compile time), or where a domain pass marks it so
(:meth:`flexlib.compile.passes.Pass.marks`, applied by :func:`apply_marks`; the multibody pass marks the frames'
and joints' accelerations, :mod:`flexlib.compile.passes.multibody.kinematics`). A kinematic intermediate (a frame's
velocity and accelerations along the tree) is eliminated where a row gives it explicitly. A declaration can still
say either (``Variable(error_test=False)``, ``Variable(intermediate=True)``) for a component outside any pass.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

from flexlib.core.component import Component, Connector, Node
from flexlib.errors import ModelError

__all__ = ["apply_marks", "instance_nominals", "key_nominals"]


def _value(raw: Any) -> float | None:
    """``raw`` as a positive finite float, or None (the declaration's nominal stays)."""
    try:
        v = float(raw)
    except (TypeError, ValueError):
        return None
    return v if v > 0 and math.isfinite(v) else None


def _holder(node: Component, name: str) -> tuple[Node, str]:
    """The node that declares ``name`` (``"port_A.m_flow"``: the connector ``port_A``) and the bare name."""
    owner, _, leaf = name.rpartition(".")
    holder: Node = node
    for part in owner.split(".") if owner else ():
        holder = holder._children.get(part)
        if not isinstance(holder, (Component, Connector)):
            raise ModelError(f"{node.path or type(node).__name__}.nominals(): {name!r} names no connector or "
                             "sub-component of the component")
    if leaf not in holder._decls:
        raise ModelError(f"{node.path or type(node).__name__}.nominals(): {name!r} is not a variable of "
                         f"{holder.path or type(holder).__name__}")
    return holder, leaf


def instance_nominals(nodes: list[Node]) -> dict[tuple[int, str], float]:
    """The nominals the components' ``nominals()`` give, by ``(id(holder), variable name)``, at their current
    parameter values (only positive finite values; see the module doc)."""
    out: dict[tuple[int, str], float] = {}
    for node in nodes:
        rule = getattr(type(node), "nominals", None) if isinstance(node, Component) else None
        if rule is None:
            continue
        given = node.nominals()
        if not isinstance(given, Mapping):
            raise ModelError(f"{node.path or type(node).__name__}.nominals() must return a dict of variable names "
                             f"to values, got {type(given).__name__}")
        for name, raw in given.items():
            value = _value(raw)
            if value is not None:
                holder, leaf = _holder(node, name)
                out[(id(holder), leaf)] = value
    return out


def key_nominals(root: Component) -> tuple[tuple[str, float], ...]:
    """The evaluated ``nominals()`` of the model below ``root`` by variable label, for the cache key."""
    nodes = root.walk()
    by_id = {id(n): n for n in nodes}
    return tuple(sorted((by_id[h]._label(name), v) for (h, name), v in instance_nominals(nodes).items()))


def apply_marks(variables: list[Any], by_hash: dict[int, int], untested: set[int], intermediate: set[int]) -> None:
    """Mark the flat variables whose symbol hash (``by_hash``: hash → index in ``variables``) is in ``untested``
    (out of the error test) or ``intermediate`` (kinematic intermediate), in place."""
    for h in untested | intermediate:
        k = by_hash.get(h)
        if k is not None:
            v = variables[k]
            variables[k] = dataclasses.replace(v, error_test=v.error_test and h not in untested,
                                               intermediate=v.intermediate or h in intermediate)
