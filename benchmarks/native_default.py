"""Benchmark: the default backend before (IDA stepped from Python) and after (the C driver) it became ``ida-native``.

Four-bar linkage (``models/planar_mechanisms.py``, 10 s) and hydraulic servo (``benchmarks/hydraulic_servo.py``,
20 s), rtol 1e-6 / atol 1e-8, 0.01 s grid, dynamic state selection on (the default), both models compiled once in
this process. Each backend runs the same compiled model, best of ``REPEAT`` runs (the machine is shared: read the
ratios, not the absolute times):

* ``ida-sksundae``: the default before (and its fallback without gcc): scikit-sundae's IDA stepped from Python;
* ``ida``: the default now: the C driver, Python only at outputs, events and due monitor checks;
* ``casadi-idas``: for reference.

Columns: run time (whole ``Simulation.run``), IDA steps, switches, monitor indicator checks / full tests, the
integration's split into model / IDA / Python (C driver only: measured around each call in C), and the largest
deviation from ``ida-sksundae`` on the grid relative to each variable's range.

``--boom`` adds the boom proxy without linkages (``models/boom_proxy.py``, 434 unknowns, 20 s), run once gcc has
finished its generated C (waited for), so that both routes evaluate the same library.

Run: ``python benchmarks/native_default.py [--boom]`` from the repository root. No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import flexlib as fl  # noqa: E402

REPEAT = 3
SOLVERS = ("ida-sksundae", "ida", "casadi-idas")


def main() -> None:
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    from hydraulic_servo import HydraulicServo

    from flexlib.models.planar_mechanisms import FourBarLinkage
    from flexlib.solve.native import native_available

    t = time.perf_counter()
    ok = native_available()
    print(f"C driver available: {ok} ({time.perf_counter() - t:.2f} s to compile or load)\n")
    print(f"best of {REPEAT}; rtol 1e-6, atol 1e-8, dt_out 0.01 s\n")
    print("| model | backend | run (s) | × vs ida-sksundae | steps | switches | monitor checks / full | "
          "model / IDA / Python (ms) | max |Δ| |")
    print("|---|---|---|---|---|---|---|---|---|")
    models = [("four-bar 10 s", FourBarLinkage, 10.0), ("hydraulic servo 20 s", HydraulicServo, 20.0)]
    if "--boom" in sys.argv[1:]:
        from models.boom_proxy import BoomProxy

        models.append(("boom proxy, direct cylinders, 20 s", lambda: BoomProxy(linkages=False), 20.0))
    for name, factory, t_end in models:
        sim = fl.Simulation(factory())
        deadline = time.monotonic() + 600.0
        while sim.compiled.library_pending is not None and sim.compiled.library is None:  # wait for gcc
            if time.monotonic() > deadline:
                print(f"{name}: gcc has not finished after 600 s; running on CasADi's VM")
                break
            time.sleep(0.1)
            sim.compiled.function("res")
        out = {}
        for solver in SOLVERS:
            best, res, counts = np.inf, None, None
            for _ in range(REPEAT):
                mon = sim._monitor() if sim.compiled.has_state_choice else None
                before = dict(mon.counts) if mon is not None else {}
                w = time.perf_counter()
                try:
                    r = sim.run(t_end, dt_out=0.01, rtol=1e-6, atol=1e-8, progress=False, solver=solver)
                except fl.SolverError as err:  # reported in the table
                    r = err.result
                w = time.perf_counter() - w
                if w < best:
                    best, res = w, r
                    counts = {k: v - before.get(k, 0) for k, v in mon.counts.items()} if mon is not None else None
            out[solver] = (best, res, counts)
        ref = out["ida-sksundae"][1]
        for solver in SOLVERS:
            best, res, counts = out[solver]
            st = res.stats
            split = ("–" if "wall_model" not in st else
                     f"{1e3 * st['wall_model']:.0f} / {1e3 * st['wall_ida']:.0f} / {1e3 * st['wall_python']:.0f}")
            mon = "–" if counts is None else f"{counts['indicator']} / {counts['full']}"
            if not res.success:
                solver = f"{solver} (failed at t = {res.t[-1]:.3g} s)"
            print(f"| {name} | {solver} | {best:.3f} | {out['ida-sksundae'][0] / best:.1f} | {st['steps']} | "
                  f"{st.get('state_switches', 0)} | {mon} | {split} | {deviation(res, ref):.1e} |", flush=True)


def deviation(r: fl.Result, ref: fl.Result) -> float:
    """Largest difference on the common output times, relative to each variable's range (at least 1e-6)."""
    common, ia, ib = np.intersect1d(r.t, ref.t, return_indices=True)
    if not len(common):
        return float("nan")
    a, b = r.values[ia], ref.values[ib]
    scale = np.maximum(np.abs(b).max(axis=0), 1e-6)
    return float(np.max(np.abs(a - b) / scale))


if __name__ == "__main__":
    main()
