"""Design record of the 32 m four-section boom (issue 28, second machine) and the record for N = 4 … 6 sections.

References: issue 28's design check (every bore 100–280 mm at a system pressure <= 350 bar, holding at
``p_hold_fraction`` of it, transmission angles >= the record's minimum, retracted length >= stroke + dead length),
evaluated by the same sizing code as the 42 m record (:func:`statics.sizing`); the four-section statics: the joint-1
torque against the gravity moment in closed form at 1e-12 (every cylinder force against free-body statics in
``test_hand_statics.py``).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from flexlib.errors import ParameterError
from flexlib.models.pump_truck.parameters import PumpTruckParameters
from flexlib.models.pump_truck.record32 import BOOM32
from flexlib.models.pump_truck.statics import (
    cylinder_forces,
    design_cylinders,
    joint_torques,
    mass_properties,
    point_masses,
    sizing,
)

REC42 = PumpTruckParameters()


def test_four_sections_three_lever_and_link_drives_about_28_m_long():
    assert BOOM32.n_sections == 4 and len(BOOM32.linkages) == 3
    assert sum(s.length for s in BOOM32.sections) == pytest.approx(28.0)  # 32Z-Meter: 92 ft horizontal reach
    for k, sec in enumerate(BOOM32.sections):
        assert mass_properties(BOOM32, k, pipe=False)["m"] == pytest.approx(sec.mass, rel=0.01)


def test_bores_pressures_transmission_and_dead_length():
    """Issue 28's check on the second machine: every bore 100–280 mm, worst holding pressure <= 80 % of
    p_system <= 350 bar (pipe filled, full reach, cylinder housings and rods counted), every transmission angle
    >= the record's minimum, retracted length >= stroke + dead length."""
    assert BOOM32.p_system <= 35e6
    rows = sizing(BOOM32)
    assert len(rows) == 4
    for row in rows:
        assert row["sized"], row
        assert 0.1 <= row["bore"] <= 0.28, row
        assert row["p_worst"] <= BOOM32.p_hold_fraction * BOOM32.p_system, row
        assert max(row["p_worst_A"], row["p_worst_B"]) == row["p_worst"]
        assert row["min_transmission_deg"] >= BOOM32.min_transmission_deg, row
        assert row["fits"] and row["l_min"] >= row["stroke"] + row["dead"], row
        assert row["m_housing"] > 0 and row["m_rod"] > 0
    assert [round(r["bore"] * 1e3) for r in rows] == [180, 180, 180, 100]


def test_sized_once_on_the_worst_case_whatever_the_pipe_state():
    empty = replace(BOOM32, pipe=replace(BOOM32.pipe, filled=False))
    assert [(r["bore"], r["rod"], r["stroke"]) for r in sizing(empty)] == \
        [(r["bore"], r["rod"], r["stroke"]) for r in sizing(BOOM32)]


@pytest.mark.parametrize("k", range(1, 5))
def test_no_dead_centre_inside_the_range(k):
    drive = BOOM32.drive(k)
    qs = np.linspace(drive.q_min, drive.q_max, 361)
    arms = [drive.state(q).lever_arm for q in qs]
    assert np.all(np.sign(arms) == np.sign(arms[0]))
    assert min(min(drive.state(q).transmission.values()) for q in qs) >= BOOM32.min_transmission_deg


@pytest.mark.parametrize("q_deg", [(0, 0, 0, 0), (50, 10, -30, 20), (30, 120, -90, 150)])
def test_four_section_torques_at_joint_1_are_the_gravity_moment(q_deg):
    """Every mass but cylinder 1's turns rigidly with joint 1 (drives 2-4 ride on the boom): with cylinder 1 taken
    massless, ``tau_1 = g Σ m_i x_i`` about the origin (every cylinder force against free-body statics, cylinder 1's
    weight included: ``test_hand_statics.py``)."""
    q = np.radians(q_deg)
    cyls = (dict(design_cylinders(BOOM32)[0], m_housing=0.0, m_rod=0.0), *design_cylinders(BOOM32)[1:])
    J, m, x = point_masses(BOOM32, q, cyls)
    tau = joint_torques(BOOM32, q, cyls)
    F, arm = cylinder_forces(BOOM32, q, cyls)
    assert J.shape == (5, 2) and tau.shape == F.shape == arm.shape == (4,)
    assert tau[0] == pytest.approx(BOOM32.g * float(m @ x[:, 0]), rel=1e-12)
    np.testing.assert_allclose(F * arm, tau, rtol=1e-12)


def test_a_six_section_record_is_sized_joint_by_joint():
    six = replace(REC42, sections=(*REC42.sections, replace(REC42.sections[-1], length=4.0, mass=200.0)),
                  linkages=(*REC42.linkages, REC42.linkages[-1]))
    rows = sizing(six)
    assert [r["joint"] for r in rows] == [1, 2, 3, 4, 5, 6]
    J, _, _ = point_masses(six, np.zeros(6))
    assert J.shape == (7, 2) and J[-1][0] == pytest.approx(sum(s.length for s in six.sections))


@pytest.mark.parametrize(("sections", "linkages", "match"), [
    (REC42.sections[:4], REC42.linkages,
     r"sections must be 5 SectionSpec records \(root to tip\), got tuple of 4, for 4 linkages \(joints 2 \.\.\. 5\): "
     r"sections and linkages disagree, len\(linkages\) must be len\(sections\) - 1"),
    (REC42.sections, REC42.linkages[:3], r"sections must be 4 SectionSpec records .* got tuple of 5, for 3 linkages"),
    (REC42.sections[:3], REC42.linkages[:2], r"sections must be 4 to 6 SectionSpec records \(root to tip\), got 3"),
    ((*REC42.sections, *REC42.sections[:2]), (*REC42.linkages, *REC42.linkages[:2]),
     r"sections must be 4 to 6 SectionSpec records \(root to tip\), got 7"),
    (REC42.sections, (*REC42.linkages[:3], "joint5"),
     r"linkages must be a sequence of FourBar records \(joints 2 \.\.\. N\), got tuple of 4: FourBar, FourBar, "
     r"FourBar, str"),
])
def test_section_and_linkage_counts_are_checked(sections, linkages, match):
    with pytest.raises(ParameterError, match=r"pump-truck record: " + match):
        replace(REC42, sections=sections, linkages=linkages)


def test_the_joint_ranges_of_the_z_fold():
    folds = [math.copysign(1.0, d.q_max + d.q_min) for d in BOOM32.linkages]
    assert folds == [1.0, -1.0, 1.0]  # joints 2 and 4 fold up, joint 3 down
