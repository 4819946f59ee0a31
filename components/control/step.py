"""Step signal."""

from __future__ import annotations

from flexlib import Parameter, eq, if_else, time

from .interfaces import PartialSignalSource

__all__ = ["Step"]


class Step(PartialSignalSource):
    """Step signal: ``y = offset`` before ``start_time``, ``offset + height`` from then on.

    The switch is a time event: the integrator stops exactly at ``start_time``.

    Parameters
    ----------
    start_time : float
        Time of the step [s].

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.Step``.
    """

    height = Parameter(1.0, unit="1", doc="Height of the step")

    def equations(self) -> list:
        return [eq(self.y, self.offset + if_else(time >= self.start_time, self.height, 0.0))]
