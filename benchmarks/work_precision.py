"""Work–precision benchmark: error against a tight reference vs CPU time.

Systems, tolerances rtol = 1e-5 … 1e-10 (atol = rtol/100 for the mechanisms, atol = rtol for the servo:
with atol = rtol/100 the servo fails at t ≈ 1e-15 s for rtol ≤ 1e-10 on both backends, step-size underflow in
the start transient; flexlib scales atol by each unknown's nominal):

* **four-bar** (``models/planar_mechanisms.py``, crank-rocker, no gravity, 6 rad/s), ``--t-end`` s (default
  2 s, about two crank turns). Error: largest absolute error of any absolute link angle [rad] on a 0.01 s
  grid against the minimal-coordinate ODE in CVODE at rtol 1e-13, atol 1e-15 (``benchmarks/minimal_dae.py``;
  its own error, estimated against rtol 1e-12, is printed).
* **7-body 3-loop** planar mechanism, the same error measure and reference kind.
* **hydraulic servo** (``HydraulicServo`` imported from ``benchmarks/hydraulic_servo.py``), first 3 s (start
  transient and the set-point ramp towards the rod-end stop; over 5 s, with the stop contact at 3.6 s, the
  casadi-idas reference at rtol 1e-11 stops with IDA_TOO_MUCH_WORK at the contact). Error: largest absolute error of
  the piston position ``cylinder.x`` [m] on a 0.01 s grid against ``solver="casadi-idas"`` at rtol = atol =
  1e-11 (its own error is estimated against 1e-10 and printed).

Routes: flexlib's default backend (``solver="ida"``), ``solver="casadi-idas"``, and for the mechanisms the
hand-written minimal dummy-derivative DAE (``MinimalDAE``, scikit-sundae IDA, angles and speeds in the
error test). CPU = ``time.process_time()`` of the run (build excluded; the models are built once, the generated C is
waited for, and every route runs once untimed first, so one-off loading costs stay out). The
ratio "default / hand-written CPU at equal accuracy" interpolates the hand-written curve log-log at the
default run's error (monotone envelope: least CPU reaching at least that accuracy); points outside the
hand-written range are not compared.

Run: ``python benchmarks/work_precision.py`` (repository root; ``--quick`` for rtol 1e-5…1e-8,
``--systems fourbar,threeloop,servo``, ``--budget 120`` stops a route once one run takes longer [s CPU]).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import argparse
import sys
import tempfile
import time
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.models.planar_mechanisms import FourBarLinkage, ThreeLoopLinkage, fourbar_spec, three_loop_spec
from flexlib.models.reference.hydraulic_servo import HydraulicServo
from flexlib.models.reference.planar_minimal import MinimalDAE, MinimalODE

RTOLS = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]


def equal_accuracy_ratio(err_a: np.ndarray, cpu_a: np.ndarray, err_b: np.ndarray,
                         cpu_b: np.ndarray) -> list[float | None]:
    """CPU of route a over route b at a's errors, b interpolated log-log on its monotone envelope."""
    order = np.argsort(err_b)
    e, c = np.log(err_b[order]), np.log(cpu_b[order])
    c = np.minimum.accumulate(c[::-1])[::-1]  # least CPU that reaches at least this accuracy
    out: list[float | None] = []
    for ea, ca in zip(err_a, cpu_a, strict=True):
        le = np.log(ea)
        out.append(None if not e[0] <= le <= e[-1] else float(ca / np.exp(np.interp(le, e, c))))
    return out


def _mechanism(label: str, model: Any, spec: Any, rtols: list[float], t_end: float, budget: float) -> list[dict]:
    grid = np.linspace(0.0, t_end, round(t_end / 0.01) + 1)
    ref = MinimalODE(spec).solve(grid, rtol=1e-13)
    ref_check = MinimalODE(spec).solve(grid, rtol=1e-12)
    ref_err = max(float(np.abs(ref_check["q"][n] - ref["q"][n]).max()) for n in ref["q"])
    print(f"\n### {label}, {t_end:g} s; reference: minimal-coordinate ODE (CVODE, rtol 1e-13; vs rtol 1e-12: "
          f"{ref_err:.1e} rad)\n")
    sim = fl.Simulation(model)
    sim.compiled.wait_for_library()  # time the compiled model, not the first runs on CasADi's VM
    dae = MinimalDAE(spec)
    # one untimed run per route first: every route's one-off costs (deserialising functions, loading the driver and
    # its linear solver, building CasADi's integrator, the hand-written DAE's first IDA) stay out of the timings
    dae.solve(grid, rtol=rtols[0])
    for route in ("ida", "casadi-idas"):
        sim.run(t_end, dt_out=0.01, rtol=rtols[0], atol=rtols[0] * 1e-2, progress=False, solver=route)
    rows = []
    for route in ("ida", "casadi-idas", "hand-written"):
        for rtol in rtols:
            if route == "hand-written":
                out = dae.solve(grid, rtol=rtol)
                cpu, q, steps = out["cpu"], out["q"], "–"
            else:
                c0 = time.process_time()
                try:
                    res = sim.run(t_end, dt_out=0.01, rtol=rtol, atol=rtol * 1e-2, progress=False, solver=route)
                except fl.SolverError as err:
                    print(f"  {route} rtol {rtol:g}: failed ({str(err)[:80]})")
                    continue
                cpu = time.process_time() - c0
                q = {n: np.interp(grid, res.t, v) for n, v in model.absolute_angles(res).items()}
                steps = res.stats["steps"]
            err = max(float(np.abs(q[n] - ref["q"][n]).max()) for n in ref["q"])
            rows.append({"route": route, "rtol": rtol, "err": err, "cpu": cpu, "steps": steps})
            if cpu > budget:
                break
    return rows


def _servo(rtols: list[float], t_end: float, budget: float) -> list[dict]:
    grid = np.linspace(0.0, t_end, round(t_end / 0.01) + 1)
    sim = fl.Simulation(HydraulicServo())
    sim.compiled.wait_for_library()
    ref = sim.run(t_end, dt_out=0.01, rtol=1e-11, atol=1e-11, progress=False, solver="casadi-idas")
    chk = sim.run(t_end, dt_out=0.01, rtol=1e-10, atol=1e-10, progress=False, solver="casadi-idas")
    x_ref = ref.value("cylinder.x", grid)
    ref_err = float(np.abs(chk.value("cylinder.x", grid) - x_ref).max())
    print(f"\n### hydraulic servo, first {t_end:g} s; reference: casadi-idas at rtol 1e-11 (vs rtol 1e-10: "
          f"{ref_err:.1e} m)\n")
    sim.run(t_end, dt_out=0.01, rtol=rtols[0], atol=rtols[0], progress=False)  # untimed (see _mechanism)
    rows = []
    for route in ("ida", "casadi-idas"):
        for rtol in rtols:
            c0 = time.process_time()
            try:
                res = sim.run(t_end, dt_out=0.01, rtol=rtol, atol=rtol, progress=False, solver=route)
            except fl.SolverError as err:
                print(f"  {route} rtol {rtol:g}: failed ({str(err)[:80]})")
                continue
            cpu = time.process_time() - c0
            err = float(np.abs(res.value("cylinder.x", grid) - x_ref).max())
            rows.append({"route": route, "rtol": rtol, "err": err, "cpu": cpu, "steps": res.stats["steps"]})
            if cpu > budget:
                break
    return rows


def _table(rows: list[dict], unit: str) -> float | None:
    """Print the work–precision table; return the default backend's geometric-mean CPU ratio at equal accuracy."""
    print(f"| route | rtol | error ({unit}) | CPU (s) | IDA steps |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['route']} | {r['rtol']:.0e} | {r['err']:.2e} | {r['cpu']:.3f} | {r['steps']} |")
    by = {route: [r for r in rows if r["route"] == route] for route in ("ida", "casadi-idas", "hand-written")}
    ref_route = "hand-written" if by["hand-written"] else "casadi-idas"
    base = by[ref_route]
    if len(base) < 2:
        return None
    mean = None
    eb, cb = np.array([r["err"] for r in base]), np.array([r["cpu"] for r in base])
    for route in ("ida", "casadi-idas"):
        if route == ref_route or not by[route]:
            continue
        ea, ca_ = np.array([r["err"] for r in by[route]]), np.array([r["cpu"] for r in by[route]])
        ratios = equal_accuracy_ratio(ea, ca_, eb, cb)
        text = ", ".join(f"{r['rtol']:.0e}: {x:.1f}" for r, x in zip(by[route], ratios, strict=True) if x is not None)
        valid = [x for x in ratios if x is not None]
        gm = f"; geometric mean {np.exp(np.mean(np.log(valid))):.1f}" if valid else ""
        if route == "ida" and valid:
            mean = float(np.exp(np.mean(np.log(valid))))
        print(f"\n{route} CPU / {ref_route} CPU at equal accuracy (by {route} rtol): {text or 'no overlap'}{gm}")
    return mean


def main(argv: list[str]) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="rtol 1e-5 … 1e-8 only")
    ap.add_argument("--systems", default="fourbar,threeloop,servo")
    ap.add_argument("--t-end", type=float, default=2.0, help="mechanisms' simulated time [s]")
    ap.add_argument("--servo-t-end", type=float, default=3.0, help="servo's simulated time [s]")
    ap.add_argument("--budget", type=float, default=120.0, help="CPU seconds after which a route stops tightening")
    args = ap.parse_args(argv)
    rtols = RTOLS[:4] if args.quick else RTOLS
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    print(f"Work–precision, rtol {rtols[0]:g} … {rtols[-1]:g}, atol = rtol/100 (servo: rtol); "
          "CPU = process time of the run (build excluded); OMP_NUM_THREADS=1; machine shared with other jobs")
    systems = args.systems.split(",")
    found = {}  # name -> (rows, unit, geometric-mean CPU ratio at equal accuracy)
    if "fourbar" in systems:
        rows = _mechanism("four-bar", FourBarLinkage(), fourbar_spec(), rtols, args.t_end, args.budget)
        found["four-bar"] = (rows, "rad", _table(rows, "rad"))
    if "threeloop" in systems:
        rows = _mechanism("7-body 3-loop mechanism", ThreeLoopLinkage(), three_loop_spec(), rtols, args.t_end,
                          args.budget)
        found["7-body 3-loop"] = (rows, "rad", _table(rows, "rad"))
    if "servo" in systems:
        rows = _servo(rtols, args.servo_t_end, args.budget)
        found["hydraulic servo"] = (rows, "m", _table(rows, "m"))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures, tables = [], []
    for name, (rows, unit, mean) in found.items():
        peer = "hand-written" if any(r["route"] == "hand-written" for r in rows) else "casadi-idas"
        if mean is not None:
            figures.append((f"{name}: default / {peer} CPU at equal accuracy", mean, ""))
        tables.append(report.table(f"{name}: error against a tight reference vs process CPU of the run",
                                   ["route", "rtol", f"error [{unit}]", "CPU [s]", "IDA steps"],
                                   [(r["route"], r["rtol"], r["err"], r["cpu"], r["steps"]) for r in rows]))
    report.write_results(__file__, figures, tables=tables)


if __name__ == "__main__":
    main(sys.argv[1:])
