"""Rigid translation and rotation between two frames (MSL ``MultiBody.Parts.FixedRotation``)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Parameter, eq
from flexlib.errors import ParameterError

from .frames import absolute_rotation, planar_rotation, resolve1, resolve2
from .interfaces import PartialTwoFrames

__all__ = ["FixedRotation"]


class FixedRotation(PartialTwoFrames):
    """Massless rigid part: frame_b is frame_a shifted by ``r`` and rotated by ``angle`` about ``n``.

    With the constant relative rotation ``T_rel = planarRotation(e, angle)`` (``e = n/|n|``, maps
    frame_a-resolved to frame_b-resolved coordinates):
    ``r_0,b = r_0,a + T_aᵀ r``; and, if the orientation tree reaches the part at frame_a,
    ``T_b = T_rel T_a``, ``w_b = T_rel w_a``, ``0 = f_a + T_relᵀ f_b``, ``0 = t_a + T_relᵀ t_b − r × f_a``;
    otherwise ``T_a = T_relᵀ T_b``, ``w_a = T_relᵀ w_b``, ``0 = f_b + T_rel f_a``,
    ``0 = t_b + T_rel t_a + (T_rel r) × f_b``. A vector fixed in frame_a with coordinates ``v`` has
    coordinates ``T_rel v`` in frame_b; e.g. with ``angle = π/2`` about z, frame_b's x axis is frame_a's
    y axis (a vector ``v`` resolved in frame_b is ``T_relᵀ v`` resolved in frame_a: x ↦ y).

    Variables
    ---------
    None besides the two frames.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.FixedRotation`` (``rotationType = RotationAxis``;
    the ``TwoAxesVectors`` and ``PlanarRotationSequence`` variants are not provided).
    """

    r = Parameter([0.0, 0.0, 0.0], unit="m", shape=3, doc="Vector from frame_a to frame_b resolved in frame_a")
    n = Parameter([1.0, 0.0, 0.0], unit="1", shape=3,
                  doc="Axis of the fixed rotation resolved in frame_a (= frame_b); normalised, must not be zero")
    angle = Parameter(0.0, unit="rad", doc="Angle of rotation of frame_b relative to frame_a about n")

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        n = values.get("n")
        if n is not None and not np.linalg.norm(n) > 1e-12:
            raise ParameterError(f"{self.where}: rotation axis n = {n.tolist()} has zero length")

    def equations(self):
        a, b = self.frame_a, self.frame_b
        e = self.n / ca.norm_2(self.n)
        T_rel = planar_rotation(e, self.angle)
        eqs = [eq(b.r_0, a.r_0 + resolve1(a.T, self.r))]
        if self.rooted(a):
            eqs += [eq(b.T, absolute_rotation(a.T, T_rel)), eq(b.w, resolve2(T_rel, a.w)),
                    eq(a.f + resolve1(T_rel, b.f), 0.0),
                    eq(a.t + resolve1(T_rel, b.t) - ca.cross(self.r, a.f), 0.0)]
        else:
            eqs += [eq(a.T, absolute_rotation(b.T, T_rel.T)), eq(a.w, resolve1(T_rel, b.w)),
                    eq(b.f + resolve2(T_rel, a.f), 0.0),
                    eq(b.t + resolve2(T_rel, a.t) + ca.cross(resolve2(T_rel, self.r), b.f), 0.0)]
        return eqs
