"""External torque acting on a frame, given by a signal (MSL ``Forces.WorldTorque``)."""

from __future__ import annotations

from flexlib import Input, eq

from .interfaces import PartialWorldLoad

__all__ = ["WorldTorque"]


class WorldTorque(PartialWorldLoad):
    """The input vector ``torque`` acts on what is attached at frame_b; no force.

    ``resolve_in_frame="world"`` (default): ``t_b = −T_b·torque``; ``"frame_b"``: ``t_b = −torque``;
    ``f_b = 0``. The attached body receives ``+torque``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.WorldTorque``.
    """

    torque = Input(unit="N.m", shape=3, doc="Torque vector resolved in resolve_in_frame")

    def equations(self) -> list:
        return [eq(self.frame_b.t, -self.in_frame_b(self.torque)), eq(self.frame_b.f, 0.0)]
