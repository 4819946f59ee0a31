"""Coulomb friction with a stuck phase, shared by the rotational and translational elements (MSL ``PartialFriction``).

The friction element is in one of five modes: *free* (not engaged, no friction force), *forward* or *backward*
sliding (``v_rel > 0`` / ``< 0``; the force follows the sliding characteristic), *stuck* (``v_rel = 0``, the force is
what keeps it so), and the start of sliding from stuck (*start forward* / *start backward*: the breakaway force was
exceeded, the relative speed is still zero). One unknown, the path parameter ``sa``, describes every mode::

    a_rel = 0                 stuck:   f = sa            (the force that holds it, from the rest of the model)
    a_rel = sa                free:    f = 0
    a_rel = sa − f0_max       forward: f = f_slide(v_rel)       (and start forward)
    a_rel = sa + f0_max       backward: f = −f_slide(−v_rel)    (and start backward)

so that the equations keep one structure in every mode (only the coefficients switch at events) and sticking is
exact: the relative acceleration is zero, the relative speed stays at its value to round-off. The modes switch by
state events (Otter, Elmqvist, Mattsson 1999)::

    startForward  = pre(mode) = Stuck and (sa > f0_max or pre(startForward) and sa > f0)
                    or pre(mode) = Backward and v_rel > v_small  or initial() and v_rel > 0
    mode          = Free if free, else Forward if (pre(mode) ∈ {Forward, Free} or startForward) and v_rel > 0,
                    else Backward (likewise), else Stuck

held here by four :func:`flexlib.latch` values (forward, backward, start forward, start backward) whose conditions
read each other, as Modelica's event iteration reads ``pre()``. While the element is free, *forward* and *backward*
follow the sign of ``v_rel`` (MSL's ``pre(mode) = Free`` case when it engages again); the mode reported is Free.

References
----------
M. Otter, H. Elmqvist, S. E. Mattsson: Hybrid Modeling in Modelica based on the Synchronous Data Flow Principle.
CACSD'99, Hawaii, 1999. Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Interfaces.PartialFriction``
and ``Modelica.Mechanics.Translational.Interfaces.PartialFriction``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from flexlib import Parameter, ParameterError, define_latch, eq, if_else, initial, latch, no_event
from flexlib.core.values import numeric_array

__all__ = ["BACKWARD", "FORWARD", "FREE", "STUCK", "FrictionModes", "TableFriction", "characteristic", "check_table",
           "friction_modes", "mode_rows"]

#: MSL's mode numbers (``PartialFriction.mode``)
FREE, FORWARD, STUCK, BACKWARD = 2, 1, 0, -1


@dataclass
class FrictionModes:
    """The discrete values of one friction element (each 1.0 or 0.0, frozen between events)."""

    forward: ca.SX
    backward: ca.SX
    start_forward: ca.SX
    start_backward: ca.SX
    free: ca.SX
    locked: ca.SX
    sliding_forward: ca.SX
    """Start forward, or forward and not start backward: the branch of the forward characteristic."""

    def acceleration(self, sa: Any, f0_max: Any) -> ca.SX:
        """``a_rel`` of the path parameter ``sa`` (MSL's ``a_relfric`` row)."""
        return ca.if_else(self.locked, 0.0,
                          ca.if_else(self.free, sa, ca.if_else(self.sliding_forward, sa - f0_max, sa + f0_max)))

    def force(self, sa: Any, forward: Any, backward: Any) -> ca.SX:
        """The friction force: ``sa`` stuck, 0 free, else ``forward`` or ``backward`` (the sliding laws)."""
        return ca.if_else(self.locked, sa, ca.if_else(self.free, 0.0,
                                                       ca.if_else(self.sliding_forward, forward, backward)))

    def mode(self) -> ca.SX:
        """MSL's ``mode``: Free 2, Forward 1, Stuck 0, Backward −1."""
        sliding = ca.if_else(self.forward, FORWARD, ca.if_else(self.backward, BACKWARD, STUCK))
        return ca.if_else(self.free, FREE, sliding)


def friction_modes(v_rel: Any, sa: Any, f0: Any, f0_max: Any, free: Any, v_small: Any,
                   forward_allowed: Any = True, backward_allowed: Any = True) -> FrictionModes:
    """Declare the mode logic of one friction element (call inside ``equations()``).

    Parameters
    ----------
    v_rel : casadi.SX
        Relative speed of the frictional surfaces [m/s or rad/s].
    sa : casadi.SX
        The path parameter (an unknown of the element) [N or N.m].
    f0 : casadi.SX
        Friction force at ``v_rel = 0`` when sliding forward [N or N.m].
    f0_max : casadi.SX
        Breakaway (maximum static) friction force, ``≥ f0`` [N or N.m].
    free : casadi.SX or bool
        False for an element always engaged, or a relation (``fn <= 0``) that makes it free (no friction).
    v_small : casadi.SX
        Relative speed below which a reversal from sliding passes through stuck [m/s or rad/s] (MSL ``v_small``,
        ``w_small``; large by default: a reversal always passes through stuck).
    forward_allowed, backward_allowed : casadi.SX or bool
        Relations that must hold to start or go on sliding forward / backward (a hard stop: ``s < s_max``; MSL's
        ``MassWithStopAndFriction``); True: always.
    """
    if isinstance(free, (bool, np.bool_)):
        is_free = ca.SX(float(free))
    else:
        is_free = if_else(free, 1.0, 0.0)  # its relation becomes a discrete value (an event where it switches)
    fw, bw = latch(name="forward sliding"), latch(name="backward sliding")
    sf, sb = latch(name="start forward"), latch(name="start backward")
    engaged = is_free < 0.5  # a discrete value: its margin changes only at events
    stuck = ca.logic_and(engaged, ca.logic_and(ca.logic_not(fw), ca.logic_not(bw)))
    start = initial()
    def allowed(cond: ca.SX, gate: Any) -> ca.SX:
        return cond if isinstance(gate, (bool, np.bool_)) and gate else ca.logic_and(cond, gate)

    moving_fw, moving_bw = v_rel > 0, v_rel < 0
    reverse_fw = ca.logic_and(bw, v_rel > v_small)
    reverse_bw = ca.logic_and(fw, v_rel < -v_small)
    define_latch(sf, ca.logic_or(ca.logic_or(allowed(ca.logic_and(stuck, sa > f0_max), forward_allowed), reverse_fw),
                                 ca.logic_and(start, moving_fw)),
                 ca.logic_or(ca.logic_or(allowed(ca.logic_and(stuck, sa > f0), forward_allowed), reverse_fw),
                             ca.logic_and(start, moving_fw)))
    define_latch(sb, ca.logic_or(ca.logic_or(allowed(ca.logic_and(stuck, sa < -f0_max), backward_allowed),
                                             reverse_bw), ca.logic_and(start, moving_bw)),
                 ca.logic_or(ca.logic_or(allowed(ca.logic_and(stuck, sa < -f0), backward_allowed), reverse_bw),
                             ca.logic_and(start, moving_bw)))
    define_latch(fw, allowed(ca.logic_and(ca.logic_or(is_free > 0.5, sf), moving_fw), forward_allowed),
                 allowed(moving_fw, forward_allowed))
    define_latch(bw, allowed(ca.logic_and(ca.logic_or(is_free > 0.5, sb), moving_bw), backward_allowed),
                 allowed(moving_bw, backward_allowed))
    free_d = is_free > 0.5
    locked = ca.logic_and(ca.logic_not(free_d),
                          ca.logic_not(ca.logic_or(ca.logic_or(fw, sf), ca.logic_or(bw, sb))))
    sliding_fw = ca.logic_or(sf, ca.logic_and(ca.logic_not(sb), fw))
    return FrictionModes(fw, bw, sf, sb, free_d, locked, sliding_fw)


def mode_rows(node: Any, v_rel: Any, a_rel: Any, f0: Any, f0_max: Any, free: Any, v_small: Any,
              forward_allowed: Any = True, backward_allowed: Any = True) -> tuple[FrictionModes, list]:
    """The modes of a friction element ``node`` (with the variables ``sa``, ``mode``, ``start_forward``,
    ``start_backward``, ``locked``) and its rows: ``a_rel`` of ``sa`` and the reported discrete values."""
    m = friction_modes(v_rel, node.sa, f0, f0_max, free, v_small, forward_allowed, backward_allowed)
    return m, [eq(a_rel, m.acceleration(node.sa, f0_max)), eq(node.mode, m.mode()),
               eq(node.start_forward, ca.if_else(m.start_forward, 1.0, 0.0)),
               eq(node.start_backward, ca.if_else(m.start_backward, 1.0, 0.0)),
               eq(node.locked, ca.if_else(m.locked, 1.0, 0.0))]


class TableFriction:
    """A friction element whose sliding law is a table of the positive characteristic (a mixin of components that
    set ``table_name`` and ``table_doc`` and have the variable ``sa``)."""

    table_name = ""
    table_doc = ""

    def table(self, value: Any) -> None:
        """Declare the table parameter ``table_name`` with ``value`` (checked: rows ``[v, value]``, ``v`` rising)."""
        arr = check_table(self, self.table_name, value)
        setattr(self, self.table_name, Parameter(unit="1", shape=arr.shape, doc=self.table_doc))
        setattr(self, self.table_name, arr)

    def check(self, values: dict) -> None:
        """A table given at run time (``params=``) is checked as one given to the constructor."""
        super().check(values)  # type: ignore[misc]
        if values.get(self.table_name) is not None:
            check_table(self, self.table_name, values[self.table_name])

    def sliding(self, m: FrictionModes, sa: Any, w: Any, scale: Any) -> ca.SX:
        """The friction torque: ``sa`` stuck, else ``scale`` times the characteristic at ``±w`` (by the branch)."""
        tab = getattr(self, self.table_name)
        return m.force(sa, scale * characteristic(tab, w), -scale * characteristic(tab, -w))


def check_table(owner: Any, name: str, table: Any, columns: int = 2, row: str = "[v, value]") -> np.ndarray:
    """A characteristic ``[[v, value, ...], ...]`` (rows of increasing ``v ≥ 0``) as an ``(n, columns)`` array."""
    where = f"{type(owner).__name__}: {name}"
    arr = np.atleast_2d(numeric_array(table, where, f"a table of rows {row}", ParameterError))
    if arr.ndim != 2 or arr.shape[1] != columns or arr.shape[0] == 0:
        raise ParameterError(f"{where} must be a table of rows {row} (shape (n, {columns})), got shape {arr.shape}")
    if np.any(arr[:, 0] < 0) or np.any(np.diff(arr[:, 0]) <= 0):
        raise ParameterError(f"{where}: the speeds (first column) must be ≥ 0 and strictly increasing, got "
                             f"{arr[:, 0].tolist()}")
    return arr


def characteristic(table: ca.SX, x: Any) -> ca.SX:
    """Linear interpolation in ``table`` (``(n, 2)``: abscissa, value) at ``x``, extrapolated through the first and
    the last two rows (``Modelica.Math.Vectors.interpolate``; a one-row table is constant). Continuous in ``x``:
    evaluated without events, as a Modelica function is."""
    n = table.shape[0]
    if n == 1:
        return table[0, 1]
    xs, ys = table[:, 0], table[:, 1]
    slope = [(ys[k + 1] - ys[k]) / (xs[k + 1] - xs[k]) for k in range(n - 1)]
    out = ys[0] + slope[0] * (x - xs[0])
    for k in range(1, n - 1):  # from the segment that holds x on
        out = no_event(x >= xs[k], ys[k] + slope[k] * (x - xs[k]), out)
    return out
