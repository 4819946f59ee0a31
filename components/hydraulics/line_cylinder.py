"""Double-acting hydraulic cylinder between two 3D frames (over the multibody LineForce)."""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import Component, Parameter, eq
from flexlib.components.mechanics.multibody.frames import resolve1, resolve2
from flexlib.components.mechanics.multibody.line_force_base import LineForceBase
from flexlib.errors import ParameterError

from .cylinder import DoubleActingCylinder
from .interfaces import Port

__all__ = ["LineCylinder", "LineTwoMasses"]


class LineCylinder(Component):
    """Double-acting cylinder acting along the straight line between the origins of two 3D frames.

    A :class:`~flexlib.components.mechanics.multibody.LineForce` carries a
    :class:`DoubleActingCylinder` between its 1D flanges: the cylinder housing is pinned at ``frame_a``
    and the rod end at ``frame_b``, so the piston position is ``x = |r_b − r_a| − L0`` with ``L0`` the
    closed length (pin-to-pin distance at x = 0). The cylinder force acts along the line on both frames
    (no torques: pin joints at both ends). The rod inertia ``m`` acts along the line with the acceleration
    of the length (``d²|r_b − r_a|/dt²``), exact when frame_a does not accelerate; it has no weight and
    no transverse inertia.

    Housing and rod weight (MSL ``LineForceWithTwoMasses``): ``m_housing`` at ``L_housing`` from frame_a
    and ``m_rod`` at ``L_rod`` from frame_b, point masses on the line that move with it (gravity, and
    inertia along and across the line), carried by the pins as :class:`LineTwoMasses` (the inner
    component ``masses``, built only if a mass is given > 0: without them the component and its
    compiled model are those of the massless cylinder). ``m_rod`` is the full rod (and piston) mass:
    give it there *instead of* ``m`` (set ``m = 0``), or ``m`` counts the rod's inertia along the line
    twice; ``m`` stays for a model that wants the rod's inertia along the line only, without weight.

    Parameters
    ----------
    x_fixed : bool
        True if the cylinder's start position is an initial condition (structural; default False:
        the position follows from the 3D model's initial conditions).
    s_small : float
        Regularisation length of the line [m] (see LineForce); passed as ``s_small=``.
    m_housing, m_rod : float
        Point masses of the housing and of the rod on the line [kg] (default 0: none; ≥ 0).
    L_housing, L_rod : float
        Distance of the housing's centre of mass from frame_a and of the rod's from frame_b, along the
        line [m] (default 0: at the pin; ≥ 0).
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
    Those of ``cylinder`` (x, v, p_A, p_B, F, ...), of ``line`` (length, f_a, f_b) and, with masses, of
    ``masses``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.LineForceWithMass`` (1D element
    between two frames) and ``LineForceWithTwoMasses`` (housing and rod masses); MathWorks Simscape Fluids,
    *Double-Acting Actuator (IL)* with Simscape Multibody (actuator between two frames).
    """

    def __init__(self, x_fixed: bool = False, s_small: float = 1e-6, m_housing: float = 0.0, L_housing: float = 0.0,
                 m_rod: float = 0.0, L_rod: float = 0.0, **cylinder: Any) -> None:
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
        masses = {"m_housing": m_housing, "L_housing": L_housing, "m_rod": m_rod, "L_rod": L_rod}
        for name, value in masses.items():
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not value >= 0.0:
                raise ParameterError(f"LineCylinder: {name} must be a number >= 0, got {value!r}")
        if m_housing > 0.0 or m_rod > 0.0:
            self.masses = LineTwoMasses(m_a=m_housing, L_a=L_housing, m_b=m_rod, L_b=L_rod, s_small=s_small)
            self.connect(self.frame_a, self.masses.frame_a)
            self.connect(self.frame_b, self.masses.frame_b)


class LineTwoMasses(LineForceBase):
    """Two point masses on the line between two frame origins, carried by the frames (pins, no torques).

    The massive part of MSL's ``LineForceWithTwoMasses``, without the 1D flanges (a :class:`LineCylinder`
    puts its ``LineForce`` in parallel): ``m_a`` at ``r_1 = r_a + L_a e`` (the housing, rigid with
    frame_a along the line) and ``m_b`` at ``r_2 = r_b − L_b e`` (the rod, rigid with frame_b), with
    ``e = (r_b − r_a)/ℓ``. Their accelerations less gravity follow from the frames' (``a``, ``v`` of the
    recursive kinematics, resolved in world) without derivatives::

        r = r_b − r_a,  ṙ = v_b − v_a,  r̈ = a_b − a_a,  ℓ̇ = e·ṙ,  ė = (ṙ − e ℓ̇)/ℓ,
        ℓ̈ = e·r̈ + ė·ṙ,  ë = (r̈ − e ℓ̈ − 2 ė ℓ̇)/ℓ,  α_1 = a_a + L_a ë,  α_2 = a_b − L_b ë

    Along the line each mass is carried by its own pin; across it the two pins share the load as a beam
    pinned at both ends (moment balance about each pin: the point masses have no rotary inertia). The
    forces of the frames on the line (world; ``x⊥ = x − (x·e) e``)::

        F_a = m_a (α_1·e) e + (1 − L_a/ℓ) m_a α_1⊥ + (L_b/ℓ) m_b α_2⊥
        F_b = m_b (α_2·e) e + (L_a/ℓ) m_a α_1⊥ + (1 − L_b/ℓ) m_b α_2⊥

    ``frame_a.f = T_a F_a``, ``frame_b.f = T_b F_b``, no torques; ``ℓ`` is bounded below by ``s_small``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.LineForceWithTwoMasses``.
    """

    m_a = Parameter(0.0, unit="kg", min=0.0, doc="Mass at frame_a's side (housing)")
    L_a = Parameter(0.0, unit="m", min=0.0, doc="Distance of m_a from frame_a along the line")
    m_b = Parameter(0.0, unit="kg", min=0.0, doc="Mass at frame_b's side (rod)")
    L_b = Parameter(0.0, unit="m", min=0.0, doc="Distance of m_b from frame_b along the line")

    def equations(self) -> list:
        a, b = self.frame_a, self.frame_b
        ell = ca.fmax(self.length, self.s_small)
        e = self.e_rel_0
        v_a, v_b = resolve1(a.T, a.v), resolve1(b.T, b.v)
        acc_a, acc_b = resolve1(a.T, a.a), resolve1(b.T, b.a)
        rd, rdd = v_b - v_a, acc_b - acc_a
        ld = ca.dot(e, rd)
        ed = (rd - e * ld) / ell
        ldd = ca.dot(e, rdd) + ca.dot(ed, rd)
        edd = (rdd - e * ldd - 2 * ed * ld) / ell
        f_1 = self.m_a * (acc_a + self.L_a * edd)
        f_2 = self.m_b * (acc_b - self.L_b * edd)
        n_1, n_2 = f_1 - e * ca.dot(f_1, e), f_2 - e * ca.dot(f_2, e)
        x_1, x_2 = self.L_a / ell, self.L_b / ell
        F_a = e * ca.dot(f_1, e) + (1 - x_1) * n_1 + x_2 * n_2
        F_b = e * ca.dot(f_2, e) + x_1 * n_1 + (1 - x_2) * n_2
        return [*super().equations(), eq(a.f, resolve2(a.T, F_a)), eq(b.f, resolve2(b.T, F_b))]

