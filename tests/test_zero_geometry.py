"""Planar geometry assumed by default (``assume_zero_geometry``, flexlib/compile/constants.py; issue 9, item 3).

A planar mechanism built from 3D components is planar only because some frame parameters are zero (in-plane
joint-axis components, out-of-plane rod and centre-of-mass offsets, products of inertia). By default the build
takes those zeros as constants, so the out-of-plane forces, torques and velocities leave the DAE; the opt-out
(``assume_zero_geometry=False`` or ``FLEXLIB_ZERO_GEOMETRY=0``) keeps them run-time parameters.

Models: ``models/planar_mechanisms.py`` (the crank-rocker four-bar and the 7-body 3-loop chain, all joint axes
along world z). References: the closed-form four-bar position analysis (Norton, *Design of Machinery* §4.5,
``flexlib.models.reference.closed_form``),
and the planar Newton–Euler equations: with every joint axis along z, a centre
of mass moved along z changes no moment of inertia about z and no in-plane force, so the joint angles are the
same and only the out-of-plane reaction torques change.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.planar_mechanisms import FourBarLinkage, ThreeLoopLinkage
from flexlib.models.reference import closed_form as ref

OUT_OF_PLANE = ("f[2]", "t[0]", "t[1]", "w[0]", "w[1]", "v_0[2]", "a_0[2]", "z_a[0]", "z_a[1]")


def _lifted(h: float) -> FourBarLinkage:
    """The four-bar with the coupler's centre of mass moved by ``h`` [m] out of the plane."""
    model = FourBarLinkage()
    model.coupler_mass.r_CM = [0.35, 0.0, h]
    return model


@pytest.mark.parametrize("make", [FourBarLinkage, ThreeLoopLinkage])
def test_default_drops_the_out_of_plane_unknowns(make):
    """Default vs opt-out build of the same mechanism: no out-of-plane cut force, torque, angular or linear
    velocity or acceleration remains an unknown (four-bar 62 → 25, 7-body 164 → 59 when measured), the
    unknowns at least halve, the states are the same, and the eliminated quantities stay in results by name."""
    full = fl.Simulation(make(), use_cache=False, assume_zero_geometry=False)
    planar = fl.Simulation(make(), use_cache=False)
    assert full.compiled.assumed == {}
    assert any(n.endswith(OUT_OF_PLANE) for n in full.compiled.y_names)
    assert not [n for n in planar.compiled.y_names if n.endswith(OUT_OF_PLANE)]
    assert 2 * planar.compiled.n <= full.compiled.n
    assert planar.states == full.states
    assert planar.compiled.assumed["rev_crank.n[0]"] == "= 0" and planar.compiled.assumed["rev_crank.n[2]"] == "> 0"
    res = planar.run(0.05, dt_out=0.01, progress=False)
    with pytest.warns(fl.IndeterminateReactionWarning):  # the zeroed out-of-plane reactions: indeterminate
        assert np.all(res["rev_crank.frame_a.t"][:, :2] == 0.0) and np.all(res["rev_crank.frame_a.f"][:, 2] == 0.0)


def test_default_agrees_with_the_opt_out_build():
    """The four-bar over 1 s (crank about 1.5 turns) at rtol 1e-11: the two builds agree to 1e-7 rad (speeds to
    1e-7 of their largest value) and both follow the closed-form rocker angle θ4(θ2) to 1e-7 rad.

    Run at rtol 1e-11 (measured differences: angles 3.5e-9 rad, speeds 7.3e-9 of the largest, on both IDA routes):
    at rtol 1e-10 the opt-out build's own speed error, against its rtol 1e-12 run, is 7.6e-7 rad/s on the
    scikit-sundae route (SuperLU_MT, 3326 steps) and 2.2e-7 on the C driver (KLU, 6213 steps), the default build's
    9.2e-8 on both — the opt-out build alone reaches this test's speed tolerance there."""
    runs = [fl.Simulation(FourBarLinkage(), use_cache=False, assume_zero_geometry=z)
            .run(1.0, dt_out=0.01, rtol=1e-11, atol=1e-13, progress=False) for z in (True, False)]
    for name in ("rev_crank.phi", "rev_coupler.phi", "rev_rocker.phi"):
        np.testing.assert_allclose(runs[0][name], runs[1][name], rtol=0, atol=1e-7)
    for name in ("rev_crank.w", "rev_rocker.w"):  # rad/s: 1e-7 of the largest speed (≈ 16 rad/s)
        np.testing.assert_allclose(runs[0][name], runs[1][name], rtol=0, atol=1e-7 * np.abs(runs[1][name]).max())
    for res in runs:
        theta2 = res["rev_crank.phi"]
        assert theta2[-1] - theta2[0] > 2 * np.pi
        _, th4 = ref.fourbar_angles(0.2, 0.7, 0.9, 0.6, theta2, "open")
        wrap = (res["rev_rocker.phi"] - th4 + np.pi) % (2 * np.pi) - np.pi
        np.testing.assert_allclose(wrap, 0.0, atol=1e-7)


def test_sweeping_an_out_of_plane_offset_needs_the_opt_out():
    """A run override of an assumed-zero parameter is refused by the default build (named), and runs with
    ``assume_zero_geometry=False``: the lifted centre of mass leaves the joint angles unchanged (planar
    Newton–Euler, 1e-7 rad) and puts an out-of-plane reaction torque on the coupler's joint (> 1e-3 N·m)."""
    lift = {"coupler_mass.r_CM": [0.35, 0.0, 0.05]}
    with pytest.raises(fl.StructureChangedError, match=r"coupler_mass\.r_CM\[2\] = 0\.05 .*assume_zero_geometry"):
        fl.Simulation(FourBarLinkage(), use_cache=False).run(0.1, params=lift, progress=False)
    sim = fl.Simulation(FourBarLinkage(), use_cache=False, assume_zero_geometry=False)
    flat = sim.run(0.5, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False)
    lifted = sim.run(0.5, dt_out=0.01, rtol=1e-10, atol=1e-12, params=lift, progress=False)
    np.testing.assert_allclose(lifted["rev_rocker.phi"], flat["rev_rocker.phi"], rtol=0, atol=1e-7)
    with pytest.warns(fl.IndeterminateReactionWarning, match=r"rev_coupler\.frame_b\.t\[0\]"):
        assert np.abs(flat["rev_coupler.frame_b.t"][:, :2]).max() < 1e-9
        # its share of the lifted mass's moment is one admissible split: out of the plane the loop is indeterminate
        assert np.abs(lifted["rev_coupler.frame_b.t"][:, :2]).max() > 1e-3


def test_cached_planar_entry_is_rebuilt_for_a_nonzero_value(tmp_path, monkeypatch):
    """Same structure key: a model instance whose out-of-plane offset is not zero does not reuse the entry built
    with the zero (it is rebuilt and does not assume it; same joint angles, 1e-7 rad, out-of-plane reaction
    torque present); an instance with the zero again loads the entry. The option is part of the key."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    first = fl.Simulation(FourBarLinkage())
    assert "coupler_mass.r_CM[2]" in first.compiled.assumed and not first.build_info["cached"]
    lifted = fl.Simulation(_lifted(0.05))
    assert not lifted.build_info["cached"]
    assert "coupler_mass.r_CM[2]" not in lifted.compiled.assumed
    a = first.run(0.3, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False)
    b = lifted.run(0.3, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False)
    np.testing.assert_allclose(b["rev_rocker.phi"], a["rev_rocker.phi"], rtol=0, atol=1e-7)
    with pytest.warns(fl.IndeterminateReactionWarning):  # out of the plane the loop is statically indeterminate
        assert np.abs(b["rev_coupler.frame_b.t"][:, :2]).max() > 1e-3
    assert fl.Simulation(FourBarLinkage()).build_info["cached"]
    opt_out = fl.Simulation(FourBarLinkage(), assume_zero_geometry=False)
    assert not opt_out.build_info["cached"] and opt_out.build_info["model_key"] != first.build_info["model_key"]
    monkeypatch.setenv("FLEXLIB_ZERO_GEOMETRY", "0")
    env = fl.Simulation(FourBarLinkage())
    assert env.build_info["cached"] and env.compiled.n == opt_out.compiled.n and env.compiled.assumed == {}
