"""Benchmark: build and run times of the seed-002 robots, rigid and flexible.

Cartesian manipulator (``models/robots/cartesian.py``): the three drives on trapezoidal speed profiles for 0.6 s
(the default profiles of ``CartesianRobot``), rigid and flexible arms (default record: 12 beam elements, 6 constraint
+ 4 fixed-interface modes per arm), at ``rtol`` 1e-6. Printed per variant: unknowns and states, cold build (fresh
cache directory, until runnable) and cached build in CPU time of this process and its gcc children, the run's CPU
time, steps and the ratio of run CPU to simulated time; then the flexible/rigid ratios. The flexible robot starts
in its sagged static equilibrium (``steady_state=True``). No timing is asserted.

POLYCRANK fragment (``models/robots/polycrank.py``, rigid links): cold and cached build, and a 0.5 s run released
with the drive torques 10 % below the holding torques. With flexible pull rods (30 Craig–Bampton rods, the study
model of ``models/robots/polycrank_study.py``): cold build (until runnable; its C library then compiles in the
background: its wall time reported apart), cached build, the 1 s torque-pulse run with friction and preload
(static start included) and one locked modal analysis.

Run: ``python benchmarks/robots.py`` (repository root).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import tempfile
import time


def _cpu() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def bench(flexible: bool, t_end: float = 0.6) -> dict:
    with tempfile.TemporaryDirectory() as cache:
        os.environ["FLEXLIB_CACHE_DIR"] = cache
        import flexlib as fl
        from flexlib.models.robots import CartesianRobot

        c0 = _cpu()
        sim = fl.Simulation(CartesianRobot(flexible=flexible))
        cold = _cpu() - c0
        sim.compiled.wait_for_library()
        c0 = _cpu()
        sim = fl.Simulation(CartesianRobot(flexible=flexible))
        cached = _cpu() - c0
        c0 = _cpu()
        res = sim.run(t_end, dt_out=0.005, rtol=1e-6, atol=1e-8, steady_state=flexible, progress=False)
        run = _cpu() - c0
    variant = "flexible" if flexible else "rigid"
    print(f"cartesian / {variant}: {sim.compiled.n} unknowns, {len(sim.states)} states; build cold {cold:.2f} s, "
          f"cached {cached:.2f} s CPU; run {t_end} s simulated in {run:.2f} s CPU "
          f"(real-time factor {t_end / run:.2f}), "
          f"{res.stats['steps']} steps, status {res.status}")
    return {"model": f"cartesian / {variant}", "unknowns": sim.compiled.n, "states": len(sim.states), "cold": cold,
            "cached": cached, "t_sim": t_end, "run": run, "steps": res.stats["steps"]}


def bench_polycrank(t_end: float = 0.5) -> dict:
    """The POLYCRANK fragment, rigid links, released from rest in its pose with the drive torques set off by 10 %."""
    with tempfile.TemporaryDirectory() as cache:
        os.environ["FLEXLIB_CACHE_DIR"] = cache
        import flexlib as fl
        from flexlib.models.robots import PolycrankFragment

        c0 = _cpu()
        sim = fl.Simulation(PolycrankFragment(angles=(0.3, 0.5, -0.2, 0.1)))
        cold = _cpu() - c0
        sim.compiled.wait_for_library()
        c0 = _cpu()
        sim = fl.Simulation(PolycrankFragment(angles=(0.3, 0.5, -0.2, 0.1)))
        cached = _cpu() - c0
        names = [n for n in sim.compiled.param_names if n.endswith(".tau_drive") and not n.startswith(("c", "o"))]
        params = {n: 0.9 * float(sim.parameter_vector()[sim.compiled.param_names.index(n)]) for n in names}
        c0 = _cpu()
        res = sim.run(t_end, dt_out=0.005, rtol=1e-6, atol=1e-8, params=params, progress=False)
        run = _cpu() - c0
    print(f"polycrank / rigid: {sim.compiled.n} unknowns, {len(sim.states)} states, "
          f"{len(sim.compiled.report.redundant)} redundant rows dropped; build cold {cold:.2f} s, "
          f"cached {cached:.2f} s CPU; run {t_end} s simulated in {run:.2f} s CPU, {res.stats['steps']} steps, "
          f"status {res.status}")
    return {"model": "polycrank / rigid", "unknowns": sim.compiled.n, "states": len(sim.states), "cold": cold,
            "cached": cached, "t_sim": t_end, "run": run, "steps": res.stats["steps"]}


def bench_polycrank_flexible(t_end: float = 1.0) -> dict:
    """The POLYCRANK fragment with flexible pull rods: the torque-pulse study run (friction, 500 N preload)."""
    with tempfile.TemporaryDirectory() as cache:
        os.environ["FLEXLIB_CACHE_DIR"] = cache
        import flexlib as fl
        from flexlib.models.robots.polycrank import preload_params
        from flexlib.models.robots.polycrank_study import LOCKED, PRELOAD, no_friction, pulse_model

        c0 = _cpu()
        sim = fl.Simulation(pulse_model(True))
        cold = _cpu() - c0
        w0 = time.perf_counter()
        sim.compiled.wait_for_library()  # a detached gcc (its CPU is not in os.times): its wall time
        background = time.perf_counter() - w0
        c0 = _cpu()
        model = pulse_model(True)
        sim = fl.Simulation(model)
        cached = _cpu() - c0
        c0 = _cpu()
        res = sim.run(t_end, dt_out=0.005, steady_state=True, params=preload_params(model, PRELOAD), progress=False)
        run = _cpu() - c0
        c0 = _cpu()
        modes = fl.modal_analysis(sim, lock=LOCKED, steady_state=True,
                                  params={**no_friction(), **preload_params(model, PRELOAD)})
        modal = _cpu() - c0
    print(f"polycrank / flexible rods: {sim.compiled.n} unknowns, {len(sim.states)} states, "
          f"{len(sim.compiled.report.redundant)} rows dropped; build cold {cold:.1f} s CPU (its C library "
          f"ready {background:.0f} s of wall time later), cached {cached:.2f} s CPU; run {t_end} s simulated in "
          f"{run:.1f} s CPU "
          f"(real-time factor {t_end / run:.2f}), {res.stats['steps']} steps, status {res.status}; locked modal "
          f"analysis {modal:.1f} s CPU (lowest {modes.frequencies[modes.oscillatory].min():.1f} Hz)")
    return {"model": "polycrank / flexible rods", "unknowns": sim.compiled.n, "states": len(sim.states), "cold": cold,
            "cached": cached, "t_sim": t_end, "run": run, "steps": res.stats["steps"], "modal": modal}


def main() -> None:
    rigid = bench(False)
    flexible = bench(True)
    print(f"flexible / rigid: cold build {flexible['cold'] / rigid['cold']:.1f}, run "
          f"{flexible['run'] / rigid['run']:.1f}")
    rows = [rigid, flexible, bench_polycrank(), bench_polycrank_flexible()]

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    keys = ["model", "unknowns", "states", "cold", "cached", "t_sim", "run", "steps"]
    report.write_results(__file__, [
        *((f"{r['model']}: run / simulated time", r["run"] / r["t_sim"], "") for r in rows),
        ("cartesian: flexible / rigid run", flexible["run"] / rigid["run"], "")], tables=[report.table(
            "Seed-002 robots, rtol 1e-6; CPU of this process and its gcc children",
            ["model", "unknowns", "states", "cold [s]", "cached [s]", "simulated [s]", "run [s]", "steps"],
            [[r[k] for k in keys] for r in rows])],
        notes=[f"polycrank / flexible rods: locked modal analysis {rows[-1]['modal']:.3g} s CPU"])


if __name__ == "__main__":
    main()
