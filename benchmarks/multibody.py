"""Benchmark: multibody build and run times (issue 3).

* N-link pendulum chain (N = 2, 5, 10, 20, 50), 10 s, rtol 1e-6: build time (cold), unknowns and
  states, run time, steps — and how both grow with N. Build times exclude the generated C, which
  gcc compiles in the background (``codegen="auto"``); runs are timed once it is ready.
* Planar four-bar of four Revolutes (3 redundant loop rows) and the slider-crank, 10 s.

Run: ``python benchmarks/multibody.py`` (from the repository root; ``python benchmarks/multibody.py 2 5``
for chosen chain sizes). No timing is asserted.
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
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "tests" / "components" / "mechanics" / "multibody"))


def _run(model: fl.Model, t_end: float = 10.0, rtol: float = 1e-6) -> tuple[fl.Simulation, float, fl.Result, float]:
    t = time.perf_counter()
    sim = fl.Simulation(model, use_cache=False)
    build = time.perf_counter() - t
    m = sim.compiled  # generated C compiles in the background: time the runs on it
    while m.library is None and m.library_pending is not None:
        time.sleep(0.1)
        m.function("res")
    best, res = np.inf, None
    for _ in range(2):
        t = time.perf_counter()
        res = sim.run(t_end, dt_out=0.01, rtol=rtol, atol=rtol * 1e-2, progress=False)
        best = min(best, time.perf_counter() - t)
    return sim, build, res, best


def main(argv: list[str]) -> None:
    sizes = [int(a) for a in argv] or [2, 5, 10, 20, 50]
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    print("N-link pendulum chain, 10 s, rtol 1e-6, 1001 output points (times: run best of 2)\n")
    print("| N | unknowns | states | build (s) | run (s) | IDA steps | res evals | jac evals | state switches |")
    print("|---|---|---|---|---|---|---|---|---|")
    rows = []
    for n in sizes:
        sim, build, res, run = _run(NLinkPendulum(n))
        s = res.stats
        rows.append((n, build, run))
        print(f"| {n} | {sim.compiled.n} | {int(sim.compiled.differential.sum())} | {build:.2f} | {run:.2f} | "
              f"{s['steps']} | {s['nfev']} | {s['njev']} | {s['state_switches']} |")
    if len(rows) >= 3:
        n, b, r = (np.array(c, dtype=float) for c in zip(*rows, strict=True))
        kb = np.polyfit(np.log(n), np.log(b), 1)[0]
        kr = np.polyfit(np.log(n), np.log(r), 1)[0]
        print(f"\nGrowth (log-log slope over N): build ~ N^{kb:.2f}, run ~ N^{kr:.2f}")

    import references_multibody as ref
    from test_loops import A, B, C, D, FourBar, SliderCrank

    th3, th4 = ref.fourbar_angles(A, B, C, D, 0.3, "open")
    print("\n| mechanism | unknowns | states | redundant rows | build (s) | run 10 s (s) | IDA steps | switches |")
    print("|---|---|---|---|---|---|---|---|")
    for name, model in (("four-bar (4 Revolutes)", FourBar(0.3, th3, th4, 6.0)),
                        ("slider-crank", SliderCrank(0.4, 0.1, 0.35, w0=8.0))):
        sim, build, res, run = _run(model)
        s = res.stats
        print(f"| {name} | {sim.compiled.n} | {int(sim.compiled.differential.sum())} | {len(sim.report.redundant)} | "
              f"{build:.2f} | {run:.2f} | {s['steps']} | {s['state_switches']} |")


if __name__ == "__main__":
    main(sys.argv[1:])
