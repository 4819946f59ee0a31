"""Benchmark: the planar pendulum in Cartesian coordinates, written as raw equations (index 3).

    x' = u,  y' = v,  m·u' = −λ·x,  m·v' = −λ·y − m·g,  x² + y² = L²

m = L = 1, g = 9.81, released at rest from 45°, 10 s simulated at rtol 1e-8 (atol 1e-10). Reports
the build time (stages 1–5, cold and cached), the index-reduction result, and per integrator
backend the run time (best of 3), the number of steps and evaluations, the largest constraint
residuals |x² + y² − L²| and |x·u + y·v| and the largest energy drift |E − E0| over all output
rows (every step for the default backend, a 1000-interval grid for the CasADi backend).

Run: ``python benchmarks/pendulum.py`` (from the repository root). No timing is asserted.
"""

from __future__ import annotations

import os
from functools import partial

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import sys
import tempfile
import time

import numpy as np

import flexlib as fl
from flexlib.models.reference.cartesian_pendulum import CartesianPendulum
from flexlib.solve.solvers import integrate

T_END, RTOL, ATOL, REPEAT = 10.0, 1e-8, 1e-10, 3
THETA0 = np.pi / 4


def make() -> CartesianPendulum:
    return CartesianPendulum.released_at(THETA0)


def quality(res: fl.Result) -> dict:
    x, y, u, v = res["x"], res["y"], res["u"], res["v"]
    energy = 0.5 * (u**2 + v**2) + 9.81 * y
    return {"g": float(np.max(np.abs(x**2 + y**2 - 1.0))), "g1": float(np.max(np.abs(x * u + y * v))),
            "dE": float(np.max(np.abs(energy - energy[0]))), "dE_end": float(abs(energy[-1] - energy[0]))}


def main() -> None:
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    wall = time.perf_counter()
    sim = fl.Simulation(make())
    build_cold = time.perf_counter() - wall
    wall = time.perf_counter()
    fl.Simulation(make())
    build_cached = time.perf_counter() - wall
    m = sim.compiled

    rows = []
    # default backend, every step recorded
    best, res = np.inf, None
    for _ in range(REPEAT):
        wall = time.perf_counter()
        res = sim.run(T_END, rtol=RTOL, atol=ATOL)
        best = min(best, time.perf_counter() - wall)
    rows.append(("flexlib IDA (default), every step", best, res.stats["wall_integrate"], res.stats, len(res.t),
                 quality(res)))
    # the same with a 1000-interval grid (output by IDA interpolation)
    best = np.inf
    for _ in range(REPEAT):
        wall = time.perf_counter()
        res = sim.run(T_END, dt_out=T_END / 1000, rtol=RTOL, atol=ATOL)
        best = min(best, time.perf_counter() - wall)
    rows.append(("flexlib IDA (default), 1001 points", best, res.stats["wall_integrate"], res.stats, len(res.t),
                 quality(res)))
    # casadi_idas backend on the same inputs as Simulation.run
    pvec = sim.parameter_vector()
    p = np.concatenate([pvec, np.zeros(m.n_relations)])
    _, starts = sim.model.values()
    y0, yp0 = sim._initialize(0.0, p, starts, False)
    for name, fn in (("casadi_idas backend, 1001 points", partial(integrate, "casadi-idas")),):
        best, traj = np.inf, None
        for _ in range(REPEAT + 1):  # the first call builds the CasADi integrator
            wall = time.perf_counter()
            traj = fn(m, sim.initializer, p.copy(), y0, yp0, 0.0, T_END, None, rtol=RTOL, atol=ATOL)
            best = min(best, time.perf_counter() - wall)
        r = sim._result(traj, pvec, 0.0, RTOL, ATOL)
        rows.append((name, best, best, r.stats, len(r.t), quality(r)))

    print(f"\nCartesian pendulum (index 3), m = L = 1, 45° at rest, {T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}; "
          f"OMP_NUM_THREADS=1\n")
    print(f"Build: cold {1e3 * build_cold:.1f} ms "
          f"(flatten {1e3 * sim.build_info['flatten']:.1f}, simplify {1e3 * sim.build_info['simplify']:.1f}, "
          f"index reduction {1e3 * sim.build_info['index_reduction']:.1f}, "
          f"compile {1e3 * sim.build_info['compile']:.1f}); cached {1e3 * build_cached:.1f} ms")
    print(f"DAE after index reduction: {m.n} unknowns ({', '.join(m.y_names)}), "
          f"{int(m.differential.sum())} states")
    print("  " + str(m.report).replace("\n", "\n  ") + "\n")
    print("| route | run (ms) | integrate (ms) | steps | res evals | jac evals | rows | max abs(x²+y²−1) "
          "| max abs(x·u+y·v) | max abs(E−E0) | abs(E−E0) at 10 s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, run, integ, st, nrows, q in rows:
        print(f"| {name} | {1e3 * run:.1f} | {1e3 * integ:.1f} | {st['steps']} | {st['nfev']} | {st['njev']} | "
              f"{nrows} | {q['g']:.1e} | {q['g1']:.1e} | {q['dE']:.1e} | {q['dE_end']:.1e} |")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    default, casadi = rows[0], rows[-1]
    report.write_results(__file__, figures=[
        ("build cold", build_cold, "s"), ("run, every step", default[1], "s"), ("steps", default[3]["steps"], ""),
        ("max |x²+y²−1|", default[5]["g"], "m²"), ("max |E−E0|", default[5]["dE"], "J/kg"),
        ("casadi-idas run", casadi[1], "s")], tables=[report.table(
            f"Cartesian pendulum, {T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}",
            ["route", "run [s]", "integrate [s]", "steps", "res evals", "jac evals", "rows", "max |x²+y²−1| [m²]",
             "max |x·u+y·v| [m²/s]", "max |E−E0| [J/kg]", "|E−E0| at t_end [J/kg]"],
            [(name, run, integ, st["steps"], st["nfev"], st["njev"], nrows, q["g"], q["g1"], q["dE"], q["dE_end"])
             for name, run, integ, st, nrows, q in rows])])


if __name__ == "__main__":
    sys.exit(main())
