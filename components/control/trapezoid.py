"""Trapezoidal signal."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from flexlib import Parameter, eq, if_else, time
from flexlib.core.options import remember_option
from flexlib.errors import ModelError

from .interfaces import PartialSignalSource

__all__ = ["Trapezoid", "period_count"]


def period_count(block: Any, nperiod: Any) -> int:
    """``nperiod`` as an int >= 0 (a whole float such as 2.0 is accepted); a string, a bool, NaN or a negative
    count is refused naming the block (not left to ``int()``, which fails on ``"1.0"`` and NaN and reads ``True``
    as 1)."""
    ok = (isinstance(nperiod, (int, np.integer, float, np.floating)) and not isinstance(nperiod, (bool, np.bool_))
          and math.isfinite(nperiod) and int(nperiod) == nperiod and nperiod >= 0)
    if not ok:
        raise ModelError(f"{type(block).__name__}: nperiod must be an integer >= 0, got {nperiod!r} (infinitely many "
                         "periods, MSL's nperiod < 0, cannot be time events; give the number of periods)")
    remember_option(block, "nperiod", lambda v: period_count(block, v))
    return int(nperiod)


class Trapezoid(PartialSignalSource):
    """Trapezoidal signal: ``nperiod`` periods of rise, plateau, fall and zero, then ``offset``.

    In period ``k`` (starting at ``Ts = start_time + k period``) the output is ``offset`` plus
    ``amplitude (time - Ts)/rising`` until ``Ts + rising``, ``amplitude`` until
    ``Ts + rising + width``, a linear fall to 0 during ``falling``, then 0 until the next
    period. Before ``start_time`` and after ``nperiod`` periods it is ``offset``. Every corner
    is a time event, so the integrator never steps across a kink.

    Parameters
    ----------
    nperiod : int
        Number of periods, >= 0 (structural: 4 time events per period).

    Notes
    -----
    MSL's ``nperiod < 0`` (infinitely many periods) is not supported: the engine's time
    events are relations affine in time, one per corner, so their number is fixed when the
    model is built. Give enough periods for the run (``nperiod >= t_end / period``).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.Trapezoid``.
    """

    amplitude = Parameter(1.0, unit="1", doc="Amplitude of trapezoid")
    rising = Parameter(0.0, unit="s", min=0.0, doc="Rising duration of trapezoid")
    width = Parameter(0.5, unit="s", min=0.0, doc="Width (plateau) duration of the trapezoid")
    falling = Parameter(0.0, unit="s", min=0.0, doc="Falling duration of trapezoid")
    period = Parameter(unit="s", gt=0.0, doc="Time for one period; a phase that does not fit is cut at the period end")

    def __init__(self, nperiod: int, **kw: Any) -> None:
        count = period_count(self, nperiod)
        super().__init__(**kw)
        self.nperiod = count

    def equations(self) -> list:
        A, P = self.amplitude, self.period
        T_r = self.rising
        T_w = T_r + self.width
        T_f = T_w + self.falling
        shape: Any = 0.0  # after the last period
        for k in reversed(range(self.nperiod)):
            Ts = self.start_time + k * P
            fall = if_else(time < Ts + T_f, A * (Ts + T_f - time) / self.falling, 0.0)
            inside = if_else(time < Ts + T_r, A * (time - Ts) / self.rising, if_else(time < Ts + T_w, A, fall))
            shape = if_else(time < Ts + P, inside, shape)
        return [eq(self.y, self.offset + if_else(time < self.start_time, 0.0, shape))]
