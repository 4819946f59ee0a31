"""Partial models of the multibody sensors, world loads (MSL ``Sensors.Internal``, ``Forces.Internal``) and
one-axis joints.

Each sensor or load partial holds a component's frames, the loads it puts on them and its ``resolve_in_frame``
choice; a sensor or load derived from one adds only the equation of its own vector. As in MSL with the default
``resolveInFrame``, there is no ``frame_resolve`` connector (see :mod:`._resolve`).
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Component, eq
from flexlib.core.options import flag
from flexlib.errors import ParameterError

from ._resolve import check_resolve_in_frame
from .interfaces import Frame, PartialTwoFrames

__all__ = ["PartialAbsoluteSensor", "PartialAxisJoint", "PartialRelativeSensor", "PartialWorldLoad", "add_axis_flange",
           "check_axis"]


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
