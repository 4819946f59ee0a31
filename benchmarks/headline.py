"""Headline figures: the four-bar, the hydraulic servo and the chains, one run, one machine, against floors.

* four-bar (``models/planar_mechanisms.py``), 10 s at rtol 1e-6 / atol 1e-8: build, default backend,
  ``solver="casadi-idas"``; floors timed in the same run: the minimal-coordinate ODE in CVODE and the
  hand-written minimal DAE in IDA (``benchmarks/minimal_dae.py``), same tolerances.
* hydraulic servo (``benchmarks/hydraulic_servo.py``), 20 s at rtol 1e-6 / atol 1e-8: both backends.
* N-link pendulum chain (``models/n_link_pendulum.py``), N = 2, 5, 10, 20, 50 (``--quick``: up to 20): cold
  build and a 10 s run at rtol 1e-6, with the log-log growth exponents over N.
* chain of N = 100 and 1000 masses (``models/n_mass_chain.py``): cold build + 10 s run (rtol 1e-6, atol 1e-8),
  cached build.

Every build is cold (a fresh ``FLEXLIB_CACHE_DIR``) unless marked cached. Times are wall clock
(``perf_counter``) with the CPU time (this process and its gcc children) beside it: on a shared machine the
CPU time is the steadier figure. Run: ``python benchmarks/headline.py`` (repository root; ``--quick`` skips
N = 50 and N = 1000).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
import sys
import tempfile
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.models.n_link_pendulum import NLinkPendulum
from flexlib.models.n_mass_chain import NMassChain
from flexlib.models.planar_mechanisms import FourBarLinkage, fourbar_spec
from flexlib.models.reference.hydraulic_servo import HydraulicServo
from flexlib.models.reference.planar_minimal import MinimalDAE, MinimalODE

RTOL, ATOL = 1e-6, 1e-8


def _cpu() -> float:
    """CPU time of this process and its finished children (gcc of the code generation) [s]."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def timed(fn: Callable[[], Any]) -> tuple[Any, float, float]:
    """(result, wall s, CPU s including child processes) of ``fn()``."""
    w, c = time.perf_counter(), _cpu()
    out = fn()
    return out, time.perf_counter() - w, _cpu() - c


def fresh_cache() -> None:
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")


ROWS: list[tuple] = []  # every printed row, for the results file


def row(name: str, wall: float, cpu: float, extra: str = "", floor: float | None = None) -> None:
    """One table row; ``floor`` is the floor's CPU time (the ratio is taken on CPU time, steadier under load)."""
    ratio = f"{cpu / floor:.1f}" if floor else ""
    print(f"| {name} | {wall:.3f} | {cpu:.3f} | {ratio} | {extra} |", flush=True)
    ROWS.append((name, wall, cpu, cpu / floor if floor else None, extra))


def main(argv: list[str]) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N-link chain up to N = 20, mass chain N = 100 only")
    args = ap.parse_args(argv)
    print(f"Headline figures, rtol {RTOL:g}, atol {ATOL:g}; OMP_NUM_THREADS=1; wall and CPU seconds; "
          "ratios to the floor timed in this run (CPU)\n")
    print("| figure | wall (s) | CPU (s) | × floor (CPU) | notes |")
    print("|---|---|---|---|---|")

    # four-bar, 10 s
    spec = fourbar_spec()
    grid = np.linspace(0.0, 10.0, 1001)
    ode, w_ode_b, _ = timed(lambda: MinimalODE(spec))
    out, w_ode, c_ode = timed(lambda: ode.solve(grid, rtol=RTOL, atol=ATOL))
    row("four-bar 10 s: minimal-coordinate ODE, CVODE (floor)", w_ode, c_ode,
        f"construction {w_ode_b:.3f} s; {out['nfev']} rhs evals")
    dae, w_dae_b, _ = timed(lambda: MinimalDAE(spec))
    out, w_dae, c_dae = timed(lambda: dae.solve(grid, rtol=RTOL, atol=ATOL))
    row("four-bar 10 s: hand-written minimal DAE, IDA", w_dae, c_dae,
        f"construction {w_dae_b:.3f} s; {dae.n} unknowns", c_ode)
    fresh_cache()
    sim, w_b, c_b = timed(lambda: fl.Simulation(FourBarLinkage()))
    row("four-bar: build (cold)", w_b, c_b, f"{sim.compiled.n} unknowns")
    for solver in ("ida", "ida-native", "casadi-idas"):
        res, w, c = timed(lambda s=solver: sim.run(10.0, dt_out=0.01, rtol=RTOL, atol=ATOL, progress=False, solver=s))
        st = res.stats
        row(f"four-bar 10 s: run, {solver}", w, c, f"{st['steps']} steps, {st.get('state_switches', 0)} switches",
            c_ode)

    # hydraulic servo, 20 s
    fresh_cache()
    sim, w_b, c_b = timed(lambda: fl.Simulation(HydraulicServo()))
    row("hydraulic servo: build (cold)", w_b, c_b, f"{sim.compiled.n} unknowns")
    for solver in ("ida", "ida-native", "casadi-idas"):
        try:
            res, w, c = timed(lambda s=solver: sim.run(20.0, dt_out=0.01, rtol=RTOL, atol=ATOL, progress=False,
                                                       solver=s))
        except fl.SolverError as err:  # reported, not hidden: the table says which route failed and where
            print(f"| hydraulic servo 20 s: run, {solver} | failed | {str(err).splitlines()[0]} |")
            continue
        row(f"hydraulic servo 20 s: run, {solver}", w, c, f"{res.stats['steps']} steps")

    # N-link chain
    sizes = [2, 5, 10, 20] if args.quick else [2, 5, 10, 20, 50]
    data = []
    for n in sizes:
        fresh_cache()
        sim, w_b, c_b = timed(lambda n=n: fl.Simulation(NLinkPendulum(n)))
        res, w_r, c_r = timed(lambda sim=sim: sim.run(10.0, dt_out=0.01, rtol=RTOL, atol=ATOL, progress=False))
        data.append((n, w_b, w_r, c_b, c_r))
        row(f"N-link chain N = {n}: build (cold)", w_b, c_b, f"{sim.compiled.n} unknowns")
        row(f"N-link chain N = {n}: run 10 s", w_r, c_r, f"{res.stats['steps']} steps")
    n, wb, wr, cb, cr = (np.array(v, dtype=float) for v in zip(*data, strict=True))
    fit = {k: np.polyfit(np.log(n), np.log(v), 1)[0] for k, v in (("build", wb), ("run", wr), ("build CPU", cb),
                                                                    ("run CPU", cr))}
    print(f"| N-link chain growth over N = {sizes[0]}…{sizes[-1]} (log-log slope) | | | | "
          + ", ".join(f"{k} ~ N^{v:.2f}" for k, v in fit.items()) + " |")

    # chain of masses
    for n in ([100] if args.quick else [100, 1000]):
        fresh_cache()

        def cold(n: int = n) -> Any:
            s = fl.Simulation(NMassChain(n))
            return s, s.run(10.0, dt_out=0.1, rtol=RTOL, atol=ATOL, progress=False)

        (sim, res), w, c = timed(cold)
        row(f"mass chain N = {n}: cold build + 10 s run", w, c,
            f"{sim.compiled.n} unknowns, {res.stats['steps']} steps")
        _, w, c = timed(lambda n=n: fl.Simulation(NMassChain(n)))
        row(f"mass chain N = {n}: cached build", w, c)

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    cpu = {r[0]: r[2] for r in ROWS}
    ratio = {r[0]: r[3] for r in ROWS}
    figures = [("four-bar run (ida) / ODE floor", ratio["four-bar 10 s: run, ida"], ""),
               ("servo run (ida)", cpu.get("hydraulic servo 20 s: run, ida", "failed"), "s"),
               (f"N-link chain N = {sizes[-1]}: build", cpu[f"N-link chain N = {sizes[-1]}: build (cold)"], "s"),
               ("run", cpu[f"N-link chain N = {sizes[-1]}: run 10 s"], "s"),
               ("growth: build CPU", f"N^{fit['build CPU']:.2f}", ""), ("run CPU", f"N^{fit['run CPU']:.2f}", ""),
               ("mass chain N = 100: cold build + run", cpu["mass chain N = 100: cold build + 10 s run"], "s")]
    report.write_results(__file__, figures, tables=[report.table(
        f"Headline figures, rtol {RTOL:g}, atol {ATOL:g}; ratios to the floor timed in this run (CPU)",
        ["figure", "wall [s]", "CPU [s]", "× floor (CPU)", "notes"], ROWS)])


if __name__ == "__main__":
    main(sys.argv[1:])
