"""The POLYCRANK fragment's dynamic study after seed 002 (§4.2, its Figs. 11–13): a torque pulse, then free
vibration, for the rigid fragment and the four flexible variants (friction in the bearings or not, pull rods
preloaded or not), and the lowest frequencies with the drives locked in several poses.

Set-up (assumed; the seed gives no numbers for its driving torque): the fragment hangs (shield 4 along ``−y``,
the channels at 10°–20° from the parallelograms' change points, which come every 30° of relative rotation), the
four drives hold it at rest with the torques the initialisation finds (``drive="trim"``), and shield 4's drive adds
``PULSE`` for ``PULSE_WIDTH``. The fragment then swings as a pendulum about ``A0``; friction and preload take the
energy out (the preload's self-stress loads the bearings, and the journal friction grows with the radial load).

One flexible build serves the four flexible variants: friction is built in and switched off with zero
coefficients (:func:`no_friction`), the preload is set by the rods' mount offsets (:func:`preload_params`).

Run ``python -m flexlib.models.robots.polycrank_study [--out DIR] [--t-end T]``: a table of the figures and the PNGs
``energy.png`` (energy above the start), ``reactions.png`` (force in the grip disc's bearing, the cap–disc joint
of the seed's Fig. 13, in shield 5's bearing, and the friction torque in shield 4's), ``stress.png`` (largest von
Mises stress over the pull rods) and ``shield.png`` (shield 4's angle, speed and acceleration). With ``--shield``
it prints only the lowest locked frequencies in the three poses with rigid and flexible shield 5
(:func:`shield_frequencies`).

The rigid fragment's bearing forces are statically indeterminate (``Result.indeterminate``: the over-constrained
parallelograms share the load with the bearings as the dropped loop rows let them); the table marks them with
``*`` and the figure's panel titles name the variants whose force is indeterminate; their reads here do not warn.
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import flexlib as fl

from .polycrank import PolycrankFragment, PolycrankParameters, mechanical_energy, preload_params, rod_stress

__all__ = [
    "BEARINGS",
    "LOCKED",
    "LOCKED_POSES",
    "PRELOAD",
    "PULSE",
    "SWING_POSE",
    "bearing_force",
    "locked_frequencies",
    "no_friction",
    "plot_study",
    "pulse_model",
    "run_variants",
    "shield_frequencies",
    "summary",
]

#: Hanging start pose [rad]: shield 4 along −y; outer, c3 and c4 discs 20°, 10° and 40° from it.
SWING_POSE = (-math.pi / 2, -math.pi / 2 + math.radians(20), -math.pi / 2 + math.radians(10),
              -math.pi / 2 + math.radians(40))
#: Torque pulse on shield 4's drive [N.m], its start and its width [s]: 12 N.m breaks the preloaded bearings loose
#: (with 5 N.m the friction of the preload's bearing loads holds the fragment: it never moves, peak 0.009 rad/s),
#: and keeps the free swing (0.12 rad) short of the channels' change points (10° away at the start)
PULSE, PULSE_START, PULSE_WIDTH = 12.0, 0.05, 0.05
#: Pull-rod preload of the preloaded variants [N] (assumed: 35 % of the rod's Euler load 1.46 kN, 18 MPa).
PRELOAD = 500.0
#: The nine bearings (friction switched by their coefficients).
BEARINGS = ("j4", "j5", "d0o", "d0c3", "d0c4", "d1c3", "d1c4", "d2c3", "d2c4")
#: Joints locked for the modal analysis (ADAMS: "all rigid degrees of freedom blocked").
LOCKED = ["j4", "d0o", "d0c3", "d0c4"]
#: Poses of the locked modal analysis [rad]: the hanging pose, then every angle 45° and 90° further.
LOCKED_POSES = [tuple(a + math.radians(turn) for a in SWING_POSE) for turn in (0, 45, 90)]


def bearing_force(res: fl.Result, joint: str) -> tuple[np.ndarray, bool]:
    """Magnitude of the force across bearing ``joint`` over a result [N] and whether it is statically indeterminate
    (some component in ``res.indeterminate``: the value is one admissible load split of the rigid fragment)."""
    name = f"{joint}.frame_a.f"
    marked = any(e in res.indeterminate for e in res.elements(name))
    with warnings.catch_warnings():  # marked by the caller instead
        warnings.simplefilter("ignore", fl.IndeterminateReactionWarning)
        return np.linalg.norm(res[name], axis=1), marked


def no_friction() -> dict[str, float]:
    """Run-time parameters that switch the bearings' friction off (zero Coulomb and viscous coefficients)."""
    return {f"{j}.{k}": 0.0 for j in BEARINGS for k in ("mu", "tau_c0", "d")}


def pulse_model(flexible: bool, params: PolycrankParameters | None = None,
                angles: tuple[float, float, float, float] = SWING_POSE, pulse: float = PULSE,
                flexible_shield: bool = False) -> PolycrankFragment:
    """The fragment with bearing friction, trimmed drives and the torque pulse ``pulse`` [N.m] on shield 4
    (flexible: rods built with ``PRELOAD``, so that the preload is a run-time parameter; ``flexible_shield``: shield
    5 flexible)."""
    t0, t1 = PULSE_START, PULSE_START + PULSE_WIDTH
    torques = (((0.0, t0, t1), (0.0, float(pulse), 0.0)), ((0.0,), (0.0,)), ((0.0,), (0.0,)), ((0.0,), (0.0,)))
    return PolycrankFragment(angles=angles, drive="trim", torques=torques, friction=True, flexible=flexible,
                             flexible_shield=flexible_shield, preload=PRELOAD if flexible else 0.0, params=params)


def run_variants(t_end: float = 1.0, params: PolycrankParameters | None = None,
                 dt_out: float = 0.002) -> dict[str, tuple[PolycrankFragment, fl.Result]]:
    """Run the rigid fragment and the four flexible variants; ``{name: (model, result)}`` with names ``rigid``,
    ``flexible``, ``friction``, ``preload``, ``friction+preload``."""
    out: dict[str, tuple[PolycrankFragment, fl.Result]] = {}
    rigid = pulse_model(False, params)
    out["rigid"] = (rigid, fl.Simulation(rigid).run(t_end, dt_out=dt_out, params=no_friction(), progress=False))
    flex = pulse_model(True, params)
    sim = fl.Simulation(flex)
    for name, fric, pre in (("flexible", False, 0.0), ("friction", True, 0.0), ("preload", False, PRELOAD),
                            ("friction+preload", True, PRELOAD)):
        p = {**preload_params(flex, pre), **({} if fric else no_friction())}
        out[name] = (flex, sim.run(t_end, dt_out=dt_out, steady_state=True, params=p, progress=False))
    return out


def summary(runs: dict[str, tuple[PolycrankFragment, fl.Result]], at: float = 0.3) -> list[dict[str, Any]]:
    """Per variant: the pulse's energy left at ``at`` [s] (fraction of the frictionless rigid run's), the largest
    force in the grip disc's bearing ``d2c3`` and in shield 5's ``j5`` [N], the largest rod von Mises stress [Pa]
    (flexible), the trims (holding torques) [N.m], the largest friction torque in shield 4's bearing [N.m] and
    ``indeterminate``, the bearings whose force the model leaves statically indeterminate (:func:`bearing_force`)."""
    rows = []
    ref = None
    for name, (model, res) in runs.items():
        E = mechanical_energy(model, res)
        k = int(np.searchsorted(res.t, at))
        gained = float(E[k] - E[0])
        if ref is None:
            ref = gained
        forces = {joint: bearing_force(res, joint) for joint in ("d2c3", "j5")}
        row = {"variant": name, "energy_left": gained / ref, "d2c3_force": float(forces["d2c3"][0].max()),
               "j5_force": float(forces["j5"][0].max()),
               "indeterminate": [joint for joint, (_, marked) in forces.items() if marked],
               "trims": [float(res[f"trim_{j}.b"][0]) for j in ("j4", "d0o", "d0c3", "d0c4")],
               "friction_j4": float(np.abs(res["j4.tau_f"]).max()) if "j4.tau_f" in res else 0.0}
        if model.flexible:
            row["von_mises"] = float(max(s.max() for s in rod_stress(model, res).values()))
        rows.append(row)
    return rows


def locked_frequencies(poses: list[tuple[float, float, float, float]], preload: float = PRELOAD,
                       n: int = 4, params: PolycrankParameters | None = None, flexible_shield: bool = False,
                       flexible: bool = True, codegen: bool | None = None) -> np.ndarray:
    """Lowest ``n`` vibration frequencies [Hz] of the fragment with the drives locked, at rest in each pose (one
    build: the poses are start values and guesses), without friction; (len(poses), n). ``flexible``: flexible pull
    rods (with rigid ones ``preload`` must be 0 and the fragment needs ``flexible_shield``: rigid, it has no
    degree of freedom left); ``flexible_shield``: shield 5 flexible; ``codegen``: the build's C code
    (:class:`~flexlib.Simulation`; default its own)."""
    out = []
    for pose in poses:
        model = pulse_model(flexible, params, angles=pose, flexible_shield=flexible_shield)
        sim = fl.Simulation(model) if codegen is None else fl.Simulation(model, codegen=codegen)
        p = {**no_friction(), **(preload_params(model, preload) if flexible else {})}
        modes = fl.modal_analysis(sim, lock=LOCKED, steady_state=True, params=p)
        f = modes.frequencies[modes.oscillatory]
        out.append(np.sort(f)[:n])
    return np.array(out)


def shield_frequencies(preloads: tuple[float, ...] = (0.0, PRELOAD), n: int = 3,
                       params: PolycrankParameters | None = None,
                       codegen: bool | None = None) -> dict[str, np.ndarray]:
    """The lowest ``n`` locked frequencies [Hz] (:func:`locked_frequencies`) in the study's three poses
    (:data:`LOCKED_POSES`), rigid against flexible shield 5: ``{"rigid shield, <T> N": …, "flexible shield, <T>
    N": …}`` for each rod preload ``T`` [N] (flexible pull rods), and ``"rigid rods, flexible shield"`` (the
    shield's own mode on rigid links); each (3, n)."""
    out = {}
    for pre in preloads:
        for shield in (False, True):
            name = f"{'flexible' if shield else 'rigid'} shield, {pre:.0f} N"
            out[name] = locked_frequencies(LOCKED_POSES, pre, n, params, flexible_shield=shield, codegen=codegen)
    out["rigid rods, flexible shield"] = locked_frequencies(LOCKED_POSES, 0.0, n, params, flexible_shield=True,
                                                            flexible=False, codegen=codegen)
    return out


def plot_study(runs: dict[str, tuple[PolycrankFragment, fl.Result]], out: str | Path) -> list[Path]:
    """Write ``energy.png``, ``reactions.png``, ``stress.png`` and ``shield.png`` into ``out``; their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    # the variants overlap where friction and preload change nothing (rigid, flexible, preload before the pulse):
    # a style per variant keeps each one visible
    styles = {"rigid": dict(color="k", lw=2.6, ls="-"), "flexible": dict(color="C0", lw=1.8, ls="--"),
              "friction": dict(color="C1", lw=1.4, ls="-"), "preload": dict(color="C2", lw=1.8, ls=":"),
              "friction+preload": dict(color="C3", lw=1.2, ls="-.")}

    def style(name: str) -> dict[str, Any]:
        return styles.get(name, {})

    def save(fig: Any, name: str, legend_ax: Any) -> None:
        # one legend outside the axes, above the figure: it hides no curve
        handles, labels = legend_ax.get_legend_handles_labels()
        fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 5), bbox_to_anchor=(0.5, 1.0),
                   frameon=False)
        paths.append(out / name)
        fig.savefig(paths[-1], dpi=120, bbox_inches="tight")
        plt.close(fig)

    fig, ax = plt.subplots(figsize=(7.5, 4))
    for name, (model, res) in runs.items():
        E = mechanical_energy(model, res)
        ax.plot(res.t, 1e3 * (E - E[0]), label=name, **style(name))
    ax.set(xlabel="t [s]", ylabel="E − E(0) [mJ]", title="Torque pulse, then free swing")
    save(fig, "energy.png", ax)
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    marked: dict[str, list[str]] = {"d2c3": [], "j5": []}  # variants whose bearing force is indeterminate
    for name, (_model, res) in runs.items():
        for ax, joint in zip(axes[:2], ("d2c3", "j5"), strict=True):
            force, indeterminate = bearing_force(res, joint)
            ax.plot(res.t, force, label=name, **style(name))
            if indeterminate:
                marked[joint].append(name)
        if "j4.tau_f" in res:
            axes[2].plot(res.t, res["j4.tau_f"], label=name, **style(name))
    for ax, joint, title in zip(axes[:2], ("d2c3", "j5"), ("grip disc bearing d2c3", "shield 5 bearing j5"),
                                strict=True):
        note = f"\n{', '.join(marked[joint])}: statically indeterminate (one admissible split)" if marked[joint] else ""
        ax.set(ylabel=f"|F| {joint} [N]", yscale="log", title=title + note)
    axes[2].set(xlabel="t [s]", ylabel="τ_f [N.m]", title="friction torque in shield 4's bearing j4")
    fig.tight_layout()
    save(fig, "reactions.png", axes[0])
    fig, ax = plt.subplots(figsize=(7, 4))
    for name, (model, res) in runs.items():
        if model.flexible:
            ax.plot(res.t, 1e-6 * np.max(list(rod_stress(model, res).values()), axis=0), label=name, **style(name))
    ax.set(xlabel="t [s]", ylabel="largest von Mises stress in the pull rods [MPa]")
    save(fig, "stress.png", ax)
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    for name, (_model, res) in runs.items():
        for ax, var in zip(axes, ("phi", "w", "a"), strict=True):
            ax.plot(res.t, res[f"j4.{var}"], label=name, **style(name))
    for ax, label in zip(axes, ("shield 4 angle [rad]", "speed [rad/s]", "acceleration [rad/s2]"), strict=True):
        ax.set(ylabel=label)
    axes[-1].set(xlabel="t [s]")
    save(fig, "shield.png", axes[0])
    return paths


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="polycrank_study", help="folder for the PNGs")
    parser.add_argument("--t-end", type=float, default=1.0, help="simulated time [s]")
    parser.add_argument("--shield", action="store_true",
                        help="only the lowest locked frequencies with rigid and flexible shield 5 (no pulse runs)")
    args = parser.parse_args()
    if args.shield:
        print("lowest frequencies, drives locked, in the three poses (hanging, +45°, +90°) [Hz]:")
        for name, f in shield_frequencies(codegen=False).items():
            print(f"  {name:<28} " + "; ".join(", ".join(f"{x:.1f}" for x in row) for row in f))
        return
    runs = run_variants(args.t_end)
    print(f"{'variant':<18} {'energy left at 0.3 s':>21} {'|F| d2c3 [N]':>13} {'|F| j5 [N]':>11} "
          f"{'von Mises [MPa]':>16} {'friction j4 [N.m]':>18}")
    rows = summary(runs)
    for row in rows:
        vm = f"{row['von_mises'] / 1e6:16.1f}" if "von_mises" in row else f"{'–':>16}"
        d2c3, j5 = (f"{row[f'{j}_force']:.0f}" + ("*" if j in row["indeterminate"] else "") for j in ("d2c3", "j5"))
        print(f"{row['variant']:<18} {row['energy_left']:21.3f} {d2c3:>13} {j5:>11} {vm} {row['friction_j4']:18.3f}")
    if any(row["indeterminate"] for row in rows):
        print("* statically indeterminate: one admissible load split of the over-constrained rigid fragment "
              "(Result.indeterminate); the flexible pull rods determine it")
    for pre in (0.0, PRELOAD):
        f = locked_frequencies(LOCKED_POSES, preload=pre)
        print(f"lowest frequencies, drives locked, preload {pre:.0f} N [Hz]: "
              + "; ".join(", ".join(f"{x:.1f}" for x in row) for row in f))
    for p in plot_study(runs, args.out):
        print("wrote", p)


if __name__ == "__main__":
    main()
