"""The pump truck's Monte Carlo study over manufacturing tolerances (``flexlib.models.pump_truck.studies.tolerances``)
with two samples: the variants lie in their bands around the nominal machine, every run succeeds, the nominal row
equals a serial run of the scenario, and the figure is written."""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib import registry
from flexlib.models.pump_truck.studies import tolerances as study


def test_variants_lie_in_their_tolerance_bands_and_are_reproducible():
    """Bores within ±1 %, section masses within ±3 %, seal friction within ±30 % of the nominal machine (first
    variant); the same seed gives the same samples."""
    v = study.variants(50, seed=3)
    nominal, samples = v[0], v[1:]
    for name, spread in study.tolerances().items():
        x = np.array([s[name] for s in samples]) / nominal[name] - 1.0
        assert np.all(np.abs(x) <= spread) and np.ptp(x) > spread, name
    assert study.variants(50, seed=3) == v and study.variants(50, seed=4) != v


def test_two_samples_run_and_the_nominal_row_is_the_serial_run(tmp_path):
    """The nominal machine and two samples on one worker: all succeed, the nominal row's peak hinge forces equal
    a serial run's exactly, the samples differ from it, the table and the figure exist."""
    result = study.run(2, workers=1, out=tmp_path, progress=False)
    assert [r["status"] for r in result.rows] == ["success"] * 3
    instance, scen = registry.scenario_model("pump-truck", study.SCENARIO)
    res = fl.Simulation(instance).run(scen.t_end, params=dict(scen.params), progress=False, **dict(scen.run))
    for key, reduce in study.REDUCTIONS.items():
        assert result.rows[0][key] == reduce(res), key
    assert result.rows[1]["peak_f2"] != result.rows[0]["peak_f2"]
    study.figure(result, tmp_path / "tolerances.png")
    assert (tmp_path / "tolerances.parquet").stat().st_size > 0 and (tmp_path / "tolerances.png").stat().st_size > 0


def test_drivers_find_the_parameter_a_reduction_follows():
    """Synthetic rows where every peak is ``1 + 2·(relative bore deviation of axis 2)``: the linear fit explains all of
    the variance (R² = 1 to 1e-12) and axis 2's bore carries all of it (share 1)."""
    from flexlib.study.run import StudyResult

    v = study.variants(40, seed=5)
    nominal = v[0]
    rows = []
    for sample in v:
        dev = sample["axis2.cylinder.cylinder.d_bore"] / nominal["axis2.cylinder.cylinder.d_bore"] - 1.0
        rows.append({**sample, "status": "success", **{k: 1.0 + 2.0 * dev for k in study.REDUCTIONS}})
    for r2, top in study.drivers(StudyResult(rows, None)).values():
        assert abs(r2 - 1.0) < 1e-12
        assert top[0][0] == "axis2.cylinder.cylinder.d_bore" and abs(top[0][1] - 1.0) < 1e-9 and top[1][1] < 1e-9
