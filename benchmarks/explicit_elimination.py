"""Explicit algebraics eliminated after index reduction (``flexlib/compile/explicit.py``): off, on and all.

Every system is built three times in this one process, with the stage off (``FLEXLIB_EXPLICIT=0``), on (``1``, the
default: only unknowns outside IDA's error test eliminated) and ``FLEXLIB_EXPLICIT=all``, without the disk cache,
and run once on the default backend after its generated C (if any) is in use. Reported per build: unknowns,
states, residual / Jacobian operations (``Function.n_instructions()`` of the compiled functions, which merge
common subexpressions; in brackets without that merge), structural nonzeros of the Jacobian,
build CPU (process time, without the background gcc), run CPU (process time; the native IDA driver runs in
this process), IDA steps and Jacobian evaluations, and the largest difference of the run's reference
outputs from the build without the stage (all at the same tolerances).

Usage (repository root)::

    FLEXLIB_ZERO_GEOMETRY=1 python benchmarks/explicit_elimination.py [--systems fourbar,threeloop,...]

Systems: ``fourbar``, ``threeloop`` (7-body, 3 loops), ``servo`` (``benchmarks/hydraulic_servo.py``),
``boom`` (``models/boom_proxy.py`` with linkages, 20 s), ``chain5``, ``chain10``, ``chain20`` (N-link pendulum,
10 s at rtol 1e-6), ``masses100`` (chain of 100 masses, 10 s).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")  # before numpy / sksundae are imported

import argparse
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

ROOT = Path(__file__).resolve().parent.parent

import flexlib as fl  # noqa: E402


def _systems() -> dict[str, tuple[Callable[[], fl.Model], dict[str, Any], list[str]]]:
    """name -> (model factory, run arguments, reference outputs compared between the builds)."""
    from flexlib.models.boom_proxy import BoomProxy
    from flexlib.models.n_link_pendulum import NLinkPendulum
    from flexlib.models.n_mass_chain import NMassChain
    from flexlib.models.planar_mechanisms import FourBarLinkage, ThreeLoopLinkage, three_loop_spec
    from flexlib.models.reference.hydraulic_servo import ATOL, RTOL, T_END, HydraulicServo

    mech = {"t_end": 10.0, "dt_out": 0.01, "rtol": 1e-6, "atol": 1e-8}
    boom = BoomProxy.experiment
    return {
        "fourbar": (FourBarLinkage, mech, ["rev_crank.phi", "rev_coupler.phi", "rev_rocker.phi"]),
        "threeloop": (ThreeLoopLinkage, mech, [f"rev_{lk.name}.phi" for lk in three_loop_spec().links]),
        "servo": (HydraulicServo, {"t_end": T_END, "dt_out": 0.01, "rtol": RTOL, "atol": ATOL},
                  ["cylinder.x", "cylinder.p_A"]),
        "boom": (lambda: BoomProxy(linkages=True),
                 {"t_end": 20.0, "dt_out": boom.dt_out, "rtol": boom.rtol, "atol": boom.atol},
                 [f"angle{n}.phi" for n in range(1, 6)]),
        "chain5": (lambda: NLinkPendulum(5), mech, [f"joint{k}.phi" for k in range(1, 6)]),
        "chain10": (lambda: NLinkPendulum(10), mech, [f"joint{k}.phi" for k in range(1, 11)]),
        "chain20": (lambda: NLinkPendulum(20), mech, [f"joint{k}.phi" for k in range(1, 21)]),
        "masses100": (lambda: NMassChain(100), {"t_end": 10.0, "dt_out": 0.1, "rtol": 1e-6, "atol": 1e-8},
                      ["mass99.s", "mass49.s"]),
    }


def measure(factory: Callable[[], fl.Model], run: dict[str, Any], flag: str) -> dict[str, Any]:
    """Build (stage on if ``flag`` is "1") and run once; sizes, CPU times and the result."""
    os.environ["FLEXLIB_EXPLICIT"] = flag
    c0 = time.process_time()
    sim = fl.Simulation(factory(), use_cache=False)
    build = time.process_time() - c0
    m = sim.compiled
    m.wait_for_library()
    F, y, yp, cj = sim.build.dae.residual, sim.build.dae.y, sim.build.dae.yp, ca.SX.sym("cj")
    syms = [*ca.symvar(F), cj]
    raw = ca.Function("r", syms, [F]).n_instructions()
    raw_j = ca.Function("j", syms, [ca.jacobian(F, y) + cj * ca.jacobian(F, yp)]).n_instructions()
    args = dict(run)
    t_end = args.pop("t_end")
    c0 = time.process_time()
    res = sim.run(t_end, progress=False, **args)
    cpu = time.process_time() - c0
    return {"n": m.n, "states": int(m.differential.sum()), "res": m.sx_function("res").n_instructions(),
            "res_raw": raw, "jac": m.sx_function("jac").n_instructions(), "jac_raw": raw_j, "nnz": len(m.jac_row),
            "build": build, "run": cpu, "steps": res.stats["steps"], "njev": res.stats["njev"],
            "C": m.library is not None, "result": res}


def main(argv: list[str]) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--systems", default="fourbar,threeloop,servo,boom,chain5,chain10,chain20,masses100")
    args = ap.parse_args(argv)
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    systems = _systems()
    print(f"Explicit algebraics eliminated: off (FLEXLIB_EXPLICIT=0), 1 (the default: unknowns outside IDA's error "
          f"test), all (FLEXLIB_EXPLICIT=all); FLEXLIB_ZERO_GEOMETRY={os.environ.get('FLEXLIB_ZERO_GEOMETRY', '0')}; "
          "CPU = process time; one run per cell\n")
    print("| system | stage | unknowns | states | residual ops (unmerged) | Jacobian ops (unmerged) | Jacobian nnz | "
          "build CPU (s) | run CPU (s) | IDA steps | Jacobians | C | max output difference to 'off' |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows, runs = [], {}
    for name in args.systems.split(","):
        factory, run, refs = systems[name]
        grid = np.linspace(0.0, run["t_end"], 501)
        base = None
        for flag, label in (("0", "off"), ("1", "1"), ("all", "all")):
            r = measure(factory, run, flag)
            if base is None:
                base, d = r["result"], ""
            else:
                d = f"{max(float(np.abs(base.value(v, grid) - r['result'].value(v, grid)).max()) for v in refs):.1e}"
            print(f"| {name} | {label} | {r['n']} | {r['states']} | {r['res']} ({r['res_raw']}) | "
                  f"{r['jac']} ({r['jac_raw']}) | "
                  f"{r['nnz']} | {r['build']:.2f} | {r['run']:.2f} | {r['steps']} | {r['njev']} | "
                  f"{'yes' if r['C'] else 'no'} | {d} |", flush=True)
            rows.append((name, label, r["n"], r["states"], r["res"], r["res_raw"], r["jac"], r["jac_raw"], r["nnz"],
                         r["build"], r["run"], r["steps"], r["njev"], r["C"], d))
            runs[name, label] = r
    os.environ.pop("FLEXLIB_EXPLICIT", None)

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures = []
    for name in args.systems.split(","):
        off, on = runs[name, "off"], runs[name, "1"]
        figures += [(f"{name}: unknowns", f"{off['n']} → {on['n']}", ""), ("run / off", on["run"] / off["run"], "")]
    report.write_results(__file__, figures, tables=[report.table(
        "Explicit algebraics eliminated: off (FLEXLIB_EXPLICIT=0), 1 (default), all; process CPU, one run per cell",
        ["system", "stage", "unknowns", "states", "residual ops", "unmerged", "Jacobian ops", "unmerged",
         "Jacobian nnz", "build CPU [s]", "run CPU [s]", "IDA steps", "Jacobians", "C", "max output diff to off"],
        rows)])


if __name__ == "__main__":
    main(sys.argv[1:])
