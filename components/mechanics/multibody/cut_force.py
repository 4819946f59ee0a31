"""Sensor of the cut force between two coinciding frames (MSL ``Sensors.CutForce``)."""

from __future__ import annotations

from flexlib import Output, eq

from .interfaces import PartialCutSensor

__all__ = ["CutForce"]


class CutForce(PartialCutSensor):
    """Measures the force exerted by the frame_a side on the frame_b side; the loads pass through.

    The frames coincide rigidly: ``r_0,b = r_0,a``, ``T_b = T_a``, ``w_b = w_a`` (an orientation
    branch, like FixedTranslation with ``r = 0``); ``f_a + f_b = 0``, ``t_a + t_b = 0``. Output
    ``force = f_a`` (``resolve_in_frame="frame_a"``, default) or ``T_aᵀ f_a`` (``"world"``): ``f_a`` is the
    cut force acting on the sensor at frame_a, i.e. what the frame_a side exerts on everything behind
    frame_b (a body hanging below the sensor: ``+m·g`` upwards).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.CutForce``.
    """

    force = Output(unit="N", shape=3, doc="Force exerted by the frame_a side on the frame_b side")

    def measurement_equations(self) -> list:
        return [eq(self.force, self.resolved(self.frame_a.f))]
