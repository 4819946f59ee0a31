"""Connectors and partial models of the 3D multibody library.

The :class:`Frame` follows MSL ``MultiBody.Interfaces.Frame``: the origin position ``r_0``
resolved in the world frame, the orientation ``(T, w)`` (over-determined: 12 entries for 3
degrees of freedom, equated along a spanning tree of the connection graph, loop closures by
:func:`~.frames.equality_constraint`), and the cut force ``f`` and cut torque ``t`` resolved in
the frame, positive when acting on the component.

The partial models hold what a family of components shares, as MSL's ``Interfaces``, ``Sensors.Internal`` and
``Forces.Internal``: two frames related by a branch, the cut, absolute and relative sensors (frames, zero loads,
``resolve_in_frame``; a sensor adds only the equation of its own vector; as in MSL with the default
``resolveInFrame``, no ``frame_resolve`` connector, see :mod:`._resolve`), the world loads and the one-axis joints.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Component, Connector, Flow, Potential, eq
from flexlib.core.options import flag
from flexlib.errors import ParameterError

from ._resolve import check_resolve_in_frame
from .frames import equality_constraint, resolve1, skew

__all__ = ["Frame", "PartialAbsoluteSensor", "PartialAxisJoint", "PartialCutSensor", "PartialRelativeSensor",
           "PartialTwoFrames", "PartialWorldLoad", "add_axis_flange", "check_axis", "support_grounded"]


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


class PartialAbsoluteSensor(Component):
    """Base of the absolute sensors (MSL ``Sensors.Internal.PartialAbsoluteSensor``): one measured frame, on which
    the sensor exerts no load.

    ``f_a = t_a = 0``; no orientation branch. A subclass adds the equation of its measured output
    (:meth:`measurement_equations`).

    Parameters
    ----------
    resolve_in_frame : {"world", "frame_a"}
        Frame in which the output is resolved (structural constructor argument).
    """

    frame_a = Frame(doc="Measured frame")

    def __init__(self, resolve_in_frame: str = "world", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("world", "frame_a"))

    def measurement_equations(self) -> list:
        """Equations of the measured output."""
        raise NotImplementedError

    def equations(self) -> list:
        a = self.frame_a
        return [eq(a.f, 0.0), eq(a.t, 0.0), *self.measurement_equations()]


class PartialRelativeSensor(Component):
    """Base of the relative sensors (MSL ``Sensors.Internal.PartialRelativeSensor``): a quantity of frame_b
    measured relative to frame_a, with no load on either frame.

    ``f_a = f_b = 0``, ``t_a = t_b = 0``. No orientation branch: the frames are independent. A subclass adds
    the equation of its measured output (:meth:`measurement_equations`), from the relative position
    ``r_rel_0 = r_0,b − r_0,a``, resolved with :meth:`resolved`.

    Parameters
    ----------
    resolve_in_frame : {"frame_a", "frame_b", "world"}
        Frame in which the output is resolved (structural constructor argument).
    """

    frame_a = Frame(doc="Reference frame")
    frame_b = Frame(doc="Measured frame")

    def __init__(self, resolve_in_frame: str = "frame_a", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("frame_a", "frame_b", "world"))

    def resolved(self, in_a: Any, in_b: Any, in_world: Any) -> Any:
        """The one of the vector's three resolutions (in frame_a, in frame_b, in world) that is asked for."""
        return {"frame_a": in_a, "frame_b": in_b, "world": in_world}[self.resolve_in_frame]

    def measurement_equations(self, r_rel_0: Any) -> list:
        """Equations of the measured output, given ``r_rel_0 = r_0,b − r_0,a`` (resolved in world)."""
        raise NotImplementedError

    def equations(self) -> list:
        a, b = self.frame_a, self.frame_b
        return [eq(a.f, 0.0), eq(a.t, 0.0), eq(b.f, 0.0), eq(b.t, 0.0), *self.measurement_equations(b.r_0 - a.r_0)]


class PartialWorldLoad(Component):
    """Base of the external loads given by a signal (MSL ``Forces.Internal.BasicWorldForce`` /
    ``BasicWorldTorque``): a vector acting on what is attached at frame_b.

    The reaction goes to nobody, and there is no orientation branch: frame_b's orientation comes from what
    it is connected to. :meth:`in_frame_b` resolves the input vector in frame_b.

    Parameters
    ----------
    resolve_in_frame : {"world", "frame_b"}
        Frame in which the input is resolved (structural constructor argument): ``"world"`` (default), given
        in world coordinates; ``"frame_b"``, given in frame_b and turning with it.
    """

    frame_b = Frame(doc="Frame the load acts on, at its origin")

    def __init__(self, resolve_in_frame: str = "world", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.resolve_in_frame = check_resolve_in_frame(self, resolve_in_frame, ("world", "frame_b"))

    def in_frame_b(self, vector: Any) -> Any:
        """The input ``vector`` resolved in frame_b: ``T_b·vector`` if given in world, else itself."""
        return ca.mtimes(self.frame_b.T, vector) if self.resolve_in_frame == "world" else vector


class PartialAxisJoint(PartialTwoFrames):
    """Base of the joints along or about one axis ``n`` (a parameter of the subclass, resolved in frame_a), which
    must not have zero length; :meth:`unit_axis` is ``n / |n|``."""

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        check_axis(self, values, "n")

    def unit_axis(self) -> Any:
        """The unit vector ``n / |n|`` of the joint axis, resolved in frame_a [1]."""
        return self.n / ca.norm_2(self.n)


def add_axis_flange(joint: Any, use_axis_flange: bool, flange: type, axis_doc: str, support_doc: str) -> None:
    """The structural option ``use_axis_flange`` of ``joint``; when on, its 1D drive flange ``axis`` and the
    drive's housing ``support``, both of class ``flange`` (of the translational or rotational library)."""
    joint.use_axis_flange = flag(joint, "use_axis_flange", use_axis_flange, structural=True)
    if joint.use_axis_flange:
        joint.axis = flange(doc=axis_doc)
        joint.support = flange(doc=support_doc)


def check_axis(component: Any, values: dict[str, Any], name: str, what: str = "joint axis") -> None:
    """Raise :class:`~flexlib.ParameterError` if the axis ``values[name]`` of ``component`` has zero length."""
    n = values.get(name)
    if n is not None and not np.linalg.norm(n) > 1e-12:
        raise ParameterError(f"{component.where}: {what} {name} = {n.tolist()} has zero length")


def support_grounded(support: Connector, prescribing: tuple[type, ...]) -> bool:
    """True if a joint's drive ``support`` flange is grounded inside the joint, as in MSL's joints (their support is
    connected to an internal ``Fixed``: "the support flange is fixed to ground"): a spring, damper, torque or force
    source, gear or sensor between ``support`` and ``axis`` then acts between the housing and the axis, the
    reaction going into ``frame_a`` with the rest of the joint's load.

    Not grounded when the support's connection set holds the ``flange`` of a component that prescribes its position
    itself (``prescribing``: a ``Fixed``, a position or speed source): that component then determines the support,
    and the joint applies its reaction to it (``Fixed`` on the support, written in models before MSL's semantics).
    """
    return not any(isinstance(c._parent, prescribing) and c is getattr(c._parent, "flange", None)
                   for c in support.connection_set())
