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

from flexlib import Component, Connector, Flow, Potential, eq

from ._resolve import check_resolve_in_frame
from .frames import equality_constraint, resolve1, skew

__all__ = ["Frame", "PartialCutSensor", "PartialTwoFrames", "support_grounded"]


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

    The multibody compile pass gives every frame three more quantities it carries along the spanning tree (recursive
    kinematics, as in Featherstone's articulated-body and recursive Newton–Euler algorithms): the velocity ``v``, the
    acceleration less gravity ``a = T (d²r_0/dt² − g)`` (what an accelerometer fixed to the frame reads) and the
    angular acceleration ``z``, resolved in the frame. It relates them between the two frames of each branch from the
    component's own rows (``flexlib/compile/passes/multibody/kinematics.py``) and keeps ``a`` and ``z`` out of IDA's
    local error test (``docs/engine.md``, "Error-test policy"); a body reads them (``frame.a``) instead of the second
    time derivative of its position, which depends on every joint coordinate between it and the root.
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

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Interfaces.PartialTwoFrames``.
    """

    frame_a = Frame(doc="First frame")
    frame_b = Frame(doc="Second frame")

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.branch(self.frame_a, self.frame_b)


class PartialCutSensor(PartialTwoFrames):
    """Base of the cut sensors: two rigidly coinciding frames through which all loads pass.

    ``r_0,b = r_0,a``, ``T_b = T_a``, ``w_b = w_a`` (an orientation branch in the direction given by
    ``rooted(frame_a)``), ``f_a + f_b = 0``, ``t_a + t_b = 0``. A subclass adds the equation of its
    measured output (:meth:`measurement_equations`), the cut load at frame_a with MSL's ``positiveSign = true``.

    Parameters
    ----------
    resolve_in_frame : {"frame_a", "world"}
        Frame in which the output is resolved (structural constructor argument).

    Connectors
    ----------
    frame_a, frame_b : Frame
        The two sides of the cut.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Sensors.Internal.BasicCutForce`` / ``BasicCutTorque``.
    """

    def __init__(self, resolve_in_frame: str = "frame_a", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("frame_a", "world"))

    def resolved(self, v_a: Any) -> Any:
        """A vector resolved in frame_a, resolved in ``resolve_in_frame``."""
        return v_a if self.resolve_in_frame == "frame_a" else resolve1(self.frame_a.T, v_a)

    def measurement_equations(self) -> list:
        """Equations of the measured output."""
        raise NotImplementedError

    def equations(self) -> list:
        a, b = self.frame_a, self.frame_b
        src, dst = (a, b) if self.rooted(a) else (b, a)
        orient = [eq(dst.T, src.T), eq(dst.w, src.w)]
        return [eq(b.r_0, a.r_0), *orient, eq(a.f + b.f, 0.0), eq(a.t + b.t, 0.0),
                *self.measurement_equations()]



def support_grounded(support: Connector, sensors: tuple[type, ...]) -> bool:
    """True if a joint's drive ``support`` flange is grounded inside the joint (MSL's joints: "the support
    is assumed to be fixed in the world frame"; a 1D component's ``useSupport = false``).

    That is the case unless the support is connected to a component other than a pure measuring sensor
    (``sensors``: the 1D sensors that exert no force and fix no position): a housing, a ``Fixed`` or a
    torque source then determine the support themselves, as before. So a relative angle sensor between
    ``support`` and ``axis`` reads the joint angle.
    """
    return all(isinstance(c._parent, sensors) for c in support.connection_set())
