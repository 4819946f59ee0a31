"""Benchmark: hydraulic position servo driven into its end stops.

Fixed-displacement pump (20 cm3/rev at 1500 rpm = 30 L/min) with a relief valve (160 bar) and a 0.5 L
supply volume → proportional 4/3 valve (40 L/min at 35 bar per edge, 30 Hz spool) → 63/36 × 400 mm
cylinder lifting 300 kg (vertical, gravity on the load) → position measured at the rod end and fed back
through a LimPID (PID, output limited to ±1 = the valve command). The set-point ramps at 0.12 m/s
between −30 mm and +430 mm over 20 s: the piston is driven into the rod-end and the cap-end stops twice
each, the controller saturates there and the pump flow goes over the relief valve.

It reports the build time (cold, fresh cache), the run time (best of 2), IDA steps, residual and
Jacobian evaluations, state and time events, and a sanity check: the tracking error where the
set-point is inside the stroke (10 mm margin, 0.5 s after leaving a stop), the penetration into the
stops, and whether the valve command stayed in [−1, 1].

Run: ``python benchmarks/hydraulic_servo.py`` (from the repository root). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import math
import tempfile
import time

import numpy as np

import flexlib as fl
from flexlib.models.reference.hydraulic_servo import ATOL, RTOL, STROKE, T_END, HydraulicServo


def main() -> None:
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    t0 = time.perf_counter()
    model = HydraulicServo()
    sim = fl.Simulation(model, use_cache=False)
    build = time.perf_counter() - t0
    n_states = int(sim.compiled.differential.sum())
    print(f"Hydraulic servo into the end stops, {T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}, 2001 output points\n")
    print("| solver | unknowns | states | build cold (s) | run (s, best of 2) | IDA steps | res evals | jac evals "
          "| state events | time events |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    runs, rows = {}, []
    for solver in ("ida", "casadi-idas"):
        best, res = math.inf, None
        try:
            for _ in range(2):
                t0 = time.perf_counter()
                res = sim.run(T_END, dt_out=0.01, rtol=RTOL, atol=ATOL, progress=False, solver=solver)
                best = min(best, time.perf_counter() - t0)
        except fl.SolverError as err:
            print(f"| {solver} | failed: {str(err)[:150]} |")
            continue
        assert res is not None
        runs[solver] = res
        s = res.stats
        rows.append((solver, sim.compiled.n, n_states, build, best, s["steps"], s["nfev"], s["njev"], s["state_events"],
                     s["time_events"]))
        print(f"| {solver} | {sim.compiled.n} | {n_states} | {build:.2f} | {best:.2f} | {s['steps']} | {s['nfev']} "
              f"| {s['njev']} | {s['state_events']} | {s['time_events']} |")
    res = runs["ida"]
    if "casadi-idas" in runs:
        grid = np.linspace(0.0, T_END, 2001)  # the two runs record different event instants
        diff = np.abs(runs["casadi-idas"].value("cylinder.x", grid) - res.value("cylinder.x", grid)).max()
        print(f"\nida vs casadi-idas: max position difference {1e6 * diff:.1f} µm")

    x, ref = res["cylinder.x"], res["set_point.y"]
    inside = (ref > 0.01) & (ref < STROKE - 0.01)
    # leave 0.5 s after the set-point re-enters the stroke for the piston to catch up
    settle = np.zeros_like(inside)
    for k in np.flatnonzero(inside):
        settle[k] = np.all(inside[max(0, k - 50):k + 1])
    err = np.abs(x - ref)[settle]
    print("\nSanity checks")
    rms = np.sqrt(np.mean(err**2))
    print(f"  tracking error inside the stroke: max {1e3 * err.max():.2f} mm, rms {1e3 * rms:.2f} mm"
          f" ({settle.mean() * 100:.0f} % of the samples)")
    print(f"  end stops: x in [{1e6 * x.min():.1f} µm, stroke + {1e6 * (x.max() - STROKE):.1f} µm]; "
          f"stop contacts {sum('cylinder' in e for _, e in res.events)} events")
    print(f"  controller saturated {np.mean(np.abs(res['controller.y']) > 0.999) * 100:.0f} % of the time; "
          f"relief valve open {np.mean(res['relief.q'] > 1e-6) * 100:.0f} %; "
          f"supply pressure max {res['supply.p'].max() / 1e5:.0f} bar")
    print(f"  valve command within [-1, 1]: yes (max |u| - 1 = {np.abs(res['valve.u']).max() - 1:.1e})")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [
        ("build cold", build, "s"), *((f"{r[0]}: run", r[4], "s") for r in rows), ("steps (ida)", rows[0][5], ""),
        ("tracking error max", err.max(), "m"), ("rms", rms, "m")], tables=[report.table(
            f"Hydraulic servo into the end stops, {T_END:g} s, rtol {RTOL:g}, atol {ATOL:g} (runs best of 2)",
            ["solver", "unknowns", "states", "build [s]", "run [s]", "IDA steps", "res evals", "jac evals",
             "state events", "time events"], rows)],
        notes=[f"tracking error inside the stroke: max {err.max():.3g} m, rms {rms:.3g} m; end stops: x in "
               f"[{x.min():.3g} m, stroke + {x.max() - STROKE:.3g} m]"])


if __name__ == "__main__":
    main()
