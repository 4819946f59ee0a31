"""Benchmark: forward sensitivities (``Simulation.sensitivities``) of the rigid pump truck's ``hold`` against one run
and against central finite differences (issue 33).

Five parameters (the bores of axes 1–4 and axis 3's counterbalance pilot ratio), the four cylinders' cap-side
pressures as outputs, over the scenario's 30 s, tolerances of the runs (rtol 1e-6). CPU seconds of this process,
fastest of ``--repeat`` (default 2) calls after a first call that builds the sensitivity integrator (reported on its
own; gcc's compile of the sensitivity DAE, ~95 s once per model and number of parameters, is cached in
``$FLEXLIB_CACHE_DIR/sensitivity`` and runs in a child process, outside these CPU figures): one run; the
sensitivities (nominal run, the start's differences, the sensitivity integration, the outputs); the 2·5 + 1 runs
central differences need. Accuracy: the sensitivities of each cylinder's pressure by its own bore against central
differences of runs at rtol 1e-10 (relative step 1e-4), largest deviation over the largest magnitude. Target
(issue 33): sensitivities of 5 parameters ≤ 3× one run.

Run: ``python benchmarks/sensitivities.py [--repeat 2]`` (repository root).
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import argparse
import time

PARAMS = ["axis1.cylinder.cylinder.d_bore", "axis2.cylinder.cylinder.d_bore", "axis3.cylinder.cylinder.d_bore",
          "axis4.cylinder.cylinder.d_bore", "axis3.cbv_hold.pilot_ratio"]
OUTPUTS = [f"axis{k}.cylinder.cylinder.p_A" for k in (1, 2, 3, 4)]


def cpu(fn: object) -> tuple[float, object]:
    """CPU seconds of ``fn()`` in this process, and its value."""
    c = time.process_time()
    out = fn()  # type: ignore[operator]
    return time.process_time() - c, out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    import numpy as np

    import flexlib as fl
    from flexlib import registry

    instance, scen = registry.scenario_model("pump-truck", "hold")
    sim = fl.Simulation(instance)
    sim.compiled.wait_for_library()
    t_end, base = scen.t_end, dict(scen.params)
    run_opts = {"dt_out": 0.1, "rtol": 1e-6, "atol": 1e-8}

    def one_run() -> fl.Result:
        return sim.run(t_end, params=base, progress=False, **run_opts)

    def sens() -> object:
        return sim.sensitivities(t_end, PARAMS, OUTPUTS, values=base, **run_opts)

    one_run()
    t_first, _ = cpu(sens)
    t_run = min(cpu(one_run)[0] for _ in range(args.repeat))
    timed = [cpu(sens) for _ in range(args.repeat)]
    t_sens, s = min(timed, key=lambda r: r[0])
    values = sim.parameter_vector(base)
    names = sim.compiled.param_names

    def fd_runs() -> None:
        one_run()
        for name in PARAMS:
            v = float(values[names.index(name)])
            for sign in (1.0, -1.0):
                sim.run(t_end, params={**base, name: v * (1 + sign * 1e-4)}, progress=False, **run_opts)

    t_fd, _ = cpu(fd_runs)
    worst = 0.0
    for k in range(4):
        name, out = PARAMS[k], OUTPUTS[k]
        v = float(values[names.index(name)])
        h = 1e-4 * v
        r = [sim.run(t_end, params={**base, name: v + sign * h}, progress=False, dt_out=0.1, rtol=1e-10, atol=1e-12)
             for sign in (1.0, -1.0)]
        fd = (r[0].value(out, s.t, side="right") - r[1].value(out, s.t, side="right")) / (2 * h)
        worst = max(worst, float(np.max(np.abs(s[out, name] - fd)) / np.max(np.abs(fd))))
    st = s.stats
    print(f"one run {t_run:.3f} s CPU; sensitivities of {len(PARAMS)} parameters {t_sens:.3f} s "
          f"({t_sens / t_run:.1f}× a run: nominal run {st['run_cpu']:.3f}, start differences {st['start_cpu']:.3f}, "
          f"sensitivity integration and outputs {st['sens_cpu']:.3f}); first call (builds the integrator) "
          f"{t_first:.2f} s; central differences ({2 * len(PARAMS) + 1} runs) {t_fd:.3f} s ({t_fd / t_run:.1f}× a "
          f"run); sensitivities / differences {t_sens / t_fd:.2f}; worst deviation from central differences at "
          f"rtol 1e-10: {worst:.1e} of the largest")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [("sensitivities / one run", t_sens / t_run, "× (target ≤ 3)"),
                                    ("sensitivities / central differences", t_sens / t_fd, "×"),
                                    ("deviation from central differences", worst, "of the largest")],
                         tables=[report.table("pump truck hold, 5 parameters, CPU [s]",
                                              ["one run", "sensitivities", "start differences",
                                               "integration + outputs", "first call", "11 runs"],
                                              [[t_run, t_sens, st["start_cpu"], st["sens_cpu"], t_first, t_fd]])])


if __name__ == "__main__":
    main()
