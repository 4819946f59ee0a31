"""Connectors and partial models of the 3D multibody library.

The :class:`Frame` follows MSL ``MultiBody.Interfaces.Frame``: the origin position ``r_0``
resolved in the world frame, the orientation ``(T, w)`` (over-determined: 12 entries for 3
degrees of freedom, equated along a spanning tree of the connection graph, loop closures by
:func:`~.frames.equality_constraint`), and the cut force ``f`` and cut torque ``t`` resolved in
the frame, positive when acting on the component.
"""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Component, Connector, Flow, Potential

from .frames import equality_constraint, skew

__all__ = ["Frame", "PartialTwoFrames"]


class Frame(Connector):
    """Coordinate system fixed to a component (MSL ``Interfaces.Frame``).

    Variables
    ---------
    r_0 : [m]
        Position of the frame origin, resolved in the world frame.
    T : [1]
        Transformation matrix world → frame (``v_frame = T @ v_world``); over-determined. Its derivative
        is known, ``der(T) = −[w×] T``, so index reduction never makes it an unknown (MSL's derivative
        annotation of ``Frames.Orientation``).
    w : [rad/s]
        Angular velocity of the frame, resolved in the frame; over-determined.
    f : [N]
        Cut force acting on the component, resolved in the frame (flow).
    t : [N.m]
        Cut torque acting on the component, resolved in the frame (flow).
    """

    r_0 = Potential(unit="m", shape=3, doc="Position of the frame origin resolved in world")
    T = Potential(unit="1", shape=(3, 3), overdetermined=True, doc="Transformation matrix world to frame",
                  derivative=lambda frame: -ca.mtimes(skew(frame.w), frame.T))
    w = Potential(unit="rad/s", shape=3, overdetermined=True, doc="Angular velocity resolved in frame")
    f = Flow(unit="N", shape=3, doc="Cut force resolved in frame")
    t = Flow(unit="N.m", shape=3, doc="Cut torque resolved in frame")

    def equality_constraint(self, other: Any) -> Any:
        """Three residues closing a kinematic loop between two frames that should coincide in orientation."""
        return equality_constraint(self.T, other.T)


class PartialTwoFrames(Component):
    """Base of components with two frames whose orientations are related by this component's equations.

    Declares ``branch(frame_a, frame_b)``: the subclass computes one frame's orientation from the other,
    in the direction given by ``rooted(frame_a)``.

    Connectors
    ----------
    frame_a, frame_b : Frame

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Interfaces.PartialTwoFrames``.
    """

    frame_a = Frame(doc="First frame")
    frame_b = Frame(doc="Second frame")

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.branch(self.frame_a, self.frame_b)
