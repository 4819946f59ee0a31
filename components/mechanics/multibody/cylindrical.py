"""Cylindrical joint (MSL ``MultiBody.Joints.Cylindrical``): prismatic and revolute about one axis."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Variable, eq

from .body_shape import build_part, unit_vector
from .interfaces import Frame
from .prismatic import Prismatic
from .revolute import Revolute

__all__ = ["Cylindrical"]


class Cylindrical(Component):
    """Translation along and rotation about the same axis ``n`` (2 degrees of freedom).

    A composite as in MSL: frame_a → ``prismatic`` (axis ``n``, distance ``s``) → ``revolute`` (axis ``n``,
    angle ``phi``) → frame_b: ``r_0,b = r_0,a + T_aᵀ (e s)``, ``T_b = T(n, φ) T_a``; no force along and no
    torque about the axis is transmitted. The joint variables below are aliases of the parts' (``s =
    prismatic.s``, ``phi = revolute.phi``, ...) and are the preferred states; give initial conditions with
    ``init={"s": ..., "v": ..., "phi": ..., "w": ...}``.

    The axis is a constructor argument; it becomes the run-time parameters ``<name>.prismatic.n`` and
    ``<name>.revolute.n`` (change both together).

    Parameters
    ----------
    n : array_like (3,), optional
        Axis of translation and rotation, resolved in frame_a (= frame_b) [1]; default ``(1, 0, 0)``; must
        not be zero.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.Cylindrical``.
    """

    #: ``state_select="always"`` (one value, MSL's ``stateSelect``) applies to these
    state_select_variables = ("s", "v", "phi", "w")

    frame_a = Frame(doc="First frame")
    frame_b = Frame(doc="Second frame")
    s = Variable(unit="m", state_select="prefer", doc="Relative distance along n")
    v = Variable(unit="m/s", state_select="prefer", doc="Relative velocity along n")
    a = Variable(unit="m/s2", doc="Relative acceleration along n")
    phi = Variable(unit="rad", state_select="prefer", doc="Relative rotation angle about n")
    w = Variable(unit="rad/s", state_select="prefer", doc="Relative angular velocity about n")
    wd = Variable(unit="rad/s2", doc="Relative angular acceleration about n")

    def __init__(self, *, n: Any = (1.0, 0.0, 0.0), **kwargs: Any) -> None:
        super().__init__(**kwargs)
        unit_vector(n, "n", type(self).__name__)
        self.prismatic = build_part(self, Prismatic, n=n)
        self.revolute = build_part(self, Revolute, n=n)
        self.connect(self.frame_a, self.prismatic.frame_a)
        self.connect(self.prismatic.frame_b, self.revolute.frame_a)
        self.connect(self.revolute.frame_b, self.frame_b)

    def equations(self):
        p, r = self.prismatic, self.revolute
        return [eq(self.s, p.s), eq(self.v, p.v), eq(self.a, p.a), eq(self.phi, r.phi), eq(self.w, r.w),
                eq(self.wd, r.a)]
