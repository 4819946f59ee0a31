"""Ideal gear without inertia, elasticity, backlash or losses."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, Variable, eq
from flexlib.errors import ParameterError

from .interfaces import PartialTwoFlangesAndSupport

__all__ = ["IdealGear"]


class IdealGear(PartialTwoFlangesAndSupport):
    """Ideal gear: ``phi_a = ratio * phi_b`` and ``0 = ratio * flange_a.tau + flange_b.tau``.

    Angles are relative to the support, so ``w_b = w_a / ratio`` for a fixed housing, and
    the power flowing in at ``flange_a`` flows out at ``flange_b``.

    Connectors
    ----------
    flange_a, flange_b : Flange
        Input and output shafts.
    support : Flange
        Housing (only if ``use_support``); takes ``-(flange_a.tau + flange_b.tau)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.IdealGear``.
    """

    ratio = Parameter(unit="1",
                      doc=("Transmission ratio ``flange_a.phi / flange_b.phi``, nonzero (a zero ratio holds flange_a "
                           "and leaves flange_b free: a singular model)"))
    phi_a = Variable(unit="rad", doc="Angle of flange_a relative to the support")
    phi_b = Variable(unit="rad", doc="Angle of flange_b relative to the support")

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        ratio = values.get("ratio")
        if ratio is not None and float(ratio) == 0.0:  # was a singular initialisation ("dependent equations")
            raise ParameterError(f"{self.param_label('ratio')} = 0: the transmission ratio flange_a.phi/flange_b.phi "
                                 "must be != 0 (0 holds flange_a still and leaves flange_b free)")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        return [*self.support_equations(),
                eq(self.phi_a, fa.phi - self.phi_support), eq(self.phi_b, fb.phi - self.phi_support),
                eq(self.phi_a, self.ratio * self.phi_b),
                eq(self.ratio * fa.tau + fb.tau, 0.0)]
