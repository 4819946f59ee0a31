"""Sensor of the distance between two frame origins (MSL ``Sensors.Distance``)."""

from __future__ import annotations

from flexlib import Component, Output, Parameter, eq

from .interfaces import Frame
from .line_force_base import smooth_length

__all__ = ["Distance"]


class Distance(Component):
    """Distance ``|r_0,b − r_0,a|`` between the origins of frame_a and frame_b; the sensor exerts no load.

    Below ``s_small`` the distance is the smooth approximation of
    :func:`~.line_force_base.smooth_length` (exact above it), so its derivatives stay finite when the
    origins coincide. ``f = t = 0`` at both frames; no orientation branch.

    Connectors
    ----------
    frame_a, frame_b : Frame
        Measured frames.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.Distance``.
    """

    s_small = Parameter(1e-10, unit="m", min=1e-12, doc="Regularisation length for coinciding frames")
    distance = Output(unit="m", doc="Distance between the origins of frame_a and frame_b")
    frame_a = Frame(doc="First frame")
    frame_b = Frame(doc="Second frame")

    def equations(self) -> list:
        a, b = self.frame_a, self.frame_b
        return [eq(a.f, 0.0), eq(a.t, 0.0), eq(b.f, 0.0), eq(b.t, 0.0),
                eq(self.distance, smooth_length(b.r_0 - a.r_0, self.s_small))]
