"""Benchmark: hydraulic chamber formulations and physical error weights.

Part 1 — chamber formulations. A pump–relief–valve–cylinder circuit (the circuit of
``tests/components/hydraulics/test_cylinder_valves.py::test_mass_balance_pump_valve_cylinder``: 10 cm3/rev pump at
1500 rpm, 150 bar relief, 0.5 L supply volume, 4/3 valve driven by a 0.7 Hz sine, 63/36 × 400 mm cylinder with
internal leakage and a drained rod seal, 50 kg load; 3 s) is built three times, identical except for the chamber
formulation (``chamber_form`` of the cylinder and the supply volume, see
``flexlib.components.hydraulics.chamber_equations``):

* ``mass``       — the default: state = deviation of the stored mass from rho_ref·V_ref (exact mass balance);
* ``pressure``   — pressure as state (mass conserved only to the integration tolerance);
* ``mass_total`` — the stored mass itself as state (the earlier formulation, kept for comparison).

For rtol 1e-6 … 1e-9 it prints IDA steps, process CPU time, the largest errors of the piston position and of the
cap-side pressure against a reference run (rtol 1e-11, atol 1e-13) and the mass-balance error (pumped − returned −
Δstored, relative to the pumped mass), on the default backend and on ``solver="casadi-idas"``, for two
absolute-tolerance policies: atol = rtol and atol = 1e-4·rtol (both scaled by each variable's nominal).

Part 1b — the same comparison (default backend, 4 s) on variants of the circuit set through run-time parameters:
slow large travel, a start near the cap-end stop, a 2000 kg load.

Part 2 — error weights. The hydraulic servo of ``benchmarks/hydraulic_servo.py`` (read, not changed) at rtol
1e-5 … 1e-7 with the nominal values the hydraulics library declared earlier ("before": spool speed,
relief flow, pump torque, chamber masses and volumes at nominal 1 or 0.1) and with today's physical ones
("after"), against a reference run at rtol 1e-10: IDA steps, wall time and the largest piston-position error on a
2001-point grid, i.e. steps at equal accuracy.

Run: ``python benchmarks/hydraulic_chamber.py`` (from the repository root; ~5 min on a loaded 2-core VM);
``--quick`` runs rtol 1e-6 and 1e-8 only, ``--ida-only`` skips casadi-idas, ``--no-servo`` skips part 2,
``--no-chambers`` part 1. Nothing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import sys
import tempfile
import time

import numpy as np

import flexlib as fl
from flexlib.models.reference.hydraulic_circuit import PumpValveCylinder, mass_balance_error

T_END = 3.0


def part1(rtols: list[float], solvers: tuple[str, ...]) -> None:
    forms = ("mass", "pressure", "mass_total")
    sims = {f: fl.Simulation(PumpValveCylinder(f), use_cache=False) for f in forms}
    t0 = time.process_time()
    ref = sims["mass"].run(T_END, dt_out=0.01, rtol=1e-11, atol=1e-13, progress=False, max_steps=2_000_000)
    print(f"## Part 1: chamber formulations, pump–valve–cylinder circuit, {T_END:g} s, 301 output points\n")
    print(f"Reference: chamber_form='mass', rtol 1e-11, atol 1e-13, {ref.stats['steps']} steps "
          f"({time.process_time() - t0:.1f} s CPU). Cells: steps / CPU s / max|x − x_ref| [m] / "
          "max|p_A − p_A,ref| [Pa] / mass-balance error")
    for solver in solvers:
        for label, afac in (("atol = rtol", 1.0), ("atol = 1e-4·rtol", 1e-4)):
            print(f"\n### {solver}, {label} (× nominal)\n")
            print("| rtol | " + " | ".join(forms) + " | steps mass / pressure |")
            print("|---|" + "---|" * (len(forms) + 1))
            for rtol in rtols:
                cells, steps = [], {}
                for f in forms:
                    t0 = time.process_time()
                    try:
                        res = sims[f].run(T_END, dt_out=0.01, rtol=rtol, atol=afac * rtol, progress=False,
                                          solver=solver, max_steps=400_000)
                    except fl.SolverError as err:
                        cells.append(f"failed ({str(err).splitlines()[0][:60]})")
                        continue
                    cpu = time.process_time() - t0
                    steps[f] = res.stats["steps"]
                    ex = np.abs(res["cylinder.x"] - ref["cylinder.x"]).max()
                    ep = np.abs(res["cylinder.p_A"] - ref["cylinder.p_A"]).max()
                    cells.append(f"{steps[f]} / {cpu:.2f} / {ex:.1e} / {ep:.1e} / {mass_balance_error(res):.0e}")
                ratio = f"{steps['mass'] / steps['pressure']:.2f}" if {"mass", "pressure"} <= steps.keys() else "–"
                print(f"| {rtol:g} | " + " | ".join(cells) + f" | {ratio} |", flush=True)


#: Variants of the circuit through run-time parameters (circuits the formulation was not tuned on).
VARIANTS = {"slow, large travel": {"command.f": 0.25, "command.amplitude": 1.0},
            "start near the cap-end stop": {"cylinder.x_start": 0.02, "command.f": 0.4},
            "2000 kg load": {"load.m": 2000.0}}


def variants() -> None:
    """The circuit's variants (``VARIANTS``), 4 s, default backend: steps of the mass and pressure forms."""
    sims = {f: fl.Simulation(PumpValveCylinder(f), use_cache=False) for f in ("mass", "pressure")}
    print("\n## Part 1b: variants of the circuit, 4 s, default backend\n")
    print("Cells: steps mass / steps pressure (ratio), max|x_mass − x_pressure| [m]\n")
    cases = ((1e-6, 1.0), (1e-8, 1e-4), (1e-9, 1e-4))
    print("| variant | " + " | ".join(f"rtol {r:g}, atol {a * r:g}" for r, a in cases) + " |")
    print("|---|" + "---|" * len(cases))
    for name, params in VARIANTS.items():
        cells = []
        for rtol, afac in cases:
            out: dict[str, fl.Result | str] = {}
            for f, sim in sims.items():
                try:
                    out[f] = sim.run(4.0, dt_out=0.01, rtol=rtol, atol=afac * rtol, progress=False, params=params,
                                     max_steps=500_000)
                except fl.SolverError as err:
                    out[f] = f"{f} failed: {str(err).splitlines()[0][:50]}"
            m, p = out["mass"], out["pressure"]
            if isinstance(m, fl.Result) and isinstance(p, fl.Result):
                dx = np.abs(m["cylinder.x"] - p["cylinder.x"]).max()
                cells.append(f"{m.stats['steps']} / {p.stats['steps']} ({m.stats['steps'] / p.stats['steps']:.2f}), "
                             f"{dx:.1e}")
            else:
                cells.append("; ".join(v if isinstance(v, str) else f"{k} {v.stats['steps']}" for k, v in out.items()))
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)


#: Nominals the hydraulics library declared before the physical error weights (same variables, old values).
LEGACY_NOMINALS = {"valve.vs": 1.0, "relief.q": 1.0, "pump.tau": 1.0, "supply.m": 1.0, "supply.dm": 1.0,
                   "cylinder.dm_A": 0.1, "cylinder.dm_B": 0.1, "cylinder.V_A": 1.0, "cylinder.V_B": 1.0,
                   "cylinder.x": 1.0, "cylinder.v": 1.0}


def part2(rtols: list[float]) -> None:
    from flexlib.models.reference.hydraulic_servo import HydraulicServo

    sim = fl.Simulation(HydraulicServo(), use_cache=False)
    names = sim.compiled.y_names
    physical = np.asarray(sim.compiled.nominal, dtype=float).copy()
    legacy = physical.copy()
    for i, n in enumerate(names):
        if n in LEGACY_NOMINALS:
            legacy[i] = LEGACY_NOMINALS[n]
    changed = [f"{n}: {legacy[i]:g} → {physical[i]:g}" for i, n in enumerate(names) if legacy[i] != physical[i]]
    print("\n## Part 2: hydraulic servo (benchmarks/hydraulic_servo.py), 20 s, error weights before/after\n")
    print("Nominals changed (y entries of this model): " + "; ".join(changed) + "\n")
    grid = np.linspace(0.0, 20.0, 2001)

    def run(nominal: np.ndarray, rtol: float) -> tuple[fl.Result, float]:
        sim.compiled.nominal = nominal
        t0 = time.perf_counter()
        res = sim.run(20.0, dt_out=0.01, rtol=rtol, progress=False)
        return res, time.perf_counter() - t0

    try:
        ref, _ = run(physical, 1e-10)
        x_ref = ref.value("cylinder.x", grid)
        print(f"Reference: rtol 1e-10, {ref.stats['steps']} steps\n")
        print("| rtol | before: steps / wall s / max abs(x − x_ref) | after: steps / wall s / max abs(x − x_ref) |")
        print("|---|---|---|")
        for rtol in rtols:
            cells = []
            for nominal in (legacy, physical):
                res, wall = run(nominal, rtol)
                err = np.abs(res.value("cylinder.x", grid) - x_ref).max()
                cells.append(f"{res.stats['steps']} / {wall:.2f} / {err:.1e} m")
            print(f"| {rtol:g} | " + " | ".join(cells) + " |", flush=True)
    finally:
        sim.compiled.nominal = physical


def main() -> None:
    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    quick = "--quick" in sys.argv
    solvers = ("ida",) if "--ida-only" in sys.argv else ("ida", "casadi-idas")
    with report.printed() as out:
        if "--no-chambers" not in sys.argv:
            part1([1e-6, 1e-8] if quick else [1e-6, 1e-7, 1e-8, 1e-9], solvers)
            variants()
        if "--no-servo" not in sys.argv:
            part2([1e-6] if quick else [1e-5, 1e-6, 1e-7])
    tables = report.markdown_tables(out.getvalue())
    figures = [(f"{t['title']}, rtol {t['rows'][-1][0]}: steps mass / pressure form", t["rows"][-1][-1], "")
               for t in tables if t["columns"][-1] == "steps mass / pressure"]
    report.write_results(__file__, figures, tables=tables)


if __name__ == "__main__":
    main()
