"""Universal (Cardan) joint (MSL ``MultiBody.Joints.Universal``): two revolutes in series."""

from __future__ import annotations

from typing import Any

import numpy as np

from flexlib import Component, Variable, eq
from flexlib.errors import ParameterError

from .body_shape import build_part, unit_vector
from .interfaces import Frame
from .revolute import Revolute

__all__ = ["Universal"]


class Universal(Component):
    """Two revolute joints in series: about ``n_a`` (fixed in frame_a), then about ``n_b`` (fixed in frame_b).

    A composite as in MSL: frame_a → ``revolute_a`` (axis ``n_a``, angle ``phi_a``) → ``revolute_b`` (axis
    ``n_b``, angle ``phi_b``) → frame_b, so ``T_b = T(n_b, φ_b) T(n_a, φ_a) T_a`` and both origins coincide;
    no torque is transmitted about either axis. The joint variables below are aliases of the revolutes'
    (``phi_a = revolute_a.phi``, ...) and are the preferred states; give initial conditions on them with
    ``init={"phi_a": ..., "w_a": ..., "phi_b": ..., "w_b": ...}``.

    The axes are constructor arguments; they become the run-time parameters ``<name>.revolute_a.n`` and
    ``<name>.revolute_b.n``.

    Parameters
    ----------
    n_a : array_like (3,), optional
        Axis of the first rotation, resolved in frame_a [1]; default ``(1, 0, 0)``; must not be zero.
    n_b : array_like (3,), optional
        Axis of the second rotation, resolved in frame_b [1]; default ``(0, 1, 0)``; must not be zero nor
        parallel to ``n_a`` (the joint would have the same rotational freedom twice).

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.Universal``.
    """

    #: ``state_select="always"`` (one value, MSL's ``stateSelect``) applies to these
    state_select_variables = ("phi_a", "phi_b", "w_a", "w_b")

    frame_a = Frame(doc="First frame (fixed to the first revolute's housing)")
    frame_b = Frame(doc="Second frame")
    phi_a = Variable(unit="rad", state_select="prefer", doc="Relative rotation angle about n_a")
    phi_b = Variable(unit="rad", state_select="prefer", doc="Relative rotation angle about n_b")
    w_a = Variable(unit="rad/s", state_select="prefer", doc="Relative angular velocity about n_a")
    w_b = Variable(unit="rad/s", state_select="prefer", doc="Relative angular velocity about n_b")
    a_a = Variable(unit="rad/s2", doc="Relative angular acceleration about n_a")
    a_b = Variable(unit="rad/s2", doc="Relative angular acceleration about n_b")

    def __init__(self, *, n_a: Any = (1.0, 0.0, 0.0), n_b: Any = (0.0, 1.0, 0.0), **kwargs: Any) -> None:
        super().__init__(**kwargs)
        owner = type(self).__name__
        e_a, e_b = unit_vector(n_a, "n_a", owner), unit_vector(n_b, "n_b", owner)
        if not np.linalg.norm(np.cross(e_a, e_b)) > 1e-6:
            raise ParameterError(f"{owner}: axes n_a = {e_a.tolist()} and n_b = {e_b.tolist()} (normalised) are "
                                 "parallel; a universal joint needs two different rotation axes")
        self.revolute_a = build_part(self, Revolute, n=n_a)
        self.revolute_b = build_part(self, Revolute, n=n_b)
        self.connect(self.frame_a, self.revolute_a.frame_a)
        self.connect(self.revolute_a.frame_b, self.revolute_b.frame_a)
        self.connect(self.revolute_b.frame_b, self.frame_b)

    def equations(self):
        ra, rb = self.revolute_a, self.revolute_b
        return [eq(self.phi_a, ra.phi), eq(self.phi_b, rb.phi), eq(self.w_a, ra.w), eq(self.w_b, rb.w),
                eq(self.a_a, ra.a), eq(self.a_b, rb.a)]
