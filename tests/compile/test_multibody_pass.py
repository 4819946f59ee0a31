"""The multibody compile pass (``flexlib/compile/passes/multibody``): a joint written as MSL writes it.

``MSLRevolute`` relates its frames with MSL's rows only (``r_0``, ``T``, ``w``, ``f``, ``t``; Modelica Standard
Library 4.0, ``MultiBody.Joints.Revolute`` without drive and friction): the pass introduces the frames'
velocities and accelerations along the spanning tree. The crank-rocker four-bar built with it (both branch
directions: the loop's cut joint is rooted at frame_b) compiles to the four-bar built with the library's
Revolute, whose equations write the recursion by hand: the same unknowns, states and Jacobian nonzeros, the same
residual at random points (to round-off, 1e-14 relative), and the same run (step counts, joint angles, speeds and
cut forces).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
import flexlib.models.planar_mechanisms as pm
from flexlib import Parameter, Variable, der, eq
from flexlib.compile.flatten import flatten
from flexlib.components.mechanics.multibody import Body, World
from flexlib.components.mechanics.multibody.frames import absolute_rotation, planar_rotation, resolve1
from flexlib.components.mechanics.multibody.interfaces import PartialTwoFrames


class MSLRevolute(PartialTwoFrames):
    """Revolute joint with MSL's rows: origins equal, ``T_b = T_rel(n, φ) T_a``, ``w_b = T_rel w_a + n·w``, cut
    loads transformed back; the torque about the axis is the constant ``tau_drive`` (the library joint's rows
    without drive flange and friction, ``tau_f = 0``)."""

    n = Parameter([0.0, 0.0, 1.0], unit="1", shape=3, doc="Axis of rotation resolved in frame_a")
    tau_drive = Parameter(0.0, unit="N.m", doc="Constant drive torque about the axis, acting on frame_b")
    phi = Variable(unit="rad", state_select="prefer", doc="Relative rotation angle")
    w = Variable(unit="rad/s", state_select="prefer", doc="Relative angular velocity")
    a = Variable(unit="rad/s2", doc="Relative angular acceleration")
    tau = Variable(unit="N.m", doc="Net torque about the axis on the frame_b side")
    tau_f = Variable(unit="N.m", doc="Friction torque (none)")

    def equations(self) -> list:
        fa, fb = self.frame_a, self.frame_b
        e = self.n / ca.norm_2(self.n)
        eqs = [eq(fb.r_0, fa.r_0), eq(der(self.phi), self.w), eq(der(self.w), self.a)]
        if self.rooted(fa):
            R = planar_rotation(e, self.phi)
            eqs += [eq(fb.T, absolute_rotation(fa.T, R)), eq(fb.w, ca.mtimes(R, fa.w) + e * self.w),
                    eq(fa.f, -resolve1(R, fb.f)), eq(fa.t, -resolve1(R, fb.t))]
        else:
            R = planar_rotation(-e, self.phi)
            eqs += [eq(fa.T, absolute_rotation(fb.T, R)), eq(fa.w, ca.mtimes(R, fb.w) - e * self.w),
                    eq(fb.f, -resolve1(R, fa.f)), eq(fb.t, -resolve1(R, fa.t))]
        return [*eqs, eq(self.tau, -ca.dot(e, fb.t)), eq(self.tau_f, 0.0), eq(self.tau, self.tau_drive - self.tau_f)]


def _fourbar(monkeypatch: pytest.MonkeyPatch | None) -> pm.FourBarLinkage:
    if monkeypatch is not None:
        monkeypatch.setattr(pm, "Revolute", MSLRevolute)
    return pm.FourBarLinkage()


SIGNALS = ["rev_crank.phi", "rev_crank.w", "cut1.frame_a.f[0]", "cut1.frame_a.f[1]"]


def test_msl_joint_compiles_to_the_library_joint(monkeypatch: pytest.MonkeyPatch) -> None:
    """Same unknowns, states, Jacobian sparsity and residual (module doc)."""
    ref = fl.Simulation(_fourbar(None), use_cache=False).compiled
    msl = fl.Simulation(_fourbar(monkeypatch), use_cache=False).compiled
    assert msl.y_names == ref.y_names
    assert list(msl.differential) == list(ref.differential)
    assert list(msl.jac_row) == list(ref.jac_row) and list(msl.jac_colind) == list(ref.jac_colind)
    f, g = ref.sx_function("res"), msl.sx_function("res")
    rng = np.random.default_rng(20261127)
    for _ in range(3):
        y, yp = rng.standard_normal(ref.n), rng.standard_normal(ref.n)
        r_ref = np.asarray(f(0.1, y, yp, ref.param_defaults)).ravel()
        r_msl = np.asarray(g(0.1, y, yp, msl.param_defaults)).ravel()
        np.testing.assert_allclose(r_msl, r_ref, rtol=1e-14, atol=1e-14 * np.abs(r_ref).max())


def test_msl_joint_runs_the_fourbar_as_the_library_joint(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same run: step counts and signals (module doc)."""
    ref = fl.Simulation(_fourbar(None), use_cache=False).run(0.5, dt_out=0.01, rtol=1e-8, atol=1e-10)
    res = fl.Simulation(_fourbar(monkeypatch), use_cache=False).run(0.5, dt_out=0.01, rtol=1e-8, atol=1e-10)
    assert res.stats["steps"] == ref.stats["steps"]
    for name in SIGNALS:
        np.testing.assert_allclose(res[name], ref[name], rtol=1e-12, atol=1e-12 * np.abs(ref[name]).max())


def test_pass_introduces_the_recursion_only_where_it_is_missing(monkeypatch: pytest.MonkeyPatch) -> None:
    """The MSL joints get 9 generated rows each (v, a, z of the frame they compute); the library's do not."""
    lib = flatten(_fourbar(None), check=False)
    msl = flatten(_fourbar(monkeypatch), check=False)
    assert not [e for e in lib.equations if "multibody kinematics pass" in e.label]
    assert len([e for e in msl.equations if "multibody kinematics pass" in e.label]) == 9 * 4  # four revolutes
    assert len(msl.equations) == len(lib.equations)


class SlidingPin(MSLRevolute):
    """Not a relative motion: frame_b's origin offset along a world axis, whatever frame_a's orientation."""

    def equations(self) -> list:
        rows = super().equations()
        rows[0] = eq(self.frame_b.r_0, self.frame_a.r_0 + ca.DM([0.1, 0.0, 0.0]))
        return rows


class Pendulum(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.world = World()
        self.joint = SlidingPin(init={"phi": 0.3, "w": 0.0})
        self.body = Body(m=1.0, r_CM=[0.5, 0.0, 0.0])
        self.connect(self.world.frame_b, self.joint.frame_a)
        self.connect(self.joint.frame_b, self.body.frame_a)


def test_a_relation_that_is_not_a_relative_motion_is_named() -> None:
    """The pass refuses to guess the recursion of rows it cannot read as a relative motion, naming the joint."""
    with pytest.raises(fl.ModelError, match=r"joint: the rows relating its frames are not a relative motion"):
        flatten(Pendulum(), check=False)
