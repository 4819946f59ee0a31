"""Benchmark: a chain of N masses and nonlinear spring-dampers (``models/n_mass_chain.py``).

For N = 10, 100, 1000 masses (10 s simulated, rtol 1e-6, atol 1e-8, 101 output points) it reports

* the build time of stages 1–5, cold (fresh, empty ``FLEXLIB_CACHE_DIR``) and cached (a second
  ``Simulation`` of a new instance with the same structure), the size of the DAE after alias
  elimination and index reduction;
* ``Simulation.run`` (best of 3; the run total and its integration part), IDA steps, residual and
  Jacobian evaluations;
* the *same* flattened DAE (``sim.compiled``'s SX residual) integrated by CasADi's own C IDAS
  (``casadi.integrator('idas')``, ``linear_solver='csparse'``, implicit trick x = y_d,
  z = [y_d'; y_a]; same tolerances, initial values and output grid; build time excluded), with the
  ratio flexlib / CasADi-IDAS, twice: error test on ``y`` only (as flexlib; the derivatives added by
  the implicit trick get atol 1e10) and with CasADi's defaults (error test on x and z);
* flexlib's alternative backend ``flexlib.solve.backends.casadi`` (integrators cached);
* agreement: the largest relative difference of all mass positions against flexlib's default run.

Run: ``python benchmarks/chain.py [N ...]`` (from the repository root). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import sys
import tempfile
import time

import casadi as ca
import numpy as np

import flexlib as fl
from flexlib.models.n_mass_chain import NMassChain
from flexlib.solve.solvers import integrate

T_END, RTOL, ATOL, N_OUT, REPEAT = 10.0, 1e-6, 1e-8, 101, 3


def best_of(fn, repeat: int = REPEAT):
    """Smallest wall time of ``repeat`` calls, and the last result."""
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def casadi_reference(m, p, y0, yp0, grid, *, y_only: bool):
    """CasADi's own IDAS on the compiled residual (notes §5 implicit trick), natural variable order."""
    res = m.sx_function("res")
    diff = np.flatnonzero(m.differential)
    alg = np.flatnonzero(~m.differential)
    t = ca.SX.sym("t")
    x, w, ya = ca.SX.sym("x", len(diff)), ca.SX.sym("w", len(diff)), ca.SX.sym("ya", len(alg))
    ps = ca.SX.sym("p", len(p))
    y = [None] * m.n
    yp = [ca.SX(0.0)] * m.n
    for k, i in enumerate(diff):
        y[i], yp[i] = x[k], w[k]
    for k, i in enumerate(alg):
        y[i] = ya[k]
    dae = {"t": t, "x": x, "z": ca.vertcat(w, ya), "p": ps, "ode": w,
           "alg": res(t, ca.vertcat(*y), ca.vertcat(*yp), ps)}
    opts = {"linear_solver": "csparse", "reltol": RTOL, "abstol": ATOL, "max_num_steps": 100000}
    if y_only:
        opts["abstolv"] = np.concatenate([ATOL * m.nominal[diff], np.full(len(diff), 1e10),
                                          ATOL * m.nominal[alg]]).tolist()
    wall = time.perf_counter()
    F = ca.integrator("ref", "idas", dae, float(grid[0]), [float(g) for g in grid[1:]], opts)
    build = time.perf_counter() - wall
    x0, z0 = y0[diff], np.concatenate([yp0[diff], y0[alg]])
    run, out = best_of(lambda: F(x0=x0, z0=z0, p=p))
    st = F.stats()
    Y = np.empty((m.n, len(grid)))
    Y[diff, 0], Y[alg, 0] = y0[diff], y0[alg]
    Y[diff, 1:] = np.asarray(out["xf"])
    Y[alg, 1:] = np.asarray(out["zf"])[len(diff):]
    return {"build": build, "run": run, "steps": int(st["nsteps"]), "nfev": int(st["n_call_daeF"]),
            "njev": int(st["n_call_jacF"]), "Y": Y}


def positions(m, values_of) -> np.ndarray:
    names = [nm for nm in m.y_names if nm.startswith("mass") and nm.endswith(".s")]
    return np.array([values_of(nm) for nm in names])


def rel_diff(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300)))


def bench(n: int) -> dict:
    row: dict = {"N": n}
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    wall = time.perf_counter()
    model = NMassChain(n)
    row["instantiate"] = time.perf_counter() - wall
    wall = time.perf_counter()
    sim = fl.Simulation(model)
    row["build_cold"] = time.perf_counter() - wall
    assert not sim.build_info["cached"]
    row["stages"] = {k: v for k, v in sim.build_info.items() if k in ("flatten", "simplify", "index_reduction",
                                                                         "compile")}
    wall = time.perf_counter()
    sim2 = fl.Simulation(NMassChain(n))
    row["build_cached"] = time.perf_counter() - wall
    assert sim2.build_info["cached"]
    m = sim.compiled
    row["unknowns"], row["states"], row["codegen"] = m.n, int(m.differential.sum()), bool(m.library)
    row["aliases"] = m.stats.get("n_aliases")

    def run():
        return sim.run(T_END, dt_out=T_END / (N_OUT - 1), rtol=RTOL, atol=ATOL)

    wall = time.perf_counter()
    first = run()
    row["run_first"] = time.perf_counter() - wall
    totals, integ = [], []
    for _ in range(REPEAT):
        wall = time.perf_counter()
        res = run()
        totals.append(time.perf_counter() - wall)
        integ.append(res.stats["wall_integrate"])
    row["run"], row["integrate"] = min(totals), min(integ)
    row.update(steps=res.stats["steps"], nfev=res.stats["nfev"], njev=res.stats["njev"])
    grid = res.t
    assert len(grid) == N_OUT and first.stats["steps"] == res.stats["steps"]
    s_ref = positions(m, lambda nm: res[nm])

    # same inputs as Simulation.run
    pvec = sim.parameter_vector()
    p = np.concatenate([pvec, np.zeros(m.n_relations)])
    _, starts = sim.model.values()
    y0, yp0 = sim._initialize(0.0, p, starts, False)
    idx = {nm: i for i, nm in enumerate(m.y_names)}
    for key, y_only in (("cas", True), ("cas_default", False)):
        ref = casadi_reference(m, p, y0, yp0, grid, y_only=y_only)
        row[key] = {k: v for k, v in ref.items() if k != "Y"}
        row[key]["diff"] = rel_diff(positions(m, lambda nm, Y=ref["Y"]: Y[idx[nm]]), s_ref)

    # flexlib's casadi_idas backend (first call builds and caches its integrators)
    def backend():
        return integrate("casadi-idas", m, sim.initializer, p.copy(), y0, yp0, 0.0, T_END, grid, rtol=RTOL, atol=ATOL)

    wall = time.perf_counter()
    backend()
    first_backend = time.perf_counter() - wall
    t_b, traj = best_of(backend)
    Yb = np.array(traj.y).T
    row["backend"] = {"run": t_b, "first": first_backend, "steps": traj.stats["steps"], "nfev": traj.stats["nfev"],
                      "njev": traj.stats["njev"],
                      "diff": rel_diff(positions(m, lambda nm: Yb[idx[nm]]), s_ref)}
    return row


def ms(x: float) -> str:
    return f"{1e3 * x:.1f}"


def main(sizes: list[int]) -> None:
    rows = []
    for n in sizes:
        print(f"N = {n} ...", file=sys.stderr, flush=True)
        rows.append(bench(n))
    print(f"\nChain of N masses, {T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}, {N_OUT} output points; "
          f"times in ms (runs: best of {REPEAT}); OMP_NUM_THREADS=1\n")
    print("| N | unknowns | states | codegen | build cold | (flatten/simplify/index/compile) | build cached "
          "| run total | integrate | IDA steps | res evals | jac evals |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        st = r["stages"]
        stages = "/".join(ms(st.get(k, 0.0)) for k in ("flatten", "simplify", "index_reduction", "compile"))
        print(f"| {r['N']} | {r['unknowns']} | {r['states']} | {'yes' if r['codegen'] else 'no'} | "
              f"{ms(r['build_cold'])} | {stages} | {ms(r['build_cached'])} | {ms(r['run'])} | {ms(r['integrate'])} "
              f"| {r['steps']} | {r['nfev']} | {r['njev']} |")
    print("\nSame DAE, integration only (build excluded). Ratio = flexlib integrate / CasADi-IDAS "
          "(targets: <= 3 at N=100, <= 1.3 at N=1000); diff = max relative difference of all positions vs flexlib.\n")
    print("| N | flexlib integrate | CasADi-IDAS (y-only error test) | steps / res / jac | ratio | diff "
          "| CasADi-IDAS (defaults) | steps | ratio | diff | casadi_idas backend | steps / res / jac | ratio | diff |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        c, d, b = r["cas"], r["cas_default"], r["backend"]
        print(f"| {r['N']} | {ms(r['integrate'])} | {ms(c['run'])} | {c['steps']} / {c['nfev']} / {c['njev']} | "
              f"{r['integrate'] / c['run']:.2f} | {c['diff']:.1e} | {ms(d['run'])} | {d['steps']} | "
              f"{r['integrate'] / d['run']:.2f} | {d['diff']:.1e} | {ms(b['run'])} | "
              f"{b['steps']} / {b['nfev']} / {b['njev']} | {r['integrate'] / b['run']:.2f} | {b['diff']:.1e} |")
    print("\nOne-off costs (ms): CasADi integrator construction (y-only / defaults); casadi_idas backend first run "
          "(includes building its integrators); first Simulation.run (includes stage 4)")
    for r in rows:
        print(f"  N = {r['N']}: {ms(r['cas']['build'])} / {ms(r['cas_default']['build'])}; "
              f"{ms(r['backend']['first'])}; {ms(r['run_first'])}")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures = []
    for r in rows:
        figures += [(f"N = {r['N']}: run", r["run"], "s"), ("flexlib / CasADi-IDAS", r["integrate"] / r["cas"]["run"],
                                                                ""), ("build cached", r["build_cached"], "s")]
    report.write_results(__file__, figures, tables=[
        report.table(f"Chain of N masses, {T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}, {N_OUT} output points; runs best "
                     f"of {REPEAT}", ["N", "unknowns", "states", "codegen", "build cold [s]", "build cached [s]",
                                      "run [s]", "integrate [s]", "IDA steps", "res evals", "jac evals"],
                     [[r[k] for k in ("N", "unknowns", "states", "codegen", "build_cold", "build_cached", "run",
                                      "integrate", "steps", "nfev", "njev")] for r in rows]),
        report.table("Same DAE, integration only: flexlib against CasADi's IDAS (y-only error test, defaults) and the "
                     "casadi_idas backend; diff = largest relative difference of the positions",
                     ["N", "flexlib [s]", "CasADi-IDAS y-only [s]", "ratio", "diff", "CasADi-IDAS defaults [s]",
                      "ratio", "diff", "casadi_idas backend [s]", "ratio", "diff"],
                     [[r["N"], r["integrate"]] + [v for k in ("cas", "cas_default", "backend") for v in
                                                  (r[k]["run"], r["integrate"] / r[k]["run"], r[k]["diff"])]
                      for r in rows])])


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [10, 100, 1000])
