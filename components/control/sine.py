"""Sine signal."""

from __future__ import annotations

import math

import casadi as ca

from flexlib import Parameter, eq, if_else, time

from .interfaces import PartialSignalSource

__all__ = ["Sine"]


class Sine(PartialSignalSource):
    """Sine signal: ``y = offset + amplitude * sin(2 pi f (time - start_time) + phase)``.

    Before ``start_time`` the output is ``offset``; the switch is a time event.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.Sine``.
    """

    amplitude = Parameter(1.0, unit="1", doc="Amplitude of the sine wave (default 1, as MSL's)")
    f = Parameter(unit="Hz", doc="Frequency of the sine wave")
    phase = Parameter(0.0, unit="rad", doc="Phase of the sine wave")

    def equations(self) -> list:
        wave = self.amplitude * ca.sin(2.0 * math.pi * self.f * (time - self.start_time) + self.phase)
        return [eq(self.y, self.offset + if_else(time < self.start_time, 0.0, wave))]
