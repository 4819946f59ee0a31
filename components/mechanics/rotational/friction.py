"""Coulomb friction with exact sticking: bearing friction, clutch and brake (MSL ``PartialFriction``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Input, Parameter, Variable, define_latch, der, eq, if_else, initial, latch

from ..friction import FrictionModes, TableFriction, characteristic, mode_rows
from .interfaces import PartialCompliantWithRelativeStates, PartialTwoFlangesAndSupport

__all__ = ["BearingFriction", "Brake", "Clutch", "OneWayClutch"]

#: MSL's relative hysteresis of the one-way clutch's breakaway torque (``OneWayClutch.eps0``)
ONE_WAY_EPS = 1e-4


class _Friction(TableFriction):
    """The variables of the mode logic (``components.mechanics.friction``) every friction element reports."""

    peak = Parameter(1.0, unit="1", min=1.0, doc="Breakaway torque over the sliding torque at w = 0 (≥ 1)")
    w_small = Parameter(1e10, unit="rad/s", gt=0.0,
                        doc="Relative speed below which a reversal passes through stuck (MSL w_small; large: always)")
    sa = Variable(unit="1", doc="Path parameter of the friction characteristic (torque [N.m] stuck, else a_rel + "
                                "tau0_max)")
    tau0 = Variable(unit="N.m", doc="Sliding friction torque at w_rel = 0")
    tau0_max = Variable(unit="N.m", doc="Breakaway friction torque (peak * tau0)")
    mode = Variable(unit="1", doc="Mode: 2 free, 1 forward sliding, 0 stuck, -1 backward sliding (MSL mode)")
    start_forward = Variable(unit="1", doc="1 while starting to slide forward from stuck (MSL startForward)")
    start_backward = Variable(unit="1", doc="1 while starting to slide backward from stuck (MSL startBackward)")
    locked = Variable(unit="1", doc="1 while stuck (relative speed held at zero)")

    def mode_rows(self, w_rel: Any, a_rel: Any, free: Any) -> tuple[FrictionModes, list]:
        """The modes of relative speed ``w_rel``, and the rows of ``a_rel``, the breakaway torque and the reported
        discrete values."""
        m, rows = mode_rows(self, w_rel, a_rel, self.tau0, self.tau0_max, free, self.w_small)
        return m, [*rows, eq(self.tau0_max, self.peak * self.tau0)]


class BearingFriction(_Friction, PartialTwoFlangesAndSupport):
    """Coulomb friction in a bearing, between the rigidly connected flanges and the housing, with a stuck phase.

    With ``phi = flange_a.phi − phi_support``, ``w = der(phi)``, ``a = der(w)``::

        flange_a.tau + flange_b.tau = tau
        tau = sa                       stuck (a = 0)
            =  tau_pos(w)              sliding forward (a = sa − tau0_max)
            = −tau_pos(−w)             sliding backward (a = sa + tau0_max)

    with ``tau0 = tau_pos(0)`` and the breakaway torque ``tau0_max = peak * tau0``. The modes switch by state events
    (:mod:`components.mechanics.friction`); stuck, the speed is held exactly.

    Parameters
    ----------
    tau_pos : array_like
        Positive sliding friction torque [N.m] against speed [rad/s], rows ``[w, tau]`` with ``w ≥ 0`` increasing,
        linear in between and extrapolated (MSL default ``[[0, 1]]``).
    use_support : bool
        True: the housing is the ``support`` flange; False: it is grounded.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.BearingFriction`` (without the heat
    port); the mode logic of ``Rotational.Interfaces.PartialFriction``.
    """

    table_name, table_doc = "tau_pos", "Positive sliding friction torque [N.m] against speed [rad/s], rows [w, tau]"
    phi = Variable(unit="rad", doc="Angle of the flanges relative to the support")
    w = Variable(unit="rad/s", doc="Angular velocity relative to the support")
    a = Variable(unit="rad/s2", doc="Angular acceleration relative to the support")
    tau = Variable(unit="N.m", doc="Friction torque")

    def __init__(self, tau_pos: Any = ((0.0, 1.0),), use_support: bool = False, **kw: Any) -> None:
        super().__init__(use_support=use_support, **kw)
        self.table(tau_pos)

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        m, rows = self.mode_rows(self.w, self.a, False)
        return [*self.support_equations(), *rows,
                eq(self.phi, fa.phi - self.phi_support), eq(fb.phi, fa.phi),
                eq(self.w, der(self.phi)), eq(self.a, der(self.w)),
                eq(fa.tau + fb.tau - self.tau, 0.0),
                eq(self.tau0, characteristic(self.tau_pos, 0.0)),
                eq(self.tau, self.sliding(m, self.sa, self.w, 1.0))]


class _NormalForce(_Friction):
    """Clutch and brake: the friction coefficient table, the normal force from a normalised input."""

    table_name, table_doc = "mu_pos", "Positive sliding friction coefficient [1] against speed [rad/s], rows [w, mu]"
    cgeo = Parameter(1.0, unit="m", min=0.0, doc="Geometry constant: friction torque = cgeo * mu * fn")
    fn_max = Parameter(unit="N", min=0.0, doc="Maximum normal force")
    f_normalized = Input(unit="1", doc="Normalised normal force 0..1 (normal force = fn_max * f_normalized)")
    fn = Variable(unit="N", doc="Normal force")
    mu0 = Variable(unit="1", doc="Friction coefficient at w = 0 when sliding forward")

    def normal_rows(self) -> list:
        return [eq(self.mu0, characteristic(self.mu_pos, 0.0)), eq(self.fn, self.fn_max * self.f_normalized),
                eq(self.tau0, self.mu0 * self.cgeo * self.fn)]

    def engaged_torque(self, m: FrictionModes, w: Any) -> ca.SX:
        """``cgeo * fn * mu(±w)`` by the branch, ``sa`` stuck, 0 free."""
        return self.sliding(m, self.sa, w, self.cgeo * self.fn)


class Clutch(_NormalForce, PartialCompliantWithRelativeStates):
    """Clutch by Coulomb friction between its two flanges, engaged by a normal force, with a stuck phase.

    ``fn = fn_max * f_normalized``; free (no torque) while ``fn ≤ 0``. Engaged, with ``tau0 = cgeo mu_pos(0) fn``
    and the breakaway torque ``tau0_max = peak tau0``::

        tau = sa                               stuck (a_rel = 0)
            =  cgeo fn mu_pos(w_rel)           sliding forward
            = −cgeo fn mu_pos(−w_rel)          sliding backward

    Parameters
    ----------
    mu_pos : array_like
        Positive sliding friction coefficient [1] against relative speed [rad/s], rows ``[w, mu]`` (MSL default
        ``[[0, 0.5]]``).

    Notes
    -----
    MSL writes the start-backward branch ``-interpolate(mu_pos, w_rel)``, the start-forward branch's argument; here it
    is ``-mu_pos(-w_rel)`` as in sliding backward (the same at ``w_rel = 0``, where starting happens, and for
    a constant coefficient).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.Clutch`` (without the heat port).
    """

    a_rel = Variable(unit="rad/s2", doc="Relative angular acceleration, der(w_rel)")

    def __init__(self, mu_pos: Any = ((0.0, 0.5),), **kw: Any) -> None:
        super().__init__(**kw)
        self.table(mu_pos)

    def equations(self) -> list:
        m, rows = self.mode_rows(self.w_rel, self.a_rel, self.fn <= 0)
        return [*super().equations(), *rows, *self.normal_rows(), eq(self.a_rel, der(self.w_rel)),
                eq(self.tau, self.engaged_torque(m, self.w_rel))]


class Brake(_NormalForce, PartialTwoFlangesAndSupport):
    """Brake by Coulomb friction between the rigidly connected flanges and the housing, with a stuck phase.

    As :class:`Clutch`, with the speed ``w`` of the flanges relative to the support in place of ``w_rel`` and the
    torque balance ``flange_a.tau + flange_b.tau = tau``.

    Parameters
    ----------
    mu_pos : array_like
        Positive sliding friction coefficient [1] against speed [rad/s], rows ``[w, mu]`` (MSL default ``[[0, 0.5]]``).
    use_support : bool
        True: the housing is the ``support`` flange; False: it is grounded.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.Brake`` (without the heat port).
    """

    phi = Variable(unit="rad", doc="Angle of the flanges relative to the support")
    w = Variable(unit="rad/s", doc="Angular velocity relative to the support")
    a = Variable(unit="rad/s2", doc="Angular acceleration relative to the support")
    tau = Variable(unit="N.m", doc="Friction torque")

    def __init__(self, mu_pos: Any = ((0.0, 0.5),), use_support: bool = False, **kw: Any) -> None:
        super().__init__(use_support=use_support, **kw)
        self.table(mu_pos)

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        m, rows = self.mode_rows(self.w, self.a, self.fn <= 0)
        return [*self.support_equations(), *rows, *self.normal_rows(),
                eq(self.phi, fa.phi - self.phi_support), eq(fb.phi, fa.phi),
                eq(self.w, der(self.phi)), eq(self.a, der(self.w)),
                eq(fa.tau + fb.tau - self.tau, 0.0),
                eq(self.tau, self.engaged_torque(m, self.w))]



class OneWayClutch(TableFriction, PartialCompliantWithRelativeStates):
    """A clutch in parallel with a freewheel: ``flange_b`` may overrun ``flange_a`` (``w_rel > 0``) against the
    clutch's friction, never lag behind it (``w_rel ≥ 0``: stuck when it would).

    With ``fn = fn_max * f_normalized`` (0 while ``f_normalized ≤ 0``: the clutch is open), ``tau0 = cgeo mu_pos(0) fn``
    and the breakaway torque ``tau0_max = max(peak, 1 + 1e-4) tau0`` (open: ``1e-4 cgeo mu_pos(0) fn_max``, so
    that the freewheel alone releases)::

        stuck         = locked or w_rel ≤ 0
        start_forward = pre(stuck) and (sa > tau0_max or pre(start_forward) and sa > tau0 or w_rel > w_small)
                        or initial() and w_rel > 0
        locked        = pre(stuck) and not start_forward
        a_rel = 0 if locked, else sa − tau0;   tau = sa if locked, else cgeo fn mu_pos(w_rel)

    ``stuck`` and ``start_forward`` are :func:`flexlib.latch` values (state events); stuck, the relative speed is
    held exactly. Start with ``w_rel ≥ 0``.

    Parameters
    ----------
    mu_pos : array_like
        Positive sliding friction coefficient [1] against relative speed [rad/s], rows ``[w, mu]`` (MSL default
        ``[[0, 0.5]]``).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.OneWayClutch`` (without the heat
    port); validated against the reference result of ``Rotational.Examples.OneWayClutch``.
    """

    table_name, table_doc = "mu_pos", "Positive sliding friction coefficient [1] against speed [rad/s], rows [w, mu]"
    peak = Parameter(1.0, unit="1", min=1.0, doc="Breakaway torque over the sliding torque at w_rel = 0 (≥ 1)")
    cgeo = Parameter(1.0, unit="m", min=0.0, doc="Geometry constant: friction torque = cgeo * mu * fn")
    fn_max = Parameter(unit="N", min=0.0, doc="Maximum normal force")
    w_small = Parameter(1e10, unit="rad/s", gt=0.0,
                        doc="Relative speed above which a stuck clutch starts sliding forward (MSL w_small)")
    f_normalized = Input(unit="1", doc="Normalised normal force 0..1 (normal force = fn_max * f_normalized)")
    a_rel = Variable(unit="rad/s2", doc="Relative angular acceleration, der(w_rel)")
    fn = Variable(unit="N", doc="Normal force")
    mu0 = Variable(unit="1", doc="Friction coefficient at w_rel = 0")
    tau0 = Variable(unit="N.m", doc="Sliding friction torque at w_rel = 0")
    tau0_max = Variable(unit="N.m", doc="Breakaway friction torque")
    sa = Variable(unit="1", doc="Path parameter of the friction characteristic (torque [N.m] stuck, else a_rel + tau0)")
    start_forward = Variable(unit="1", doc="1 while starting to slide forward from stuck (MSL startForward)")
    locked = Variable(unit="1", doc="1 while stuck and not starting (relative speed held at zero)")
    stuck = Variable(unit="1", doc="1 while w_rel = 0 (locked or starting forward)")

    def __init__(self, mu_pos: Any = ((0.0, 0.5),), **kw: Any) -> None:
        super().__init__(**kw)
        self.table(mu_pos)

    def equations(self) -> list:
        w = self.w_rel
        is_free = if_else(self.f_normalized <= 0, 1.0, 0.0)
        stuck, start = latch(name="stuck"), latch(name="start forward")
        define_latch(stuck, w <= 0, ca.logic_or(ca.logic_not(start), w <= 0))
        first = ca.logic_and(initial(), w > 0)
        define_latch(start, ca.logic_or(ca.logic_and(stuck, ca.logic_or(self.sa > self.tau0_max, w > self.w_small)),
                                        first),
                     ca.logic_or(ca.logic_and(stuck, ca.logic_or(self.sa > self.tau0, w > self.w_small)), first))
        locked = ca.logic_and(stuck, ca.logic_not(start))
        peak2 = ca.fmax(self.peak, 1 + ONE_WAY_EPS)
        return [*super().equations(), eq(self.a_rel, der(w)),
                eq(self.mu0, characteristic(self.mu_pos, 0.0)),
                eq(self.fn, (1 - is_free) * self.fn_max * self.f_normalized),
                eq(self.tau0, self.mu0 * self.cgeo * self.fn),
                eq(self.tau0_max, is_free * ONE_WAY_EPS * self.mu0 * self.cgeo * self.fn_max
                   + (1 - is_free) * peak2 * self.tau0),
                eq(self.a_rel, ca.if_else(locked, 0.0, self.sa - self.tau0)),
                eq(self.tau, ca.if_else(locked, self.sa, self.cgeo * self.fn * characteristic(self.mu_pos, w))),
                eq(self.stuck, ca.if_else(stuck, 1.0, 0.0)), eq(self.start_forward, ca.if_else(start, 1.0, 0.0)),
                eq(self.locked, ca.if_else(locked, 1.0, 0.0))]
