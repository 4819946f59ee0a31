"""Switch between two real signals by a third (Boolean-valued) signal."""

from __future__ import annotations

from flexlib import Input, eq, if_else

from .interfaces import PartialSO

__all__ = ["Switch"]

#: ``u2`` above this value counts as true (signals carry Booleans as 1.0 / 0.0).
THRESHOLD = 0.5


class Switch(PartialSO):
    """Switch: ``y = u1`` if ``u2`` is true, else ``y = u3``.

    MSL's ``Logical.Switch`` has a Boolean ``u2``; flexlib signals are real, so ``u2`` is
    true when ``u2 > 0.5`` (a Boolean carried as 1.0 / 0.0, e.g. from a ``Step`` of height 1).
    The switching is an event: a time event if ``u2`` changes at a time event, otherwise a
    state event located where ``u2`` crosses 0.5.

    Connectors
    ----------
    y : Output [1]
        Selected signal.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Logical.Switch``.
    """

    u1 = Input(unit="1", doc="Output signal if u2 > 0.5")
    u2 = Input(unit="1", doc="Switching signal, true if > 0.5")
    u3 = Input(unit="1", doc="Output signal if u2 <= 0.5")

    def equations(self) -> list:
        return [eq(self.y, if_else(self.u2 > THRESHOLD, self.u1, self.u3))]
