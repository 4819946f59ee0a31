"""Trim: the input plus a constant offset that the initialisation finds."""

from __future__ import annotations

from flexlib import Variable, der, eq

from .interfaces import PartialSISO

__all__ = ["Trim"]


class Trim(PartialSISO):
    """Trim: ``y = u + b`` with a constant ``b`` that the initialisation solves for.

    ``b`` is a state with ``der(b) = 0`` and no initial condition of its own: another initial condition of the
    model fixes it — the holding torque of a drive whose joint starts at rest and not accelerating
    (``Revolute(init={"phi": ..., "w": 0, "a": 0})``), the throttle that keeps a vehicle at its start speed. This
    is the parameter of Modelica's ``parameter Real b(fixed = false)`` (computed by the initial equations) and the
    "trim" of flight dynamics: the steady input found at the start, on which the run's inputs ``u`` are added.
    ``Trim(guess={"b": ...})`` starts the initialisation's Newton iteration from a hand estimate of the trim.

    Connectors
    ----------
    u : Input [1]
        Input signal added to the trim.
    y : Output [1]
        ``u + b``.

    References
    ----------
    Modelica Language Specification 3.6, §8.6 (initialization; parameters with ``fixed = false`` are computed
    during initialization). B. L. Stevens, F. L. Lewis, E. N. Johnson, *Aircraft Control and Simulation*, 3rd ed.,
    Wiley 2016, §3.6 (steady-state flight, the trim problem).
    """

    b = Variable(unit="1", doc="Trim: the constant found at the start")

    def equations(self) -> list:
        return [eq(der(self.b), 0.0), eq(self.y, self.u + self.b)]
