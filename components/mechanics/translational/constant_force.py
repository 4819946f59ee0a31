"""Constant force acting on a flange, independent of its speed."""

from __future__ import annotations

from flexlib import Parameter, Variable, eq

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["ConstantForce"]


class ConstantForce(PartialOneFlangeAndSupport):
    """Constant force source: ``f = f_constant`` drives the flange, ``flange.f = −f``, at any speed.

    A positive ``f_constant`` accelerates the flange in the positive direction; a negative one acts as a load in
    the positive direction of motion. The reaction acts on the support.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Sources.ConstantForce`` (its relative speed
    ``v`` is not a variable here: read the flange's, e.g. a mass's ``v``).
    """

    f_constant = Parameter(unit="N", doc="Constant force (negative: a load in the positive direction)")
    f = Variable(unit="N", doc="Accelerating force acting at the flange (= -flange.f)")

    def equations(self) -> list:
        return [*self.support_equations(), eq(self.f, self.f_constant), eq(self.flange.f, -self.f)]
