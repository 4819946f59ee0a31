"""Robustness of the tree-frame rule (``flexlib/compile/passes/multibody/tearing.py::tear_or_keep_frames``): a bad
``FLEXLIB_TREE_FRAMES`` is refused naming the variable and its value; a cached build with kept frames, loaded for an
instance with other start angles, still initialises at that instance's configuration (reference: the chain's
forward kinematics, body k at k·L·(cos φ0, sin φ0, 0) with joint 1 at φ0 and the others at 0, to 1e-9 m)."""

import numpy as np
import pytest

import flexlib as fl
from flexlib.compile.passes.multibody import tearing
from flexlib.models.n_link_pendulum import NLinkPendulum


def test_bad_tree_frames_setting_is_refused(monkeypatch):
    monkeypatch.setenv("FLEXLIB_TREE_FRAMES", "sometimes")
    with pytest.raises(fl.RunArgumentError, match=r"FLEXLIB_TREE_FRAMES = 'sometimes': expected 'auto', 'tear'"):
        fl.Simulation(NLinkPendulum(2), use_cache=False)


def test_cached_kept_build_initialises_at_other_start_angles(monkeypatch, tmp_path):
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("FLEXLIB_TREE_FRAMES", raising=False)
    n, L = tearing.KEEP_DEPTH + 1, 0.5
    first = fl.Simulation(NLinkPendulum(n, L=L, phi0=-0.8), codegen=False)
    assert first.report.tree_frames.startswith("kept")
    phi0 = 2.5  # far from the build instance's -0.8: the build-time guesses of T are rotations by the wrong angle
    sim = fl.Simulation(NLinkPendulum(n, L=L, phi0=phi0), codegen=False)
    assert sim.build.timings["cached"]
    res = sim.run(0.01, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False)
    for k in (1, 7, n):
        np.testing.assert_allclose(res[f"body{k}.r_0"][0], k * L * np.array([np.cos(phi0), np.sin(phi0), 0.0]),
                                   atol=1e-9)
