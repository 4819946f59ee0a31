"""The pump truck's emergency stop over start poses and counterbalance pilot ratios (issue 33, study a).

Eight start poses (the boom raised 35, 50, 65 or 80°, section 3 opened −30° or −60°, the rest as the working pose)
× six pilot ratios of the counterbalance valves of the two moving axes (1 and 2, holding and overrunning sides alike,
2 … 5; the design's is 3): the rigid boom's ``emergency-stop`` (joints 1 and 2 lowering on open-loop commands, every
valve closed abruptly at 4 s) run once per pose and ratio on Dask, one ``run_study`` per pose on one cluster (a pose
is a scenario record of its own: a start pose is not a parameter). Kept of each run: the peak pressure in the
chambers of axes 1 and 2 (the largest absolute pressure, either side) and the peak in-plane hinge forces of joints
1 and 2. The envelope is each quantity's largest value over the poses, per pilot ratio; the figure shows both as
heat maps.

Run: ``python -m flexlib.models.pump_truck.studies.envelope [--workers 2] [--out DIR]`` (48 runs, about a minute on
2 cores).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.study import Maximum, local_cluster, run_study, start_pose

from .tolerances import HingeForce

SCENARIO = "emergency-stop"
BOOM = (35.0, 50.0, 65.0, 80.0)  # joint 1 [deg]
SECTION3 = (-30.0, -60.0)  # joint 3 [deg]
RATIOS = (2.0, 2.5, 3.0, 3.5, 4.0, 5.0)
VALVES = ("axis1.cbv_hold", "axis1.cbv_over", "axis2.cbv_hold", "axis2.cbv_over")
REDUCTIONS = {**{f"max_p{k}{side}": Maximum(f"axis{k}.cylinder.cylinder.p_{side}") for k in (1, 2) for side in "AB"},
              "peak_f1": HingeForce(1), "peak_f2": HingeForce(2)}


def poses() -> list[tuple[float, ...]]:
    """The start poses ``(slew, joint 1 … 5)`` [deg]: the working pose with joints 1 and 3 changed."""
    from flexlib.models.pump_truck.model import WORKING_POSE_DEG

    w = WORKING_POSE_DEG
    return [(w[0], j1, w[2], j3, w[4], w[5]) for j1 in BOOM for j3 in SECTION3]


def variants(ratios: tuple[float, ...] = RATIOS) -> list[dict[str, float]]:
    """One variant per pilot ratio, the four valves of axes 1 and 2 alike."""
    return [{v + ".pilot_ratio": float(r) for v in VALVES} for r in ratios]


def run(workers: int = 2, out: Path | None = None, pose_list: list[tuple[float, ...]] | None = None,
        ratios: tuple[float, ...] = RATIOS, progress: bool | None = None) -> list[tuple[tuple[float, ...], Any]]:
    """Every pose × ratio on one local cluster: ``[(pose, StudyResult), ...]``."""
    out_list = []
    with local_cluster(workers) as cluster:
        for i, pose in enumerate(pose_list or poses()):
            scen = start_pose("pump-truck", SCENARIO, pose, name=f"{SCENARIO}@pose{i}")
            table = out / f"envelope_pose{i}.parquet" if out is not None else None
            out_list.append((pose, run_study("pump-truck", variants(ratios), REDUCTIONS, scenario=scen,
                                             scheduler=cluster.scheduler_address, out=table, progress=progress)))
    return out_list


def matrices(results: list[tuple[tuple[float, ...], Any]]) -> dict[str, np.ndarray]:
    """Per reduction a (poses × ratios) array (NaN where a run failed); ``"max_p"``: the larger of the four
    chambers."""
    out = {k: np.array([[r[k] if r["status"] == "success" else np.nan for r in res.rows] for _, res in results])
           for k in REDUCTIONS}
    out["max_p"] = np.fmax.reduce([out[f"max_p{k}{s}"] for k in (1, 2) for s in "AB"])
    return out


def figure(results: list[tuple[tuple[float, ...], Any]], ratios: tuple[float, ...], path: Path) -> None:
    """Heat maps of the peak chamber pressure [bar] and joint 1's peak hinge force [kN] over pose and ratio."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = matrices(results)
    labels = [f"j1 {p[1]:.0f}°, j3 {p[3]:.0f}°" for p, _ in results]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), constrained_layout=True)
    for ax, (key, scale, title) in zip(axes, [("max_p", 1e-5, "peak chamber pressure, axes 1–2 [bar abs.]"),
                                              ("peak_f1", 1e-3, "joint 1 peak hinge force [kN]")], strict=True):
        data = m[key] * scale
        im = ax.imshow(data, aspect="auto", cmap="viridis")
        ax.set_xticks(range(len(ratios)), [f"{r:g}" for r in ratios])
        ax.set_yticks(range(len(labels)), labels)
        ax.set_xlabel("counterbalance pilot ratio, axes 1 and 2")
        ax.set_title(title, fontsize=10)
        for i in range(data.shape[0]):
            for j in range(data.shape[1]):
                ax.text(j, i, f"{data[i, j]:.0f}", ha="center", va="center", color="w", fontsize=7)
        fig.colorbar(im, ax=ax)
    fig.suptitle("Emergency stop: start pose × counterbalance pilot ratio")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path("."), help="directory of the tables and the figure")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    results = run(args.workers, args.out)
    m = matrices(results)
    failed = int(np.isnan(m["peak_f1"]).sum())
    print(f"{len(results)} poses × {len(RATIOS)} pilot ratios, {failed} runs failed")
    print("pilot ratio            " + " ".join(f"{r:>8g}" for r in RATIOS))
    print("envelope p [bar abs.]  " + " ".join(f"{v:8.1f}" for v in np.nanmax(m["max_p"], axis=0) * 1e-5))
    print("envelope f1 [kN]       " + " ".join(f"{v:8.1f}" for v in np.nanmax(m["peak_f1"], axis=0) * 1e-3))
    print("envelope f2 [kN]       " + " ".join(f"{v:8.1f}" for v in np.nanmax(m["peak_f2"], axis=0) * 1e-3))
    figure(results, RATIOS, args.out / "envelope.png")
    print(f"tables {args.out}/envelope_pose*.parquet, figure {args.out / 'envelope.png'}")


if __name__ == "__main__":
    main()
