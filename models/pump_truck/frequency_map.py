"""The boom's lowest natural frequencies over its working poses: a modal sweep along the unfolding.

The expand scenario moves the boom from the transport fold to the working pose one joint after the other; at
``n_poses`` instants of that run the boom is linearised (:func:`flexlib.modal_sweep`) and its lowest vibration
modes are taken — with the oil compliance of every chamber, the counterbalance valves, the controllers and
(flexible boom) the sections' elastic modes, or with the rigid degrees of freedom locked (``lock="rigid"``: the
slew and the five boom joints held; the elastic modes of the structure in that pose, as ADAMS gives them).

Reported are the boom's vibration modes: complex modes above ``F_MIN`` with damping ratios up to ``ZETA_MAX``
(the controllers' slow modes and the valve spools' are left out). The operating points are the run's states
(quasi-static: the boom moves at up to 2.5°/s, so the velocity terms are small against the oil-spring and
elastic stiffness).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

__all__ = ["F_MIN", "ZETA_MAX", "FrequencyMap", "frequency_map", "plot_frequency_map"]

#: Structural modes only: below this frequency [Hz] the complex modes are the slow closed-loop modes of the joint
#: controllers with the counterbalance valves (0.005–0.07 Hz in the working pose), not vibration of the boom
#: (its lowest, the slew drive's oil column, is 0.4–1.5 Hz over the unfolding)
F_MIN = 0.2
#: ... and above this damping ratio [1] the valve spools' second-order modes (20 Hz, 70 %)
ZETA_MAX = 0.5


@dataclass
class FrequencyMap:
    """Frequencies [Hz] and damping ratios [1] of the lowest modes (``(n_poses, n_modes)``) at times ``t`` [s]
    of the expand run, with the joint angles [rad] (``(n_poses, 5)``) of each pose."""

    t: np.ndarray
    joint_angles: np.ndarray
    frequencies: np.ndarray
    damping: np.ndarray
    lock: Any
    flexible: bool


def frequency_map(*, flexible: bool = False, n_poses: int = 50, n_modes: int = 4, lock: Any = None,
                  scenario: str = "expand", result: Any = None, sim: Any = None) -> FrequencyMap:
    """Sweep the boom's lowest ``n_modes`` vibration modes over ``n_poses`` instants of a scenario run.

    Parameters
    ----------
    flexible : bool
        Flexible sections (MPF modes) instead of rigid ones.
    n_poses : int
        Number of poses, evenly spaced in time over the run.
    n_modes : int
        Modes kept per pose.
    lock : None, "rigid" or list of str
        Joints held (:func:`flexlib.modal_analysis`).
    scenario : str
        Registered pump-truck scenario whose run gives the poses.
    result, sim : Result and Simulation, optional
        An existing run of that scenario and its simulation (skips the run).
    """
    import flexlib as fl
    from flexlib.registry import get_model

    if result is None or sim is None:
        entry = get_model("pump-truck")
        sc = entry.scenario(scenario)
        sc = replace(sc, options={**sc.options, "flexible": flexible})
        sim = fl.Simulation(entry.factory(sc))
        result = sim.run(sc.t_end, progress=False, params=dict(sc.params),
                         **{**sc.run, "dt_out": min(0.5, sc.t_end / (4 * n_poses))})
    times = np.linspace(result.t[0], result.t[-1], n_poses)
    sweep = fl.modal_sweep(sim, at=result, times=times, lock=lock, n_modes=n_modes, f_min=F_MIN, max_damping=ZETA_MAX)
    angles = np.array([[result.value(f"joint{j}.phi", tk) for j in range(1, 6)] for tk in times])
    return FrequencyMap(times, angles, sweep.frequencies, sweep.damping, lock, flexible)


def plot_frequency_map(fmap: FrequencyMap, path: str) -> None:
    """PNG: the lowest frequencies over the unfolding (top) and the joint angles that make each pose (bottom)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    for k in range(fmap.frequencies.shape[1]):
        ax.plot(fmap.t, fmap.frequencies[:, k], "o-", ms=3, label=f"mode {k + 1}")
    ax.set_yscale("log")
    ax.set_ylabel("natural frequency [Hz]")
    what = "flexible" if fmap.flexible else "rigid"
    held = "free" if fmap.lock is None else f"locked: {fmap.lock}"
    ax.set_title(f"pump-truck boom ({what} sections, {held}): lowest modes over the unfolding")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    for j in range(5):
        ax2.plot(fmap.t, np.degrees(fmap.joint_angles[:, j]), label=f"joint {j + 1}")
    ax2.set_xlabel("time in the expand run [s]")
    ax2.set_ylabel("joint angle [deg]")
    ax2.legend(fontsize=8, ncol=5)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
