"""Benchmark: ``solver="ida-native"`` (SUNDIALS IDA stepped in C) against the default backend and casadi-idas.

Models: the N-mass chain (N = 10 and 100, 10 s, 0.1 s grid), the Cartesian pendulum (10 s, 0.01 s grid, rtol 1e-8),
the planar four-bar of four Revolutes (10 s, 0.01 s grid, ``dynamic_states=False``) and the hydraulic servo driven
into its end stops (20 s, 0.01 s grid); the pendulum and the servo with the dynamic state-selection monitor on (the
default) and off. Every backend runs the same compiled model in the same process, best of ``REPEAT`` runs (this
machine is shared: read the ratios, not the absolute times).

Columns: run time (whole ``Simulation.run``), IDA steps, µs per step, speed-up of ida-native over ida, and the
split of the integration time into

* **model**: residual, Jacobian and event-indicator evaluations;
* **IDA**: everything else SUNDIALS does (Newton, LU, error test, interpolation, root finding);
* **Python**: the rest (callbacks' glue, the step loop, events, result rows).

For ida-native the split is measured (clock in C around each model call and around the C step loop). For the
``ida`` route it is estimated from the same run: model = nfev × (C cost of one residual) + njev × (C
cost of one Jacobian) as measured in the ida-native run of the same model, IDA = ida-native's IDA time × the ratio
of steps (same SUNDIALS, same options), Python = the remainder.

Run: ``python benchmarks/native_ida.py`` (from the repository root; ``python benchmarks/native_ida.py servo chain``
runs the cases whose name contains one of the words). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

import flexlib as fl  # noqa: E402
from flexlib.models.n_mass_chain import NMassChain  # noqa: E402

REPEAT = 2
SOLVERS = ("ida", "casadi-idas", "ida-native")


def cases() -> list[tuple[str, Callable[[], fl.Model], dict, bool]]:
    """(name, model factory, run arguments, generated C)."""
    from pendulum import make as pendulum

    from flexlib.models.reference import closed_form as ref
    from flexlib.models.reference.four_bar import A, B, C, D, FourBar
    from flexlib.models.reference.hydraulic_servo import HydraulicServo

    th3, th4 = ref.fourbar_angles(A, B, C, D, 0.3, "open")
    fixed = {"dynamic_states": False}
    pend = {"t_end": 10.0, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}
    four = {"t_end": 10.0, "dt_out": 0.01, "rtol": 1e-6, "atol": 1e-8, **fixed}
    servo = {"t_end": 20.0, "dt_out": 0.01, "rtol": 1e-6, "atol": 1e-8}
    return [
        ("chain N=10", lambda: NMassChain(10), {"t_end": 10.0, "dt_out": 0.1}, False),
        ("chain N=100", lambda: NMassChain(100), {"t_end": 10.0, "dt_out": 0.1}, False),
        ("chain N=100, C", lambda: NMassChain(100), {"t_end": 10.0, "dt_out": 0.1}, True),
        ("pendulum (rtol 1e-8), monitor on", pendulum, pend, False),
        ("pendulum (rtol 1e-8), dynamic_states=False", pendulum, {**pend, **fixed}, False),
        ("four-bar, dynamic_states=False", lambda: FourBar(0.3, th3, th4, 6.0), four, False),
        ("four-bar, dynamic_states=False, C", lambda: FourBar(0.3, th3, th4, 6.0), four, True),
        ("hydraulic servo, monitor on", HydraulicServo, servo, False),
        ("hydraulic servo, dynamic_states=False", HydraulicServo, {**servo, **fixed}, False),
        ("hydraulic servo, dynamic_states=False, C", HydraulicServo, {**servo, **fixed}, True),
    ]


def best_run(sim: fl.Simulation, solver: str, kw: dict) -> tuple[float, fl.Result]:
    best, res = np.inf, None
    for _ in range(REPEAT):
        t = time.perf_counter()
        r = sim.run(solver=solver, progress=False, **kw)
        wall = time.perf_counter() - t
        if wall < best:
            best, res = wall, r
    return best, res


def ms(x: float) -> str:
    return f"{1e3 * x:.1f}"


def main() -> None:
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    from flexlib.solve.native import driver_library

    t = time.perf_counter()
    driver_library()
    print(f"driver compile (once per machine): {time.perf_counter() - t:.2f} s\n")
    print(f"Run time best of {REPEAT}; split of the integration time (ms): model / IDA / Python\n")
    print("| model | n | backend | run (ms) | steps | µs/step | × vs ida | model | IDA | Python | max |Δ| vs ida |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    chosen = [c for c in cases() if not sys.argv[1:] or any(a in c[0] for a in sys.argv[1:])]
    rows = []
    for name, model, kw, codegen in chosen:
        sim = fl.Simulation(model(), use_cache=False, codegen=codegen)
        out = {s: best_run(sim, s, kw) for s in SOLVERS}
        nat = out["ida-native"][1].stats
        ref = out["ida"][1]
        for s in SOLVERS:
            run, r = out[s]
            st = r.stats
            steps = st["steps"]
            if s == "ida-native":
                parts = (st["wall_model"], st["wall_ida"], st["wall_python"])
            elif s == "ida":  # estimated from the native run of the same model (see the module docstring)
                scale = steps / max(nat["steps"], 1)
                m_est = (st["nfev"] * nat["wall_res"] / max(nat["nfev"], 1)
                         + st["njev"] * nat["wall_jac"] / max(nat["njev"], 1) + nat["wall_root"] * scale)
                ida_est = nat["wall_ida"] * scale
                parts = (m_est, ida_est, max(st["wall_integrate"] - m_est - ida_est, 0.0))
            else:
                parts = None
            split = " | ".join(ms(x) for x in parts) if parts else "– | – | –"
            print(f"| {name} | {sim.compiled.n} | {s} | {ms(run)} | {steps} | "
                  f"{1e6 * st['wall_integrate'] / max(steps, 1):.1f} | {out['ida'][0] / run:.2f} | {split} | "
                  f"{deviation(r, ref):.1e} |", flush=True)
            rows.append((name, sim.compiled.n, s, run, steps, st["wall_integrate"] / max(steps, 1), out["ida"][0] / run,
                         *(parts or ("–",) * 3), deviation(r, ref)))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [(f"{r[0]}: {r[2]} / ida", 1 / r[6], "") for r in rows if r[2] != "ida"],
                         tables=[report.table(
                             f"Backends on the same compiled model, run best of {REPEAT}; split of the integration",
                             ["model", "n", "backend", "run [s]", "steps", "integrate per step [s]", "ida / this",
                              "model [s]", "IDA [s]", "Python [s]", "max |Δ| / range vs ida"], rows)])


def deviation(r: fl.Result, ref: fl.Result) -> float:
    """Largest difference to the default backend on their common output times, relative to each variable's range."""
    common, ia, ib = np.intersect1d(r.t, ref.t, return_indices=True)
    if not len(common):
        return float("nan")
    a, b = r.values[ia], ref.values[ib]
    scale = np.maximum(np.abs(b).max(axis=0), 1e-6)
    return float(np.max(np.abs(a - b) / scale))


if __name__ == "__main__":
    main()
