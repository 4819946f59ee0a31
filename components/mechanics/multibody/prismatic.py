"""Prismatic joint (MSL ``MultiBody.Joints.Prismatic``)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Parameter, Variable, der, eq
from flexlib.components.mechanics.translational.fixed import Fixed
from flexlib.components.mechanics.translational.interfaces import Flange
from flexlib.components.mechanics.translational.position import Position
from flexlib.components.mechanics.translational.speed import Speed

from .frames import resolve1
from .interfaces import PartialAxisJoint, add_axis_flange, support_grounded

__all__ = ["Prismatic"]


class Prismatic(PartialAxisJoint):
    """Translation of frame_b relative to frame_a by ``s`` along the fixed axis ``n``; same orientation.

    ``r_0,b = r_0,a + T_aᵀ (e s)``; ``T_b = T_a``, ``w_b = w_a``; ``f_a + f_b = 0``;
    ``t_a + t_b + (e s) × f_b = 0``; the driving force along the axis is ``f = −e·f_b``: the flange force plus
    the constant ``f_drive`` (only ``f_drive`` without an axis flange).

    Parameters
    ----------
    use_axis_flange : bool
        True if the joint has a drive flange ``axis`` and its housing ``support`` (structural).

    Connectors
    ----------
    frame_a, frame_b : Frame
    axis, support : translational Flange (if ``use_axis_flange``)
        Drive flange (position ``s``, force ``f``) and its housing. As in MSL the support is grounded inside the
        joint (``support.s = 0``), so a spring, damper or force source between ``support`` and ``axis`` acts
        between housing and axis and a ``RelativePositionSensor`` there reads ``s``; only a support connected to
        the flange of a ``Fixed``, ``Position`` or ``Speed`` is placed by that component and takes ``-f``.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.Prismatic``.
    """

    #: ``state_select="always"`` (one value, MSL's ``stateSelect``) applies to these
    state_select_variables = ("s", "v")

    n = Parameter([1.0, 0.0, 0.0], unit="1", shape=3,
                  doc="Direction of translation resolved in frame_a; normalised, must not be zero")
    f_drive = Parameter(0.0, unit="N",
                        doc=("Constant drive force along the axis on frame_b; a load case, and the channel through "
                             "which :func:`flexlib.analysis.modal_analysis` holds the joint when it is locked"))
    s = Variable(unit="m", state_select="prefer", doc="Relative distance from frame_a to frame_b along n")
    v = Variable(unit="m/s", state_select="prefer", doc="Relative velocity")
    a = Variable(unit="m/s2", doc="Relative acceleration")
    f = Variable(unit="N", doc="Driving force in direction of the axis")

    def __init__(self, use_axis_flange: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        add_axis_flange(self, use_axis_flange, Flange, "Drive flange (s, f)", "Housing of the drive")

    def equations(self):
        a, b = self.frame_a, self.frame_b
        e = self.unit_axis()
        es = e * self.s
        eqs = [eq(b.r_0, a.r_0 + resolve1(a.T, es)), eq(der(self.s), self.v), eq(der(self.v), self.a),
               eq(a.f + b.f, 0.0), eq(a.t + b.t + ca.cross(es, b.f), 0.0), eq(self.f, -ca.dot(e, b.f))]
        eqs += [eq(b.T, a.T), eq(b.w, a.w)] if self.rooted(a) else [eq(a.T, b.T), eq(a.w, b.w)]
        if self.use_axis_flange:
            eqs += [eq(self.axis.s - self.support.s, self.s), eq(self.axis.f + self.f_drive, self.f)]
            if support_grounded(self.support, (Fixed, Position, Speed)):
                eqs.append(eq(self.support.s, 0.0, label="support grounded in the world (MSL)"))
            else:
                eqs.append(eq(self.support.f, -self.f))
        else:
            eqs.append(eq(self.f, self.f_drive, label="no drive flange: only f_drive acts along the axis"))
        return eqs
