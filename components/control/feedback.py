"""Difference of a command and a feedback signal."""

from __future__ import annotations

from flexlib import eq

from .interfaces import PartialSI2SO

__all__ = ["Feedback"]


class Feedback(PartialSI2SO):
    """Feedback: ``y = u1 - u2`` (command minus feedback).

    Connectors
    ----------
    u1 : Input [1]
        Commanded signal.
    u2 : Input [1]
        Feedback signal.
    y : Output [1]
        Control error ``u1 - u2``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Math.Feedback``.
    """

    def equations(self) -> list:
        return [eq(self.y, self.u1 - self.u2)]
