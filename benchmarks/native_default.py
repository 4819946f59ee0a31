"""Benchmark: the default backend's C driver against IDA stepped from Python, SuperLU_MT and casadi-idas.

Four-bar linkage (``models/planar_mechanisms.py``, 10 s) and hydraulic servo (``benchmarks/hydraulic_servo.py``,
20 s), rtol 1e-6 / atol 1e-8, 0.01 s grid, dynamic state selection on (the default), both models compiled once in
this process. Each backend runs the same compiled model, best of ``REPEAT`` runs (the machine is shared: read the
ratios, not the absolute times):

* ``ida-sksundae``: the fallback without gcc: scikit-sundae's IDA stepped from Python;
* ``ida (SuperLU_MT)``: the C driver with SUNDIALS' SuperLU_MT above 40 unknowns, dense LU below
  (``FLEXLIB_LINSOL=superlumt``; what it runs without kvxopt);
* ``ida``: the default: the C driver with its linear-solver rule (dense LU up to 40 unknowns, KLU above),
  Python only at outputs, events and due monitor checks;
* ``casadi-idas``: for reference.

Columns: run time (whole ``Simulation.run``, CPU time of this process and wall time; best of ``REPEAT`` by CPU),
IDA steps, switches, monitor indicator checks / full tests, linear-solver setups (factorisations) with their CPU time
per setup and per solve, the integration's split into model / IDA (incl. linear algebra) / Python in CPU time (C
driver only: thread CPU time measured around each call in C), and the largest deviation from the first row of the
model on the grid relative to each variable's range.

``--boom`` adds the boom proxy (``models/boom_proxy.py``, 20 s) without (434 unknowns) and with (794 unknowns) its
four-bar linkages, run once gcc has finished its generated C (waited for), so that every route evaluates the same
library; on these only the two C-driver routes run (the Python-stepped and casadi-idas routes take minutes).

Run: ``python benchmarks/native_default.py [--boom]`` from the repository root. No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

from native_ida import deviation  # noqa: E402  (largest difference relative to each variable's range)

import flexlib as fl  # noqa: E402

REPEAT = 3
SOLVERS = ("ida-sksundae", "ida (SuperLU_MT)", "ida", "casadi-idas")


def main() -> None:
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    from flexlib.models.planar_mechanisms import FourBarLinkage
    from flexlib.models.reference.hydraulic_servo import HydraulicServo
    from flexlib.solve.native import klu_available, native_available, use_cpu_clock

    t = time.perf_counter()
    ok = native_available()
    print(f"C driver available: {ok} ({time.perf_counter() - t:.2f} s to compile or load); KLU: {klu_available()}\n")
    use_cpu_clock(True)
    print(f"best of {REPEAT} by CPU time; rtol 1e-6, atol 1e-8, dt_out 0.01 s\n")
    print("| model | backend | run CPU / wall (s) | × real time (CPU) | steps | switches | monitor checks / full | "
          "setups: µs each / µs per solve | model / IDA / Python CPU (ms) | max |Δ| |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    models = [("four-bar 10 s", FourBarLinkage, 10.0, SOLVERS), ("hydraulic servo 20 s", HydraulicServo, 20.0, SOLVERS)]
    if "--boom" in sys.argv[1:]:
        from flexlib.models.boom_proxy import BoomProxy

        c_only = ("ida (SuperLU_MT)", "ida")
        models.append(("boom proxy, direct cylinders, 20 s", lambda: BoomProxy(linkages=False), 20.0, c_only))
        models.append(("boom proxy, linkages, 20 s", lambda: BoomProxy(linkages=True), 20.0, c_only))
    rows = []
    for name, factory, t_end, solvers in models:
        sim = fl.Simulation(factory())
        deadline = time.monotonic() + 600.0
        while sim.compiled.library_pending is not None and sim.compiled.library is None:  # wait for gcc
            if time.monotonic() > deadline:
                print(f"{name}: gcc has not finished after 600 s; running on CasADi's VM")
                break
            time.sleep(0.1)
            sim.compiled.function("res")
        out = {}
        for label in solvers:
            solver = label.split(" ")[0]
            if "SuperLU_MT" in label:
                os.environ["FLEXLIB_LINSOL"] = "superlumt"
            best, res, counts = (np.inf, np.inf), None, None
            for _ in range(REPEAT):
                mon = sim._monitor() if sim.compiled.has_state_choice else None
                before = dict(mon.counts) if mon is not None else {}
                w, c = time.perf_counter(), time.process_time()
                try:
                    r = sim.run(t_end, dt_out=0.01, rtol=1e-6, atol=1e-8, progress=False, solver=solver)
                except fl.SolverError as err:  # reported in the table
                    r = err.result
                w, c = time.perf_counter() - w, time.process_time() - c
                if c < best[0]:
                    best, res = (c, w), r
                    counts = {k: v - before.get(k, 0) for k, v in mon.counts.items()} if mon is not None else None
            os.environ.pop("FLEXLIB_LINSOL", None)
            out[label] = (best, res, counts)
        ref = out[solvers[0]][1]
        for label in solvers:
            (cpu, wall), res, counts = out[label]
            st = res.stats
            if "wall_model" in st:
                python = cpu - st["wall_model"] - st["wall_ida"]  # the run's CPU time outside the C step loop
                split = f"{1e3 * st['wall_model']:.0f} / {1e3 * st['wall_ida']:.0f} / {1e3 * python:.0f}"
                la = (f"{st['n_lsetup']}: {1e6 * st['wall_lsetup'] / max(st['n_lsetup'], 1):.0f} / "
                      f"{1e6 * st['wall_lsolve'] / max(st['n_lsolve'], 1):.1f} ({st['linear_solver']})")
            else:
                split = la = "–"
            mon = "–" if counts is None else f"{counts['indicator']} / {counts['full']}"
            if not res.success:
                label = f"{label} (failed at t = {res.t[-1]:.3g} s)"
            print(f"| {name} | {label} | {cpu:.3f} / {wall:.3f} | {t_end / cpu:.1f} | {st['steps']} | "
                  f"{st.get('state_switches', 0)} | {mon} | {la} | {split} | {deviation(res, ref):.1e} |", flush=True)
            rows.append((name, label, cpu, wall, t_end / cpu, st["steps"], st.get("state_switches", 0), mon, la,
                         split, deviation(res, ref)))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    cpu = {(r[0], r[1]): r[2] for r in rows}
    figures = []
    for name, *_ in models:
        if (name, "ida") in cpu:
            figures.append((f"{name}: ida run", cpu[name, "ida"], "s"))
        if (name, "ida-sksundae") in cpu:
            figures.append(("ida-sksundae / ida", cpu[name, "ida-sksundae"] / cpu[name, "ida"], ""))
    report.write_results(__file__, figures, tables=[report.table(
        f"Default backend routes, best of {REPEAT} by CPU; rtol 1e-6, atol 1e-8, dt_out 0.01 s",
        ["model", "backend", "run CPU [s]", "run wall [s]", "× real time (CPU)", "steps", "switches",
         "monitor checks / full", "setups: each / per solve [µs]", "model / IDA / Python CPU [ms]",
         "max |Δ| / range"], rows)])


if __name__ == "__main__":
    main()
