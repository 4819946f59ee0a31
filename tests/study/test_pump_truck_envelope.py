"""The pump truck's emergency-stop envelope study (``flexlib.models.pump_truck.studies.envelope``) on one start pose
other than the scenario's and two pilot ratios: a study on a scenario record of the user's (another start pose), its
rows equal to serial runs of that record, the pilot ratio set on the four valves of axes 1 and 2."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import flexlib as fl
from flexlib import registry
from flexlib.models.pump_truck.studies import envelope as study


def test_one_pose_two_ratios_equal_serial_runs_of_the_pose(tmp_path):
    pose = study.poses()[-1]  # boom raised 80°, section 3 at −60°: not the scenario's pose
    results = study.run(workers=1, out=tmp_path, pose_list=[pose], ratios=(2.5, 4.0), progress=False)
    (got_pose, res), = results
    assert got_pose == pose and [r["status"] for r in res.rows] == ["success"] * 2
    base = registry.get_scenario("pump-truck", study.SCENARIO)
    scen = replace(base, data={**dict(base.data), "pose": list(pose)})
    instance, scen = registry.scenario_model("pump-truck", scen)
    sim = fl.Simulation(instance)
    for row, ratio in zip(res.rows, (2.5, 4.0), strict=True):
        params = {**dict(scen.params), **{v + ".pilot_ratio": ratio for v in study.VALVES}}
        run = sim.run(scen.t_end, params=params, progress=False, **dict(scen.run))
        assert abs(run["joint1.phi"][0] - np.radians(pose[1])) < 1e-9  # started in the record's pose
        for key, reduce in study.REDUCTIONS.items():
            assert row[key] == reduce(run), key
    assert res.rows[0]["max_p1A"] != res.rows[1]["max_p1A"]
    m = study.matrices(results)
    assert m["max_p"].shape == (1, 2) and np.all(m["max_p"] >= m["max_p1A"])
    study.figure(results, (2.5, 4.0), tmp_path / "envelope.png")
    assert (tmp_path / "envelope.png").stat().st_size > 0
