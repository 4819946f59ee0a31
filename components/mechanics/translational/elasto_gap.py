"""Spring and damper in parallel that act only in contact (a gap that can lift off)."""

from __future__ import annotations

import casadi as ca

from flexlib import Parameter, Variable, eq, if_else

from .interfaces import PartialCompliantWithRelativeStates

__all__ = ["ElastoGap"]


class ElastoGap(PartialCompliantWithRelativeStates):
    """Spring ``c`` and damper ``d`` in parallel acting only in contact, ``s_rel < s_rel0``; they lift off above.

    In contact (a state event at ``s_rel = s_rel0``)::

        f_c = −c |s_rel − s_rel0|^n,   f_d = clip(d v_rel, f_c, −f_c),   f = f_c + f_d

    and ``f = 0`` out of contact: the damping force is bounded by the spring force, so the contact only pushes and
    its force is continuous when contact begins (``n = 1.5`` Hertzian contact of spheres, ``n = 1`` of plates).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.ElastoGap`` (without the heat
    port); validated against the Modelica Association's reference result of ``Translational.Examples.ElastoGap``.
    H. M. Lankarani, P. E. Nikravesh, "Continuous contact force models for impact analysis in multibody systems",
    *Nonlinear Dynamics* 5 (1994) 193–207.
    """

    c = Parameter(unit="N/m", min=0.0, doc="Spring constant")
    d = Parameter(unit="N.s/m", min=0.0, doc="Damping constant")
    s_rel0 = Parameter(0.0, unit="m", doc="Unstretched spring length (contact below it)")
    n = Parameter(1.0, unit="1", min=1.0, doc="Exponent of the spring force, f_c = -c |s_rel - s_rel0|^n")
    f_c = Variable(unit="N", doc="Spring force")
    f_d = Variable(unit="N", doc="Damping force, bounded by the spring force (|f_d| <= |f_c|)")

    def equations(self) -> list:
        contact = self.s_rel < self.s_rel0
        f_c = -self.c * ca.fabs(self.s_rel - self.s_rel0) ** self.n
        return [*super().equations(),
                eq(self.f_c, if_else(contact, f_c, 0.0)),
                eq(self.f_d, if_else(contact, ca.fmin(ca.fmax(self.d * self.v_rel, self.f_c), -self.f_c), 0.0)),
                eq(self.f, self.f_c + self.f_d)]
