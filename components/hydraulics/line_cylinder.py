"""Double-acting hydraulic cylinder between two 3D frames (over the multibody LineForce)."""

from __future__ import annotations

from typing import Any

from flexlib import Component

from .cylinder import DoubleActingCylinder
from .interfaces import Port

__all__ = ["LineCylinder"]


class LineCylinder(Component):
    """Double-acting cylinder acting along the straight line between the origins of two 3D frames.

    A :class:`~flexlib.components.mechanics.multibody.LineForce` carries a
    :class:`DoubleActingCylinder` between its 1D flanges: the cylinder housing is pinned at ``frame_a``
    and the rod end at ``frame_b``, so the piston position is ``x = |r_b − r_a| − L0`` with ``L0`` the
    closed length (pin-to-pin distance at x = 0). The cylinder force acts along the line on both frames
    (no torques: pin joints at both ends). The rod inertia ``m`` acts along the line with the acceleration
    of the length (``d²|r_b − r_a|/dt²``), exact when frame_a does not accelerate; its transverse
    inertia is not represented (put a Body on frame_b for that, or set ``m = 0``).

    Parameters
    ----------
    x_fixed : bool
        True if the cylinder's start position is an initial condition (structural; default False:
        the position follows from the 3D model's initial conditions).
    s_small : float
        Regularisation length of the line [m] (see LineForce); passed as ``s_small=``.
    **cylinder
        Parameters of :class:`DoubleActingCylinder` (``d_bore``, ``d_rod``, ``stroke``, ``L0``, ``m``,
        ...), and its structural options ``p_fixed``, ``use_drain``, ``fluid``. They live on the
        sub-component ``cylinder``: run-time overrides are ``params={"<name>.cylinder.d_bore": ...}``.
        ``init``, ``guess`` and ``state_select`` name the cylinder's variables (``init={"p_A": 2e6}``).

    Connectors
    ----------
    frame_a, frame_b : multibody Frame
        Pin points of the housing and of the rod end.
    port_A, port_B : Port
        Cap-side and rod-side chambers.
    port_D : Port
        Rod-seal drain (only with ``use_drain=True``).

    Variables
    ---------
    Those of ``cylinder`` (x, v, p_A, p_B, F, ...) and of ``line`` (length, f_a, f_b).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.LineForceWithMass`` (1D element
    between two frames); MathWorks Simscape Fluids, *Double-Acting Actuator (IL)* with Simscape Multibody
    (actuator between two frames).
    """

    def __init__(self, x_fixed: bool = False, s_small: float = 1e-6, **cylinder: Any) -> None:
        from flexlib.components.mechanics.multibody.interfaces import Frame
        from flexlib.components.mechanics.multibody.line_force import LineForce

        doc = cylinder.pop("doc", "")
        super().__init__(doc=doc)  # init/guess/state_select name the cylinder's variables: passed to it below
        self.frame_a = Frame(doc="Housing pin")
        self.frame_b = Frame(doc="Rod-end pin")
        self.port_A = Port(doc="Cap-side chamber")
        self.port_B = Port(doc="Rod-side chamber")
        self.line = LineForce(s_small=s_small)
        self.cylinder = DoubleActingCylinder(x_fixed=x_fixed, **cylinder)
        self.connect(self.frame_a, self.line.frame_a)
        self.connect(self.frame_b, self.line.frame_b)
        self.connect(self.line.flange_a, self.cylinder.flange_a)
        self.connect(self.line.flange_b, self.cylinder.flange_b)
        self.connect(self.port_A, self.cylinder.port_A)
        self.connect(self.port_B, self.cylinder.port_B)
        if self.cylinder.use_drain:
            self.port_D = Port(doc="Rod-seal drain")
            self.connect(self.port_D, self.cylinder.port_D)

