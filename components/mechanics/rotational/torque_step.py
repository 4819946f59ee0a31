"""Torque step acting on a flange."""

from __future__ import annotations

from flexlib import Parameter, Variable, eq, if_else, time

from .interfaces import PartialOneFlangeAndSupport

__all__ = ["TorqueStep"]


class TorqueStep(PartialOneFlangeAndSupport):
    """Torque ``tau = offset_torque`` before ``start_time``, ``offset_torque + step_torque`` from then on (a time
    event), driving the flange: ``flange.tau = −tau``; the reaction acts on the support.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Sources.TorqueStep``.
    """

    step_torque = Parameter(unit="N.m", doc="Height of the torque step (negative: a load)")
    offset_torque = Parameter(0.0, unit="N.m", doc="Torque before the step")
    start_time = Parameter(0.0, unit="s", doc="Time of the step")
    tau = Variable(unit="N.m", doc="Accelerating torque acting at the flange (= -flange.tau)")

    def equations(self) -> list:
        return [*self.support_equations(), eq(self.flange.tau, -self.tau),
                eq(self.tau, self.offset_torque + if_else(time < self.start_time, 0.0, self.step_torque))]
