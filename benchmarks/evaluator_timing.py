"""Check: a run does not depend on when the compiled model library arrives.

A model above the size where C pays is compiled by gcc in the background while its first run starts on CasADi's
SX virtual machine; the run adopts the library mid-run when gcc has finished (``flexlib/compile/codegen.py``). A
loaded machine moves that moment. This script runs the pump truck's expand-fold (rigid and flexible) three ways,
each in a fresh process:

* ``absent``: no library (``codegen=False``): the virtual machine from start to end;
* ``late``: an empty cache: gcc compiles in the background and the run switches to C where it is ready;
* ``ready``: the cached build with its library, in use from the first step;

and prints, per variant, the steps, where the switch happened, and the largest difference from ``absent`` over every
variable at every output time (also as a SHA-256 of the whole result matrix). Expected: identical to the last bit
(the compiled C performs the same operations in the same order as the virtual machine).

Run: ``python benchmarks/evaluator_timing.py [--rigid-only | --flexible-only]`` (about 5 minutes).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
import hashlib
import json
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve()


def child(variant: str, flexible: bool, out: str) -> None:
    """One run in this process (``variant``), its golden signals and a hash of the whole result written to ``out``."""
    import flexlib as fl
    from flexlib.models.pump_truck.goldens import golden_signals
    from flexlib.registry import get_model

    entry = get_model("pump-truck")
    sc = entry.scenario("expand-fold")
    sc = replace(sc, options={**sc.options, "flexible": flexible})
    sim = fl.Simulation(entry.factory(sc), codegen=False if variant == "absent" else "auto")
    pending = sim.compiled.library_pending is not None
    if variant == "ready" and not sim.compiled.wait_for_library():
        raise SystemExit("ready: no compiled library")
    if variant == "late" and not pending:
        raise SystemExit("late: the library was not being compiled (a warm cache?)")
    c0 = time.process_time()
    res = sim.run(sc.t_end, params=dict(sc.params), progress=False, **dict(sc.run))
    cpu = time.process_time() - c0
    names = golden_signals(res)
    np.savez(out, t=res.t, values=np.column_stack([res[n] for n in names]), names=np.array(names))
    digest = hashlib.sha256(np.ascontiguousarray(res.t).tobytes() + np.ascontiguousarray(res.values).tobytes())
    Path(out + ".json").write_text(json.dumps({
        "steps": int(res.stats["steps"]), "compiled_at": res.stats.get("compiled_at"), "cpu": cpu,
        "rows": len(res.t), "variables": len(res.names), "sha256": digest.hexdigest()}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rigid-only", action="store_true")
    parser.add_argument("--flexible-only", action="store_true")
    parser.add_argument("--child", nargs=3, metavar=("VARIANT", "FLEXIBLE", "OUT"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.child[0], args.child[1] == "1", args.child[2])
        return
    kinds = [False] if args.rigid_only else [True] if args.flexible_only else [False, True]
    table = []
    with tempfile.TemporaryDirectory() as work:
        for flexible in kinds:
            cache = Path(work) / f"cache-{int(flexible)}"  # empty: the first 'auto' build compiles in the background
            env = {**os.environ, "FLEXLIB_CACHE_DIR": str(cache)}
            rows = {}
            for variant in ("absent", "late", "ready"):
                out = str(Path(work) / f"{variant}-{int(flexible)}.npz")
                subprocess.run([sys.executable, str(HERE), "--child", variant, str(int(flexible)), out], env=env,
                               check=True)
                rows[variant] = (np.load(out), json.loads(Path(out + ".json").read_text()))
            ref, ref_info = rows["absent"]
            print(f"\n{'flexible' if flexible else 'rigid'} expand-fold ({ref_info['rows']} rows x "
                  f"{ref_info['variables']} variables)")
            print(f"{'variant':8s} {'steps':>8s} {'C from t [s]':>13s} {'CPU [s]':>8s} "
                  f"{'max |diff| golden signals':>26s}  whole result")
            for variant, (data, info) in rows.items():
                same_t = data["t"].shape == ref["t"].shape and np.array_equal(data["t"], ref["t"])
                diff = float(np.max(np.abs(data["values"] - ref["values"]))) if same_t else float("nan")
                at = info["compiled_at"]
                when = "never" if variant == "absent" else "start" if variant == "ready" and at is None else \
                    f"{at:.1f}" if at is not None else "start"
                whole = "identical" if info["sha256"] == ref_info["sha256"] else "DIFFERS"
                print(f"{variant:8s} {info['steps']:8d} {when:>13s} {info['cpu']:8.1f} {diff:26.3g}  {whole}")
                table.append(("flexible" if flexible else "rigid", variant, info["steps"], when, info["cpu"], diff,
                              whole))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [(f"{r[0]}, {r[1]}", r[6], "") for r in table if r[1] != "absent"],
                         tables=[report.table("Pump-truck expand-fold with the compiled library absent, arriving late "
                                              "and ready; differences from 'absent'",
                                              ["variant", "library", "steps", "C from t [s]", "CPU [s]",
                                               "max |diff|", "whole result"], table)])


if __name__ == "__main__":
    main()
