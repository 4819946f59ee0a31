"""The POLYCRANK power-transmission fragment of seed 002 (``models/robots/polycrank.py``).

References: the seed's counts (Grübler −111, real mobility 4) and our schema's count of redundant loop rows
(30 loops × 6 rows − (69 joint coordinates − 4 degrees of freedom) = 115); the drive torques that hold the
fragment from a hand virtual-work calculation on its closed-form potential energy (``drive_torques``, no engine
code); the vertical bearing reactions summing to the weight (16.25 kg, the seed's total).
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.robots.polycrank import PolycrankFragment, PolycrankParameters

POSE = (0.3, 0.5, -0.2, 0.1)


def test_mobility_four_and_every_redundant_row_reported():
    par = PolycrankParameters()
    assert abs(par.total_mass - 16.25) < 1e-12
    sim = fl.Simulation(PolycrankFragment(angles=POSE))
    dropped = sim.build.compiled.report.redundant
    assert len(dropped) == 30 * 6 - (69 - 4)
    assert all("dropped redundant constraint" in line for line in dropped)
    n, joints = fl.analysis.mobility(sim)
    assert n == 4 and len(joints) == 4
    assert len(sim.states) == 8


def test_holding_torques_and_bearing_reactions_match_hand_statics():
    """With the hand-statics drive torques the fragment starts at rest with zero accelerations (to 1e-6 rad/s2: a
    torque error below 1e-7 of the holding torques, the issue asks 1 %) and stays put; the four ground bearings
    carry the whole weight (1e-9), each an indeterminate share of it."""
    par = PolycrankParameters()
    res = fl.Simulation(PolycrankFragment(angles=POSE)).run(0.2, dt_out=0.1, rtol=1e-9, atol=1e-11, progress=False)
    for j in ("j4", "d0o", "d0c3", "d0c4"):
        assert abs(res[f"{j}.a"][0]) < 1e-6
    np.testing.assert_allclose(res["j4.phi"][-1], POSE[0], atol=1e-8)
    np.testing.assert_allclose(res["d0o.phi"][-1], POSE[1], atol=1e-8)
    # world on the bearings: each bearing's share is statically indeterminate (the parallelograms' self-stresses
    # move load between them), their sum is the weight
    with pytest.warns(fl.IndeterminateReactionWarning, match="statically indeterminate"):
        up = sum(res[f"{j}.frame_a.f[1]"][0] for j in ("j4", "d0o", "d0c3", "d0c4"))
    np.testing.assert_allclose(up, par.total_mass * par.g, rtol=1e-9)


def test_bearing_friction_makes_the_energy_decay():
    """Released with speeds on all four drives (holding torques on): without friction the mechanical energy
    (kinetic + gravity − drive-torque work) is conserved over 0.15 s to 1e-8 of the weight times the fragment's
    length (the scale of the terms that cancel; rtol 1e-8); with the bearings' friction it falls (the seed's
    finding, Fig. 12)."""
    from flexlib.models.robots.polycrank import mechanical_energy

    speeds = (0.5, -0.4, 0.6, -0.5)
    drop = {}
    for friction in (False, True):
        model = PolycrankFragment(angles=POSE, speeds=speeds, friction=friction)
        res = fl.Simulation(model).run(0.15, dt_out=0.005, rtol=1e-8, atol=1e-10, progress=False)
        E = mechanical_energy(model, res)
        drop[friction] = E[0] - E[-1]
        if not friction:
            par = model.par
            np.testing.assert_allclose(E, E[0], rtol=0, atol=1e-8 * par.total_mass * par.g * (par.L4 + par.L5))
    assert drop[True] > 1e-3 > abs(drop[False])


def test_rigid_bearing_reactions_are_marked_indeterminate():
    """Issue 30's example: the load split between shield 5's bearing j5 and the parallelograms' extra links depends on
    which of the 115 repeated loop rows the build dropped. Every component of j5's bearing force is marked, and
    reading it warns, naming it, the dropped rows and the compliant alternatives. Not marked, by hand: the force
    across shield 4's base bearing normal to the shield, ``j4.frame_b.f[1]`` (resolved in shield 4's frame; the
    parallelograms' self-stresses are link forces, and the links of body 4 stay parallel to shield 4), and the
    forces on the load, a body whose motion determines them. The variant with flexible pull rods drops and marks
    nothing (``test_robots_polycrank_flexible.py``)."""
    res = fl.Simulation(PolycrankFragment(angles=POSE)).initialize()
    assert {f"j5.frame_a.f[{k}]" for k in range(3)} <= set(res.indeterminate)
    assert len(res.indeterminate["j5.frame_a.f[0]"]) > 1  # several parallel links share the load with j5
    assert "j4.frame_b.f[1]" not in res.indeterminate
    assert not [n for n in res.indeterminate if n.startswith("load.")]
    with pytest.warns(fl.IndeterminateReactionWarning) as caught:
        force = np.linalg.norm(res["j5.frame_a.f"], axis=1)
    text = str(caught[0].message)
    assert text.startswith("result of PolycrankFragment: j5.frame_a.f[0], j5.frame_a.f[1], j5.frame_a.f[2] are "
                           "statically indeterminate")
    assert "dropped redundant constraint" in text and "Bushing" in text and "FlexibleBody" in text
    assert force[0] > 1.0  # it carries load: the mark is not about a zero
