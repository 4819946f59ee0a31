"""Benchmark: the ``casadi-idas`` backend (SX virtual machine, compiled C, an older revision) against the default.

For each model it runs, in one process and on the same compiled model (C library in use, ``wait_for_library``):

* ``ida`` — the default backend (SUNDIALS IDA stepped in C), the floor;
* ``casadi-idas before`` — ``flexlib/solve/casadi_idas.py`` as of git revision ``--before`` (default ``e34cab5``:
  SX virtual machine, reverse Cuthill–McKee order, no start fall-backs), loaded from ``git show``;
* ``casadi-idas SX`` — today's module with ``USE_LIBRARY = False`` (CasADi's SX virtual machine);
* ``casadi-idas C`` — today's default: the model's compiled library with its Jacobian companion.

Columns: process CPU time [s] (steadier than wall time on this shared machine), ratio to the floor, IDAS
steps, Jacobian evaluations, integrator calls (each a cold IDAS start), state events, and the largest
difference of a watched variable from the floor's result on the output grid.

Run: ``python benchmarks/casadi_idas.py`` (repository root; models ``chain10 chain100 fourbar servo boom
boomlink`` as arguments, default all). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
import importlib.util
import subprocess
import sys
import tempfile
import time
import types
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

import flexlib as fl  # noqa: E402
from flexlib.solve import casadi_runner  # noqa: E402


def _old_module(rev: str) -> types.ModuleType | None:
    """``flexlib/solve/casadi_idas.py`` at git revision ``rev`` as a module (None if git cannot show it)."""
    try:
        src = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:flexlib/solve/casadi_idas.py"],
                             capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    path = Path(tempfile.mkdtemp(prefix="flexlib_bench_")) / "casadi_idas_before.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location("casadi_idas_before", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # (dataclasses look their module up there)
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    return mod


def _model(name: str) -> tuple[fl.Model, float, float, float, float, str]:
    """(model, t_end [s], output step [s], rtol, atol, watched variable)."""
    if name.startswith("chain"):
        from flexlib.models.n_mass_chain import NMassChain
        return NMassChain(int(name[5:])), 10.0, 0.1, 1e-6, 1e-8, "mass1.s"
    if name == "fourbar":
        from flexlib.models.planar_mechanisms import FourBarLinkage
        return FourBarLinkage(), 10.0, 0.01, 1e-6, 1e-8, "rev_crank.phi"
    if name == "servo":
        from flexlib.models.reference.hydraulic_servo import HydraulicServo
        return HydraulicServo(), 20.0, 0.01, 1e-6, 1e-8, "cylinder.x"
    from flexlib.models.boom_proxy import BoomProxy
    e = BoomProxy.experiment
    return BoomProxy(linkages=name == "boomlink"), 20.0, e.dt_out, e.rtol, e.atol, "angle2.phi"


def _known_options(fn, known, *args, **kwargs):
    """Call ``fn`` with the keyword arguments it declares (an older module's signature)."""
    return fn(*args, **{k: v for k, v in kwargs.items() if k in known})


def _on_grid(r: fl.Result, name: str, dt: float) -> np.ndarray:
    keep = np.abs(r.t / dt - np.round(r.t / dt)) < 1e-7
    _, first = np.unique(r.t[keep], return_index=True)
    return r[name][keep][first]


def main(argv: list[str]) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", nargs="*", default=["chain10", "chain100", "fourbar", "servo", "boom", "boomlink"])
    ap.add_argument("--before", default="e34cab5", help="git revision of the 'before' module")
    args = ap.parse_args(argv)
    old = _old_module(args.before)
    print(f"casadi-idas before ({args.before}) / SX / C against the default backend; OMP_NUM_THREADS=1; process CPU "
          "seconds, one run each after a warm-up run of each route\n")
    print("| model | unknowns | C library | route | CPU (s) | × ida | steps | Jacobians | integrator calls "
          "| state events | max diff to ida |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for name in args.models:
        os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
        model, t_end, dt, rtol, atol, watch = _model(name)
        sim = fl.Simulation(model)
        lib = sim.compiled.wait_for_library(1200)
        routes: list[tuple[str, object]] = [("ida", None)]
        if old is not None:
            routes.append(("casadi-idas before", old))
        routes += [("casadi-idas SX", False), ("casadi-idas C", True)]
        floor, ref = None, None
        for label, how in routes:
            sim.compiled._functions.pop("casadi_idas", None)
            solver = "ida" if how is None else "casadi-idas"
            if isinstance(how, types.ModuleType):
                print(f"| {name} | | | {label} | skipped: the run loop takes an adapter, not a module | | | | | | |")
                continue
            casadi_runner.USE_LIBRARY = bool(how) if how is not None else True
            try:
                cpu, res, err = None, None, ""
                for _ in range(2):  # warm-up (integrator construction, companion library), then timed
                    c0 = time.process_time()
                    try:
                        res = sim.run(t_end, dt_out=dt, rtol=rtol, atol=atol, progress=False, solver=solver)
                    except fl.SolverError as exc:
                        err = str(exc).splitlines()[0][:80]
                        break
                    cpu = time.process_time() - c0
            finally:
                casadi_runner.USE_LIBRARY = True
            n = sim.compiled.n
            if res is None or err:
                print(f"| {name} | {n} | {lib} | {label} | failed: {err} | | | | | | |", flush=True)
                continue
            x = _on_grid(res, watch, dt)
            if floor is None:
                floor, ref = cpu, x
            diff = float(np.abs(x - ref).max()) if len(x) == len(ref) else float("nan")
            s = res.stats
            print(f"| {name} | {n} | {lib} | {label} | {cpu:.3f} | {cpu / floor:.2f} | {s['steps']} | {s['njev']} | "
                  f"{s.get('integrator_calls', '')} | {s.get('state_events', 0)} | {diff:.1e} |", flush=True)
            rows.append((name, n, lib, label, cpu, cpu / floor, s["steps"], s["njev"], s.get("integrator_calls", ""),
                         s.get("state_events", 0), diff))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [(f"{r[0]}: casadi-idas C / ida", r[5], "") for r in rows
                                    if r[3] == "casadi-idas C"], tables=[report.table(
        f"casadi-idas before ({args.before}) / SX / C against the default backend (the floor); process CPU, one run "
        "each after a warm-up run", ["model", "unknowns", "C library", "route", "CPU [s]", "× ida", "steps",
                                     "Jacobians", "integrator calls", "state events", "max diff to ida"], rows)])


if __name__ == "__main__":
    main(sys.argv[1:])
