"""Smoothness of the pump truck's cylinder flows in a scenario (issue 28's check), and its peak chamber pressures.

Per cylinder side and per move of its joint (an interval where the joint's target column changes; consecutive ones
joined): the number of runs of ``|dq/dt|`` above 20 % of its largest value in the move, ``q`` the port flow on the
scenario's output grid. Issue 28 asks for at most two per move (the acceleration and the deceleration of a smooth
speed profile). Also the peak pressure of every chamber over the run.

Run: ``python benchmarks/pump_truck_flows.py [--model pump-truck] [--scenario expand-fold]`` (repository root).
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np


def peak_runs(x: np.ndarray, fraction: float = 0.2) -> int:
    """Number of runs of |x| above ``fraction`` of its maximum."""
    above = np.abs(x) > fraction * np.max(np.abs(x))
    return int(np.count_nonzero(above[1:] & ~above[:-1]) + above[0])


def main() -> None:
    from flexlib.registry import get_model, run_scenario

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", default="pump-truck")
    parser.add_argument("--scenario", default="expand-fold")
    args = parser.parse_args()
    scenario = get_model(args.model).scenario(args.scenario)
    res = run_scenario(args.model, scenario, progress=False).result
    t, keep = np.unique(res.t, return_index=True)
    table = scenario.data["targets"]
    tt = np.asarray(table["t"])
    counts = []
    joints = sorted(k for k in table if k.startswith("joint"))
    for name in joints:
        n = int(name[5:])
        col = np.asarray(table[name])
        moving = np.flatnonzero(col[1:] != col[:-1])
        if moving.size == 0:
            continue
        starts, ends = moving[np.r_[True, np.diff(moving) > 1]], moving[np.r_[np.diff(moving) > 1, True]]
        for a, b in zip(tt[starts], tt[ends + 1], strict=True):
            window = (t >= a) & (t <= b)
            for side in "AB":
                q = np.asarray(res[f"axis{n}.cylinder.cylinder.q_{side}"])[keep]
                c = peak_runs(np.gradient(q, t)[window])
                counts.append(c)
                print(f"cylinder {n} port {side}, move {a:7.1f} … {b:7.1f} s: {c} run(s) of |dq/dt| above 20 %")
    smooth = sum(c <= 2 for c in counts)
    print(f"moves with at most two: {smooth} of {len(counts)} (issue 28: all)")
    peak = 0.0
    for name in joints:
        n = int(name[5:])
        peaks = [float(np.max(res[f"axis{n}.cylinder.cylinder.p_{s}"])) / 1e5 for s in "AB"]
        peak = max(peak, *peaks)
        print(f"cylinder {n}: peak chamber pressures A {peaks[0]:.0f} bar, B {peaks[1]:.0f} bar (absolute)")
    if args.model != "pump-truck" or args.scenario != "expand-fold":
        return
    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [("cylinder moves with at most two flow-rate peaks", smooth, f"of {len(counts)}"),
                                    ("most flow-rate peaks in a move", max(counts), ""),
                                    ("peak chamber pressure", peak, "bar")])


if __name__ == "__main__":
    main()
