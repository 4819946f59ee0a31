"""DRAFT (issue 28): the boom composed of the parts holds every pose with the independent hand statics' forces.

Reference: :func:`flexlib.models.pump_truck.statics.cylinder_forces` — virtual work on the record's own geometry with
sections, pipe, hose, cylinder housings and rods (``LineForceWithTwoMasses`` positions) and levers and links, none of
it read from the simulation model. The holding chamber's pressure at the static start is ``p_T + F/A`` (cap side
when the cylinder pushes, rod side when it pulls); checked to 1 % in five poses (measured: 1e-14).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.pump_truck.composed import ComposedPumpTruck
from flexlib.models.pump_truck.parameters import PumpTruckParameters
from flexlib.models.pump_truck.statics import cylinder_forces, design_cylinders, sizing

REC = PumpTruckParameters()
P_T = 1.01325e5
POSES_DEG = {  # q1 … q5
    "extended": (0.0, 0.0, 0.0, 0.0, 0.0),
    "working": (50.0, 10.0, -30.0, 20.0, -40.0),
    "steep": (75.0, 20.0, -40.0, 60.0, -30.0),
    "half folded": (30.0, 90.0, -90.0, 90.0, -90.0),
    "near the fold": (5.0, 160.0, -160.0, 160.0, -160.0),
}


@pytest.mark.parametrize("pose", POSES_DEG)
def test_static_start_holds_with_the_hand_statics_forces(pose: str) -> None:
    q = np.radians(POSES_DEG[pose])
    F, _ = cylinder_forces(REC, q, design_cylinders(REC))
    res = fl.Simulation(ComposedPumpTruck(q0=(0.0, *q), slewing=False), codegen=False).run(
        0.1, dt_out=0.1, progress=False)
    for k, row in enumerate(sizing(REC)):
        A_p, A_r = math.pi / 4 * row["bore"] ** 2, math.pi / 4 * (row["bore"] ** 2 - row["rod"] ** 2)
        side, area = ("p_A", A_p) if F[k] >= 0 else ("p_B", A_r)
        p = res[f"axis{k + 1}.cylinder.cylinder.{side}"][0]
        assert p == pytest.approx(P_T + abs(F[k]) / area, rel=1e-2), (pose, k + 1)
