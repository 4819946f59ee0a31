"""The multibody compile pass (``flexlib/compile/passes/multibody``): joints written as MSL writes them.

The library's :class:`~flexlib.components.mechanics.multibody.Revolute` relates its frames with MSL's rows only
(``r_0``, ``T``, ``w``, ``f``, ``t``; Modelica Standard Library 4.0, ``MultiBody.Joints.Revolute``) plus friction:
the pass introduces the frames' velocities and accelerations ``v``, ``a``, ``z`` along the spanning tree.
``HandRevolute`` writes that recursion by hand, as the joints did before the pass. The crank-rocker four-bar
(both branch directions: the loop's cut joint is rooted at frame_b) and the pump truck's boom (slew, five
section joints and the lever-and-link pins of joints 2–5) compile with either to the same unknowns, states and
Jacobian sparsity and the same residual at random points (to round-off: bit for bit), and run the same steps and
signals. The :class:`Frame` connector declares MSL's quantities only; the pass declares ``v``, ``a``, ``z`` on each
frame and writes them for the tree's roots too.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
import flexlib.models.boom.linkage as boom_linkage
import flexlib.models.boom.turret as boom_turret
import flexlib.models.planar_mechanisms as pm
import flexlib.models.pump_truck.machine as pump_truck_machine
from flexlib import eq
from flexlib.compile.cache_key import model_key
from flexlib.compile.flatten import FlatSystem, flatten
from flexlib.components.mechanics.multibody import Body, Frame, Revolute, World
from flexlib.components.mechanics.multibody.frames import planar_rotation
from flexlib.registry import get_model


class HandRevolute(Revolute):
    """The library joint with the frames' ``v``, ``a``, ``z`` related by hand (before its orientation rows)."""

    def equations(self) -> list:
        rows = super().equations()
        a, b = self.frame_a, self.frame_b
        e = self.n / ca.norm_2(self.n)
        if self.rooted(a):
            R = planar_rotation(e, self.phi)
            hand = [eq(b.v, ca.mtimes(R, a.v)), eq(b.a, ca.mtimes(R, a.a)),
                    eq(b.z, ca.mtimes(R, a.z) + e * self.a + ca.cross(ca.mtimes(R, a.w), e * self.w))]
        else:
            R = planar_rotation(-e, self.phi)
            hand = [eq(a.v, ca.mtimes(R, b.v)), eq(a.a, ca.mtimes(R, b.a)),
                    eq(a.z, ca.mtimes(R, b.z) - e * self.a + ca.cross(ca.mtimes(R, b.w), -e * self.w))]
        return [*rows[:3], *hand, *rows[3:]]


def _fourbar(monkeypatch: pytest.MonkeyPatch | None) -> pm.FourBarLinkage:
    if monkeypatch is not None:
        monkeypatch.setattr(pm, "Revolute", HandRevolute)
    return pm.FourBarLinkage()


SIGNALS = ["rev_crank.phi", "rev_crank.w", "cut1.frame_a.f[0]", "cut1.frame_a.f[1]"]


def test_library_revolute_writes_msl_rows_only() -> None:
    """No row of the library joint names a frame's v, a or z."""
    model = _fourbar(None)
    flat = flatten(model, check=False)
    frames = [f for j in (model.rev_crank, model.rev_coupler, model.cut1) for f in (j.frame_a, j.frame_b)]
    vaz = ca.vertcat(*[ca.vec(f._symbol(n)) for f in frames for n in ("v", "a", "z")])
    own = [e.expr for e in flat.equations if e.owner == "rev_crank" and "kinematics pass" not in e.label]
    assert own and not ca.depends_on(ca.vertcat(*own), vaz)


def test_generated_recursion_compiles_as_the_hand_written_one(monkeypatch: pytest.MonkeyPatch) -> None:
    """Same unknowns, states, Jacobian sparsity and residual (module doc)."""
    lib = fl.Simulation(_fourbar(None), use_cache=False).compiled
    hand = fl.Simulation(_fourbar(monkeypatch), use_cache=False).compiled
    assert lib.y_names == hand.y_names
    assert list(lib.differential) == list(hand.differential)
    assert list(lib.jac_row) == list(hand.jac_row) and list(lib.jac_colind) == list(hand.jac_colind)
    f, g = hand.sx_function("res"), lib.sx_function("res")
    rng = np.random.default_rng(20261127)
    for _ in range(3):
        y, yp = rng.standard_normal(hand.n), rng.standard_normal(hand.n)
        r_hand = np.asarray(f(0.1, y, yp, hand.param_defaults)).ravel()
        r_lib = np.asarray(g(0.1, y, yp, lib.param_defaults)).ravel()
        np.testing.assert_allclose(r_lib, r_hand, rtol=1e-14, atol=1e-14 * np.abs(r_hand).max())


def test_generated_recursion_runs_as_the_hand_written_one(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same run: step counts and signals (module doc)."""
    lib = fl.Simulation(_fourbar(None), use_cache=False).run(0.5, dt_out=0.01, rtol=1e-8, atol=1e-10)
    hand = fl.Simulation(_fourbar(monkeypatch), use_cache=False).run(0.5, dt_out=0.01, rtol=1e-8, atol=1e-10)
    assert lib.stats["steps"] == hand.stats["steps"]
    for name in SIGNALS:
        np.testing.assert_allclose(lib[name], hand[name], rtol=1e-12, atol=1e-12 * np.abs(hand[name]).max())


def test_pass_introduces_the_recursion_only_where_it_is_missing(monkeypatch: pytest.MonkeyPatch) -> None:
    """The library revolutes get 9 generated rows each (v, a, z of the frame they compute); the hand-written do
    not."""
    lib = flatten(_fourbar(None), check=False)
    hand = flatten(_fourbar(monkeypatch), check=False)
    def generated(flat: FlatSystem) -> list:
        return [e for e in flat.equations if e.owner.startswith(("rev_", "cut")) and "kinematics pass" in e.label]

    assert not generated(hand)
    assert len(generated(lib)) == 9 * 4  # four revolutes
    assert len(lib.equations) == len(hand.equations)


class SlidingPin(Revolute):
    """Not a relative motion: frame_b's origin offset along a world axis, whatever frame_a's orientation."""

    def equations(self) -> list:
        rows = super().equations()
        rows[0] = eq(self.frame_b.r_0, self.frame_a.r_0 + ca.DM([0.1, 0.0, 0.0]))
        return rows


class Pendulum(fl.Model):
    """A body on a SlidingPin at the world."""

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


def test_frame_declares_msl_quantities_only() -> None:
    """The connector declares r_0, T, w, f, t (MSL ``Interfaces.Frame``); v, a, z come from the pass, on the instances
    of a flattened model only, and do not enter the cache key's declarations or connectability."""
    assert set(Frame().class_declarations()) == {"r_0", "T", "w", "f", "t"}
    model = _fourbar(None)
    frame = model.rev_coupler.frame_b
    before = frame.signature()
    flat = flatten(model, check=False)  # the loop's redundant rows go later
    assert list(frame._decls) == ["r_0", "T", "w", "v", "a", "z", "f", "t"]
    assert frame.signature() == before and set(frame.class_declarations()) == {"r_0", "T", "w", "f", "t"}
    generated = {e.label.split(" from ")[0] for e in flat.equations if "kinematics pass" in e.label}
    assert {"world.frame_b.v", "world.frame_b.a", "world.frame_b.z", "rev_crank.frame_b.v"} <= generated


def _boom(monkeypatch: pytest.MonkeyPatch | None) -> tuple[fl.Model, dict]:
    entry = get_model("pump-truck")
    scenario = entry.scenario("expand")
    if monkeypatch is not None:
        for module in (pump_truck_machine, boom_turret, boom_linkage):  # the boom's joints, the slew, the linkages
            monkeypatch.setattr(module, "Revolute", HandRevolute)
    return entry.factory(scenario), dict(scenario.run)


def test_pump_truck_linkage_runs_with_msl_joints_as_with_hand_written_ones(monkeypatch: pytest.MonkeyPatch) -> None:
    """The rigid pump truck's joints (all library revolutes, MSL's rows only) against the same joints with the
    recursion written by hand: same compiled system, residual to round-off, same steps and signals over the first
    2 s of the expand scenario (module doc)."""
    lib_model, run = _boom(None)
    hand_model, _ = _boom(monkeypatch)
    assert isinstance(hand_model.turret.slew, HandRevolute) and not isinstance(lib_model.turret.slew, HandRevolute)
    assert isinstance(hand_model.linkage3.bracket, HandRevolute) and isinstance(hand_model.joint2, HandRevolute)
    lib = fl.Simulation(lib_model, use_cache=False, codegen=False)
    hand = fl.Simulation(hand_model, use_cache=False, codegen=False)
    a, b = lib.compiled, hand.compiled
    assert a.y_names == b.y_names and list(a.differential) == list(b.differential)
    assert list(a.jac_row) == list(b.jac_row) and list(a.jac_colind) == list(b.jac_colind)
    p = np.concatenate([lib.parameter_vector(), np.zeros(a.n_relations)])
    rng = np.random.default_rng(20261128)
    y, yp = rng.standard_normal(a.n), rng.standard_normal(a.n)
    r_lib = np.asarray(a.sx_function("res")(0.1, y, yp, p)).ravel()
    r_hand = np.asarray(b.sx_function("res")(0.1, y, yp, p)).ravel()
    np.testing.assert_allclose(r_lib, r_hand, rtol=1e-14, atol=1e-14 * np.abs(r_hand).max())
    res_lib = lib.run(2.0, progress=False, **run)
    res_hand = hand.run(2.0, progress=False, **run)
    assert res_lib.stats["steps"] == res_hand.stats["steps"]
    for name in ("joint1.phi", "joint2.w", "linkage3.bracket.phi", "turret.slew.frame_b.t[1]"):
        x, ref = res_lib[name], res_hand[name]
        np.testing.assert_allclose(x, ref, rtol=1e-12, atol=1e-12 * max(np.abs(ref).max(), 1e-300))


def test_a_start_value_may_name_a_frame_kinematic_quantity_before_the_build() -> None:
    """``guess={"frame_a.a": ...}`` declares the pass's ``a`` on that frame at once (in its place after ``w``, ``v``);
    the build adds the others in order, and an initial condition given to one enters the cache key."""
    plain = _fourbar(None)
    guessed = _fourbar(None)
    guessed.rev_crank.frame_b.set_start("a", [0.0, 1.0, 0.0], fixed=False)
    frame = guessed.rev_crank.frame_b
    assert list(frame._decls) == ["r_0", "T", "w", "a", "f", "t"]
    assert frame.start_of("a")[0].tolist() == [0.0, 1.0, 0.0]
    flatten(guessed, check=False)
    assert list(frame._decls) == ["r_0", "T", "w", "v", "a", "z", "f", "t"]
    key = model_key(plain, {})
    assert model_key(guessed, {}) == key  # a guess decides nothing of the structure
    guessed.rev_crank.frame_b.set_start("a", [0.0, 1.0, 0.0], fixed=True)
    assert model_key(guessed, {}) != key



class CoupledPin(Revolute):
    """frame_b's orientation rows recombined (row 0 + row 1 in place of row 0): the same equations, but no row gives
    ``T_b[0, 0]`` alone, as MSL writes a joint."""

    def equations(self) -> list:
        rows = super().equations()
        T_b = ca.vec(self.frame_b.T)
        k = next(k for k, r in enumerate(rows) if ca.depends_on(r.residual, T_b) and r.residual.numel() == 9)
        res = ca.vec(rows[k].residual)
        rows[k] = eq(ca.vertcat(res[0] + res[1], res[1:]), 0.0)
        return rows


def test_a_joint_whose_rows_do_not_place_its_frame_is_named(monkeypatch: pytest.MonkeyPatch) -> None:
    """The pass refuses to guess the recursion of a joint whose rows give its frame's orientation only in
    combination, naming the joint and what it needs (it was an unbalanced model naming v, a, z)."""
    monkeypatch.setattr(pm, "Revolute", CoupledPin)
    with pytest.raises(fl.ModelError, match=r"rev_crank: declares branch\(rev_crank.frame_a, rev_crank.frame_b\) but "
                                            r"its rows do not give rev_crank.frame_b's r_0, T and w explicitly"):
        flatten(pm.FourBarLinkage(), check=False)
