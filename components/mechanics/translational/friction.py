"""Coulomb friction with exact sticking: friction in a support and a brake (MSL ``PartialFriction``)."""

from __future__ import annotations

from typing import Any

from flexlib import Input, Parameter, Variable, der, eq

from ..friction import FrictionModes, TableFriction, characteristic, mode_rows
from .interfaces import PartialTwoFlangesAndSupport

__all__ = ["Brake", "SupportFriction"]


class _Friction(TableFriction, PartialTwoFlangesAndSupport):
    """Rigidly connected flanges sliding on the support (housing) with friction; the mode logic of
    :mod:`components.mechanics.friction`."""

    peak = Parameter(1.0, unit="1", min=1.0, doc="Breakaway force over the sliding force at v = 0 (≥ 1)")
    v_small = Parameter(1e10, unit="m/s", gt=0.0,
                        doc="Speed below which a reversal passes through stuck (MSL v_small; large: always)")
    sa = Variable(unit="1", doc="Path parameter of the friction characteristic (force [N] stuck, else a + f0_max)")
    f0 = Variable(unit="N", doc="Sliding friction force at v = 0")
    f0_max = Variable(unit="N", doc="Breakaway friction force (peak * f0)")
    mode = Variable(unit="1", doc="Mode: 2 free, 1 forward sliding, 0 stuck, -1 backward sliding (MSL mode)")
    start_forward = Variable(unit="1", doc="1 while starting to slide forward from stuck (MSL startForward)")
    start_backward = Variable(unit="1", doc="1 while starting to slide backward from stuck (MSL startBackward)")
    locked = Variable(unit="1", doc="1 while stuck (speed held at zero)")
    s = Variable(unit="m", doc="Position of the flanges relative to the support")
    v = Variable(unit="m/s", doc="Velocity relative to the support")
    a = Variable(unit="m/s2", doc="Acceleration relative to the support")
    f = Variable(unit="N", doc="Friction force")

    def friction_rows(self, free: Any, scale: Any) -> list:
        """The kinematics, the force balance and the friction force, ``scale`` times the table's characteristic."""
        fa, fb = self.flange_a, self.flange_b
        m: FrictionModes
        m, rows = mode_rows(self, self.v, self.a, self.f0, self.f0_max, free, self.v_small)
        return [*self.support_equations(), *rows, eq(self.f0_max, self.peak * self.f0),
                eq(self.s, fa.s - self.s_support), eq(fb.s, fa.s),
                eq(self.v, der(self.s)), eq(self.a, der(self.v)),
                eq(fa.f + fb.f - self.f, 0.0), eq(self.f, self.sliding(m, self.sa, self.v, scale))]


class SupportFriction(_Friction):
    """Coulomb friction between the rigidly connected flanges and the support, with a stuck phase.

    With ``s = flange_a.s − s_support``, ``v = der(s)``, ``a = der(v)``::

        flange_a.f + flange_b.f = f
        f = sa              stuck (a = 0)
          =  f_pos(v)       sliding forward (a = sa − f0_max)
          = −f_pos(−v)      sliding backward (a = sa + f0_max)

    with ``f0 = f_pos(0)`` and the breakaway force ``f0_max = peak * f0``; the modes switch by state events
    (:mod:`components.mechanics.friction`); stuck, the speed is held exactly.

    Parameters
    ----------
    f_pos : array_like
        Positive sliding friction force [N] against speed [m/s], rows ``[v, f]`` with ``v ≥ 0`` increasing, linear in
        between and extrapolated (MSL default ``[[0, 1]]``).
    use_support : bool
        True: the support is the ``support`` flange; False: it is grounded.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.SupportFriction`` (without the heat
    port); the mode logic of ``Translational.Interfaces.PartialFriction``.
    """

    table_name, table_doc = "f_pos", "Positive sliding friction force [N] against speed [m/s], rows [v, f]"

    def __init__(self, f_pos: Any = ((0.0, 1.0),), use_support: bool = False, **kw: Any) -> None:
        super().__init__(use_support=use_support, **kw)
        self.table(f_pos)

    def equations(self) -> list:
        return [*self.friction_rows(False, 1.0), eq(self.f0, characteristic(self.f_pos, 0.0))]


class Brake(_Friction):
    """Brake by Coulomb friction between the rigidly connected flanges and the support, engaged by a normal force.

    ``fn = fn_max * f_normalized``; free (no force) while ``fn ≤ 0``. Engaged, with ``f0 = cgeo mu_pos(0) fn`` and the
    breakaway force ``f0_max = peak f0``::

        f = sa                        stuck (a = 0)
          =  cgeo fn mu_pos(v)        sliding forward
          = −cgeo fn mu_pos(−v)       sliding backward

    Parameters
    ----------
    mu_pos : array_like
        Positive sliding friction coefficient [1] against speed [m/s], rows ``[v, mu]`` (MSL default ``[[0, 0.5]]``).
    use_support : bool
        True: the support is the ``support`` flange; False: it is grounded.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Translational.Components.Brake`` (without the heat port).
    """

    table_name, table_doc = "mu_pos", "Positive sliding friction coefficient [1] against speed [m/s], rows [v, mu]"
    cgeo = Parameter(1.0, unit="1", min=0.0, doc="Geometry constant: friction force = cgeo * mu * fn")
    fn_max = Parameter(unit="N", min=0.0, doc="Maximum normal force")
    f_normalized = Input(unit="1", doc="Normalised normal force 0..1 (normal force = fn_max * f_normalized)")
    fn = Variable(unit="N", doc="Normal force")
    mu0 = Variable(unit="1", doc="Friction coefficient at v = 0 when sliding forward")

    def __init__(self, mu_pos: Any = ((0.0, 0.5),), use_support: bool = False, **kw: Any) -> None:
        super().__init__(use_support=use_support, **kw)
        self.table(mu_pos)

    def equations(self) -> list:
        return [*self.friction_rows(self.fn <= 0, self.cgeo * self.fn),
                eq(self.mu0, characteristic(self.mu_pos, 0.0)), eq(self.fn, self.fn_max * self.f_normalized),
                eq(self.f0, self.mu0 * self.cgeo * self.fn)]
