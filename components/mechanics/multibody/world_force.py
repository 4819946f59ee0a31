"""External force acting at a frame, given by a signal (MSL ``Forces.WorldForce``)."""

from __future__ import annotations

from flexlib import Input, eq

from .interfaces import PartialWorldLoad

__all__ = ["WorldForce"]


class WorldForce(PartialWorldLoad):
    """The input vector ``force`` acts on what is attached at frame_b, at its origin; no torque.

    ``resolve_in_frame="world"`` (default): ``f_b = −T_b·force``; ``"frame_b"``: ``f_b = −force``;
    ``t_b = 0``. (The minus sign: ``f_b`` is the cut force acting on this component, so the attached
    body receives ``+force``.)

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.WorldForce``.
    """

    force = Input(unit="N", shape=3, doc="Force vector resolved in resolve_in_frame")

    def equations(self) -> list:
        return [eq(self.frame_b.f, -self.in_frame_b(self.force)), eq(self.frame_b.t, 0.0)]
