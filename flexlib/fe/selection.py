"""Mode selection (by count, frequency cut-off, modal participation factors) and default modal damping.

The modal participation factor (MPF) method of Cuadrado, Dopico, González and Naya:
take the loads acting on the body at the most critical instant of a rigid-body run, solve the static problem
in modal coordinates, ``q_i = phi_i^T F / k_i`` (``k_i = omega_i^2`` for mass-normalised modes), and express
each ``|q_i|`` as a percentage of the largest one (the convention of the paper's Table 2, where the dominant
mode has 100 %); modes above the threshold (1 % by default) are kept.

The default modal damping follows the rule of the modal neutral file workflow (after Adams/Flex):
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
from typing import Any

import numpy as np

from flexlib.errors import ModalFileError, RunArgumentError

from .modal_data import ModalData

__all__ = [
    "ParticipationRow",
    "ParticipationTable",
    "default_damping_ratio",
    "modal_damping_matrix",
    "modal_participation",
    "nodal_generalized_forces",
    "participation_from_load_cases",
    "planar_modes",
    "select_modes",
]

#: A plane by name: the axis normal to it (0 x, 1 y, 2 z)
_NORMALS = {"xy": 2, "yx": 2, "yz": 0, "zy": 0, "xz": 1, "zx": 1}


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

    Raises
    ------
    RunArgumentError
        (a ``ValueError``) An argument that is not an array of finite real numbers (text, bools, NaN are
        refused), of the wrong shape, a stiffness that is not positive or not diagonal, ``threshold`` not a
        fraction in ``[0, 1]``; the message names the argument.
    """
    func = "modal_participation"
    modes = _numbers(func, "modes", modes)
    F = _numbers(func, "loads", loads)
    F = F[:, None] if F.ndim == 1 else F
    if modes.ndim != 2:
        raise RunArgumentError(f"{func}: argument 'modes' must be a matrix (n DOFs, M modes), got shape {modes.shape}")
    if F.ndim != 2 or F.shape[0] != modes.shape[0]:
        raise RunArgumentError(f"{func}: argument 'loads' has shape {F.shape}: it must have one row per DOF of "
                               f"'modes' {modes.shape} (n, or (n, k) for k load cases)")
    return _table(modes.T @ F, stiffness, frequencies, threshold, func)


def nodal_generalized_forces(data: ModalData, nodal_loads: Mapping[int, Sequence[float]]) -> np.ndarray:
    """Generalised forces ``sum_p Phi_p^T f_p + Phi*_p^T m_p`` [N per unit modal coordinate] of loads at nodes.

    Parameters
    ----------
    data : ModalData
        Modal data (mode shapes per node).
    nodal_loads : mapping of node id to 6 floats
        Force ``(fx, fy, fz)`` [N] and moment ``(mx, my, mz)`` [N m] in body axes at each loaded node.

    Raises
    ------
    RunArgumentError
        (a ``ValueError``) ``data`` not a ModalData, ``nodal_loads`` not a mapping, a node the data do not have
        (or not a whole number), a load that is not six finite numbers (text is refused).
    """
    func = "nodal_generalized_forces"
    data = _modal_data(func, data)
    if not isinstance(nodal_loads, Mapping):
        raise RunArgumentError(f"{func}: argument 'nodal_loads' must be a mapping {{node id: (fx, fy, fz, mx, my, "
                               f"mz)}} [N, N m], got {type(nodal_loads).__name__} {nodal_loads!r:.60}")
    out = np.zeros(data.n_modes)
    for node, load in nodal_loads.items():
        f = _numbers(func, f"nodal_loads[{node!r}]", load)
        if f.shape != (6,):
            raise RunArgumentError(f"{func}: nodal load at node {node!r}: expected 6 finite values (fx, fy, fz, mx, "
                                   f"my, mz) [N, N m], got {load!r}")
        p = data.node_index(node)
        out += data.translational_modes[:, p, :] @ f[:3] + data.rotational_modes[:, p, :] @ f[3:]
    return out


def _numbers(func: str, name: str, value: Any) -> np.ndarray:
    """An array of finite real numbers (not text, bools or complex), naming the argument."""
    try:
        kind = "U" if isinstance(value, str | bytes) else np.asarray(value).dtype.kind
    except (TypeError, ValueError):
        kind = "O"
    if kind not in "iuf":
        raise RunArgumentError(f"{func}: argument {name!r} must be an array of real numbers, got "
                               f"{type(value).__name__} {value!r:.80}")
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        where = tuple(int(x) for x in np.argwhere(~np.isfinite(a))[0])
        raise RunArgumentError(f"{func}: argument {name!r} has a non-finite value {a[where]} at index {where}")
    return a


def _modal_data(func: str, data: Any) -> ModalData:
    if not isinstance(data, ModalData):
        raise RunArgumentError(f"{func}: argument 'data' must be a ModalData (ModalData.read(path), "
                               f"modal_data_from_fe(...) or body.modal_data), got {type(data).__name__} {data!r:.60}")
    return data


def _threshold(func: str, threshold: Any) -> float:
    if not _real(threshold) or not 0.0 <= float(threshold) <= 1.0:
        pct = _real(threshold) and 1.0 < float(threshold) <= 100.0
        raise RunArgumentError(f"{func}: threshold must be a fraction in [0, 1] (0.01 for 1 %), got {threshold!r}"
                               + (f" (a percentage? {float(threshold):g} % is {float(threshold) / 100:g})"
                                  if pct else ""))
    return float(threshold)


def _table(Q: np.ndarray, stiffness: np.ndarray, frequencies: np.ndarray | None,
           threshold: float, func: str = "modal_participation") -> ParticipationTable:
    threshold = _threshold(func, threshold)
    k = _numbers(func, "stiffness", stiffness)
    if k.ndim == 2:
        off = np.abs(k - np.diag(np.diag(k))).max(initial=0.0)
        if off > 1e-9 * np.abs(k).max(initial=1.0):
            raise RunArgumentError(f"{func}: the generalised stiffness is not diagonal (non-orthogonal modes)")
        k = np.diag(k)
    if k.shape != (Q.shape[0],) or np.any(k <= 0):
        raise RunArgumentError(f"{func}: one positive generalised stiffness per mode is needed ({Q.shape[0]} modes, "
                               f"got {np.shape(stiffness)} with smallest {float(k.min(initial=np.inf)):.3g}; "
                               "rigid-body modes have no static amplitude)")
    q = np.abs(Q / k[:, None])
    top = q.max(axis=0)
    share = np.max(np.divide(q, top, out=np.zeros_like(q), where=top > 0), axis=1) * 100.0
    f = np.full(k.shape, math.nan) if frequencies is None else _numbers(func, "frequencies", frequencies)
    if f.shape != k.shape:
        raise RunArgumentError(f"{func}: argument 'frequencies' has shape {f.shape}, expected ({k.size},): one "
                               "frequency [Hz] per mode")
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
    ModalFileError
        The data hold no static load responses (a ``ValueError``).
    RunArgumentError
        (a ``ValueError``) ``data`` not a ModalData; amplitudes that are not finite numbers or of the wrong shape;
        ``threshold`` not a fraction in ``[0, 1]``.
    """
    func = "participation_from_load_cases"
    data = _modal_data(func, data)
    if data.load_cases is None:
        raise ModalFileError(f"{func}: modal data {data.title!r} has no static load responses (dataset "
                             "'/static_loads'; make it with modal_data_from_fe(..., static_loads=True))")
    A = np.atleast_2d(_numbers(func, "amplitudes", amplitudes))
    if A.ndim != 2 or A.shape[1] != len(data.load_cases):
        raise RunArgumentError(f"{func}: amplitudes must be finite, shape (k, {len(data.load_cases)}) (one per load "
                               f"case {list(data.load_cases[:4])}...), got {np.shape(amplitudes)}")
    return _table(data.static_modal_loads.T @ A.T, data.generalized_stiffness, data.frequencies, threshold, func)


def _normal(func: str, plane: Any) -> int:
    """The axis normal to ``plane`` ("xy", "yz" or "xz", either order)."""
    if not isinstance(plane, str) or plane.lower() not in _NORMALS:
        raise RunArgumentError(f"{func}: plane must be one of 'xy', 'yz', 'xz' (the body axes a mode moves in), got "
                               f"{plane!r}")
    return _NORMALS[plane.lower()]


def planar_modes(data: ModalData, plane: str = "xy", *, tol: float = 1e-6) -> list[int]:
    """Indices of the modes that move the body in one of its coordinate planes, by ascending frequency.

    A mode is planar in ``"xy"`` when its translations along ``z`` and its rotations about ``x`` and ``y`` carry at
    most ``tol`` of its squared amplitude, rotations weighted by the body's size ``L`` (the largest distance of a
    node from the body frame's origin), ``(Σ u_z² + L² Σ (θ_x² + θ_y²)) ≤ tol (Σ |u|² + L² Σ |θ|²)``. Loads that lie in
    the plane (a planar mechanism's joint forces, gravity in the plane) do not excite the others, and the others
    would make the rows a planar loop drops in 3D independent again (see ``docs/engine.md``).

    Parameters
    ----------
    data : ModalData
        Modal data to select from.
    plane : {"xy", "yz", "xz"}
        The plane in body axes.
    tol : float
        Largest out-of-plane share of a mode's squared amplitude [1], in ``[0, 1)``.

    Raises
    ------
    RunArgumentError
        ``data`` not a ModalData, an unknown plane, ``tol`` outside ``[0, 1)``.
    """
    func = "planar_modes"
    data = _modal_data(func, data)
    normal = _normal(func, plane)
    if not _real(tol) or not 0.0 <= float(tol) < 1.0:
        raise RunArgumentError(f"{func}: tol must be a fraction in [0, 1), got {tol!r}")
    T = np.asarray(data.translational_modes, dtype=float)
    R = np.asarray(data.rotational_modes, dtype=float)
    size = float(np.max(np.linalg.norm(np.asarray(data.coordinates, dtype=float), axis=1), initial=0.0))
    in_plane_rot = [a for a in range(3) if a != normal]
    out = np.sum(T[:, :, normal] ** 2, axis=1) + size**2 * np.sum(R[:, :, in_plane_rot] ** 2, axis=(1, 2))
    total = np.sum(T**2, axis=(1, 2)) + size**2 * np.sum(R**2, axis=(1, 2))
    keep = np.flatnonzero(out <= float(tol) * np.maximum(total, 1e-300))
    return [int(k) for k in keep[np.argsort(data.frequencies[keep], kind="stable")]]


def select_modes(data: ModalData, *, count: int | None = None, max_frequency: float | None = None,
                 participation: ParticipationTable | None = None, plane: str | None = None) -> ModalData:
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
    plane : {"xy", "yz", "xz"}, optional
        Only the modes that move the body in this plane of its axes (:func:`planar_modes`): with ``count``, the
        lowest ``count`` planar modes.

    Raises
    ------
    RunArgumentError
        ``data`` not a ModalData, ``count`` not an int >= 0, ``max_frequency`` not a number >= 0,
        ``participation`` not a ParticipationTable or of another number of modes, an unknown ``plane``
        (a ``ValueError``).
    """
    data = _modal_data("select_modes", data)
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
    if plane is not None:
        planar = set(planar_modes(data, plane))
        keep = [i for i in keep if i in planar]
    if participation is not None:
        if not isinstance(participation, ParticipationTable):
            raise RunArgumentError(f"select_modes: argument 'participation' must be a ParticipationTable (of "
                                   "modal_participation or participation_from_load_cases), got "
                                   f"{type(participation).__name__} {participation!r:.60}")
        if len(participation.rows) != data.n_modes:
            raise RunArgumentError(f"select_modes: the participation table has {len(participation.rows)} modes, "
                                   f"the modal data {data.n_modes}: make the table from these data's modes")
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

    Raises
    ------
    RunArgumentError
        Frequencies that are not finite numbers >= 0 (a NaN would get the 100 % band), a bad override.
    """
    f = _numbers("default_damping_ratio", "frequencies", frequencies)
    if np.any(f < 0):
        raise RunArgumentError(f"default_damping_ratio: frequencies must be >= 0 [Hz], got {float(f.min())!r}")
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
    data = _modal_data("modal_damping_matrix", data)
    zeta = _override(np.array(data.damping_ratios(), dtype=float), overrides, "modal_damping_matrix")
    omega = 2 * math.pi * data.frequencies
    return np.diag(2.0 * zeta * omega * np.diag(data.generalized_mass))
