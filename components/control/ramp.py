"""Ramp signal."""

from __future__ import annotations

from flexlib import Parameter, eq, if_else, time

from .interfaces import PartialSignalSource

__all__ = ["Ramp"]


class Ramp(PartialSignalSource):
    """Ramp signal: rises linearly by ``height`` from ``start_time`` to ``start_time + duration``.

    .. math::

        y = \\text{offset} + \\begin{cases} 0 & t < t_0 \\\\ h (t - t_0)/T & t_0 \\le t < t_0 + T
            \\\\ h & t \\ge t_0 + T \\end{cases}

    Both corners are time events, so the integrator never steps across a kink.

    Parameters
    ----------
    start_time : float
        Start time of the ramp [s].

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.Ramp``.
    """

    height = Parameter(1.0, unit="1", doc="Height of the ramp")
    duration = Parameter(unit="s", min=0.0, doc="Duration of the ramp (0 degenerates to a step)")

    def equations(self) -> list:
        t0, T, h = self.start_time, self.duration, self.height
        rising = if_else(time < t0 + T, h * (time - t0) / T, h)
        return [eq(self.y, self.offset + if_else(time < t0, 0.0, rising))]
