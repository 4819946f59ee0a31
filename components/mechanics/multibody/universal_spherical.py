"""Universal and spherical joint connected by a massless rod (MSL ``MultiBody.Joints.UniversalSpherical``)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Component, Parameter, Variable, der, eq
from flexlib.core.options import flag
from flexlib.errors import ParameterError

from .body_shape import build_part, unit_vector, vector3
from .fixed_translation import FixedTranslation
from .frames import resolve1
from .interfaces import Frame, PartialTwoFrames
from .spherical import Spherical
from .universal import Universal

__all__ = ["UniversalSpherical"]


class _Rod(PartialTwoFrames):
    """The joint's rod when its length is found at the start: frame_b is frame_a shifted by ``length · e`` (``e`` a
    unit vector resolved in frame_a), same orientation, massless. The length is constant as a state with a rate and
    an acceleration (``der(length) = length_v``, ``der(length_v) = length_a = 0``, ``length_v = 0`` at the start), so
    that the frame kinematics differentiate it as they differentiate a prismatic joint's ``s``."""

    e = Parameter([1.0, 0.0, 0.0], unit="1", shape=3, doc="Unit vector along the rod, resolved in frame_a")
    length = Variable(unit="m", state_select="always", doc="Rod length (a state: integrated exactly, it stays put)")
    length_v = Variable(unit="m/s", start=0.0, fixed=True, state_select="always", doc="Rate of the rod length (0)")
    length_a = Variable(unit="m/s2", doc="Second derivative of the rod length (0)")

    def equations(self):
        a, b = self.frame_a, self.frame_b
        r = self.length * self.e
        orient = [eq(b.T, a.T), eq(b.w, a.w)] if self.rooted(a) else [eq(a.T, b.T), eq(a.w, b.w)]
        return [eq(b.r_0, a.r_0 + resolve1(a.T, r)), *orient,
                eq(der(self.length), self.length_v), eq(der(self.length_v), self.length_a), eq(self.length_a, 0.0),
                eq(a.f + b.f, 0.0), eq(a.t + b.t + ca.cross(r, b.f), 0.0)]


class UniversalSpherical(Component):
    """A universal joint at frame_a and a spherical joint at frame_b, connected by a rigid massless rod.

    The rod's frame ``frame_ia`` (the universal's moving frame, at the origin of frame_a) holds the rod vector
    ``rRod_ia``: ``r_0,b = r_0,a + T_iaᵀ · rodLength · e_rod`` with ``e_rod = rRod_ia / |rRod_ia|``. The universal
    turns about ``n1_a`` (fixed in frame_a), then about ``e2 = n1_a × e_rod`` (normalised, fixed in frame_ia), so the
    rod reaches every direction but ``n1_a`` itself (the singular configuration) and ``frame_ia = frame_a`` where the
    rod points along ``e_rod`` resolved in frame_a. No torque acts at frame_b; frame_b's orientation is not set by
    the joint (as MSL's, the joint cuts a kinematic loop: it adds three position constraints, one of them the rod
    length). ``rodLength = |rRod_ia|``, or with ``compute_rod_length=True`` the distance of the frames found at the
    start (MSL's ``computeRodLength``: ``rRod_ia`` then gives the direction only). The rod force along the rod is
    ``f_rod`` (positive in compression: MSL's "positive, if rod is pressed").

    A composite of :class:`Universal`, the rod and :class:`Spherical`; the universal's angles ``universal.phi_a``,
    ``universal.phi_b`` are found by the loop (give no start values: the joint has no states of its own, as MSL's).

    Parameters
    ----------
    n1_a : array_like (3,)
        First universal axis, resolved in frame_a [1] (MSL default ``(0, 0, 1)``).
    rRod_ia : array_like (3,)
        Vector from frame_a to frame_b resolved in frame_ia [m] (MSL default ``(1, 0, 0)``); with
        ``compute_rod_length`` its direction only. Must not be parallel to ``n1_a``.
    compute_rod_length : bool
        True: the rod length is found at the start from the frames' positions (structural).

    Connectors
    ----------
    frame_a, frame_b : Frame
        The universal's and the spherical joint's frames.
    frame_ia : Frame
        The rod's frame at the universal joint (attach the rod's mass or a shape there).

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.UniversalSpherical`` (without animation, ``kinematicConstraint``
    and ``checkTotalPower``); validated against the reference result of ``MultiBody.Examples.Loops.Fourbar2``.
    """

    frame_a = Frame(doc="Frame of the universal joint")
    frame_b = Frame(doc="Frame of the spherical joint")
    frame_ia = Frame(doc="The rod's frame at the universal joint (x along the rod where frame_ia = frame_a)")
    rodLength = Variable(unit="m", doc="Rod length (distance of frame_a and frame_b)")
    f_rod = Variable(unit="N", doc="Rod force along the rod, positive pushing frame_b away from frame_a")

    def __init__(self, *, n1_a: Any = (0.0, 0.0, 1.0), rRod_ia: Any = (1.0, 0.0, 0.0),
                 compute_rod_length: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        owner = type(self).__name__
        n1 = unit_vector(n1_a, "n1_a", owner)
        rod = vector3(rRod_ia, "rRod_ia", owner)
        length = float(np.linalg.norm(rod))
        if not length > 1e-12:
            raise ParameterError(f"{owner}: rRod_ia = {rod.tolist()} has zero length")
        e_rod = rod / length
        n2 = np.cross(n1, e_rod)
        if not np.linalg.norm(n2) > 1e-6:
            raise ParameterError(f"{owner}: n1_a = {n1.tolist()} is parallel to rRod_ia = {rod.tolist()}: the "
                                 "universal joint is in its singular configuration (choose another n1_a)")
        self.compute_rod_length = flag(self, "compute_rod_length", compute_rod_length, structural=True)
        self.universal = build_part(self, Universal, n_a=n1, n_b=n2 / np.linalg.norm(n2))
        if self.compute_rod_length:
            self.rod = build_part(self, _Rod, e=e_rod)
            self.rod.set_start("length", length, fixed=False)  # a start guess: the start finds the length
        else:
            self.rod = build_part(self, FixedTranslation, r=rod)
        self.spherical = Spherical()
        self.connect(self.frame_a, self.universal.frame_a)
        self.connect(self.universal.frame_b, self.rod.frame_a, self.frame_ia)
        self.connect(self.rod.frame_b, self.spherical.frame_a)
        self.connect(self.spherical.frame_b, self.frame_b)

    def equations(self):
        rod = self.rod
        e = rod.e if self.compute_rod_length else rod.r / ca.norm_2(rod.r)
        length = rod.length if self.compute_rod_length else ca.norm_2(rod.r)
        return [eq(self.rodLength, length), eq(self.f_rod, -ca.dot(e, rod.frame_b.f))]
