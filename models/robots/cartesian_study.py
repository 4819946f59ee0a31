"""The parallel Cartesian manipulator's study after seed 002 (§3): drives moved by trapezoidal speed profiles (one
drive, then all three) and by forces constant over time intervals, rigid and flexible arms.

Outputs per case, flexible against rigid: the tip's rotation (zero for the rigid Tripteron, the flexible arms'
twist and bending let it turn a little), the drive forces, and the arms' elastic deflection (the largest
displacement of an arm's far pin relative to its root frame, from the modal coordinates).

Run ``python -m flexlib.models.robots.cartesian_study [--out DIR]``: a table and the PNGs ``tip_rotation.png``,
``drive_forces.png`` and ``arm_deflection.png``.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

import flexlib as fl
from flexlib.fe import node_displacements

from .cartesian import CartesianRobot

__all__ = ["CASES", "arm_deflection", "drive_force", "plot_study", "run_cases", "tip_rotation"]

#: The study's cases: (name, drive, keyword arguments of CartesianRobot, simulated time [s]).
CASES: tuple[tuple[str, str, dict[str, Any], float], ...] = (
    ("one drive", "motion", {"speeds": ((0.2, 0.1, 0.3, 0.1), (0.0, 0.1, 0.3, 0.1), (0.0, 0.1, 0.3, 0.1))}, 0.8),
    ("all three", "motion", {"speeds": ((0.2, 0.1, 0.3, 0.1), (-0.15, 0.1, 0.3, 0.1), (0.1, 0.1, 0.3, 0.1))}, 0.8),
    ("forces", "trim", {"forces": (((0.0, 0.1, 0.2, 0.3), (0.0, 20.0, -20.0, 0.0)),
                                   ((0.0, 0.15, 0.25), (0.0, 15.0, 0.0)),
                                   ((0.0, 0.2, 0.3), (0.0, -15.0, 0.0)))}, 0.6),
)


def tip_rotation(result: fl.Result) -> np.ndarray:
    """Rotation angle of the tip from its start orientation [rad], (nt,)."""
    n = len(result.t)
    T = result["tip.frame_a.T"].reshape(n, 3, 3, order="F")
    return Rotation.from_matrix(np.einsum("tij,kj->tik", T, T[0])).magnitude()  # of T(t) T(0)^T


def arm_deflection(model: CartesianRobot, result: fl.Result) -> np.ndarray:
    """Largest elastic displacement of an arm's far pin relative to its reference frame over the six arms [m],
    (nt,); zero for rigid arms. The frame is pinned at the root pin and turns with the arm's mean rotation (the
    basis of a body on hinges), so this is the pin's bending displacement, not the root slope's lever."""
    out = np.zeros(len(result.t))
    if not model.flexible:
        return out
    for k in (1, 2, 3):
        for arm in (f"arm4{k}", f"arm6{k}"):
            body = getattr(model, arm)
            data = body.modal_data
            far = [int(data.node_ids[np.argmax(data.coordinates[:, 0])])]
            u = node_displacements(data, result[f"{arm}.q"], far)[:, 0, :]
            out = np.maximum(out, np.linalg.norm(u, axis=1))
    return out


def run_cases() -> dict[str, dict[bool, tuple[CartesianRobot, fl.Result]]]:
    """Every case, rigid and flexible: ``{case: {flexible: (model, result)}}``."""
    out: dict[str, dict[bool, tuple[CartesianRobot, fl.Result]]] = {}
    for name, drive, kwargs, t_end in CASES:
        out[name] = {}
        for flexible in (False, True):
            model = CartesianRobot(flexible=flexible, drive=drive, **kwargs)
            res = fl.Simulation(model).run(t_end, dt_out=0.002, steady_state=flexible, progress=False)
            out[name][flexible] = (model, res)
    return out


def drive_force(model: CartesianRobot, res: fl.Result, k: int) -> np.ndarray:
    """Force drive ``k`` exerts on its slider along the guide's axis [N] (positive up: the holding forces are
    positive): the guide's axis flange force (``Prismatic``: ``axis.f`` drives ``frame_b`` along ``n``)."""
    return np.asarray(res[f"guide{k}.axis.f"], dtype=float)


def plot_study(runs: dict[str, dict[bool, tuple[CartesianRobot, fl.Result]]], out: str | Path) -> list[Path]:
    """Write ``tip_rotation.png``, ``drive_forces.png`` and ``arm_deflection.png`` into ``out``; their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    n = len(runs)
    figs = {key: plt.subplots(n, 1, figsize=(7, 2.6 * n), sharex=False) for key in ("rot", "force", "defl")}
    for row, (case, variants) in enumerate(runs.items()):
        for flexible, (model, res) in variants.items():
            label = "flexible" if flexible else "rigid"
            figs["rot"][1][row].plot(res.t, 1e3 * tip_rotation(res), label=label)
            for k in (1, 2, 3):
                figs["force"][1][row].plot(res.t, drive_force(model, res, k), "-" if flexible else "--",
                                           label=f"drive {k}, {label}")
            if flexible:
                figs["defl"][1][row].plot(res.t, 1e3 * arm_deflection(model, res))
        figs["rot"][1][row].set(title=case, ylabel="tip rotation [mrad]")
        figs["force"][1][row].set(title=case, ylabel="drive force [N]")
        figs["defl"][1][row].set(title=case, ylabel="largest arm deflection [mm]")
    for key, name in (("rot", "tip_rotation.png"), ("force", "drive_forces.png"), ("defl", "arm_deflection.png")):
        fig, axes = figs[key]
        axes[-1].set(xlabel="t [s]")
        if key != "defl":
            axes[0].legend(fontsize=7)
        paths.append(out / name)
        fig.tight_layout()
        fig.savefig(paths[-1], dpi=120)
        plt.close(fig)
    return paths


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="cartesian_study", help="folder for the PNGs")
    args = parser.parse_args()
    runs = run_cases()
    print(f"{'case':<10} {'tip rotation rigid [rad]':>25} {'flexible [mrad]':>16} {'arm deflection [mm]':>20} "
          f"{'peak drive force rigid / flexible [N]':>38}")
    for case, variants in runs.items():
        (mr, rr), (mf, rf) = variants[False], variants[True]
        peak = [max(np.abs(drive_force(m, r, k)).max() for k in (1, 2, 3)) for m, r in ((mr, rr), (mf, rf))]
        print(f"{case:<10} {tip_rotation(rr).max():25.2e} {1e3 * tip_rotation(rf).max():16.3f} "
              f"{1e3 * arm_deflection(mf, rf).max():20.3f} {peak[0]:18.1f} / {peak[1]:.1f}")
    for p in plot_study(runs, args.out):
        print("wrote", p)


if __name__ == "__main__":
    main()
