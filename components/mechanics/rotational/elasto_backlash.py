"""Backlash in series with a linear spring and damper, the contact modelled with elasticity (continuous torque or,
``ElastoBacklash2``, a torque that jumps at contact)."""

from __future__ import annotations

import casadi as ca

from flexlib import Parameter, Variable, eq, if_else, no_event

from .interfaces import PartialCompliantWithRelativeStates

__all__ = ["ElastoBacklash", "ElastoBacklash2"]

#: Backlash below which the element is a plain spring and damper (MSL's ``bEps``: no endless events for ``b = 0``)
B_EPS = 1e-10


class _Backlash(PartialCompliantWithRelativeStates):
    """The parameters and the spring law shared by the two backlash elements."""

    c = Parameter(unit="N.m/rad", gt=0.0, doc="Spring constant (c > 0)")
    d = Parameter(0.0, unit="N.m.s/rad", min=0.0, doc="Damping constant")
    b = Parameter(0.0, unit="rad", min=0.0, doc="Total backlash")
    phi_rel0 = Parameter(0.0, unit="rad", doc="Unstretched spring angle")
    tau_c = Variable(unit="N.m", doc="Spring torque")
    tau_d = Variable(unit="N.m", doc="Damping torque")

    def law(self) -> tuple[ca.SX, ca.SX, ca.SX, list]:
        """``φ`` (from the unstretched angle), the half backlash, whether it is a plain spring (``b`` below
        :data:`B_EPS`: parameters only, decided at the start), and the rows of ``tau_c`` and ``tau_d``."""
        phi, b_max, c = self.phi_rel - self.phi_rel0, self.b / 2, self.c
        plain = self.b <= B_EPS
        return phi, b_max, plain, [
            eq(self.tau_c, if_else(plain, c * phi, if_else(phi > b_max, c * (phi - b_max),
                                                           if_else(phi < -b_max, c * (phi + b_max), 0.0)))),
            eq(self.tau_d, self.d * self.w_rel)]


class ElastoBacklash(_Backlash):
    """Backlash ``b`` in series with a spring ``c`` and damper ``d`` in parallel; contact by elasticity.

    With ``φ = phi_rel − phi_rel0`` and the gap ``|φ| ≤ b/2``, no torque acts in the gap; in contact
    (``φ > b/2``, likewise ``φ < −b/2`` with the signs mirrored)::

        tau_c = c (φ − b/2),   tau_d = d w_rel,
        tau   = 0                        if tau_c + tau_d ≤ 0   (no pulling: the flanges separate)
              = tau_c + min(tau_c, tau_d) otherwise              (|damping| ≤ |spring|: no jump at first contact)

    Entering and leaving contact are state events; the no-pulling and damping limits are continuous (MSL's
    ``smooth(0, noEvent(...))``). A backlash below ``1e-10`` rad makes it a spring and damper,
    ``tau = c φ + d w_rel``.

    Notes
    -----
    MSL replaces the characteristic during initialisation by a monotone one (``c/3·φ`` within ``±1.5·b/2``) so that
    an inverse initialisation can solve for ``φ``; here the run's characteristic is used throughout (a start with
    ``phi_rel`` free inside the gap has no unique solution: fix the flanges' angles).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.ElastoBacklash`` (without the heat
    port); validated against the Modelica Association's reference result of ``Rotational.Examples.Backlash``.
    """

    def equations(self) -> list:
        phi, b_max, plain, rows = self.law()
        pushing = no_event(self.tau_c + self.tau_d <= 0, 0.0, self.tau_c + ca.fmin(self.tau_c, self.tau_d))
        pulling = no_event(self.tau_c + self.tau_d >= 0, 0.0, self.tau_c + ca.fmax(self.tau_c, self.tau_d))
        return [*super().equations(), *rows,
                eq(self.tau, if_else(plain, self.tau_c + self.tau_d,
                                     if_else(phi > b_max, pushing, if_else(phi < -b_max, pulling, 0.0))))]


class ElastoBacklash2(_Backlash):
    """Backlash ``b`` in series with a spring ``c`` and damper ``d``, the torque jumping at contact (MSL's
    ``ElastoBacklash2``).

    As :class:`ElastoBacklash` without limiting the damping by the spring: in contact (``φ > b/2``, mirrored below
    ``−b/2``) ``tau = tau_c + tau_d`` with ``tau_d = d w_rel``, set to 0 where it would pull (``tau_c + tau_d ≤ 0``);
    0 in the gap. At first contact the torque jumps from 0 to ``d w_rel``; entering and leaving contact and the
    no-pulling switch are all state events. A backlash below ``1e-10`` rad makes it a spring and damper.

    Notes
    -----
    As for :class:`ElastoBacklash`, MSL's monotone characteristic during initialisation is not used.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.ElastoBacklash2`` (without the heat
    port).
    """

    def equations(self) -> list:
        phi, b_max, plain, rows = self.law()
        total = self.tau_c + self.tau_d
        return [*super().equations(), *rows,
                eq(self.tau, if_else(plain, total,
                                     if_else(phi > b_max, if_else(total <= 0, 0.0, total),
                                             if_else(phi < -b_max, if_else(total >= 0, 0.0, total), 0.0))))]
