"""Sliding mass with hard stops and Stribeck friction (MSL ``MassWithStopAndFriction``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Parameter, ParameterError, Variable, der, eq, no_event, reinit

from ..friction import mode_rows
from .interfaces import PartialRigid

__all__ = ["MassWithStopAndFriction"]

#: MSL's breakaway force over the sliding force at rest (``f0_max = f0 * 1.001``)
BREAKAWAY = 1.001


class MassWithStopAndFriction(PartialRigid):
    """A mass of length ``L`` sliding on a support between two hard stops, with Stribeck friction and a stuck phase.

    With ``v = der(s)``, ``a = der(v)``::

        m a = flange_a.f + flange_b.f − f
        f = sa                                                       stuck (a = 0)
          =  F_prop v + F_Coulomb + F_Stribeck exp(−fexp |v|)        sliding forward (F_Stribeck undamped while
          =  F_prop v − F_Coulomb − F_Stribeck exp(−fexp |v|)        starting), backward

    breakaway at ``f0_max = 1.001 (F_Coulomb + F_Stribeck)``; the modes switch by state events
    (:mod:`components.mechanics.friction`), and neither sliding nor its start goes on into a stop: forward needs
    ``s < smax − L/2``, backward ``s > smin + L/2``. Where the mass reaches a stop (an event), its position is put
    on the stop and its speed to zero (:func:`flexlib.reinit`; MSL's ``when stopped <> 0 then reinit(s, …);
    reinit(v, 0)``): a fully plastic impact, after which it sticks until pulled away from the stop.

    Notes
    -----
    ``s`` and ``v`` are always states (MSL ``stateSelect = always``: they are reinitialised). MSL's assertions that
    the start lies between the stops are not made. No heat port.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.MassWithStopAndFriction``;
    validated against the reference result of ``Translational.Examples.Friction``.
    """

    m = Parameter(unit="kg", min=0.0, doc="Mass")
    F_prop = Parameter(unit="N.s/m", min=0.0, doc="Velocity dependent friction")
    F_Coulomb = Parameter(unit="N", doc="Constant friction: Coulomb force")
    F_Stribeck = Parameter(unit="N", doc="Stribeck effect")
    fexp = Parameter(unit="s/m", min=0.0, doc="Exponential decay of the Stribeck effect")
    smax = Parameter(unit="m", doc="Right stop for the right end of the mass")
    smin = Parameter(unit="m", doc="Left stop for the left end of the mass")
    v_small = Parameter(1e-3, unit="m/s", gt=0.0, doc="Speed near zero: a reversal faster than it skips stuck")
    v = Variable(unit="m/s", state_select="always", doc="Absolute velocity of flange_a and flange_b")
    a = Variable(unit="m/s2", doc="Absolute acceleration of flange_a and flange_b")
    f = Variable(unit="N", doc="Friction force (positive against the motion)")
    sa = Variable(unit="1", doc="Path parameter of the friction characteristic (force [N] stuck, else a + f0_max)")
    f0 = Variable(unit="N", doc="Friction force at v = 0 (sliding forward)")
    f0_max = Variable(unit="N", doc="Breakaway friction force")
    mode = Variable(unit="1", doc="Mode: 2 free, 1 forward sliding, 0 stuck, -1 backward sliding (MSL mode)")
    start_forward = Variable(unit="1", doc="1 while starting to slide forward from stuck (MSL startForward)")
    start_backward = Variable(unit="1", doc="1 while starting to slide backward from stuck (MSL startBackward)")
    locked = Variable(unit="1", doc="1 while stuck (speed held at zero)")
    stopped = Variable(unit="1", doc="-1 on the left stop, +1 on the right stop, 0 between (MSL stopped)")
    s_left = Variable(unit="m", doc="Position of the centre on the left stop, smin + L/2")
    s_right = Variable(unit="m", doc="Position of the centre on the right stop, smax - L/2")

    def __init__(self, **kw: Any) -> None:
        super().__init__(**kw)
        self.set_state_select("s", "always")

    def check(self, values: dict) -> None:
        super().check(values)
        lo, hi, L = values.get("smin"), values.get("smax"), values.get("L")
        if lo is not None and hi is not None and L is not None and float(hi) - float(lo) < float(L):
            raise ParameterError(f"{type(self).__name__}: smax - smin must be at least L (the mass fits between its "
                                 "stops)")

    def equations(self) -> list:
        s, v = self.s, self.v
        inside_right, inside_left = s < self.smax - self.L / 2, s > self.smin + self.L / 2
        on_right = reinit(s >= self.smax - self.L / 2, (s, self.s_right), (v, 0.0))
        on_left = reinit(s <= self.smin + self.L / 2, (s, self.s_left), (v, 0.0))
        free = ca.logic_and(ca.logic_and(self.f0 <= 0, self.F_prop <= 0), ca.logic_and(inside_left, inside_right))
        m, rows = mode_rows(self, v, self.a, self.f0, self.f0_max, free, self.v_small, inside_right, inside_left)
        speed = no_event(v >= 0, v, -v)
        stribeck = self.F_Stribeck * ca.exp(-self.fexp * speed)
        forward = ca.if_else(m.start_forward, self.F_Coulomb + self.F_Stribeck, self.F_Coulomb + stribeck)
        backward = ca.if_else(m.start_backward, self.F_Coulomb + self.F_Stribeck, self.F_Coulomb + stribeck)
        return [*super().equations(), *rows,
                eq(self.f0, self.F_Coulomb + self.F_Stribeck), eq(self.f0_max, BREAKAWAY * self.f0),
                eq(der(s), v), eq(der(v), self.a),
                eq(0.0, self.flange_a.f + self.flange_b.f - self.f - self.m * self.a),
                eq(self.f, m.force(self.sa, self.F_prop * v + forward, self.F_prop * v - backward)),
                eq(self.stopped, on_right - on_left),
                eq(self.s_left, self.smin + self.L / 2), eq(self.s_right, self.smax - self.L / 2)]

