"""Benchmark: multibody build and run times: the N-link pendulum chain, the four-bar and the slider-crank.

* N-link pendulum chain (N = 2, 5, 10, 20, 50), 10 s, rtol 1e-6: build time (cold), unknowns and
  states, run time, steps — and how both grow with N. Build times exclude the generated C, which
  gcc compiles in the background (``codegen="auto"``); runs are timed once it is ready.
* Planar four-bar of four Revolutes (3 redundant loop rows) and the slider-crank, 10 s.

Run: ``python benchmarks/multibody.py`` (from the repository root; ``python benchmarks/multibody.py 2 5``
for chosen chain sizes). No timing is asserted. Times are wall (best of 2 for runs) and process CPU; on a shared
machine compare the CPU columns.

``--tree-frames=tear|keep|auto``: sets ``FLEXLIB_TREE_FRAMES`` — tear the tree's frame kinematics
(substituted forward kinematics, the behaviour before the rule), keep frame orientations ``T`` and origins ``r_0``
as unknowns in models without loops, or let the rule of ``compile/tearing.py`` choose by depth (default).
``--keep-tree-frames`` is the old spelling of ``--tree-frames=keep``.

``--crossover N...``: for each N, build + 10 s run of the chain torn and kept, process CPU, alternating — the
measurement behind ``tearing.KEEP_DEPTH`` (``docs/decisions/``).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import flexlib as fl
from flexlib.models.n_link_pendulum import NLinkPendulum

ROOT = Path(__file__).resolve().parent.parent


def _run(model: fl.Model, t_end: float = 10.0, rtol: float = 1e-6) -> tuple[fl.Simulation, float, fl.Result, float]:
    t, c = time.perf_counter(), time.process_time()
    sim = fl.Simulation(model, use_cache=False)
    build = time.perf_counter() - t
    CPU["build"] = time.process_time() - c
    m = sim.compiled  # generated C compiles in the background: time the runs on it
    while m.library is None and m.library_pending is not None:
        time.sleep(0.1)
        m.function("res")
    best, res = np.inf, None
    for _ in range(2):
        t, c = time.perf_counter(), time.process_time()
        res = sim.run(t_end, dt_out=0.01, rtol=rtol, atol=rtol * 1e-2, progress=False)
        best = min(best, time.perf_counter() - t)
        CPU["run"] = min(CPU.get("run", np.inf), time.process_time() - c)
    return sim, build, res, best


CPU: dict[str, float] = {}


def crossover(sizes: list[int], repeats: int = 2) -> None:
    """Build + 10 s run CPU of the chain with the tree frames torn and kept (alternating, best of ``repeats``)."""
    print("| N | torn: unknowns / build / run / total CPU (s) | kept: unknowns / build / run / total CPU (s) | "
          "kept / torn |")
    print("|---|---|---|---|")
    for n in sizes:
        best: dict[str, tuple] = {}
        for _ in range(repeats):
            for mode in ("tear", "keep"):
                os.environ["FLEXLIB_TREE_FRAMES"] = mode
                CPU.clear()
                sim, _, _, _ = _run(NLinkPendulum(n))
                total = CPU["build"] + CPU["run"]
                if mode not in best or total < best[mode][3]:
                    best[mode] = (sim.compiled.n, CPU["build"], CPU["run"], total)
        t, k = best["tear"], best["keep"]
        print(f"| {n} | {t[0]} / {t[1]:.2f} / {t[2]:.2f} / {t[3]:.2f} | {k[0]} / {k[1]:.2f} / {k[2]:.2f} / {k[3]:.2f} "
              f"| {k[3] / t[3]:.2f} |", flush=True)
    os.environ.pop("FLEXLIB_TREE_FRAMES", None)


def main(argv: list[str]) -> None:
    if "--keep-tree-frames" in argv:
        argv = ["--tree-frames=keep" if a == "--keep-tree-frames" else a for a in argv]
    for a in [a for a in argv if a.startswith("--tree-frames=")]:
        argv.remove(a)
        os.environ["FLEXLIB_TREE_FRAMES"] = a.split("=", 1)[1]
        print(f"FLEXLIB_TREE_FRAMES={os.environ['FLEXLIB_TREE_FRAMES']}\n")
    if "--crossover" in argv:
        os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
        crossover([int(a) for a in argv if a != "--crossover"] or [2, 5, 8, 10, 12, 15, 20])
        return
    sizes = [int(a) for a in argv] or [2, 5, 10, 20, 50]
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    print("N-link pendulum chain, 10 s, rtol 1e-6, 1001 output points (times: run best of 2)\n")
    print("| N | unknowns | states | jac nnz | build (s) | build CPU (s) | run (s) | run CPU (s) | IDA steps | "
          "res evals | jac evals | state switches |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows, chain, mechanisms = [], [], []
    for n in sizes:
        CPU.clear()
        sim, build, res, run = _run(NLinkPendulum(n))
        s = res.stats
        rows.append((n, CPU["build"], CPU["run"]))
        chain.append((n, sim.compiled.n, int(sim.compiled.differential.sum()), len(sim.compiled.jac_row), build,
                      CPU["build"], run, CPU["run"], s["steps"], s["nfev"], s["njev"], s["state_switches"]))
        print(f"<!-- N = {n}: {sim.report.tree_frames} -->", flush=True)
        print(f"| {n} | {sim.compiled.n} | {int(sim.compiled.differential.sum())} | {len(sim.compiled.jac_row)} | "
              f"{build:.2f} | {CPU['build']:.2f} | {run:.2f} | {CPU['run']:.2f} | "
              f"{s['steps']} | {s['nfev']} | {s['njev']} | {s['state_switches']} |", flush=True)
    if len(rows) >= 3:
        n, b, r = (np.array(c, dtype=float) for c in zip(*rows, strict=True))
        kb = np.polyfit(np.log(n), np.log(b), 1)[0]
        kr = np.polyfit(np.log(n), np.log(r), 1)[0]
        print(f"\nGrowth (log-log slope over N, CPU): build ~ N^{kb:.2f}, run ~ N^{kr:.2f}")

    from flexlib.models.reference import closed_form as ref
    from flexlib.models.reference.four_bar import A, B, C, D, FourBar
    from flexlib.models.reference.slider_crank import SliderCrank

    th3, th4 = ref.fourbar_angles(A, B, C, D, 0.3, "open")
    print("\n| mechanism | unknowns | states | redundant rows | build (s) | run 10 s (s) | IDA steps | switches |")
    print("|---|---|---|---|---|---|---|---|")
    for name, model in (("four-bar (4 Revolutes)", FourBar(0.3, th3, th4, 6.0)),
                        ("slider-crank", SliderCrank(0.4, 0.1, 0.35, w0=8.0))):
        sim, build, res, run = _run(model)
        s = res.stats
        print(f"| {name} | {sim.compiled.n} | {int(sim.compiled.differential.sum())} | {len(sim.report.redundant)} | "
              f"{build:.2f} | {run:.2f} | {s['steps']} | {s['state_switches']} |")
        mechanisms.append((name, sim.compiled.n, int(sim.compiled.differential.sum()), len(sim.report.redundant),
                           build, run, s["steps"], s["state_switches"]))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    last = chain[-1]
    figures = [(f"N = {last[0]}: build CPU", last[5], "s"), ("run CPU", last[7], "s"), ("steps", last[8], "")]
    if len(rows) >= 3:
        figures += [("growth: build", f"N^{kb:.2f}", ""), ("run", f"N^{kr:.2f}", "")]
    figures += [(f"{m[0]}: run", m[5], "s") for m in mechanisms]
    report.write_results(__file__, figures, tables=[
        report.table("N-link pendulum chain, 10 s, rtol 1e-6, 1001 output points (runs best of 2)",
                     ["N", "unknowns", "states", "jac nnz", "build [s]", "build CPU [s]", "run [s]", "run CPU [s]",
                      "IDA steps", "res evals", "jac evals", "state switches"], chain),
        report.table("Closed loops, 10 s", ["mechanism", "unknowns", "states", "redundant rows", "build [s]",
                                            "run [s]", "IDA steps", "switches"], mechanisms)])


if __name__ == "__main__":
    main(sys.argv[1:])
