"""Limit the rate of change of a signal."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, Variable, der, eq
from flexlib.core.options import flag

from .interfaces import INIT_TYPES, PartialSISO, check_choice
from .limiter import limit

__all__ = ["RateLimiter"]


class RateLimiter(PartialSISO):
    """Slew-rate limiter: ``y`` follows ``u`` with a rate between ``falling`` and ``rising``.

    .. math::

        \\dot y = \\min\\bigl(\\text{rising}, \\max(\\text{falling}, (u - y)/T_d)\\bigr)

    ``(u - y)/Td`` is the derivative of the input approximated with the time constant ``Td``:
    a slow input passes with a lag ``Td``, a fast one is followed at the limiting rate. The
    switches between the three regimes are state events (unless ``strict``).

    Parameters
    ----------
    init_type : str
        ``"steady_state"`` (default, MSL): ``y = u`` at the start; ``"initial_state"`` or
        ``"initial_output"``: ``y = y_start``; ``"no_init"``: none.
    strict : bool
        True to switch the regimes continuously (no events).

    Connectors
    ----------
    y : Output [1]
        Rate-limited signal (the state).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Nonlinear.SlewRateLimiter``.
    """

    rising = Parameter(1.0, unit="1/s", gt=0.0, doc="Maximum rising slew rate")
    falling = Parameter(-1.0, unit="1/s", lt=0.0,
                        doc="Maximum falling slew rate (given explicitly: MSL's default ``-rising`` is not copied)")
    Td = Parameter(0.001, unit="s", gt=0.0, doc="Derivative time constant; smaller is nearer the ideal limiter")
    y_start = Parameter(0.0, unit="1", doc='Initial output for init_type ``"initial_state"`` or ``"initial_output"``')
    rate = Variable(unit="1/s", doc="Unlimited rate (u - y)/Td")

    def __init__(self, init_type: str = "steady_state", strict: bool = False, **kw: Any) -> None:
        super().__init__(**kw)
        self.init_type = check_choice(self, "init_type", init_type, INIT_TYPES)
        self.strict = flag(self, "strict", strict)

    def initial_equations(self) -> list:
        if self.init_type == "steady_state":
            return [eq(self.y, self.u, label="steady state y = u")]
        if self.init_type in ("initial_state", "initial_output"):
            return [eq(self.y, self.y_start, label="y = y_start")]
        return []

    def equations(self) -> list:
        return [eq(self.rate, (self.u - self.y) / self.Td),
                eq(der(self.y), limit(self.rate, self.rising, self.falling, self.strict))]
