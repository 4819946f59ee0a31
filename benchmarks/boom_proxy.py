"""Benchmark: the boom proxy of ``models/boom_proxy.py``, with and without linkages, on both backends.

Five sections on revolute joints, joints 2–5 driven through four-bar linkages (or, ``linkages=False``, by
cylinders directly), one cylinder, 4/3 valve and PI loop per joint, one pump with a relief valve, joint ramps
over 20 s. For each variant it prints the unknowns and states, the cold build (fresh cache directory) and the
cached build (best of three ``Simulation`` of a new instance, same cache, once the background gcc has stored the
compiled library in the entry, as a later session finds it), and for both backends the wall time of one
20 s run (on the default backend twice: first while gcc compiles the model's C in the background — interpreted
until it is ready — then, "C ready", once the library is in use), the real-time factor (simulated / wall time),
IDA steps and residual / Jacobian evaluations, and the largest tracking error. Times are wall / CPU (this
process and its gcc children); on a shared machine the CPU figures are the steadier ones.

Run: ``python benchmarks/boom_proxy.py`` (repository root; ``--t-end 5`` for a shorter run, ``--direct`` or
``--linkages`` for one variant). No timing is asserted. Timings depend on the machine's load: compare ratios
within one run.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
import sys
import tempfile
import time

import numpy as np

import flexlib as fl
from flexlib.models.boom_proxy import BoomProxy


def _cpu() -> float:
    """CPU time of this process and its finished children (gcc of the code generation) [s]."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def main(argv: list[str]) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=20.0, help="simulated time [s] (default 20)")
    ap.add_argument("--linkages", action="store_true", help="only the linkage variant")
    ap.add_argument("--direct", action="store_true", help="only the direct-cylinder variant")
    ap.add_argument("--solvers", default="ida,casadi-idas", help="comma-separated backends")
    args = ap.parse_args(argv)
    variants = [True, False]
    if args.linkages != args.direct:
        variants = [args.linkages]
    exp = BoomProxy.experiment
    print(f"Boom proxy, {args.t_end:g} s, rtol {exp.rtol:g}, atol {exp.atol:g}, output every {exp.dt_out:g} s; "
          "OMP_NUM_THREADS=1; one run per cell (machine shared with other jobs: compare within the table)\n")
    print("| variant | unknowns | states | build cold (s) | build cached (s) | solver | run (s) | real-time factor "
          "| IDA steps | res evals | jac evals | max tracking error (deg) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("(times: wall / CPU incl. gcc children; real-time factor = simulated time / run time, wall / CPU)")
    table = []
    for linkages in variants:
        os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
        t0, c0 = time.perf_counter(), _cpu()
        sim = fl.Simulation(BoomProxy(linkages=linkages))
        cold, cold_c = time.perf_counter() - t0, _cpu() - c0
        name = "linkages" if linkages else "direct cylinders"
        runs = args.solvers.split(",")
        rows = []
        if "ida" in runs:  # the default backend again once the background gcc has finished (C from the start)
            runs.insert(runs.index("ida") + 1, "ida (C ready)")
        for label in runs:
            solver = label.split(" ")[0]
            if label.endswith("(C ready)"):
                m = sim.compiled
                deadline = time.monotonic() + 1200.0
                while m.library is None and m.library_pending is not None and time.monotonic() < deadline:
                    if m.c_ready():
                        m.function("res")  # adopt the library
                    else:
                        time.sleep(0.2)
                if m.library is None:
                    print(f"| {name} | {m.n} | | | | {label} | no library (gcc did not finish) |")
                    continue
            t0, c0 = time.perf_counter(), _cpu()
            try:
                res = sim.run(args.t_end, dt_out=exp.dt_out, rtol=exp.rtol, atol=exp.atol, progress=False,
                              solver=solver)
            except fl.SolverError as err:
                print(f"| {name} | {sim.compiled.n} | | | | {label} | failed: {str(err)[:120]} |")
                continue
            run, run_c = time.perf_counter() - t0, _cpu() - c0
            s = res.stats
            rows.append((label, run, run_c, s, res))
        sim.compiled.wait_for_library(1200.0)  # the entry as a later session finds it: with its compiled library
        cached, cached_c = np.inf, np.inf
        for _ in range(3):  # best of 3 (a new model instance each time, same cache)
            t0, c0 = time.perf_counter(), _cpu()
            fl.Simulation(BoomProxy(linkages=linkages))
            cached, cached_c = min(cached, time.perf_counter() - t0), min(cached_c, _cpu() - c0)
        for label, run, run_c, s, res in rows:
            err = max(float(np.abs(res[f"angle{n}.phi"] - res[f"set_point{n}.y"]).max()) for n in range(1, 6))
            print(f"| {name} | {sim.compiled.n} | {int(sim.compiled.differential.sum())} | {cold:.2f} / {cold_c:.2f} | "
                  f"{cached:.3f} / {cached_c:.3f} | {label} | {run:.2f} / {run_c:.2f} | {args.t_end / run:.2f} / "
                  f"{args.t_end / run_c:.2f} | {s['steps']} | {s['nfev']} | {s['njev']} | {np.degrees(err):.3f} |",
                  flush=True)
            table.append((name, sim.compiled.n, int(sim.compiled.differential.sum()), cold, cold_c, cached, cached_c,
                          label, run, run_c, args.t_end / run, args.t_end / run_c, s["steps"], s["nfev"], s["njev"],
                          np.degrees(err)))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures = []
    for r in table:
        if r[7] == "ida (C ready)":
            figures += [(f"{r[0]}: real-time factor (C ready, CPU)", r[11], ""), ("build cold CPU", r[4], "s"),
                        ("cached CPU", r[6], "s")]
    report.write_results(__file__, figures, tables=[report.table(
        f"Boom proxy, {args.t_end:g} s, rtol {exp.rtol:g}, atol {exp.atol:g}, output every {exp.dt_out:g} s; one run "
        "per cell; CPU includes gcc children", ["variant", "unknowns", "states", "build cold [s]", "build cold CPU [s]",
                                               "build cached [s]", "build cached CPU [s]", "solver", "run [s]",
                                               "run CPU [s]", "real-time factor (wall)", "real-time factor (CPU)",
                                               "IDA steps", "res evals",
                                               "jac evals", "max tracking error [deg]"], table)])


if __name__ == "__main__":
    main(sys.argv[1:])
