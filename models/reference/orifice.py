"""Two fixed-pressure chambers through a turbulent orifice at zero pressure difference: the catalogue's singular
start.

The flow law q = k·sign(dp)·sqrt(|dp|) has an infinite derivative at dp = 0, so the Jacobian at the start holds
0·inf = NaN; an unrelated algebraic variable z = 2·p_a (+ 1e3·q) starts inconsistent (guess 0), so Newton has to
iterate. The initialisation must name the orifice equation and the variable, not report large residuals elsewhere.
"""

from __future__ import annotations

import casadi as ca

import flexlib as fl
from flexlib import Parameter, Variable, der, eq

__all__ = ["SquareRootOrifice"]


class SquareRootOrifice(fl.Model):
    """Two fixed pressures through a turbulent orifice q = k·sign(dp)·sqrt(|dp|) at dp = 0, and an unrelated
    algebraic variable z = 2·p_a whose start guess (0) is not consistent, so Newton has to iterate."""

    k = Parameter(1e-6, unit="m3/(s.Pa0.5)")
    p_a = Variable(unit="Pa", nominal=1e7, start=1e7, fixed=True)
    p_b = Variable(unit="Pa", nominal=1e7, start=1e7, fixed=True)
    q = Variable(unit="m3/s", nominal=1e-3)
    z = Variable(unit="Pa", nominal=1e7)

    def equations(self):
        dp = self.p_a - self.p_b
        return [eq(der(self.p_a), -1e9 * self.q), eq(der(self.p_b), 1e9 * self.q),
                eq(self.q, self.k * ca.sign(dp) * ca.sqrt(ca.fabs(dp)), label="turbulent orifice"),
                eq(self.z, 2.0 * self.p_a + 1e3 * self.q, label="unrelated")]
