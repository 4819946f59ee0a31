"""Figures of a pump-truck run, in the spirit of seed 000's boom study (PNG, matplotlib).

- ``flows.png``: volume flow into each cylinder's cap-side port A [L/min] (the seed's Fig. 14);
- ``pressures.png``: both chamber pressures of each cylinder [bar];
- ``hinge_forces.png``: magnitude of the force each boom joint transmits [kN] (Fig. 15), and its components in
  the joint frame;
- ``section_lengths.png``: each section's pin-to-pin length minus its nominal length [mm] (Figs. 16–17: constant
  for a rigid boom, fluctuating for a flexible one);
- ``modal_coordinates.png``: each flexible section's modal coordinates (Fig. 11), flexible runs only;
- ``tip_path.png``: the tip's path in the boom plane and the joint angles over time;
- ``boom.pvd`` (+ ``boom_*.vtu``): the moving boom for ParaView, one frame per ``VTK_DT`` of simulated time: each
  flexible section's deformed beam mesh, and stick figures of the rigid parts (rigid sections pin to pin,
  cylinders, levers and links).

Rigid and flexible runs overlaid (Fig. 13): ``flexlib compare rigid.h5 flexible.h5 --plot both.png``.

References
----------
Seed 000 (MWorks boom library: Figs. 11, 13–17).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["figures"]

#: Time between the frames of the VTK series [s].
VTK_DT = 1.0
#: A section whose pin-to-pin length stays within this of its nominal length is drawn as constant (a rigid
#: section's round-off, 1e-15 m, is not drawn as a signal) [m].
RIGID_TOL = 1e-9
#: Smallest span of the tip-path axes [m] (a boom holding its pose: a point, not a cloud of round-off).
TIP_SPAN = 2.0


def _save(fig: Any, path: Path) -> Path:
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _has(result: Any, name: str) -> bool:
    return any(n == name or n.startswith(name + "[") for n in result.names)


def _joints(result: Any) -> list[int]:
    """The boom joints of the run (``joint1``, ``joint2``, … as far as the result has them: 5 on the 42 m boom, 4
    on boom-32)."""
    n = 0
    while f"joint{n + 1}.phi" in result:
        n += 1
    return list(range(1, n + 1))


def figures(model: Any, result: Any, directory: Path) -> list[Path]:
    """Write the figures listed in the module docstring into ``directory``; returns their paths.

    Parameters
    ----------
    model : PumpTruck or Boom32
        The model of the run (its record gives the nominal section lengths).
    result : Result
        The run.
    directory : Path
        Existing directory.
    """
    directory = Path(directory)
    t = np.asarray(result.t, dtype=float)
    out = [_flows(result, t, directory), _pressures(result, t, directory), _hinge_forces(result, t, directory),
           _section_lengths(model, result, t, directory)]
    flexible = [n for n in _joints(result) if _has(result, f"section{n}.body.q")]
    if flexible:
        out.append(_modal_coordinates(model, result, t, flexible, directory))
    out.append(_tip_path(result, t, directory))
    out.append(write_boom_vtk(model, result, directory / "boom.pvd"))
    return out


def _flows(result: Any, t: np.ndarray, directory: Path) -> Path:
    """``flows.png``: the flow into each cylinder's port A."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.5))
    for n in _joints(result):
        q, unit = result.display(f"axis{n}.cylinder.cylinder.q_A")
        ax.plot(t, q, label=f"cylinder {n}")
    ax.set(xlabel="time [s]", ylabel=f"flow into port A [{unit}]", title="Cylinder port A flows")
    ax.grid(True, alpha=0.3)
    ax.legend(ncol=5, fontsize=8)
    return _save(fig, directory / "flows.png")


def _pressures(result: Any, t: np.ndarray, directory: Path) -> Path:
    """``pressures.png``: both chamber pressures of each cylinder."""
    import matplotlib.pyplot as plt

    joints = _joints(result)
    fig, axes = plt.subplots(len(joints), 1, figsize=(9, 1.8 * len(joints)), sharex=True, squeeze=False)
    for n, ax in zip(joints, axes[:, 0], strict=True):
        for side in ("A", "B"):
            p, unit = result.display(f"axis{n}.cylinder.cylinder.p_{side}")
            ax.plot(t, p, label=f"p_{side}")
        ax.set_ylabel(f"cyl. {n} [{unit} abs.]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle("Chamber pressures (absolute)")
    return _save(fig, directory / "pressures.png")


def _hinge_forces(result: Any, t: np.ndarray, directory: Path) -> Path:
    """``hinge_forces.png``: each joint's force in the boom's plane, magnitude and components in the joint frame
    (the out-of-plane component is statically indeterminate in the rigid boom: its linkages are over-constrained out
    of their plane)."""
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    for k, n in enumerate(_joints(result)):
        colour = f"C{k}"  # one colour per joint in both panels
        f = np.column_stack([result[f"joint{n}.frame_b.f[{i}]"] for i in (0, 1)])
        ax.plot(t, np.linalg.norm(f, axis=1) / 1e3, color=colour, label=f"joint {n}")
        ax2.plot(t, f[:, 0] / 1e3, color=colour, label=f"joint {n} x")
        ax2.plot(t, f[:, 1] / 1e3, "--", color=colour, label=f"joint {n} y")
    ax.set(ylabel="|force| [kN]", title="Hinge forces")
    ax2.set(xlabel="time [s]", ylabel="component in the joint frame [kN]")
    for a in (ax, ax2):
        a.grid(True, alpha=0.3)
        a.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the axes: hides no curve
    return _save(fig, directory / "hinge_forces.png")


def _section_lengths(model: Any, result: Any, t: np.ndarray, directory: Path) -> Path:
    """``section_lengths.png``: each section's pin-to-pin length minus its nominal length."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.5))
    record, joints = model.record, _joints(result)
    varying = False
    for n in joints:
        root = np.asarray(result[f"joint{n}.frame_b.r_0"], dtype=float).reshape(len(t), 3)
        tip_name = f"joint{n + 1}.frame_a.r_0" if n < joints[-1] else f"section{n}.frame_tip.r_0"
        if not _has(result, tip_name):
            continue
        tip = np.asarray(result[tip_name], dtype=float).reshape(len(t), 3)
        change = np.linalg.norm(tip - root, axis=1) - record.sections[n - 1].length
        if np.max(np.abs(change), initial=0.0) < RIGID_TOL:  # round-off: drawn as what it is, a constant length
            ax.plot(t, np.zeros_like(t), lw=0.8, label=f"section {n} (rigid: constant)")
        else:
            ax.plot(t, change * 1e3, label=f"section {n}")
            varying = True
    ax.set(xlabel="time [s]", ylabel="pin-to-pin length − nominal [mm]", title="Section lengths")
    if not varying:  # nothing but constant sections: a readable ±1 mm axis
        ax.set_ylim(-1.0, 1.0)
    ax.grid(True, alpha=0.3)
    ax.legend(ncol=5, fontsize=8)
    return _save(fig, directory / "section_lengths.png")


def _modes(model: Any, n: int, count: int) -> list[int]:
    """Section ``n``'s mode numbers (indices into its modal data, as ``model.modes`` chose them), or 0 … count−1."""
    chosen = getattr(model, "modes", None)
    if isinstance(chosen, dict) and len(chosen.get(n, ())) == count:
        return [int(k) for k in chosen[n]]
    return list(range(count))


def _modal_coordinates(model: Any, result: Any, t: np.ndarray, flexible: list[int], directory: Path) -> Path:
    """``modal_coordinates.png``: the modal coordinates of the flexible sections ``flexible``."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(flexible), 1, figsize=(9, 2 + 1.6 * len(flexible)), sharex=True, squeeze=False)
    for n, ax in zip(flexible, axes[:, 0], strict=True):
        q = np.asarray(result[f"section{n}.body.q"], dtype=float).reshape(len(t), -1)
        modes = _modes(model, n, q.shape[1])
        for j in range(q.shape[1]):
            ax.plot(t, q[:, j], lw=0.8, label=f"mode {modes[j]}")
        ax.set_ylabel(f"section {n} [1]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, ncol=2, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle("Modal coordinates [1] (the mode shapes in m per unit)")
    return _save(fig, directory / "modal_coordinates.png")


def _tip_path(result: Any, t: np.ndarray, directory: Path) -> Path:
    """``tip_path.png``: the tip's path in the boom plane and the joint angles."""
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    tip = np.asarray(result[f"section{_joints(result)[-1]}.frame_tip.r_0"], dtype=float).reshape(len(t), 3)
    ax.plot(tip[:, 0], tip[:, 1])
    ax.plot(tip[0, 0], tip[0, 1], "o", label="start")
    ax.plot(tip[-1, 0], tip[-1, 1], "s", label="end")
    ax.set(xlabel="x [m]", ylabel="y [m]", title="Tip path", aspect="equal")
    for lim, col in ((ax.set_xlim, tip[:, 0]), (ax.set_ylim, tip[:, 1])):  # a boom at rest: a point, plain ticks
        mid, half = 0.5 * (col.max() + col.min()), 0.5 * max(col.max() - col.min(), 0.0)
        if half < TIP_SPAN / 2:
            lim(mid - TIP_SPAN / 2, mid + TIP_SPAN / 2)
    ax.ticklabel_format(useOffset=False, style="plain")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    for n in _joints(result):
        ax2.plot(t, np.degrees(result[f"joint{n}.phi"]), label=f"q{n}")
    ax2.set(xlabel="time [s]", ylabel="joint angle [deg]", title="Joint angles")
    ax2.ticklabel_format(axis="y", useOffset=False, style="plain")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    return _save(fig, directory / "tip_path.png")


def write_boom_vtk(model: Any, result: Any, path: Path, dt: float = VTK_DT) -> Path:
    """The boom over time as a VTK series for ParaView (module docstring), one frame per ``dt`` [s]."""
    from flexlib.fe.vtk_series import write_model_vtk

    lines: dict[str, list[str]] = {}
    for n in _joints(result):
        if not _has(result, f"section{n}.body.q"):  # a rigid section: its pins
            lines[f"section{n}"] = [f"joint{n}.frame_b", f"section{n}.frame_tip"]
        lines[f"cylinder{n}"] = [f"axis{n}.frame_a", f"axis{n}.frame_b"]
        if n > 1:
            lines[f"linkage{n}"] = [f"linkage{n}.frame_pivot", f"linkage{n}.frame_tip", f"linkage{n}.frame_bracket"]
    t = np.asarray(result.t, dtype=float)
    stride = max(1, round(dt / max(float(np.median(np.diff(t))), 1e-12))) if t.size > 1 else 1
    return write_model_vtk(path, model, result, lines=lines, stride=stride)
