"""Component-built planar mechanisms against two hand-written formulations of the same mechanism.

References (``benchmarks/minimal_dae.py``): (1) the minimal-coordinate ODE in the crank angle (closed-form
loop closure, Lagrange's equation) integrated by CVODE at rtol 1e-12; (2) the hand-written minimal
dummy-derivative index-1 DAE in absolute link angles, IDA at rtol 1e-10. The component-built model
(``models/planar_mechanisms.py``: World, Fixed, Revolute, FixedTranslation, Body in 3D) runs at rtol 1e-10.
Tolerance: every absolute link angle within 1e-6 rad of the ODE over 1 s (measured 2e-8–1.2e-7; a 1 % error
in one coupler's mass or inertia moves the angles by 1.7e-3–1.4e-2 rad within 1 s). Energy: the ODE
conserves ``T + V`` to 1e-8 relative.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.planar_mechanisms import (
    FourBarLinkage,
    ThreeLoopLinkage,
    assemble,
    fourbar_spec,
    three_loop_spec,
)
from flexlib.models.reference.planar_minimal import MinimalDAE, MinimalODE

T_END, RTOL = 1.0, 1e-10
GRID = np.linspace(0.0, T_END, 101)


def test_fourbar_spec_is_the_test_loops_fourbar():
    """The spec's assembly at θ2 = 0.3 rad equals the closed-form open-branch position analysis (Norton §4.5)
    used by the catalogue's four-bar, to 1e-12 rad."""
    from flexlib.models.reference import closed_form as ref

    th = assemble(fourbar_spec(), 0.3)
    th3, th4 = ref.fourbar_angles(0.2, 0.7, 0.9, 0.6, 0.3, "open")
    assert th["coupler"] == pytest.approx(float(th3), abs=1e-12)
    assert th["rocker"] == pytest.approx(float(th4), abs=1e-12)


@pytest.mark.parametrize(("model_cls", "spec_fn", "n_loops"), [(FourBarLinkage, fourbar_spec, 1),
                                                               (ThreeLoopLinkage, three_loop_spec, 3)],
                         ids=["four-bar", "7-body-3-loop"])
def test_component_built_matches_hand_written(model_cls, spec_fn, n_loops):
    spec = spec_fn()
    ode = MinimalODE(spec)
    ref = ode.solve(GRID, rtol=1e-12)
    energy = [float(ode.energy(x)) for x in ref["x"]]
    assert np.ptp(energy) <= 1e-8 * max(abs(energy[0]), 1.0)
    dae = MinimalDAE(spec)
    assert dae.n == 2 + 3 * (len(spec.links) - 1) + 2 * n_loops
    hand = dae.solve(GRID, rtol=RTOL)
    model = model_cls()
    sim = fl.Simulation(model, use_cache=False)
    assert len(sim.report.redundant) == 3 * n_loops  # out-of-plane loop rows dropped
    res = sim.run(T_END, dt_out=T_END / 100, rtol=RTOL, atol=RTOL * 1e-2, progress=False)
    q_fl = model.absolute_angles(res)
    moved = 0.0
    for name in ref["q"]:
        np.testing.assert_allclose(hand["q"][name], ref["q"][name], rtol=0, atol=1e-6, err_msg=f"hand-written {name}")
        np.testing.assert_allclose(np.interp(GRID, res.t, q_fl[name]),
                                   ref["q"][name], rtol=0, atol=1e-6, err_msg=f"component-built {name}")
        moved = max(moved, float(np.ptp(ref["q"][name][1:])))
    assert ref["q"][spec.links[0].name][-1] - spec.theta0 > 2.0  # the crank really turns
    assert moved > 0.1
