"""Linear 1D translational damper."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialCompliantWithRelativeStates

__all__ = ["Damper"]


class Damper(PartialCompliantWithRelativeStates):
    """Linear 1D translational damper: ``f = d * v_rel``.

    Variables
    ---------
    f : N
        Damper force.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.Damper``.
    """

    d = Parameter(unit="N.s/m", min=0.0, doc="Damping constant")

    def equations(self) -> list:
        return [*super().equations(), eq(self.f, self.d * self.v_rel)]
