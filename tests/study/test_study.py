"""Studies on Dask (``flexlib.study``, issue 33): variants, reductions in the workers, the Parquet table, restarts.

References: each row's reductions equal the same variant run serially with ``registry.run_scenario`` (the same
build and arithmetic: exactly); Latin hypercube samples put one value in each of the ``n`` equal strata of every
parameter's range (McKay et al. 1979); a uniform Monte Carlo sample stays within ``±relative`` of the nominal values.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import flexlib as fl
from flexlib import registry
from flexlib.study import Final, Peak, grid, latin_hypercube, monte_carlo, run_study

pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

REDUCTIONS = {"peak_s2": Peak("mass2.s"), "final_v2": Final("mass2.v")}


@pytest.fixture(scope="module")
def scheduler():
    """One local cluster (2 worker processes) for the module's studies, as a study starts its own: the workers preload
    flexlib (:mod:`flexlib.study.worker`)."""
    from flexlib.study import local_cluster

    with local_cluster(2) as cluster:
        yield cluster.scheduler_address


def test_the_workers_start_ready_for_runs(scheduler):
    """Each worker ran the preload as it started: the registered models are imported and the solver's C driver
    question answered in the worker process before any task (:mod:`flexlib.study.worker`)."""
    from distributed import Client

    def state() -> tuple[bool, bool]:
        from flexlib import registry
        from flexlib.solve import native

        return registry._loaded, bool(native._AVAILABLE)

    with Client(scheduler) as client:
        assert set(client.run(state).values()) == {(True, True)}


def test_grid_and_samples():
    assert grid(a=[1, 2], b=[10.0, 20.0, 30.0])[:2] == [{"a": 1.0, "b": 10.0}, {"a": 1.0, "b": 20.0}]
    assert len(grid(a=[1, 2], b=[10.0, 20.0, 30.0])) == 6
    lhs = latin_hypercube({"a": (0.0, 1.0), "b": (10.0, 20.0)}, 8, seed=3)
    for name, (lo, hi) in {"a": (0.0, 1.0), "b": (10.0, 20.0)}.items():
        strata = sorted(int((v[name] - lo) / (hi - lo) * 8) for v in lhs)
        assert strata == list(range(8))  # one value in each stratum
    assert latin_hypercube({"a": (0.0, 1.0)}, 4, seed=3) == latin_hypercube({"a": (0.0, 1.0)}, 4, seed=3)
    mc = monte_carlo({"m": 2.0, "c": 100.0}, 200, relative={"m": 0.01}, seed=1)
    m = np.array([v["m"] for v in mc])
    assert np.all(np.abs(m / 2.0 - 1) <= 0.01) and np.ptp(m) > 0.03 and all(v["c"] == 100.0 for v in mc)
    for call, match in ((lambda: grid(a=[]), "non-empty"), (lambda: grid(a=[1, float("nan")]), "finite"),
                        (lambda: latin_hypercube({"a": (1.0, 0.0)}, 4), "below high"),
                        (lambda: monte_carlo({"m": 1.0}, 0), "positive integer"),
                        (lambda: monte_carlo({"m": 1.0}, 5, relative={"x": 0.1}), "names no parameter")):
        with pytest.raises(fl.RunArgumentError, match=match):
            call()


def test_a_study_runs_every_variant_keeps_failures_and_restarts(scheduler, tmp_path):
    out = tmp_path / "study.parquet"
    variants = [*grid(**{"mass0.m": [1.0, 1.5], "spring0.c": [100.0, 200.0]}), {"mass0.m": -1.0, "spring0.c": 1.0}]
    res = run_study("n-mass-chain", variants, REDUCTIONS, scenario="short", scheduler=scheduler, out=out,
                    progress=False)
    assert [r["variant"] for r in res.rows] == [res.rows[k]["variant"] for k in range(5)]
    assert res.column("status") == ["success"] * 4 + ["failed"]
    assert "ParameterError: mass0.m = -1.0 [kg] is below its minimum" in res.rows[4]["error"]
    assert np.isnan(res.rows[4]["peak_s2"])
    for row, params in zip(res.rows[:4], variants[:4], strict=True):
        ref = registry.run_scenario("n-mass-chain", "short", params=params, progress=False).result
        assert row["peak_s2"] == np.max(np.abs(ref["mass2.s"])) and row["final_v2"] == ref["mass2.v"][-1]
    assert sum(r["build_time"] > 0 for r in res.rows) <= 2  # each worker builds once
    # the table on disk, and a restart that runs only what is missing
    again = run_study("n-mass-chain", [*variants, {"mass0.m": 2.0, "spring0.c": 100.0}], REDUCTIONS,
                      scenario="short", scheduler=scheduler, out=out, progress=False)
    def same(a, b):  # rows equal, NaN included
        return json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)

    assert all(same(a, b) for a, b in zip(again.rows[:5], res.rows, strict=True))  # read back, not run again
    assert again.rows[5]["status"] == "success" and again.rows[5]["mass0.m"] == 2.0
    import pyarrow.parquet as pq

    assert pq.read_table(out).num_rows == 6


def test_bad_requests_are_refused_before_any_worker_starts():
    with pytest.raises(fl.RegistryError, match="no-such-model"):
        run_study("no-such-model", [{"a": 1.0}], REDUCTIONS)
    with pytest.raises(fl.RunArgumentError, match="at least one reduction"):
        run_study("n-mass-chain", [{"mass0.m": 1.0}], {}, scenario="short")
    with pytest.raises(fl.RunArgumentError, match="workers = 0"):
        run_study("n-mass-chain", [{"mass0.m": 1.0}], REDUCTIONS, scenario="short", workers=0)


def test_the_sweep_command_writes_the_table_and_study_show_reads_it(scheduler, tmp_path):
    """``flexlib sweep`` over a 3 × 2 grid (the rows in the grid's order, the same numbers as run_study), then
    ``flexlib study show`` with its heat map; bad axes and reductions refused by name."""
    from click.testing import CliRunner

    from flexlib.cli import cli
    from flexlib.study.run import read_table

    out = tmp_path / "sweep.parquet"
    res = CliRunner().invoke(cli, ["sweep", "n-mass-chain", "-s", "short", "-p", "mass0.m=1:2:3", "-p",
                                   "spring0.c=100,200", "-r", "peak:mass2.s", "--scheduler", scheduler, "-o",
                                   str(out), "--no-progress"], catch_exceptions=False)
    assert res.exit_code == 0, res.output
    assert "6 runs, 0 failed" in res.output
    rows, meta = read_table(out)
    assert [(r["mass0.m"], r["spring0.c"]) for r in rows] == [(m, c) for m in (1.0, 1.5, 2.0) for c in (100.0, 200.0)]
    assert meta["params"] == ["mass0.m", "spring0.c"] and meta["reductions"] == ["peak(mass2.s)"]
    ref = registry.run_scenario("n-mass-chain", "short", params={"mass0.m": 1.5, "spring0.c": 200.0},
                                progress=False).result
    assert rows[3]["peak(mass2.s)"] == np.max(np.abs(ref["mass2.s"]))
    shown = CliRunner().invoke(cli, ["study", "show", str(out), "--plot", str(tmp_path / "map.png")],
                               env={"COLUMNS": "200"}, catch_exceptions=False)
    assert shown.exit_code == 0 and "n-mass-chain, 6 runs, 0 failed" in shown.output
    assert (tmp_path / "map.png").stat().st_size > 1000
    for args, message in ((["-p", "mass0.m=1:2"], "give NAME=LOW:HIGH:N"), (["-r", "mean:mass2.s"], "KIND:SIGNAL")):
        base = {"-p": ["-p", "mass0.m=1:2:2"], "-r": ["-r", "peak:mass2.s"]}
        base[args[0]] = args
        bad = CliRunner().invoke(cli, ["sweep", "n-mass-chain", *base["-p"], *base["-r"], "-o",
                                       str(tmp_path / "x.parquet")], catch_exceptions=False)
        assert bad.exit_code != 0 and message in bad.output


def test_the_sweep_command_starts_from_another_pose(scheduler, tmp_path):
    """``flexlib sweep pump-truck -s hold --pose ...``: the runs start from the given pose (boom 5 held at −10°
    instead of the scenario's 0°, drifting by less than 0.01 rad in the 30 s hold); a scenario without a start pose in
    its data, or angles that are not numbers, are refused."""
    from click.testing import CliRunner

    from flexlib.cli import cli
    from flexlib.study.run import read_table

    out = tmp_path / "pose.parquet"
    res = CliRunner().invoke(cli, ["sweep", "pump-truck", "-s", "hold", "--pose", "0,0,0,0,0,-10", "-p",
                                   "axis3.cbv_hold.pilot_ratio=3,3.5", "-r", "final:joint5.phi", "--scheduler",
                                   scheduler, "-o", str(out), "--no-progress"], catch_exceptions=False)
    assert res.exit_code == 0, res.output
    rows, meta = read_table(out)
    assert meta["scenario"] == "hold@pose" and len(rows) == 2
    assert all(abs(r["final(joint5.phi)"] - np.radians(-10.0)) < 0.01 for r in rows), rows
    for args, message in ((["n-mass-chain", "-s", "short", "--pose", "1,2"], "has no start pose"),
                          (["pump-truck", "-s", "hold", "--pose", "0,a"], "DEG,DEG")):
        bad = CliRunner().invoke(cli, ["sweep", *args, "-p", "x=1,2", "-r", "peak:y", "-o",
                                       str(tmp_path / "x.parquet")], catch_exceptions=False)
        assert bad.exit_code != 0 and message in bad.output, bad.output
