"""Independent hand statics (free-body equilibrium, :mod:`models.pump_truck.free_body`) against the design statics
(virtual work, :func:`models.pump_truck.statics.cylinder_forces`), both machines, five held poses each.

References: two independent methods of the same rigid statics (Meriam & Kraige, *Engineering Mechanics: Statics*,
ch. 3 and 6 against ch. 7) must agree to round-off: cylinder forces to 1e-6 relative (measured ~1e-14). Global
check in closed form: the turret's reactions on the boom (hinge 1 and cylinder 1's housing pin) add up to the weight
of everything above joint 1 (boxes, filled or empty pipe, hose, cylinder housings and rods, levers and links) to
1e-9, and their moment about joint 1 to the gravity moment ``g Σ m x`` of the boom's lumped masses.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from flexlib.models.pump_truck.parameters import PumpTruckParameters
from flexlib.models.pump_truck.record32 import BOOM32
from flexlib.models.pump_truck.statics import cylinder_forces, design_cylinders, point_masses
from tests.models.hand_statics import hand_statics, total_weight

REC42 = PumpTruckParameters()
#: Five held poses per machine [deg]: extended, working, steep, half folded, near the fold (transport pose 176 deg).
POSES = {
    "42m": (REC42, [(0, 0, 0, 0, 0), (50, 10, -30, 20, -40), (78, 20, -10, 10, -10), (30, 90, -90, 90, -90),
                    (5, 176, -176, 176, -176)]),
    "32m": (BOOM32, [(0, 0, 0, 0), (45, 20, -40, 30), (75, 10, -10, 10), (30, 90, -90, 90), (5, 176, -176, 176)]),
}
CASES = [(name, pose) for name, (_, poses) in POSES.items() for pose in poses]


@pytest.mark.parametrize(("machine", "pose"), CASES)
def test_cylinder_forces_free_body_against_virtual_work(machine, pose):
    rec = POSES[machine][0]
    q = np.radians(pose)
    hs = hand_statics(rec, q)
    F_vw, _ = cylinder_forces(rec, q, design_cylinders(rec))
    assert hs["residual"] < 1e-12
    np.testing.assert_allclose(hs["F_cyl"], F_vw, rtol=1e-6)


@pytest.mark.parametrize("machine", ["42m", "32m"])
def test_the_cylinders_weight_counts_in_both_methods(machine):
    """Massless cylinders (housing and rod 0 kg) against ``cylinder_forces(..., cylinders=False)``; the cylinders'
    weight changes the forces by more than 1 % somewhere (so the first test sees them)."""
    rec, poses = POSES[machine]
    massless = [{**c, "m_housing": 0.0, "m_rod": 0.0} for c in design_cylinders(rec)]
    q = np.radians(poses[1])
    bare = hand_statics(rec, q, massless)["F_cyl"]
    np.testing.assert_allclose(bare, cylinder_forces(rec, q, False)[0], rtol=1e-6)
    assert np.max(np.abs(hand_statics(rec, q)["F_cyl"] / bare - 1.0)) > 0.01


@pytest.mark.parametrize("filled", [True, False])
@pytest.mark.parametrize(("machine", "pose"), CASES)
def test_turret_reactions_carry_the_boom_weight_and_moment(machine, pose, filled):
    rec = POSES[machine][0]
    rec = replace(rec, pipe=replace(rec.pipe, filled=filled))
    q = np.radians(pose)
    hs = hand_statics(rec, q)
    W = total_weight(rec)
    assert hs["turret_force"] == pytest.approx([0.0, W], rel=1e-9, abs=1e-9 * W)
    _, m, x = point_masses(rec, q)
    assert hs["turret_moment"] == pytest.approx(rec.g * float(m @ x[:, 0]), rel=1e-9)
    assert hs["F_hinge_abs"] == pytest.approx(np.hypot(*hs["F_hinge"].T), rel=1e-12)


@pytest.mark.parametrize(("machine", "pose"), CASES)
def test_hinge_forces_carry_the_outboard_boom(machine, pose):
    """Cut through hinge ``n`` and link ``n``'s pin ``C``: the two forces carry the weight of the bodies beyond the
    cut (sections ``n … N``, the hose, the drives ``n + 1 … N``: from :func:`statics.point_masses`) and balance
    their gravity moment about joint ``n``, to 1e-9."""
    rec = POSES[machine][0]
    q = np.radians(pose)
    hs = hand_statics(rec, q)
    n_sec = len(rec.sections)
    _, m, x = point_masses(rec, q)
    # point_masses order per section k: section, housing, rod, then lever and link for k >= 1; the hose last
    drive_of = []
    for k in range(n_sec):
        drive_of += [(k, "section"), (k, "drive"), (k, "drive")] + [(k, "drive")] * (2 if k > 0 else 0)
    drive_of.append((n_sec - 1, "section"))
    assert len(drive_of) == len(m)
    for n in range(2, n_sec + 1):
        beyond = [i for i, (k, kind) in enumerate(drive_of) if k > n - 1 or (k == n - 1 and kind == "section")]
        W = rec.g * m[beyond].sum()
        f_C = hs["pins"][f"C{n}"]
        assert hs["F_hinge"][n - 1] + f_C == pytest.approx([0.0, W], rel=1e-9, abs=1e-9 * W)
        J_n = hs["J"][n - 1]
        gravity = -rec.g * float(m[beyond] @ (x[beyond, 0] - J_n[0]))
        d = hs["points"][f"C{n}"] - J_n
        assert d[0] * f_C[1] - d[1] * f_C[0] + gravity == pytest.approx(0.0, abs=1e-9 * abs(gravity))


def test_sign_conventions_extended_horizontal_42m():
    """Extended horizontal: cylinder 1 pushes (lifts section 1 at its bracket with more than the boom's weight), so
    hinge 1 holds section 1 down (the turret's force on section 1 points down) and cylinder 1's housing pin carries
    more than the weight; the cylinders of joints 2-5 push or pull with the fold directions +, -, +, -."""
    hs = hand_statics(REC42, np.zeros(5))
    assert np.all(np.sign(hs["F_cyl"]) == [1, 1, -1, 1, -1])
    assert hs["F_hinge"][0][1] < 0 < total_weight(REC42) < hs["pins"]["H1"][1]
    np.testing.assert_allclose(hs["F_hinge_section"], hs["F_hinge"], rtol=1e-12)  # all sections horizontal
    with pytest.raises(ValueError, match=r"free_body_statics: q needs 5 joint angles"):
        hand_statics(REC42, np.zeros(4))
