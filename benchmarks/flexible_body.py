"""Benchmark: the cost of a FlexibleBody in a model, against a rigid body built and run the same way.

* A 500-node beam body with 20 modes (Craig–Bampton, improved; interface nodes at both ends, free-free reference)
  swinging as a pendulum on a revolute joint under gravity: cold build (empty cache: flatten → simplify → index
  reduction → compile, C code compiled in the background), cached build, and the 10 s run.
* How build and run grow with the number of modes, 5, 10, 20, 40 (same body, same motion), with the compiled
  model's size (unknowns, residual operations).

Floors timed in the same run: reading the modal file (what any tool must do) and a rigid ``Body`` pendulum built
and run the same way. Process CPU time and wall time; nothing is asserted. Targets: cold ≤ 5 s,
cached ≤ 0.2 s for 20 modes / 500 nodes.

    python benchmarks/flexible_body.py            # ~1–2 min
    python benchmarks/flexible_body.py --quick    # 5 and 20 modes only
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.components.mechanics.multibody import Body, Revolute, World
from flexlib.fe import ModalData, beam_mesh, box, modal_data_from_fe

N_NODES = 500


def body_file(directory: Path, n_modes: int) -> Path:
    """A 2 m steel box beam, 499 elements (500 nodes), ``n_modes`` modes, written to ``directory``."""
    fe = beam_mesh((0, 0, 0), (2.0, 0, 0), N_NODES - 1, box(0.06, 0.04, 0.004), E=2.1e11, rho=7850.0)
    data = modal_data_from_fe(fe, [0, N_NODES - 1], max(n_modes, 8), title=f"box beam {n_modes} modes")
    path = directory / f"beam{n_modes}.h5"
    data.select(np.argsort(data.frequencies)[:n_modes]).write(path)
    return path


class Pendulum(fl.Model):
    """A revolute at the world origin (axis z) carrying the body at its frame_a, released 0.5 rad from vertical."""

    def __init__(self, body: fl.Component) -> None:
        super().__init__()
        self.world = World(g=9.81)
        self.rev = Revolute(n=[0, 0, 1], init={"phi": -np.pi / 2 + 0.5, "w": 0.0})
        self.body = body
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.body.frame_a)


def timed(fn):
    c0, w0 = time.process_time(), time.perf_counter()
    out = fn()
    return out, time.process_time() - c0, time.perf_counter() - w0


def measure(path: Path, cache: Path) -> dict:
    os.environ["FLEXLIB_CACHE_DIR"] = str(cache)
    _, read_cpu, _ = timed(lambda: ModalData.read(path))
    sim, cold_cpu, cold_wall = timed(lambda: fl.Simulation(Pendulum(FlexibleBody(path))))
    sim.compiled.wait_for_library(120.0)  # the run measured is the C one (the first run of a new model may not be)
    _, run_cpu, run_wall = timed(lambda: sim.run(10.0, dt_out=0.01, progress=False))
    best = float("inf")
    for _ in range(5):
        _, _cpu, w = timed(lambda: fl.Simulation(Pendulum(FlexibleBody(path))))
        best = min(best, w)
    return {"read": read_cpu, "cold_cpu": cold_cpu, "cold_wall": cold_wall, "cached": best, "run_cpu": run_cpu,
            "run_wall": run_wall, "unknowns": len(sim.compiled.y_names)}


def rigid_floor(cache: Path) -> dict:
    os.environ["FLEXLIB_CACHE_DIR"] = str(cache)
    body = dict(m=3.0, r_CM=[1.0, 0, 0], I=np.diag([1e-3, 1.0, 1.0]))
    sim, cold_cpu, _ = timed(lambda: fl.Simulation(Pendulum(Body(**body))))
    _, run_cpu, _ = timed(lambda: sim.run(10.0, dt_out=0.01, progress=False))
    return {"cold_cpu": cold_cpu, "run_cpu": run_cpu}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="5 and 20 modes only")
    args = parser.parse_args()
    counts = (5, 20) if args.quick else (5, 10, 20, 40)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        floor = rigid_floor(tmp / "rigid")
        print(f"FlexibleBody pendulum, {N_NODES} nodes, 10 s; floor: rigid Body pendulum build "
              f"{floor['cold_cpu']:.2f} s CPU, run {floor['run_cpu']:.3f} s CPU")
        print(f"{'modes':>5} {'read file':>10} {'cold CPU':>9} {'cold wall':>10} {'cached':>8} {'run CPU':>8} "
              f"{'run wall':>9} {'unknowns':>9}")
        rows = []
        for n in counts:
            path = body_file(tmp, n)
            r = measure(path, tmp / f"cache{n}")
            rows.append((n, r))
            print(f"{n:>5} {r['read']:>9.3f}s {r['cold_cpu']:>8.2f}s {r['cold_wall']:>9.2f}s {r['cached']:>7.3f}s "
                  f"{r['run_cpu']:>7.2f}s {r['run_wall']:>8.2f}s {r['unknowns']:>9}")
        if len(rows) > 2:
            n = np.log([r[0] for r in rows])
            for key in ("cold_cpu", "run_cpu"):
                slope = np.polyfit(n, np.log([r[1][key] for r in rows]), 1)[0]
                print(f"growth of {key} with the number of modes: ~ M^{slope:.2f}")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    twenty = dict(rows)[20]
    report.write_results(__file__, [
        ("20 modes: cold build", twenty["cold_cpu"], "s"), ("cached", twenty["cached"], "s"),
        ("10 s run", twenty["run_cpu"], "s"), ("run / rigid floor", twenty["run_cpu"] / floor["run_cpu"], "")],
        tables=[report.table(f"FlexibleBody pendulum, {N_NODES} nodes, 10 s; process CPU unless marked wall",
                             ["modes", "read file [s]", "cold CPU [s]", "cold wall [s]", "cached [s]", "run CPU [s]",
                              "run wall [s]", "unknowns"],
                             [(n, r["read"], r["cold_cpu"], r["cold_wall"], r["cached"], r["run_cpu"], r["run_wall"],
                               r["unknowns"]) for n, r in rows])],
        notes=[f"floor: rigid Body pendulum build {floor['cold_cpu']:.3g} s CPU, run {floor['run_cpu']:.3g} s CPU"])


if __name__ == "__main__":
    main()
