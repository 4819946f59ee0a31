"""Linear 1D rotational spring."""

from __future__ import annotations

from flexlib import Parameter, eq

from .interfaces import PartialCompliant

__all__ = ["Spring"]


class Spring(PartialCompliant):
    """Linear 1D rotational spring: ``tau = c * (phi_rel - phi_rel0)``.

    Variables
    ---------
    tau : N.m
        Spring torque.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.Spring``.
    """

    c = Parameter(unit="N.m/rad", min=0.0, doc="Spring constant")
    phi_rel0 = Parameter(0.0, unit="rad", doc="Unstretched spring angle")

    def equations(self) -> list:
        return [*super().equations(), eq(self.tau, self.c * (self.phi_rel - self.phi_rel0))]
