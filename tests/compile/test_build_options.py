"""Build options are passed as values: ``BuildOptions`` is resolved once (a field left None from its environment
variable) and reaches the stages that read it and the cache key; the environment is read, never written."""

from __future__ import annotations

import os

import pytest

import flexlib as fl
from flexlib.compile.environment import DEFAULTS_FROM
from flexlib.models.n_link_pendulum import NLinkPendulum

BUILD_VARIABLES = [DEFAULTS_FROM[k] for k in ("zero_geometry", "explicit", "tree_frames")]


@pytest.fixture
def clean_environment(monkeypatch, tmp_path):
    """No build switch set, a fresh cache directory."""
    for name in BUILD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))


def test_resolved_takes_the_environment_defaults(clean_environment, monkeypatch):
    assert fl.BuildOptions().resolved() == fl.BuildOptions("auto", True, True, True, "auto")
    monkeypatch.setenv("FLEXLIB_EXPLICIT", "all")
    monkeypatch.setenv("FLEXLIB_TREE_FRAMES", "keep")
    monkeypatch.setenv("FLEXLIB_ZERO_GEOMETRY", "off")
    assert fl.BuildOptions().resolved() == fl.BuildOptions("auto", True, False, "all", "keep")
    given = fl.BuildOptions(codegen=False, zero_geometry=True, explicit=False, tree_frames="tear").resolved()
    assert given == fl.BuildOptions(False, True, True, False, "tear")  # a value given wins over the environment
    assert given.explicit_mode == "off" and fl.BuildOptions(explicit="all").explicit_mode == "all"


def test_explicit_option_is_part_of_the_cache_key(clean_environment):
    """explicit=False, then True, in one process with the cache on: the second build is not the first's entry."""
    off = fl.build(NLinkPendulum(3), options=fl.BuildOptions(codegen=False, explicit=False))
    on = fl.build(NLinkPendulum(3), options=fl.BuildOptions(codegen=False, explicit=True))
    assert off.key and on.key and off.key != on.key
    assert not on.cached and on.compiled.report.explicit and not off.compiled.report.explicit
    assert on.compiled.n < off.compiled.n
    again = fl.build(NLinkPendulum(3), options=fl.BuildOptions(codegen=False, explicit=False))
    assert again.cached and again.key == off.key and again.compiled.n == off.compiled.n
    assert not any(name in os.environ for name in BUILD_VARIABLES)  # nothing written to pass the setting


def test_tree_frames_and_zero_geometry_options_reach_their_stages(clean_environment):
    n = 3
    kept = fl.build(NLinkPendulum(n), options=fl.BuildOptions(codegen=False, tree_frames="keep"))
    torn = fl.build(NLinkPendulum(n), options=fl.BuildOptions(codegen=False, tree_frames="tear"))
    assert kept.compiled.report.tree_frames.startswith("kept")
    assert torn.compiled.report.tree_frames.startswith("torn")
    assert kept.key != torn.key and not torn.cached
    full = fl.build(NLinkPendulum(n), options=fl.BuildOptions(codegen=False, zero_geometry=False))
    planar = fl.build(NLinkPendulum(n), options=fl.BuildOptions(codegen=False, zero_geometry=True))
    assert full.key != planar.key and not planar.cached and planar.compiled.n < full.compiled.n
    assert not full.compiled.assumed and planar.assume_zero_geometry and not full.assume_zero_geometry


def test_record_wins_over_the_environment_through_every_stage(clean_environment, monkeypatch):
    """With ``FLEXLIB_EXPLICIT=all`` set, ``BuildOptions(explicit=False)`` builds without the stage, and the
    structure kept for the state-selection monitor re-assembles without it too."""
    monkeypatch.setenv("FLEXLIB_EXPLICIT", "all")
    sim = fl.Simulation(NLinkPendulum(3), build=fl.BuildOptions(codegen=False, use_cache=False, explicit=False))
    assert sim.build_options.explicit is False and not sim.report.explicit
    structure = sim.build.structure(sim.model)
    assert structure.explicit == "off"
    dummies, levels = structure.select()
    assert not structure.assemble(dummies, levels).report.explicit
    default = fl.build(NLinkPendulum(3), use_cache=False, codegen=False)  # no record: the environment's "all"
    assert default.options.explicit == "all" and default.dae.structure.explicit == "all"


def test_flexlib_build_accepts_a_record_or_keywords_not_both():
    with pytest.raises(fl.RunArgumentError, match="not both"):
        fl.build(NLinkPendulum(2), codegen=False, options=fl.BuildOptions())
    with pytest.raises(fl.RunArgumentError, match="BuildOptions"):
        fl.build(NLinkPendulum(2), options={"codegen": False})
    with pytest.raises(fl.RunArgumentError, match="codegen"):
        fl.build(NLinkPendulum(2), options=fl.BuildOptions(codegen="no"))
