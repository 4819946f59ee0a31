"""Linear 1D rotational damper."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialCompliantWithRelativeStates

__all__ = ["Damper"]


class Damper(PartialCompliantWithRelativeStates):
    """Linear 1D rotational damper: ``tau = d * w_rel``.

    Variables
    ---------
    tau : N.m
        Damper torque.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.Damper``.
    """

    d = Parameter(unit="N.m.s/rad", min=0.0, doc="Damping constant")

    def equations(self) -> list:
        return [*super().equations(), eq(self.tau, self.d * self.w_rel)]
