"""The seed-001 pinned-free beam (``models/pinned_free_beam.py``) against an independent geometrically exact
reference: a planar ANCF beam (exact curvature, Green axial strain, 128 elements, generalised-α, converged in
elements and step; ``benchmarks/references/pinned_free_beam.py``, stored in
``tests/data/pinned_free_beam_reference.npz``; its own convergence: 0.001 % tip y, 0.7 % tip deflection, 0.4 %
averaged moment). Error: the seed's eq. 2 (mean |z − z*| over 201 samples / max |z*| × 100).

Issue 10's targets with at most four modes: tip y ≤ 0.1 %, tip deflection ≤ 5 %, averaged moment ≤ 10 %.
Measured with hinged-beam modes and the mode-acceleration recovery of deflection and moment: four modes give
0.024 %, 1.56 % and 1.11 %; plain modal superposition converges slowly in the deflection (12.6, 8.7, 5.05 % for
1, 2, 4 modes; 1.6 % recovered at 4), because the pin tangent is the slope where the torque acts. The MPF method
keeps five modes at its 1 % threshold.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from flexlib.models.pinned_free_beam import (
    beam_modal_data,
    bending_modes,
    participation_table,
    seed_error,
    simulate,
    simulate_modes,
)

REFERENCE = Path(__file__).resolve().parents[1] / "data" / "pinned_free_beam_reference.npz"


@pytest.fixture(scope="module")
def reference():
    return np.load(REFERENCE)


@pytest.fixture(scope="module")
def data():
    return beam_modal_data()


def errors(run, reference, recovered: bool = True) -> tuple[float, float, float]:
    """Seed errors of tip y, tip deflection and averaged moment (mode-acceleration recovery or plain)."""
    series = (run.tip_y, run.tip_deflection_ma, run.moment_mid_avg_ma) if recovered else (
        run.tip_y, run.tip_deflection, run.moment_mid_avg)
    return tuple(seed_error(z, reference[k]) for z, k in zip(series, ("tip_y", "tip_deflection", "moment_mid_avg"),
                                                            strict=True))


def test_four_modes_meet_all_targets(data, reference):
    """Four hinged-beam modes with geometric stiffening, deflection and moment by mode-acceleration recovery: tip y
    ≤ 0.1 %, tip deflection ≤ 5 %, averaged moment ≤ 10 % (measured 0.024, 1.56, 1.11 %)."""
    e = errors(simulate(4, data=data), reference)
    assert e[0] <= 0.1
    assert e[1] <= 5.0
    assert e[2] <= 10.0


def test_mpf_selection_meets_all_targets(data, reference):
    """The MPF method (rigid run, critical instant t = 1 s, loads in equilibrium with the pin torque) keeps the modes
    at or above 1 %: five here; with them every target holds (tip y ≤ 0.1 %, deflection ≤ 5 %, moment ≤ 10 %)."""
    table, t_crit = participation_table(data)
    assert t_crit == pytest.approx(1.0, abs=1e-3)
    shares = table.shares
    assert shares[0] == pytest.approx(100.0)
    assert np.all(np.diff(shares[:8]) < 0)  # the share falls with the mode number (a smooth load)
    kept = [bending_modes(data)[k] for k in table.kept]
    assert len(kept) == 5
    e = errors(simulate_modes(kept, data=data), reference)
    assert e[0] <= 0.1 and e[1] <= 5.0 and e[2] <= 10.0


def test_errors_fall_with_modes_and_the_rigid_body_fails(data, reference):
    """The rigid body (no modes) misses the deflection entirely (error > 30 %, plain); one, two and four modes bring
    the tip deflection error down monotonically, plain (12.6 → 8.7 → 5.05 %) and recovered (4.9 → 2.9 → 1.6 %),
    and the recovery beats plain superposition at every count."""
    rigid = errors(simulate(0, data=data), reference, recovered=False)
    assert rigid[1] > 30.0
    runs = [simulate(n, data=data) for n in (1, 2, 4)]
    plain = [errors(r, reference, recovered=False)[1] for r in runs]
    recovered = [errors(r, reference)[1] for r in runs]
    assert plain[0] > plain[1] > plain[2]
    assert recovered[0] > recovered[1] > recovered[2]
    assert all(r < p for r, p in zip(recovered, plain, strict=True))
