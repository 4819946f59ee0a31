"""Benchmark: the planar mechanisms of ``models/planar_mechanisms.py`` built from components vs written by hand.

The hand-written formulations (:class:`~flexlib.models.reference.planar_minimal.MinimalDAE`, the minimal index-1
dummy-derivative DAE in absolute link angles, and :class:`~flexlib.models.reference.planar_minimal.MinimalODE`, the
minimal-coordinate ODE in the driver angle) are in :mod:`flexlib.models.reference.planar_minimal`.

Run ``python benchmarks/minimal_dae.py`` for the size comparison: unknowns and residual/Jacobian operation counts
(``Function.n_instructions()``) of the component-built model vs the hand-written DAE, and one 10 s run of each at
rtol 1e-8.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")  # before numpy / sksundae are imported

import tempfile
import time

import numpy as np

from flexlib.models.planar_mechanisms import fourbar_spec, three_loop_spec
from flexlib.models.reference.planar_minimal import MinimalDAE, MinimalODE, size_comparison


def main() -> None:
    import flexlib as fl
    from flexlib.models.planar_mechanisms import FourBarLinkage, ThreeLoopLinkage

    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    t_end, rtol = 10.0, 1e-8
    grid = np.linspace(0.0, t_end, 1001)
    print(f"Planar mechanisms: component-built (flexlib) vs hand-written minimal DAE; {t_end:g} s at rtol {rtol:g}, "
          "atol = rtol/100; CPU = process time\n")
    print("| mechanism | model | unknowns | states | residual ops | Jacobian ops | run CPU (s) | max angle diff vs "
          "minimal ODE (rad) |")
    print("|---|---|---|---|---|---|---|---|")
    rows, figures = [], []
    for label, make, spec in (("four-bar", FourBarLinkage, fourbar_spec()),
                              ("7-body 3-loop", ThreeLoopLinkage, three_loop_spec())):
        ref = MinimalODE(spec).solve(grid, rtol=1e-12)
        dae = MinimalDAE(spec)
        out = dae.solve(grid, rtol=rtol)
        err_min = max(np.abs(out["q"][n] - ref["q"][n]).max() for n in ref["q"])
        for zero, what in ((False, "component-built, 3D (assume_zero_geometry=False)"),
                           (True, "component-built (default: planar geometry assumed)")):
            model = make()
            sim = fl.Simulation(model, use_cache=False, assume_zero_geometry=zero)
            c0 = time.process_time()
            res = sim.run(t_end, dt_out=t_end / 1000, rtol=rtol, atol=rtol * 1e-2, progress=False)
            cpu_fl = time.process_time() - c0
            q_fl = model.absolute_angles(res)
            sizes = size_comparison(sim, dae)
            err_fl = max(np.abs(np.interp(grid, res.t, q_fl[n]) - ref["q"][n]).max() for n in ref["q"])
            print(f"| {label} | {what} | {sizes['unknowns'][0]} | {int(sim.compiled.differential.sum())} | "
                  f"{sizes['residual ops'][0]} | {sizes['Jacobian ops'][0]} | {cpu_fl:.2f} | {err_fl:.1e} |")
            rows.append((label, what, sizes["unknowns"][0], int(sim.compiled.differential.sum()),
                         sizes["residual ops"][0], sizes["Jacobian ops"][0], cpu_fl, err_fl))
        print(f"| {label} | hand-written DAE | {sizes['unknowns'][1]} | 2 | {sizes['residual ops'][1]} | "
              f"{sizes['Jacobian ops'][1]} | {out['cpu']:.3f} | {err_min:.1e} |")
        print(f"| {label} | ratio default / hand-written | {sizes['unknowns'][0] / sizes['unknowns'][1]:.1f} | | "
              f"{sizes['residual ops'][0] / sizes['residual ops'][1]:.1f} | "
              f"{sizes['Jacobian ops'][0] / sizes['Jacobian ops'][1]:.1f} | {cpu_fl / out['cpu']:.0f} | |")
        rows.append((label, "hand-written DAE", sizes["unknowns"][1], 2, sizes["residual ops"][1],
                     sizes["Jacobian ops"][1], out["cpu"], err_min))
        figures += [(f"{label}: unknowns default / hand-written", sizes["unknowns"][0] / sizes["unknowns"][1], ""),
                    ("Jacobian ops", sizes["Jacobian ops"][0] / sizes["Jacobian ops"][1], ""),
                    ("run CPU", cpu_fl / out["cpu"], "")]

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, figures, tables=[report.table(
        f"Planar mechanisms, component-built vs hand-written minimal DAE; {t_end:g} s at rtol {rtol:g}, "
        "atol = rtol/100; process CPU", ["mechanism", "model", "unknowns", "states", "residual ops", "Jacobian ops",
                                          "run CPU [s]", "max angle diff vs minimal ODE [rad]"], rows)])


if __name__ == "__main__":
    main()
