"""Massless line force between two frames driven by 1D translational elements (MSL ``LineForceWithMass``, m = 0)."""

from __future__ import annotations

from flexlib import Component, Connector, Variable, eq
from flexlib.components.mechanics.translational.interfaces import Flange

from .line_force_base import LineForceBase

__all__ = ["LineForce"]


class LineForce(LineForceBase):
    """Force along the line frame_a → frame_b produced by 1D translational elements between two flanges.

    The 1D elements connected between ``flange_a`` and ``flange_b`` (a spring, a damper, a hydraulic
    cylinder, a force source with its support on flange_a) see the distance between the frame origins as
    their relative position: ``flange_a.s = 0``, ``flange_b.s = length``. Their forces act along the unit
    vector ``e_rel_0`` from frame_a to frame_b, no torques:

    ``f_a = flange_a.f``, ``f_b = −flange_b.f`` (tensions: positive pulls the frames together);
    frame_a receives ``+e_rel_0·f_a``, frame_b ``−e_rel_0·f_b`` (``f_a,cut = −T_a e_rel_0 f_a``,
    ``f_b,cut = T_b e_rel_0 f_b``, ``t_a = t_b = 0``).

    For a massless 1D element ``f_a = f_b`` (action = reaction along the line); a 1D element with
    inertia (a translational mass between the flanges) makes them differ by its inertia force along the
    line, as in MSL (transverse inertia of such an element is not represented: put a Body on a frame
    for that). Unconnected flanges follow MSL's ``cardinality`` rule: if only one flange is connected,
    the other side carries the same tension (a 1D force source connected to flange_b alone, with its
    support grounded, acts between both frames, not against the world); with none connected the
    element is inert.

    Only relative positions of the 1D elements are meaningful: flange_a is at ``s = 0`` by definition,
    so do not fix a 1D element at another absolute position. The length is regularised below
    ``s_small`` (see :class:`~.line_force_base.LineForceBase`): no event, no division by zero when the
    frames coincide.

    Connectors
    ----------
    flange_a, flange_b : translational Flange
        1D ends of the line: ``flange_a.s = 0``, ``flange_b.s = length``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.LineForceWithMass`` (m = 0, no
    ``fixedRotationAtFrame_a/b``); ``Modelica.Mechanics.MultiBody.Forces.Spring`` shows the use with a
    1D spring.
    """

    f_a = Variable(unit="N", doc="Tension at frame_a (positive pulls frame_a towards frame_b)")
    f_b = Variable(unit="N", doc="Tension at frame_b (positive pulls frame_b towards frame_a)")
    flange_a = Flange(doc="1D end at frame_a (s = 0)")
    flange_b = Flange(doc="1D end at frame_b (s = length)")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        eqs = [*super().equations(), *self.line_force_equations(self.f_a, self.f_b),
               eq(fa.s, 0.0, label="flange_a at the origin of the line"),
               eq(fb.s, self.length, label="flange_b at the length of the line")]
        a_connected, b_connected = _is_connected(fa), _is_connected(fb)
        if a_connected and not b_connected:
            eqs += [eq(self.f_a, fa.f), eq(self.f_b, self.f_a, label="flange_b unconnected: same tension")]
        elif b_connected and not a_connected:
            eqs += [eq(self.f_b, -fb.f), eq(self.f_a, self.f_b, label="flange_a unconnected: same tension")]
        else:  # both connected, or neither (then both flows are 0: inert)
            eqs += [eq(self.f_a, fa.f), eq(self.f_b, -fb.f)]
        return eqs


def _is_connected(conn: Connector) -> bool:
    """True if ``conn`` appears in a ``connect`` of the model (Modelica ``cardinality(conn) > 0``)."""
    for node in conn.root.walk():
        if isinstance(node, Component):
            for pair in node._connections:
                if any(item[0] == "connector" and item[1] is conn for item in pair):
                    return True
    return False
