"""The composed pump truck holds five poses with the forces of an independent hand statics (issue 28's check).

Reference: :func:`tests.models.hand_statics.hand_statics` — free-body equilibrium of every body of the boom on its
design record (sections with pipe and hose, cylinder housings and rods as bodies on their pins, levers and links as
slender bars), solved as one linear system; nothing of it is read from the simulation model. The model's static
start (``Simulation.initialize``: joints at rest in the pose, each cylinder's free chamber at tank pressure, the
holding pressures and the cut forces solved for) in each pose:

* cylinder force ``(p_A − p_T) A_p − (p_B − p_T) A_r`` (no seal friction at rest) within 1 % of ``F_cyl``;
* hinge force on section ``n`` (``−joint{n}.frame_b.f``, section ``n``'s frame) within 1 % of the hand statics'
  magnitude, each component within 1 % of it (measured: 1e-12).

Both pipe states: filled (the worst case the machine is sized on) and empty (only the load changes).
"""

from __future__ import annotations

import pytest

import flexlib as fl
from flexlib.models.pump_truck.model import P_TANK, PumpTruck
from tests.models import hand_statics as hand

POSES_DEG = {  # q1 … q5
    "extended": (0.0, 0.0, 0.0, 0.0, 0.0),
    "working": (50.0, 10.0, -30.0, 20.0, -40.0),
    "steep": (75.0, 20.0, -40.0, 60.0, -30.0),
    "half folded": (30.0, 90.0, -90.0, 90.0, -90.0),
    "near the fold": (5.0, 160.0, -160.0, 160.0, -160.0),
}


@pytest.fixture(scope="module", params=[True, False], ids=["filled", "empty"])
def static_starts(request) -> tuple[PumpTruck, dict[str, fl.Result]]:
    """The static start of every pose, on one build (the pose is a start value)."""
    return hand.static_starts(lambda q: PumpTruck(pose=(0.0, *q), slewing=False, filled=request.param), POSES_DEG)


@pytest.mark.parametrize("pose", POSES_DEG)
def test_static_start_has_the_hand_statics_forces(static_starts, pose: str) -> None:
    model, results = static_starts
    hand.check_static_start(model, results[pose], POSES_DEG[pose], P_TANK, rel=1e-2, label=pose)
