"""Check: how close the pump truck's scenario run and its golden are to a tight-tolerance reference run.

Runs a scenario (default ``expand-fold``, ``--flexible`` for the flexible boom) at the scenario's own tolerances and at
``--rtol`` / ``--atol`` (default 1e-7 / 1e-9), and prints, for the golden's signals with the largest deviations, the
largest deviation over the golden grid of the scenario run and of the stored golden from the reference, each in
multiples of the golden test's tolerance for that signal (``models/pump_truck/goldens.py``: 1 % of the range plus a
floor). Used to decide whether a change that moves a golden moves it towards or away from the
converged solution (``python -m flexlib.models.pump_truck.goldens --regenerate`` only when it does not move away). The
reference run takes several minutes (the flexible expand-fold at rtol 1e-7: about 940 k steps).

Run: ``python benchmarks/pump_truck_reference.py [--scenario expand-fold] [--flexible] [--rtol 1e-7] [--atol 1e-9]``.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
from dataclasses import replace

import numpy as np


def main() -> None:
    import flexlib as fl
    from flexlib.models.pump_truck.goldens import TOLERANCES, _kind, golden_path
    from flexlib.registry import get_model

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="expand-fold")
    parser.add_argument("--flexible", action="store_true")
    parser.add_argument("--rtol", type=float, default=1e-7)
    parser.add_argument("--atol", type=float, default=1e-9)
    parser.add_argument("--show", type=int, default=10, help="signals listed [1]")
    args = parser.parse_args()
    entry = get_model("pump-truck")
    scenario = entry.scenario(args.scenario)
    scenario = replace(scenario, options={**scenario.options, "flexible": args.flexible})
    golden = fl.load_result(golden_path(args.scenario, args.flexible))
    sim = fl.Simulation(entry.factory(scenario))
    sim.compiled.wait_for_library()
    sim = fl.Simulation(entry.factory(scenario))
    runs = {}
    for tag, tol in (("scenario", {}), ("reference", {"rtol": args.rtol, "atol": args.atol})):
        res = sim.run(scenario.t_end, progress=False, **{**scenario.run, **tol})
        runs[tag] = res
        print(f"{tag}: {res.stats['steps']} steps", flush=True)
    rows = []
    for name in golden.names:
        if name not in runs["reference"]:
            continue
        g = golden[name]
        atol, rtol = TOLERANCES[_kind(name)]
        span = atol + rtol * float(np.ptp(g))  # the golden test's tolerance for this signal
        ref = np.interp(golden.t, runs["reference"].t, runs["reference"][name])
        new = np.interp(golden.t, runs["scenario"].t, runs["scenario"][name])
        rows.append((max(np.max(np.abs(new - ref)), np.max(np.abs(g - ref))) / span,
                     np.max(np.abs(new - ref)) / span, np.max(np.abs(g - ref)) / span, name))
    print(f"largest deviation from the rtol {args.rtol:g} reference over the golden grid, in golden tolerances:")
    print(f"{'signal':40s} {'this run':>10s} {'golden':>10s}")
    for _, new_dev, gold_dev, name in sorted(rows, reverse=True)[:args.show]:
        print(f"{name:40s} {new_dev:10.3g} {gold_dev:10.3g}")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    shown = sorted(rows, reverse=True)[:args.show]
    variant = "flexible" if args.flexible else "rigid"
    report.write_results(__file__, [
        (f"{variant}: largest deviation, this run", max(r[1] for r in rows), "tolerances"),
        ("golden", max(r[2] for r in rows), "tolerances"), ("reference steps", runs["reference"].stats["steps"], "")],
        tables=[report.table(f"Pump truck {args.scenario} ({variant}): largest deviation from the rtol {args.rtol:g} "
                             "reference over the golden grid, in golden tolerances",
                             ["signal", "this run", "golden"], [(n, a, b) for _, a, b, n in shown])])


if __name__ == "__main__":
    main()
