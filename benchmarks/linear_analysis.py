"""Benchmark: the cost of a 50-pose modal sweep of the pump-truck boom, rigid and flexible.

For each variant in one process: one run of the ``expand`` scenario (the poses), then ``modal_sweep`` at 50
instants of it, free (oil compliance, valves, controllers) and with the rigid degrees of freedom locked
(``lock="rigid"``). Printed: CPU time of the sweep and per pose, as a ratio to the expand run that produced the
poses, and to a floor timed in the same process: per pose one evaluation of the compiled iteration matrix and one
dense eigenvalue problem of the state matrix (``numpy.linalg.eig``), the two steps no linear analysis avoids.
Also the lowest frequencies at the first and last pose. No timing is asserted.

Run: ``python benchmarks/linear_analysis.py [--variant both] [--poses 50]`` (repository root).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", choices=("rigid", "flexible", "both"), default="both")
    parser.add_argument("--poses", type=int, default=50)
    args = parser.parse_args()
    rows = []
    for flexible in {"rigid": (False,), "flexible": (True,), "both": (False, True)}[args.variant]:
        rows += bench(flexible, args.poses)

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [(f"{v}, {held}: per pose", cpu / n, "s") for v, held, n, cpu, *_ in rows] + [
        (f"{v}, {held}: / floor", ratio, "") for v, held, _, _, _, ratio, *_ in rows], tables=[report.table(
            "Pump-truck boom: modal sweep over the poses of the expand scenario (process CPU)",
            ["variant", "held", "poses", "sweep [s]", "sweep / expand run", "sweep / floor", "floor per pose [s]",
             "lowest modes, transport fold [Hz]", "lowest modes, working pose [Hz]"], rows)])


def bench(flexible: bool, n_poses: int) -> list[tuple]:
    from dataclasses import replace

    import numpy as np

    import flexlib as fl
    from flexlib.models.pump_truck.frequency_map import frequency_map
    from flexlib.registry import get_model

    entry = get_model("pump-truck")
    sc = entry.scenario("expand")
    sc = replace(sc, options={**sc.options, "flexible": flexible})
    sim = fl.Simulation(entry.factory(sc))
    sim.compiled.wait_for_library()
    sim = fl.Simulation(entry.factory(sc))
    c0 = time.process_time()
    res = sim.run(sc.t_end, progress=False, params=dict(sc.params), **{**sc.run, "dt_out": 0.5})
    run_cpu = time.process_time() - c0
    variant = "flexible" if flexible else "rigid"
    print(f"pump-truck / expand / {variant}: {sim.compiled.n} unknowns, {len(sim.states)} states; "
          f"expand run {res.t[-1]:g} s simulated in {run_cpu:.2f} s CPU")
    # the floor: per pose one iteration-matrix evaluation and one dense eigenproblem of the state matrix
    lin = fl.linearize(sim, at=res, t=float(res.t[-1]))
    m = sim.compiled
    jac = m.function("jac")
    pt = lin.point
    c0 = time.process_time()
    for _ in range(n_poses):
        jac(pt.t, pt.y, pt.yp, pt.p, 0.0)
        np.linalg.eig(lin.A)
    floor = time.process_time() - c0
    rows = []
    for lock in (None, "rigid"):
        c0 = time.process_time()
        fmap = frequency_map(flexible=flexible, n_poses=n_poses, lock=lock, result=res, sim=sim)
        cpu = time.process_time() - c0
        held = "free" if lock is None else "rigid DOFs locked"
        first = ", ".join(f"{f:.3g}" for f in fmap.frequencies[0])
        last = ", ".join(f"{f:.3g}" for f in fmap.frequencies[-1])
        print(f"  {n_poses}-pose sweep, {held}: {cpu:.2f} s CPU ({1e3 * cpu / n_poses:.1f} ms per pose; "
              f"{cpu / run_cpu:.2f} x the expand run, {cpu / floor:.1f} x the floor of {1e3 * floor / n_poses:.2f} "
              f"ms per pose); lowest modes [Hz]: transport fold {first}; working pose {last}")
        rows.append((variant, held, n_poses, cpu, cpu / run_cpu, cpu / floor, floor / n_poses, first, last))
    return rows


if __name__ == "__main__":
    main()
