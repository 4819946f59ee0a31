"""Sensor of the relative velocity of two frame origins (MSL ``Sensors.RelativeVelocity``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Output, der, eq

from .frames import resolve1, resolve2
from .interfaces import PartialRelativeSensor

__all__ = ["RelativeVelocity"]


class RelativeVelocity(PartialRelativeSensor):
    """Velocity of the origin of frame_b relative to frame_a, as seen from frame_a; exerts no load.

    As in MSL the relative position is differentiated in frame_a, ``v_rel_a = der(T_a (r_0,b − r_0,a))``
    (written ``T_a der(r_rel_0) − w_a × (T_a r_rel_0)`` with ``der(T_a) = −[w_a×] T_a``), so a point fixed
    in frame_a's body has ``v_rel = 0`` however frame_a moves; this is *not* ``der(r_0,b − r_0,a)`` unless
    frame_a does not rotate. The vector is then resolved: ``v_rel = v_rel_a`` (``resolve_in_frame="frame_a"``,
    default), ``T_b T_aᵀ v_rel_a`` (``"frame_b"``) or ``T_aᵀ v_rel_a`` (``"world"``). ``f = t = 0`` at both
    frames.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Sensors.RelativeVelocity``.
    """

    v_rel = Output(unit="m/s", shape=3, doc="Velocity of frame_b's origin relative to frame_a, seen in frame_a")

    def measurement_equations(self, r_rel_0: Any) -> list:
        a, b = self.frame_a, self.frame_b
        v_rel_a = resolve2(a.T, der(r_rel_0)) - ca.cross(a.w, resolve2(a.T, r_rel_0))
        v_rel_0 = resolve1(a.T, v_rel_a)
        return [eq(self.v_rel, self.resolved(v_rel_a, resolve2(b.T, v_rel_0), v_rel_0))]
