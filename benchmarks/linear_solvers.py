"""Benchmark: the C driver's linear solvers on the models' own iteration matrices.

The measurement behind the size rule of ``flexlib.solve.backends.ida_c.linear_solver``.
Each model runs on the default backend (the C driver, generated C once gcc has finished) with each linear solver
forced through ``FLEXLIB_LINSOL``: SUNDIALS' dense LU (up to 350 unknowns), SUNDIALS' SuperLU_MT (COLAMD ordering
computed at the first setup, then ``refact = YES``; one thread) and KLU (kvxopt's SuiteSparse: BTF + AMD ordering
once, one numeric factorisation per setup). Columns: unknowns and Jacobian nonzeros, then per solver the IDA setups
(factorisations), thread CPU time per setup and per solve (measured around each call in C), IDA steps and the
run's process CPU time; best of ``REPEAT`` runs by CPU time. rtol 1e-6, atol 1e-8, 0.01 s grid.

Run: ``python benchmarks/linear_solvers.py [--quick]`` (``--quick``: without the boom proxy). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

import flexlib as fl  # noqa: E402

REPEAT = 2
DENSE_LIMIT = 350


def main(argv: list[str]) -> None:
    os.environ.setdefault("FLEXLIB_CACHE_DIR", tempfile.mkdtemp(prefix="flexlib_bench_"))
    from flexlib.models.boom_proxy import BoomProxy
    from flexlib.models.n_link_pendulum import NLinkPendulum
    from flexlib.models.n_mass_chain import NMassChain
    from flexlib.models.planar_mechanisms import FourBarLinkage, ThreeLoopLinkage
    from flexlib.models.reference.hydraulic_servo import HydraulicServo
    from flexlib.solve.native import klu_available, use_cpu_clock

    if not klu_available():
        print("KLU is not available (pip install kvxopt): only dense and SuperLU_MT are measured")
    use_cpu_clock(True)
    models = [("mass chain N = 6", lambda: NMassChain(6), 20.0), ("mass chain N = 10", lambda: NMassChain(10), 20.0),
              ("hydraulic servo", HydraulicServo, 20.0), ("pendulum N = 3", lambda: NLinkPendulum(3), 5.0),
              ("four-bar", FourBarLinkage, 10.0), ("7-body three-loop", ThreeLoopLinkage, 5.0),
              ("pendulum N = 10", lambda: NLinkPendulum(10), 2.0)]
    if "--quick" not in argv:
        models += [("boom proxy, direct", lambda: BoomProxy(linkages=False), 20.0),
                   ("boom proxy, linkages", lambda: BoomProxy(linkages=True), 20.0)]
    solvers = ["dense", "superlumt", "klu"] if klu_available() else ["dense", "superlumt"]
    print(f"best of {REPEAT} by CPU time; rtol 1e-6, atol 1e-8; per solver: setups, µs per setup / µs per solve "
          "(thread CPU), steps, run CPU (s)\n")
    print("| model | unknowns | nonzeros | " + " | ".join(solvers) + " |")
    print("|---|---|---|" + "---|" * len(solvers))
    rows, runs = [], {}
    for name, factory, t_end in models:
        sim = fl.Simulation(factory())
        sim.compiled.wait_for_library(1200.0)
        cells, run_cpu = [], {}
        for ls in solvers:
            if ls == "dense" and sim.compiled.n > DENSE_LIMIT:
                cells.append("–")
                continue
            os.environ["FLEXLIB_LINSOL"] = ls
            best = None
            for _ in range(REPEAT):
                c = time.process_time()
                r = sim.run(t_end, dt_out=0.01, rtol=1e-6, atol=1e-8, progress=False)
                c = time.process_time() - c
                if best is None or c < best[0]:
                    best = (c, r.stats)
            os.environ.pop("FLEXLIB_LINSOL", None)
            c, s = best
            run_cpu[ls] = c
            cells.append(f"{s['n_lsetup']}: {1e6 * s['wall_lsetup'] / max(s['n_lsetup'], 1):.0f} / "
                         f"{1e6 * s['wall_lsolve'] / max(s['n_lsolve'], 1):.1f} µs, {s['steps']} steps, {c:.3f} s")
        print(f"| {name} | {sim.compiled.n} | {len(sim.compiled.jac_row)} | " + " | ".join(cells) + " |", flush=True)
        rows.append((name, sim.compiled.n, len(sim.compiled.jac_row), *cells))
        runs[name] = run_cpu

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures = [(f"{name}: run, {ls}", cpu, "s") for name, by_solver in runs.items() for ls, cpu in by_solver.items()
               if name in ("hydraulic servo", "7-body three-loop", "boom proxy, linkages")]
    report.write_results(__file__, figures, tables=[report.table(
        f"Linear solvers of the C driver, best of {REPEAT} by CPU; rtol 1e-6, atol 1e-8; cells: setups: per setup / "
        "per solve (thread CPU), steps, run CPU", ["model", "unknowns", "nonzeros", *solvers], rows)])


if __name__ == "__main__":
    main(sys.argv[1:])
