"""Tree frame kinematics torn or kept as unknowns
(``flexlib/compile/passes/multibody/tearing.py::tear_or_keep_frames``, issue 9).

A model without kinematic loops whose deepest chain of frame definitions exceeds ``tearing.KEEP_DEPTH`` keeps the
frame orientations ``T`` and origins ``r_0`` as unknowns (O(N) Jacobian along a chain of N joints) instead of
substituting the forward kinematics. Reference for every comparison: the same model with the frames torn
(``FLEXLIB_TREE_FRAMES=tear``, the DAE used before the rule), run at the same tolerances; agreement is required to
the integration tolerance stated at each test.
"""

import dataclasses

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib.compile.passes.multibody import tearing
from flexlib.components.mechanics.multibody import Body, Bushing, SpringDamperLine, World
from flexlib.models.n_link_pendulum import NLinkPendulum
from flexlib.models.planar_mechanisms import FourBarLinkage
from flexlib.units import g_n

G = g_n  # standard gravity: the World's default, as MSL's


def _sim(model: fl.Model, mode: str, monkeypatch: pytest.MonkeyPatch) -> fl.Simulation:
    monkeypatch.setenv("FLEXLIB_TREE_FRAMES", mode)
    return fl.Simulation(model, use_cache=False)


def test_rule_decision_is_reported(monkeypatch):
    """Auto: a chain one joint deeper than KEEP_DEPTH keeps its frames, a 3-link chain is torn; a model with a
    kinematic loop is torn even when keeping is forced. The decision and its reason are in ``Simulation.report``."""
    monkeypatch.delenv("FLEXLIB_TREE_FRAMES", raising=False)
    deep = fl.build(NLinkPendulum(tearing.KEEP_DEPTH + 1), use_cache=False)
    assert deep.simple.tree_frames.startswith("kept")
    assert f"depth {tearing.KEEP_DEPTH + 1}" in deep.compiled.report.tree_frames
    assert "Tree frame kinematics: kept" in str(deep.compiled.report)
    shallow = fl.build(NLinkPendulum(3), use_cache=False)
    assert shallow.compiled.report.tree_frames.startswith("torn (frame-definition depth 3")

    sim = _sim(FourBarLinkage(), "keep", monkeypatch)
    assert sim.report.tree_frames.startswith("torn") and "kinematic loops" in sim.report.tree_frames


def test_kept_frames_start_at_the_start_rotation(monkeypatch):
    """Kept ``T`` start as the rotation of the start angles (never 0): every link of a chain released with joint 1
    at φ0 and the others at 0 is rotated by φ0 about z, so each kept T has T[0,0] = T[1,1] = cos φ0,
    |T[0,1]| = |T[1,0]| = |sin φ0|, T[2,2] = 1 (exact to 1e-15)."""
    monkeypatch.setenv("FLEXLIB_TREE_FRAMES", "keep")
    phi0 = -0.8
    b = fl.build(NLinkPendulum(4, phi0=phi0), use_cache=False)
    T = {}
    for v in b.simple.variables:
        if v.info.name == "T":
            T.setdefault(v.name.rsplit("[", 1)[0], {})[v.name.rsplit("[", 1)[1].rstrip("]")] = v.start
    assert len(T) >= 4
    for frame, m in T.items():
        assert m.get("0,0", np.cos(phi0)) == pytest.approx(np.cos(phi0), abs=1e-15), frame
        assert m.get("1,1", np.cos(phi0)) == pytest.approx(np.cos(phi0), abs=1e-15), frame
        assert abs(m.get("0,1", np.sin(phi0))) == pytest.approx(abs(np.sin(phi0)), abs=1e-15), frame
        assert m.get("2,2", 1.0) == pytest.approx(1.0, abs=1e-15), frame


def test_long_chain_kept_agrees_with_torn(monkeypatch):
    """12-link chain, 1 s at rtol 1e-9: joint angles with the frames kept agree with the torn build to 1e-6 rad
    (the chain is chaotic, so the bound is a few hundred times the tolerance); link 12's body position to 1e-6 m."""
    model = NLinkPendulum(12)
    runs = {}
    for mode in ("tear", "keep"):
        sim = _sim(model, mode, monkeypatch)
        assert sim.report.tree_frames.startswith("torn" if mode == "tear" else "kept")
        runs[mode] = sim.run(1.0, dt_out=0.1, rtol=1e-9, atol=1e-11, progress=False)
    for k in (1, 6, 12):
        np.testing.assert_allclose(runs["keep"][f"joint{k}.phi"], runs["tear"][f"joint{k}.phi"], atol=1e-6)
    np.testing.assert_allclose(runs["keep"]["body12.r_0"], runs["tear"]["body12.r_0"], atol=1e-6)


class DeepBushing(fl.Model):
    """A chain of ``n`` links with a body hanging from its tip on an undamped bushing (gravity −y), released with
    the bushing deflected 1 cm and twisted 0.2 rad."""

    def __init__(self, n: int) -> None:
        super().__init__()
        self.chain = NLinkPendulum(n, phi0=-1.2)
        init = {"r_rel": [0.0, -0.01, 0.0], "v_rel": [0.0, 0.0, 0.0], "phi_rel": [0.0, 0.0, 0.2],
                "phi_d": [0.0, 0.0, 0.0]}
        self.bushing = Bushing(c_trans=[4e3, 5e3, 6e3], c_rot=[30.0, 40.0, 50.0], init=init)
        self.body = Body(m=2.0, I=np.diag([0.1, 0.2, 0.3]))
        self.connect(getattr(self.chain, f"rod{n}").frame_b, self.bushing.frame_a)
        self.connect(self.bushing.frame_b, self.body.frame_a)


def test_deep_chain_with_bushing_initialises_and_agrees(monkeypatch):
    """A free body on a bushing at the tip of a chain deeper than KEEP_DEPTH (frames kept by the default rule: its
    ``T`` starts at the tip's rotation, not 0) initialises and, over 0.5 s at rtol 1e-9, agrees with the torn build:
    bushing deflection to 1e-8 m, Cardan angles to 1e-7 rad, last joint angle to 1e-7 rad."""
    monkeypatch.delenv("FLEXLIB_TREE_FRAMES", raising=False)
    n = tearing.KEEP_DEPTH + 1
    kept = fl.Simulation(DeepBushing(n), use_cache=False)
    assert kept.report.tree_frames.startswith("kept")
    torn = _sim(DeepBushing(n), "tear", monkeypatch)
    a = kept.run(0.5, dt_out=0.05, rtol=1e-9, atol=1e-11, progress=False)
    b = torn.run(0.5, dt_out=0.05, rtol=1e-9, atol=1e-11, progress=False)
    assert np.ptp(b["bushing.r_rel"][:, 1]) > 1e-4  # the bushing really deflects
    np.testing.assert_allclose(a["bushing.r_rel"], b["bushing.r_rel"], atol=1e-8)
    np.testing.assert_allclose(a["bushing.phi_rel"], b["bushing.phi_rel"], atol=1e-7)
    np.testing.assert_allclose(a[f"chain.joint{n}.phi"], b[f"chain.joint{n}.phi"], atol=1e-7)


def test_free_body_on_bushing_with_frames_kept(monkeypatch):
    """The case that failed when frames were kept without start values (``T = 0``: Cardan angles of a zero matrix):
    a body hanging on a bushing, frames forced kept, settles at the static sag −m g / c_y (1e-8 relative)."""
    m, c = 2.0, (4e3, 5e3, 6e3)

    class HangingBushing(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.world = World(g=G)
            self.bushing = Bushing(c_trans=list(c), c_rot=[30.0, 40.0, 50.0])
            self.body = Body(m=m, I=np.diag([0.1, 0.2, 0.3]))
            self.connect(self.world.frame_b, self.bushing.frame_a)
            self.connect(self.bushing.frame_b, self.body.frame_a)

    sim = _sim(HangingBushing(), "keep", monkeypatch)
    assert sim.report.tree_frames.startswith("kept")
    res = sim.run(0.1, dt_out=0.05, steady_state=True, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["bushing.r_rel"][-1], [0.0, -m * G / c[1], 0.0], rtol=1e-8, atol=1e-14)


class SpannedChain(fl.Model):
    """A 4-link pendulum chain (gravity −y) with a line spring from the tip of link 2 to the tip of link 4: the
    spring's rows relate two frames whose common frame is link 2's."""

    def __init__(self) -> None:
        super().__init__()
        self.chain = NLinkPendulum(4, phi0=-0.6)
        self.spring = SpringDamperLine(c=400.0, d=2.0, s_unstretched=0.6)
        self.connect(self.chain.rod2.frame_b, self.spring.frame_a)
        self.connect(self.chain.rod4.frame_b, self.spring.frame_b)


def test_rows_between_frames_are_written_relative_to_their_common_frame(monkeypatch):
    """``tearing._localize_rows``: the spring's length row no longer involves the joints above link 2 (structural
    locality), the report counts the rewritten rows, and 0.5 s at rtol 1e-11 agrees with the build that keeps the
    rows as torn (``_localize_rows`` replaced by the identity): joint angles and spring length to 1e-8 m."""
    monkeypatch.delenv("FLEXLIB_TREE_FRAMES", raising=False)
    b = fl.build(SpannedChain(), use_cache=False)
    assert "rows written relative to their common base frame" in b.compiled.report.tree_frames
    length = [e for e in b.simple.equations if e.owner == "spring" and "length" in e.label]
    assert length
    for e in length:
        names = {str(s) for s in ca.symvar(e.expr)}
        assert not any("joint1" in n or "joint2" in n for n in names), names
    runs = {}
    sim = fl.Simulation(SpannedChain(), use_cache=False)
    runs["local"] = sim.run(0.5, dt_out=0.05, rtol=1e-11, atol=1e-13, progress=False)
    monkeypatch.setattr(tearing, "_localize_rows", lambda simple, *args: (simple, 0))
    ref = fl.Simulation(SpannedChain(), use_cache=False)
    assert "rows written relative" not in ref.report.tree_frames
    runs["torn"] = ref.run(0.5, dt_out=0.05, rtol=1e-11, atol=1e-13, progress=False)
    assert np.ptp(runs["torn"]["spring.length"]) > 1e-2  # the spring really works
    for k in range(1, 5):
        np.testing.assert_allclose(runs["local"][f"chain.joint{k}.phi"], runs["torn"][f"chain.joint{k}.phi"], atol=1e-8)
    np.testing.assert_allclose(runs["local"]["spring.length"], runs["torn"]["spring.length"], atol=1e-8)


def test_rows_that_are_not_invariant_are_kept_as_built():
    """The numeric check of ``_localize_rows`` rejects a row that depends on the common frame's orientation: a row
    ``r_a,x − r_b,x`` (world-resolved) between the tips of links 2 and 4 changes when link 2 turns, so it is kept;
    the spring's length row (invariant) is rewritten."""
    from flexlib.compile.flatten import flatten
    from flexlib.compile.simplify import simplify
    from flexlib.compile.tearing import explicit_definitions

    model = SpannedChain()
    flat = flatten(model, check=False)
    params = {q.sym.element_hash(): q.value for q in flat.parameters}
    simple = simplify(flat)
    ids = tearing._frame_ids(simple)
    vs, defs, _ = explicit_definitions(simple, ids)
    by_name = {v.name: v.sym for v in simple.variables}
    world_row = by_name["spring.frame_a.r_0[0]"] - by_name["spring.frame_b.r_0[0]"]
    probe = dataclasses.replace(simple.equations[0], expr=world_row, label="world-resolved probe")
    probed = dataclasses.replace(simple, equations=[*simple.equations, probe])
    out, n = tearing._localize_rows(probed, vs, defs, params)
    assert n >= 1
    assert out.equations[-1].expr is probe.expr  # not invariant: kept as built
    changed = [e.label for e, o in zip(probed.equations, out.equations, strict=True) if e.expr is not o.expr]
    assert any("length" in lab for lab in changed), changed


def test_a_joint_written_without_the_frame_rates_gets_them_from_the_pass():
    """A user joint that relates r_0, T and w but not the frame's v, a, z (MSL's rows) gets the recursive
    kinematics from the multibody compile pass (it used to leave them undetermined and the balance check named
    them): the welded body stays at the world's origin and the weld carries its weight (1e-9)."""
    from flexlib import eq
    from flexlib.components.mechanics.multibody.interfaces import PartialTwoFrames

    class OldStyleWeld(PartialTwoFrames):
        def equations(self):
            a, b = self.frame_a, self.frame_b
            return [eq(b.r_0, a.r_0), eq(b.T, a.T), eq(b.w, a.w), eq(a.f + b.f, 0.0), eq(a.t + b.t, 0.0)]

    class Model(fl.Model):
        def __init__(self):
            super().__init__()
            self.world, self.weld, self.body = World(), OldStyleWeld(), Body(m=1.0, I=np.eye(3))
            self.connect(self.world.frame_b, self.weld.frame_a)
            self.connect(self.weld.frame_b, self.body.frame_a)

    res = fl.Simulation(Model(), use_cache=False).run(0.1, dt_out=0.05)
    assert np.abs(res["body.frame_a.r_0[1]"]).max() < 1e-9
    np.testing.assert_allclose(res["weld.frame_a.f[1]"], g_n, rtol=1e-9)
