"""Transform a signal into a switched one with hysteresis (a relay with memory)."""

from __future__ import annotations

from flexlib import Parameter, ParameterError, eq, latch

from .interfaces import PartialSISO, scalar

__all__ = ["Hysteresis"]


class Hysteresis(PartialSISO):
    """Relay with hysteresis: ``y`` becomes 1 when ``u`` rises above ``u_high`` and stays 1 until ``u`` falls below
    ``u_low``; then 0 until ``u`` rises above ``u_high`` again (Modelica:
    ``y = not pre(y) and u > uHigh or pre(y) and u >= uLow``). Both switchings are state events; the value between
    them is held by :func:`flexlib.latch`. At the start ``pre(y)`` is 0, as MSL's default ``pre_y_start = false``.

    Connectors
    ----------
    y : Output [1]
        1.0 (on) or 0.0 (off): MSL's Boolean output as a real signal (MSL ``BooleanToReal``).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Logical.Hysteresis`` (``pre_y_start = true`` is not provided).
    """

    u_low = Parameter(unit="1", doc="If y = 1 and u < u_low, switch to y = 0")
    u_high = Parameter(unit="1", doc="If y = 0 and u > u_high, switch to y = 1 (u_high > u_low)")

    def check(self, values: dict) -> None:
        lo, hi = scalar(values, "u_low"), scalar(values, "u_high")
        if lo is not None and hi is not None and not hi > lo:
            raise ParameterError(f"{self.where}: u_high = {hi:g} must be > u_low = {lo:g} (hysteresis)")

    def equations(self) -> list:
        return [eq(self.y, latch(self.u > self.u_high, self.u >= self.u_low))]
