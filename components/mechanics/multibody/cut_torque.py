"""Sensor of the cut torque between two coinciding frames (MSL ``Sensors.CutTorque``)."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialCutSensor

__all__ = ["CutTorque"]


class CutTorque(PartialCutSensor):
    """Measures the torque exerted by the frame_a side on the frame_b side; the loads pass through.

    The frames coincide rigidly: ``r_0,b = r_0,a``, ``T_b = T_a``, ``w_b = w_a`` (an orientation
    branch); ``f_a + f_b = 0``, ``t_a + t_b = 0``. Output ``torque = t_a`` (``resolve_in_frame="frame_a"``,
    default) or ``T_aᵀ t_a`` (``"world"``): the cut torque about the common origin that the frame_a side
    exerts on everything behind frame_b.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.CutTorque``.
    """

    torque = Output(unit="N.m", shape=3, doc="Torque exerted by the frame_a side on the frame_b side")

    def measurement_equations(self) -> list:
        return [eq(self.torque, self.resolved(self.frame_a.t))]
