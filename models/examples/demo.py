"""flexlib demo: compile, run, report, plot and save a drive train (``python -m flexlib.models.examples.demo``).

The pump-truck scenario replaces this demo once the boom exists. Until then it shows the whole
pipeline on MSL's ``Rotational.Examples.First``: the index-reduction report, a run, a parameter
change without recompiling, the result file and a plot.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import flexlib as fl
from flexlib.models.examples.rotational.first import FirstDriveTrain


def main(argv: list[str] | None = None) -> None:
    """Run the demo; writes ``<out>/demo.h5`` and ``<out>/demo.png``."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", default="demo_output", help="output directory")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    t0 = time.perf_counter()
    sim = fl.Simulation(FirstDriveTrain())
    build = time.perf_counter() - t0
    print(f"Model FirstDriveTrain: built in {build * 1e3:.0f} ms "
          f"({'from cache' if sim.build_info['cached'] else 'compiled'}), {sim.compiled.n} unknowns")
    print(sim.report, end="\n\n")

    res = sim.run(result_file=str(out / "demo.h5"))
    stiff = sim.run(params={"spring.c": 1e5})
    print(f"Run 1 (c = 1e4 N.m/rad): {res.stats['steps']} steps, {res.stats['nfev']} residual evaluations, "
          f"{res.stats['wall_integrate'] * 1e3:.0f} ms")
    print(f"Run 2 (c = 1e5 N.m/rad, same compiled model): {stiff.stats['steps']} steps")
    for name in ("inertia1.w", "inertia2.w", "spring.tau"):
        print(f"  max |{name}| = {np.max(np.abs(res[name])):8.4f} [{res.unit(name)}]   (stiff shaft: "
              f"{np.max(np.abs(stiff[name])):8.4f})")
    back = fl.load_result(out / "demo.h5")
    print(f"Result file {out / 'demo.h5'}: {len(back.names)} variables × {len(back.t)} time points")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    res.plot("inertia2.w", ax=ax1, title="FirstDriveTrain: load speed")
    stiff.plot("inertia2.w", ax=ax1)
    ax1.legend(["c = 1e4 N.m/rad", "c = 1e5 N.m/rad"])
    res.plot("spring.tau", ax=ax2, title="shaft torque")
    fig.tight_layout()
    fig.savefig(out / "demo.png", dpi=110)
    print(f"Plot {out / 'demo.png'}")


if __name__ == "__main__":
    main()
