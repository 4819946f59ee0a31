"""Mode selection (by count, frequency cut-off, modal participation factors) and default modal damping.

The modal participation factor (MPF) method of Cuadrado, Dopico, González and Naya (seed 001 of issue 10):
take the loads acting on the body at the most critical instant of a rigid-body run, solve the static problem
in modal coordinates, ``q_i = phi_i^T F / k_i`` (``k_i = omega_i^2`` for mass-normalised modes), and express
each ``|q_i|`` as a percentage of the largest one (the convention of the paper's Table 2, where the dominant
mode has 100 %); modes above the threshold (1 % by default) are kept.

The default modal damping follows the rule of the modal neutral file workflow (seed 000, after Adams/Flex):
1 % of critical below 100 Hz, 10 % from 100 Hz to 1000 Hz, 100 % above 1000 Hz.

References
----------
- J. Cuadrado, D. Dopico, M. González, M. A. Naya, "Influence of modelling and numerical parameters on the
  performance of a flexible MBS formulation", *Multibody System Dynamics* (2004); Table 2 (MPFs).
- MSC Software, *Adams/Flex*: default modal damping (1 %, 10 %, 100 % of critical by frequency band).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from flexlib.errors import RunArgumentError

from .modal_data import ModalData

__all__ = [
    "ParticipationRow",
    "ParticipationTable",
    "default_damping_ratio",
    "modal_damping_matrix",
    "modal_participation",
    "nodal_generalized_forces",
    "participation_from_load_cases",
    "select_modes",
]


@dataclass(frozen=True)
class ParticipationRow:
    """One mode's static participation.

    Attributes
    ----------
    mode : int
        Mode index (0-based).
    frequency : float
        Natural frequency [Hz].
    amplitude : float
        Largest static modal amplitude over the load cases [modal coordinate units].
    share : float
        ``|q_i| / max_j |q_j|`` in percent [%] (largest over the load cases).
    kept : bool
        ``share`` at or above the threshold.
    """

    mode: int
    frequency: float
    amplitude: float
    share: float
    kept: bool


@dataclass(frozen=True)
class ParticipationTable:
    """Modal participation factors of all modes, with the threshold used.

    Attributes
    ----------
    rows : tuple of ParticipationRow
        One row per mode, in mode order.
    threshold : float
        Threshold as a fraction [1] (0.01 = 1 %).
    """

    rows: tuple[ParticipationRow, ...]
    threshold: float

    @property
    def kept(self) -> list[int]:
        """Indices of the modes at or above the threshold."""
        return [r.mode for r in self.rows if r.kept]

    @property
    def shares(self) -> np.ndarray:
        """Shares of all modes [%]."""
        return np.array([r.share for r in self.rows])

    def __str__(self) -> str:
        head = f"{'mode':>4}  {'f [Hz]':>12}  {'|q| static':>12}  {'MPF [%]':>9}"
        lines = [f"{head}  kept (>= {100 * self.threshold:g} %)"]
        for r in self.rows:
            lines.append(f"{r.mode + 1:>4}  {r.frequency:12.5g}  {r.amplitude:12.4e}  {r.share:9.3f}  "
                         f"{'yes' if r.kept else 'no'}")
        return "\n".join(lines)


def modal_participation(modes: np.ndarray, stiffness: np.ndarray, loads: np.ndarray, *,
                        frequencies: np.ndarray | None = None, threshold: float = 0.01) -> ParticipationTable:
    """Modal participation factors of ``modes`` under static ``loads`` (MPF method).

    Parameters
    ----------
    modes : ndarray (n, M)
        Mode shapes on the DOFs the loads act on (FE DOFs), per unit modal coordinate [m, rad].
    stiffness : ndarray (M,) or (M, M)
        Generalised stiffness of each mode [N/m per unit coordinate] (``omega^2`` for mass-normalised modes);
        a matrix must be diagonal (orthogonal modes).
    loads : ndarray (n,) or (n, k)
        Load vectors [N, N m] on the same DOFs, one column per load case (e.g. instants of a rigid-body run).
    frequencies : ndarray (M,), optional
        Natural frequencies for the table [Hz].
    threshold : float
        Keep modes whose share is at least this fraction of the largest amplitude [1]; default 0.01 (1 %).

    Returns
    -------
    ParticipationTable
    """
    modes = np.asarray(modes, dtype=float)
    F = np.asarray(loads, dtype=float)
    F = F[:, None] if F.ndim == 1 else F
    if modes.ndim != 2 or F.shape[0] != modes.shape[0]:
        raise ValueError(f"modal_participation: loads have {F.shape[0]} rows, modes {modes.shape}")
    return _table(modes.T @ F, stiffness, frequencies, threshold)


def nodal_generalized_forces(data: ModalData, nodal_loads: Mapping[int, Sequence[float]]) -> np.ndarray:
    """Generalised forces ``sum_p Phi_p^T f_p + Phi*_p^T m_p`` [N per unit modal coordinate] of loads at nodes.

    Parameters
    ----------
    data : ModalData
        Modal data (mode shapes per node).
    nodal_loads : mapping of node id to 6 floats
        Force ``(fx, fy, fz)`` [N] and moment ``(mx, my, mz)`` [N m] in body axes at each loaded node.
    """
    out = np.zeros(data.n_modes)
    for node, load in nodal_loads.items():
        f = np.asarray(load, dtype=float)
        if f.shape != (6,) or not np.all(np.isfinite(f)):
            raise ValueError(f"nodal load at node {node}: expected 6 finite values (fx, fy, fz, mx, my, mz), "
                             f"got {load!r}")
        p = data.node_index(node)
        out += data.translational_modes[:, p, :] @ f[:3] + data.rotational_modes[:, p, :] @ f[3:]
    return out


def _table(Q: np.ndarray, stiffness: np.ndarray, frequencies: np.ndarray | None,
           threshold: float) -> ParticipationTable:
    if not 0 <= threshold <= 1:
        raise ValueError(f"modal_participation: threshold must be a fraction in [0, 1], got {threshold!r}")
    k = np.asarray(stiffness, dtype=float)
    if k.ndim == 2:
        off = np.abs(k - np.diag(np.diag(k))).max(initial=0.0)
        if off > 1e-9 * np.abs(k).max(initial=1.0):
            raise ValueError("modal_participation: the generalised stiffness is not diagonal (non-orthogonal modes)")
        k = np.diag(k)
    if k.shape != (Q.shape[0],) or np.any(k <= 0):
        raise ValueError("modal_participation: one positive generalised stiffness per mode is needed "
                         "(rigid-body modes have no static amplitude)")
    q = np.abs(Q / k[:, None])
    top = q.max(axis=0)
    share = np.max(np.divide(q, top, out=np.zeros_like(q), where=top > 0), axis=1) * 100.0
    f = np.full(k.shape, math.nan) if frequencies is None else np.asarray(frequencies, dtype=float)
    rows = tuple(ParticipationRow(i, float(f[i]), float(q[i].max()), float(share[i]),
                                  bool(share[i] >= 100.0 * threshold)) for i in range(k.size))
    return ParticipationTable(rows, float(threshold))


def participation_from_load_cases(data: ModalData, amplitudes: np.ndarray, *,
                                  threshold: float = 0.01) -> ParticipationTable:
    """Modal participation factors (MPF method) from the amplitudes of the data's unit load cases.

    The modal load of each instant is ``sum_c a_c Phi^T f_c`` from the stored ``/static_loads/modal_loads``, so the
    loads of a rigid-body run (its frames' cut loads and its reference frame's accelerations, as
    :meth:`FlexibleBody.load_amplitudes` gives them for a flexible one) select the modes without the FE model.

    Parameters
    ----------
    data : ModalData
        Modal data with static load responses (``modal_data_from_fe(..., static_loads=True)``).
    amplitudes : ndarray (C,) or (k, C)
        Load-case amplitudes at one or ``k`` instants, in the order of ``data.load_cases``.
    threshold : float
        Keep modes whose share reaches this fraction of the largest amplitude at some instant [1].

    Returns
    -------
    ParticipationTable

    Raises
    ------
    ValueError
        The data hold no static load responses, or the amplitudes have the wrong shape.
    """
    if data.load_cases is None:
        raise ValueError(f"participation_from_load_cases: modal data {data.title!r} has no static load responses "
                         "(make it with modal_data_from_fe(..., static_loads=True))")
    A = np.atleast_2d(np.asarray(amplitudes, dtype=float))
    if A.ndim != 2 or A.shape[1] != len(data.load_cases) or not np.all(np.isfinite(A)):
        raise ValueError(f"participation_from_load_cases: amplitudes must be finite, shape (k, "
                         f"{len(data.load_cases)}) (one per load case), got {np.shape(amplitudes)}")
    return _table(data.static_modal_loads.T @ A.T, data.generalized_stiffness, data.frequencies, threshold)


def select_modes(data: ModalData, *, count: int | None = None, max_frequency: float | None = None,
                 participation: ParticipationTable | None = None) -> ModalData:
    """Keep the modes that satisfy every given criterion (in ascending frequency order).

    Parameters
    ----------
    data : ModalData
        Modal data to select from.
    count : int, optional
        At most this many modes, the lowest in frequency.
    max_frequency : float, optional
        Only modes with frequency at or below this cut-off [Hz].
    participation : ParticipationTable, optional
        Only the modes it keeps (MPF at or above its threshold).

    Raises
    ------
    RunArgumentError
        ``count`` not an int >= 0 or ``max_frequency`` not a number >= 0 (a ``ValueError``).
    """
    if count is not None and (isinstance(count, bool | np.bool_) or not isinstance(count, int | np.integer)
                              or count < 0):
        raise RunArgumentError(f"select_modes: count must be an int >= 0 (the number of lowest modes kept), got "
                               f"{count!r} ({type(count).__name__})")
    if max_frequency is not None and (not _real(max_frequency) or not float(max_frequency) >= 0.0):
        raise RunArgumentError(f"select_modes: max_frequency must be a frequency [Hz] >= 0, got {max_frequency!r} "
                               f"({type(max_frequency).__name__})")
    order = np.argsort(data.frequencies, kind="stable")
    keep = [int(i) for i in order]
    if max_frequency is not None:
        keep = [i for i in keep if data.frequencies[i] <= max_frequency]
    if participation is not None:
        if len(participation.rows) != data.n_modes:
            raise ValueError(f"select_modes: the participation table has {len(participation.rows)} modes, "
                             f"the modal data {data.n_modes}")
        kept = set(participation.kept)
        keep = [i for i in keep if i in kept]
    if count is not None:
        keep = keep[:int(count)]
    return data.select(keep)


def default_damping_ratio(frequencies: np.ndarray | Sequence[float],
                          overrides: Mapping[int, float] | None = None) -> np.ndarray:
    """Modal damping ratios [1] by frequency: 0.01 below 100 Hz, 0.10 from 100 Hz to 1000 Hz, 1.0 above.

    Parameters
    ----------
    frequencies : array of float
        Natural frequencies [Hz].
    overrides : mapping of mode index to float, optional
        Damping ratios [1] replacing the default for given modes.
    """
    f = np.asarray(frequencies, dtype=float)
    zeta = np.where(f < 100.0, 0.01, np.where(f <= 1000.0, 0.10, 1.0))
    return _override(zeta, overrides, "default_damping_ratio")


def _real(value: object) -> bool:
    """A Python or numpy real number, not a bool (nor text)."""
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool | np.bool_)


def _override(zeta: np.ndarray, overrides: Mapping[int, float] | None, caller: str) -> np.ndarray:
    for mode, value in (overrides or {}).items():
        if (isinstance(mode, bool | np.bool_) or not isinstance(mode, int | np.integer)
                or not 0 <= mode < zeta.size):
            raise RunArgumentError(f"{caller}: override for mode {mode!r}, but there are {zeta.size} modes (keys are "
                                   f"mode indices, ints 0..{zeta.size - 1})")
        if not _real(value) or not math.isfinite(value) or value < 0:
            raise RunArgumentError(f"{caller}: damping ratio of mode {mode} must be a number >= 0, got {value!r}")
        zeta[mode] = value
    return zeta


def modal_damping_matrix(data: ModalData, overrides: Mapping[int, float] | None = None) -> np.ndarray:
    """Diagonal modal damping matrix ``diag(2 zeta_j omega_j M_jj)`` [N s/m per unit coordinate].

    Parameters
    ----------
    data : ModalData
        Modal data (stored damping ratios, else the default rule).
    overrides : mapping of mode index to float, optional
        Damping ratios [1] replacing the stored/default ones for given modes.
    """
    zeta = _override(np.array(data.damping_ratios(), dtype=float), overrides, "modal_damping_matrix")
    omega = 2 * math.pi * data.frequencies
    return np.diag(2.0 * zeta * omega * np.diag(data.generalized_mass))
