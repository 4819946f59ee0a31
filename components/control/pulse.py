"""Pulse signal."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, eq, if_else, time

from .interfaces import PartialSignalSource
from .trapezoid import period_count

__all__ = ["Pulse"]


class Pulse(PartialSignalSource):
    """Rectangular pulses: ``offset + amplitude`` for the first ``width`` percent of each of ``nperiod`` periods
    from ``start_time``, ``offset`` otherwise (before ``start_time`` and after the last period too).

    Every edge is a time event, hit exactly by the integrator.

    Parameters
    ----------
    nperiod : int
        Number of periods, >= 0 (structural: two time events per period).

    Notes
    -----
    MSL's default ``nperiod = -1`` (infinitely many periods) is not supported, as for :class:`Trapezoid`: give
    enough periods for the run (``nperiod >= (t_end − start_time) / period``).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.Pulse``.
    """

    amplitude = Parameter(1.0, unit="1", doc="Amplitude of the pulse")
    width = Parameter(50.0, unit="1", gt=0.0, max=100.0, doc="Width of the pulse in percent of the period [%]")
    period = Parameter(unit="s", gt=0.0, doc="Time for one period")

    def __init__(self, nperiod: int, **kw: Any) -> None:
        count = period_count(self, nperiod)
        super().__init__(**kw)
        self.nperiod = count

    def equations(self) -> list:
        on = self.width / 100.0 * self.period
        level: Any = 0.0
        for k in reversed(range(self.nperiod)):
            start = self.start_time + k * self.period
            level = if_else(time < start + self.period, if_else(time < start + on, self.amplitude, 0.0), level)
        return [eq(self.y, self.offset + if_else(time < self.start_time, 0.0, level))]
