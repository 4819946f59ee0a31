"""The pump truck's slewing ring with stick/slip friction against the regularised law: run time and slew motion.

The ``slew`` scenario (working pose, pipe filled, the turret slewed 90° on its hydraulic drive and angle loop), rigid
boom, run with the slewing ring's Coulomb friction ``tau_c`` (Rothe Erde's estimate) as the revolute's regularised
law ``tau_c tanh(w / 0.01 rad/s)`` (the model's default) and as MSL's ``BearingFriction`` between the revolute's axis
and its housing (stick/slip: sticking exact, breakaway and stops as state events), each on its cached build with
compiled C. Interleaved, fastest of
``--repeat`` (default 2) per law: CPU time, steps, state events, and the slew angle's largest difference between the
two laws and its end value each. The decision drawn from the figures is in ``docs/pump_truck.md``.

Run: ``python benchmarks/pump_truck_friction.py [--repeat 2]`` (repository root). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
import dataclasses
import tempfile
import time

os.environ.setdefault("FLEXLIB_CACHE_DIR", tempfile.mkdtemp(prefix="flexlib_bench_"))

import numpy as np

import flexlib as fl
from flexlib.models.pump_truck.model import PumpTruck
from flexlib.models.pump_truck.parameters import PumpTruckParameters
from flexlib.models.pump_truck.scenarios import SCENARIOS


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    scenario = next(s for s in SCENARIOS if s.name == "slew")
    base = PumpTruckParameters()
    sims = {}
    for law in ("regularised", "stick-slip"):
        record = dataclasses.replace(base, turret=dataclasses.replace(base.turret, friction=law))
        fl.Simulation(PumpTruck(record=record, **scenario.options, **scenario.data)).compiled.wait_for_library()
        # the runs use the cached build with its compiled C (the first build's C compiles in the background)
        sims[law] = fl.Simulation(PumpTruck(record=record, **scenario.options, **scenario.data))
    best: dict[str, tuple[float, fl.Result]] = {}
    for _ in range(args.repeat):
        for law, sim in sims.items():
            c0 = time.process_time()
            res = sim.run(scenario.t_end, progress=False, **dict(scenario.run))
            cpu = time.process_time() - c0
            if law not in best or cpu < best[law][0]:
                best[law] = (cpu, res)
    reg, hyb = best["regularised"][1], best["stick-slip"][1]
    t = reg.t[reg.t > 0]
    diff = float(np.max(np.abs(hyb.value("turret.slew.phi", t, side="right") - reg.value("turret.slew.phi", t,
                                                                                          side="right"))))
    rows = [(law, cpu, res.stats["steps"], res.stats["state_events"], float(res["turret.slew.phi"][-1]))
            for law, (cpu, res) in best.items()]
    print(f"slew scenario, {scenario.t_end:.1f} s, rigid boom (fastest of {args.repeat}, interleaved):")
    for law, cpu, steps, events, phi in rows:
        print(f"  {law:12s} {cpu:7.2f} s CPU  {steps:6d} steps  {events:4d} state events  slew angle at the end "
              f"{np.degrees(phi):.4f} deg")
    ratio = best["stick-slip"][0] / best["regularised"][0]
    print(f"  stick-slip / regularised: {ratio:.2f}; largest slew-angle difference {np.degrees(diff):.2e} deg")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [
        ("regularised", best["regularised"][0], "s"), ("stick-slip", best["stick-slip"][0], "s"),
        ("stick-slip / regularised", ratio, ""), ("largest slew-angle difference", float(np.degrees(diff)), "deg"),
    ], tables=[report.table(f"slew scenario, {scenario.t_end:.1f} s, rigid boom, fastest of {args.repeat}",
                            ["law", "CPU [s]", "steps", "state events", "slew angle at the end [rad]"], rows)])


if __name__ == "__main__":
    main()
