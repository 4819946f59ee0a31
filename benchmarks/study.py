"""Benchmark: a 16-run sweep of the rigid pump truck's ``hold`` on Dask (``flexlib.study``) against the same runs in
one process.

Serial: one process builds the model (from a warm cache: the model and the solver's C driver compiled before) and runs
the 16 variants (axis 3's counterbalance pilot ratio 2.5 … 4 × axis 2's 2.5 … 4, a 4 × 4 grid) one after the other;
wall time. Dask: ``run_study`` with 2 worker processes on a local cluster started beforehand as a study starts its own
(:func:`flexlib.study.local_cluster`: the workers import flexlib and load the solver's driver as they start, like the
serial process before its clock starts; the start-up reported on its own), each worker building once from the same
cache; wall time of the study. Per-run overhead of a worker: from its second task on (the first builds), the time from
the end of one task to the start of the next (Dask's hand-over), as a share of the mean run's wall time; the task's
work besides the run (the reductions from the result, which the serial loop does too) reported beside it. Targets
(issue 33): Dask / serial ≤ 0.6, overhead ≤ 5 % of a run.

Run: ``python benchmarks/study.py`` (repository root).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import itertools
import tempfile
import time


def worker_overhead(rows: list[dict]) -> tuple[float, float, float]:
    """Per run of a worker after its first task (mean, [s]): Dask's hand-over (from the end of one task to the start of
    the next), the task's own work besides the run (the reductions from the result, the row), and the run."""
    gaps, inside, runs = [], [], []
    for pid in {r["worker"] for r in rows}:
        mine = sorted((r for r in rows if r["worker"] == pid), key=lambda r: r["t_start"])
        for prev, cur in itertools.pairwise(mine):
            gaps.append(cur["t_start"] - prev["t_end"])
            inside.append(cur["t_end"] - cur["t_start"] - cur["run_wall"])
            runs.append(cur["run_wall"])
    return sum(gaps) / len(gaps), sum(inside) / len(inside), sum(runs) / len(runs)


def main() -> None:
    with tempfile.TemporaryDirectory() as cache:
        os.environ["FLEXLIB_CACHE_DIR"] = cache
        import flexlib as fl
        from flexlib import registry
        from flexlib.study import Peak, grid, run_study

        variants = grid(**{"axis3.cbv_hold.pilot_ratio": [2.5, 3.0, 3.5, 4.0],
                           "axis2.cbv_hold.pilot_ratio": [2.5, 3.0, 3.5, 4.0]})
        reductions = {"peak_p3A": Peak("axis3.cylinder.cylinder.p_A"), "peak_p2A": Peak("axis2.cylinder.cylinder.p_A")}
        from flexlib.solve.native import native_available

        instance, scen = registry.scenario_model("pump-truck", "hold")
        fl.Simulation(instance).compiled.wait_for_library()  # the cache warm, the C library compiled
        native_available()  # the default solver's C driver compiled (once per machine) and loaded
        w0 = time.perf_counter()
        instance, scen = registry.scenario_model("pump-truck", "hold")
        sim = fl.Simulation(instance)
        serial = []
        for v in variants:
            res = sim.run(scen.t_end, params={**dict(scen.params), **v}, progress=False, **dict(scen.run))
            serial.append({k: f(res) for k, f in reductions.items()})
        t_serial = time.perf_counter() - w0

        from flexlib.study import local_cluster

        w0 = time.perf_counter()
        with local_cluster(2) as cluster:
            t_start = time.perf_counter() - w0
            w0 = time.perf_counter()
            table = run_study("pump-truck", variants, reductions, scenario="hold", scheduler=cluster.scheduler_address,
                              progress=False)
            t_study = time.perf_counter() - w0
    same = all(r[k] == s[k] for r, s in zip(table.rows, serial, strict=True) for k in reductions)
    builds = sum(table.column("build_time"))
    overhead, reductions_time, mean_run = worker_overhead(table.rows)
    print(f"serial: {len(variants)} runs in {t_serial:.2f} s (build from the warm cache included)")
    print(f"dask: cluster start {t_start:.2f} s; study {t_study:.2f} s with 2 workers; Dask / serial "
          f"{t_study / t_serial:.2f}; worker builds {builds:.2f} s CPU; mean run {mean_run:.3f} s; Dask's overhead per "
          f"run {overhead:.4f} s = {100 * overhead / mean_run:.1f} % of a run; reductions in the worker "
          f"{reductions_time:.3f} s a run (serial does them too); results identical to serial: {same}")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [("Dask / serial", t_study / t_serial, ""),
                                    ("overhead per run", 100 * overhead / mean_run, "% of a run"),
                                    ("cluster start", t_start, "s")],
                         tables=[report.table("16-run hold sweep, wall times", ["serial [s]", "study [s]",
                                                                                "cluster start [s]", "mean run [s]",
                                                                                "identical"],
                                              [[t_serial, t_study, t_start, mean_run, same]])])


if __name__ == "__main__":
    main()
