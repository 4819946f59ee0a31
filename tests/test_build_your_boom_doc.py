"""``docs/build_your_boom.md`` runs as written, and the physics its text states holds.

The guide's python blocks run in order in one namespace (as a reader pasting them into one session), in a fresh
directory; then the statements of its text, each against its hand calculation:

* the holding pressure of each cylinder at the start, ``(p_A − p_T) A_p``, is the virtual-work force
  ``τ_n / (dL_n/dq_n)`` of section 2 (Meriam & Kraige, *Statics*, ch. 7; Merritt §5's static balance) within 1 %
  (measured 3e-15; linkage and cylinders massless, so nothing is left out);
* joint 1's pin force plus the boom's weight is cylinder 1's push (equilibrium of the boom at rest), 1e-6 of the
  push (measured 1e-16);
* every joint ends the move within 0.15° of its target (measured 0.09°), rigid and with section 2 flexible;
* the flexible section's start deflection is the moment-area integral of its rigid-run loads within 3 % (measured
  1.1 %), and the rigid section's is zero by construction;
* the figure is written.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.doc_blocks import run_blocks


@pytest.fixture(scope="module")
def guide(tmp_path_factory):
    import matplotlib

    matplotlib.use("Agg")
    where = tmp_path_factory.mktemp("build_your_boom")
    mp = pytest.MonkeyPatch()
    mp.chdir(where)
    try:
        ns = run_blocks("docs/build_your_boom.md")
    finally:
        mp.undo()
    ns["where"] = where
    return ns


def test_holding_pressures_are_the_hand_calculation(guide):
    res, P_T = guide["res"], guide["P_TANK"]
    for n in (1, 2, 3):
        A_p = math.pi / 4 * guide["BORES"][n - 1] ** 2
        force = (res[f"axis{n}.cylinder.cylinder.p_A"][0] - P_T) * A_p
        assert force == pytest.approx(guide["F_START"][n - 1], rel=1e-2), f"joint {n}"
        assert res[f"axis{n}.cylinder.cylinder.p_B"][0] == pytest.approx(P_T, abs=1.0), f"joint {n}: free chamber"


def test_joint1_pin_balances_push_and_weight(guide):
    balance, weight = guide["balance"], guide["weight"]
    push = np.linalg.norm(guide["push"])
    assert balance[0] == pytest.approx(0.0, abs=1e-6 * push)
    assert balance[1] == pytest.approx(weight, abs=1e-6 * push)


@pytest.mark.parametrize("run", ["res", "res_flex"])
def test_joints_reach_their_targets(guide, run):
    res = guide[run]
    assert res.t[-1] == pytest.approx(20.0)
    for n in (1, 2, 3):
        assert math.degrees(res[f"joint{n}.phi"][-1]) == pytest.approx(math.degrees(guide["Q_END"][n - 1]),
                                                                      abs=0.15), f"joint {n}"


def test_flexible_deflection_is_the_moment_area_estimate(guide):
    sag, sag_hand = guide["sag"], guide["sag_hand"]
    assert sag_hand < -5e-3  # bent down, by millimetres
    assert sag[0] == pytest.approx(sag_hand, rel=0.03)
    assert "section2.deflection.r_rel" not in guide["res"].names  # the rigid section: no deflection to read


def test_figure_written(guide):
    import matplotlib.image as mpimg

    assert mpimg.imread(guide["where"] / "boom_move.png").shape[0] > 300
