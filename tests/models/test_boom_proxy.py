"""The boom proxy (``models/boom_proxy.py``): statics at the start and tracking of the joint ramps.

References: (1) virtual work on the hand-derived boom geometry (``boom_proxy.statics``: gravity generalized
forces ``Q_k = −∂V/∂q_k`` and cylinder levers ``∂l_k/∂q_k`` differentiated exactly by CasADi, independent of
flexlib's multibody equations). Started at rest with the chambers at the holding pressures, the boom must be
in equilibrium: flexlib's joint accelerations at t = 0 below 1e-6 rad/s² (a moment error of 1e-6 of joint 1's
gravity moment, 6.8e5 N.m, on the boom's ~1e6 kg.m² about joint 1 gives ~1e-6 rad/s²; measured ~1e-13), the
cylinder forces equal ``−Q_k/(∂l_k/∂q_k)`` to 1e-6 relative and the holding chamber is at 200 bar gauge.
(2) The PI loops follow the 0.5°/s joint ramps within 0.5° over the first 2 s (measured ≤ 0.27°), and every
joint moves by more than half of its set-point's 1° in that time.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.boom_proxy import BAR, P_AMB, RAMP_DEG, T_RAMP, BoomProxy, statics

T_RUN = 2.0  # s


@pytest.fixture(scope="module")
def linked() -> tuple[BoomProxy, fl.Result]:
    model = BoomProxy(linkages=True)
    res = fl.Simulation(model, use_cache=False).run(T_RUN, dt_out=0.01, rtol=1e-6, atol=1e-8, progress=False)
    return model, res


def _check_statics(model: BoomProxy, res: fl.Result) -> None:
    st = statics(model.linkages)
    assert np.all(np.abs(st["Q"]) > 1e3)  # every joint really carries a gravity moment [N.m]
    for k in range(5):
        n = k + 1
        assert abs(res[f"joint{n}.a"][0]) < 1e-6, f"joint{n} accelerates at t = 0"
        assert abs(res[f"joint{n}.w"][0]) < 1e-12
        F = res[f"cylinder{n}.cylinder.F"][0]
        assert F == pytest.approx(-st["Q"][k] / st["dl"][k], rel=1e-6)
        hold = f"cylinder{n}.cylinder.p_A" if F > 0 else f"cylinder{n}.cylinder.p_B"
        assert res[hold][0] - P_AMB == pytest.approx(200 * BAR, rel=1e-9)


def test_holding_pressures_balance_gravity_with_linkages(linked):
    model, res = linked
    assert len([c for c in vars(model) if c.startswith("link_pin")]) == 4  # four closed four-bar loops
    _check_statics(model, res)


def test_holding_pressures_balance_gravity_direct_cylinders():
    model = BoomProxy(linkages=False)
    res = fl.Simulation(model, use_cache=False).run(0.02, dt_out=0.01, rtol=1e-6, atol=1e-8, progress=False)
    _check_statics(model, res)


def test_joint_ramps_are_tracked(linked):
    _, res = linked
    for k in range(5):
        n = k + 1
        err = res[f"angle{n}.phi"] - res[f"set_point{n}.y"]
        assert np.abs(err).max() < math.radians(0.5), f"joint{n}: {np.degrees(np.abs(err).max()):.3f} deg"
        moved = res[f"angle{n}.phi"][-1] - res[f"angle{n}.phi"][0]
        travel = math.radians(RAMP_DEG[k]) * T_RUN / T_RAMP
        assert moved / travel > 0.5  # moved more than half the set-point's travel
    assert np.all(np.abs(res["valve1.u"]) < 1.0)  # not saturated: tracking by control, not by the end stops
