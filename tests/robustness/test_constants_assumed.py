"""Faults: a run that violates a parameter condition the planar reduction relied on (flexlib/compile/constants.py).

A planar four-bar built by default (``assume_zero_geometry``) eliminates its out-of-plane unknowns assuming the
in-plane axis components (and other zero frame parameters) stay zero and the axis keeps its sign. A run that
changes one must fail with StructureChangedError naming the parameter and the assumption, never run silently
wrong (issue 8: a tilted rocker axis gave a 0.25 m gap in the loop).
"""

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.reference.four_bar import FourBar


@pytest.fixture()
def sim(monkeypatch):
    monkeypatch.delenv("FLEXLIB_ZERO_GEOMETRY", raising=False)  # the default
    return fl.Simulation(FourBar(), use_cache=False)


def test_tilted_axis_through_params_is_refused(sim):
    with pytest.raises(fl.StructureChangedError, match=r"rev4\.n\[1\] = 0\.3 \(the build assumed rev4\.n\[1\] = 0\)"):
        sim.run(0.1, params={"rev4.n": [0.0, 0.3, 1.0]}, progress=False)


def test_one_axis_element_through_params_is_refused(sim):
    with pytest.raises(fl.StructureChangedError, match=r"rev1\.n\[0\] = 0\.1 .*assumed rev1\.n\[0\] = 0"):
        sim.run(0.1, params={"rev1.n[0]": 0.1}, progress=False)


def test_flipped_axis_sign_is_refused(sim):
    with pytest.raises(fl.StructureChangedError, match=r"rev2\.n\[2\] = -1 \(the build assumed rev2\.n\[2\] > 0\)"):
        sim.run(0.1, params={"rev2.n": [0.0, 0.0, -1.0]}, progress=False)


def test_product_of_inertia_is_refused(sim):
    inertia = np.diag([1e-3, 0.04, 0.04])  # positive definite (the parameter check passes), out of plane
    inertia[0, 2] = inertia[2, 0] = 1e-4
    with pytest.raises(fl.StructureChangedError, match=r"coupler_mass\.I\[0,2\] = 0\.0001"):
        sim.run(0.1, params={"coupler_mass.I": inertia}, progress=False)


def test_out_of_plane_rod_offset_is_refused(sim):
    with pytest.raises(fl.StructureChangedError, match=r"model FourBar: coupler\.r\[2\] = 0\.05"):
        sim.run(0.1, params={"coupler.r": [0.7, 0.0, 0.05]}, progress=False)


def test_value_changed_on_the_model_after_the_build_is_refused(sim):
    sim.model.rocker.r = [0.9, 0.0, 0.02]
    with pytest.raises(fl.StructureChangedError, match=r"rocker\.r\[2\] = 0\.02"):
        sim.run(0.1, progress=False)


def test_refusal_names_the_opt_out_for_sweeps(sim):
    """The message tells how to vary an assumed parameter at run time (a sweep of an out-of-plane offset)."""
    with pytest.raises(fl.StructureChangedError, match=r"crank\.r\[2\] = 0\.01 .*assume_zero_geometry=False"):
        sim.run(0.1, params={"crank.r": [0.2, 0.0, 0.01]}, progress=False)


def test_opt_out_build_assumes_nothing_and_takes_the_override():
    """``assume_zero_geometry=False``: no assumption recorded, the same override is accepted (a product of inertia
    does not change the loop's kinematics)."""
    sim = fl.Simulation(FourBar(), use_cache=False, assume_zero_geometry=False)
    assert sim.compiled.assumed == {}
    inertia = np.diag([1e-3, 0.04, 0.04])
    inertia[0, 2] = inertia[2, 0] = 1e-4
    assert sim.run(0.05, params={"coupler_mass.I": inertia}, progress=False).status == "success"
