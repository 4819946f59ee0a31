"""Modal analysis of an assembled model: eigenvalues of the linearised DAE, free or with joints locked.

The state matrix ``A`` of :mod:`.linear` (on the constraint manifold) gives the modes directly: each eigenvalue
``λ`` is a mode with undamped natural frequency ``f = |λ|/2π``, damping ratio ``ζ = −Re λ/|λ|`` and damped
frequency ``Im λ/2π`` (MATLAB's ``damp``); a conjugate pair is listed once. Its eigenvector, mapped through the
sensitivities of the linearisation, is the mode shape of any variable (a frame's position, a modal coordinate,
a chamber pressure). Oil compliance, controller states and joint friction enter as they are in the model.

**Locked joints** (ADAMS's "rigid degrees of freedom locked", as seed 002 computes the frequencies of its
robots): a locked joint keeps its coordinate ``c(x) = φ`` (or ``s``) fixed through a reaction ``λ`` acting in its
own drive channel (the joint's ``tau_drive`` / ``f_drive`` parameter, an input ``b = ∂x'/∂τ``). With the locks
``C δx = 0`` on position coordinates (``C B = 0``: relative degree two) the reactions that hold them are
``λ = −(C A B)⁻¹ C A² δx``, and the locked dynamics are those of ``A_c = A − B (C A B)⁻¹ C A²`` on the subspace
``{C δx = 0, C A δx = 0}`` (positions and rates of the locked joints zero), which ``A_c`` leaves invariant: the
zero dynamics of the locked outputs (A. Isidori, *Nonlinear Control Systems*, 3rd ed., Springer 1995, §4.3 and
§5.1). For a mechanism this is exactly the Lagrangian system with the locked coordinates removed (Géradin &
Rixen, *Mechanical Vibrations*, 3rd ed., Wiley 2015, §2.6: constraints by Lagrange multipliers). ``C A B``
singular means the chosen joints are not independent (a closed loop already holds one of them); the error
names them. ``lock="rigid"`` locks a largest set of the model's revolute and prismatic joints whose coordinates
stay independent when the bodies are rigid (pivoted QR of the joint coordinates on the state directions that
leave every elastic coordinate unchanged — the variables components name in ``elastic_coordinates``, a flexible
body's ``q``): the mechanism's rigid degrees of freedom, so that a joint of a loop closed by flexible links is
not locked as if the loop were open.
"""

from __future__ import annotations

import difflib
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg as sla

from flexlib.analysis.linear import (
    Linearizer,
    LinearSystem,
    OperatingPoint,
    as_simulation,
    flag_argument,
    mapping_argument,
    names_argument,
    operating_point,
    real_argument,
    result_parameters,
    result_point,
)
from flexlib.core.values import not_a_number
from flexlib.errors import AnalysisWarning, LinearizationError
from flexlib.results.result import Result

__all__ = ["ModalSweep", "Modes", "mobility", "modal_analysis", "modal_sweep"]

#: Eigenvalues below this magnitude [rad/s] are rigid-body (zero-frequency) modes: no damping ratio
ZERO_EIGENVALUE = 1e-6
#: Relative tolerance of the independence of locked joints (pivoted QR of ``C A B``)
LOCK_RANK_TOL = 1e-8


@dataclass
class Modes:
    """Modes of a model at an operating point, ordered by natural frequency.

    Attributes
    ----------
    eigenvalues : ndarray of complex
        One per mode [rad/s] (of a conjugate pair the one with ``Im λ > 0``).
    vectors : ndarray of complex
        ``(n_states, n_modes)`` eigenvectors in the model's states, each scaled to a largest entry of 1.
    system : LinearSystem
        The (free) linearisation they come from.
    locked : list of str
        Joints held.
    """

    eigenvalues: np.ndarray
    vectors: np.ndarray
    system: LinearSystem
    locked: list[str] = field(default_factory=list)

    @property
    def frequencies(self) -> np.ndarray:
        """Undamped natural frequencies ``|λ|/2π`` [Hz]."""
        return np.abs(self.eigenvalues) / (2 * np.pi)

    @property
    def damped_frequencies(self) -> np.ndarray:
        """Damped frequencies ``Im λ/2π`` [Hz] (0 for a real eigenvalue)."""
        return np.abs(self.eigenvalues.imag) / (2 * np.pi)

    @property
    def damping(self) -> np.ndarray:
        """Damping ratios ``−Re λ/|λ|`` [1] (NaN for a zero eigenvalue; 1 or more for a real one)."""
        mag = np.abs(self.eigenvalues)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(mag > ZERO_EIGENVALUE, -self.eigenvalues.real / mag, np.nan)

    @property
    def oscillatory(self) -> np.ndarray:
        """Mask of the modes with a complex eigenvalue (vibration modes)."""
        return np.abs(self.eigenvalues.imag) > ZERO_EIGENVALUE

    def dominant(self, k: int) -> str:
        """The state with the largest amplitude in mode ``k`` (states scaled by their nominal values)."""
        n = len(self.eigenvalues)
        if isinstance(k, (bool, np.bool_)) or not isinstance(k, (int, np.integer)) or not -n <= k < n:
            raise LinearizationError(f"Modes.dominant: mode index k = {k!r:.60} is not an integer in 0 … {n - 1} "
                                     f"({n} modes)")
        nominal = self.system.nominal
        return self.system.states[int(np.argmax(np.abs(self.vectors[:, k]) / nominal))]

    def shape(self, name: str) -> np.ndarray:
        """Complex amplitude of variable ``name`` in each mode (same scaling as :attr:`vectors`)."""
        C, _ = self.system.sensitivity([name])
        return C[0] @ self.vectors

    def table(self, n: int | None = None, *, vibration_only: bool = True) -> str:
        """A text table of the first ``n`` modes: frequency [Hz], damping ratio [%], damped frequency [Hz].

        ``vibration_only`` (default) lists the oscillatory modes (complex eigenvalues) and counts the others
        (rigid-body and first-order modes: real eigenvalues of integrators, valves, over-damped motions)."""
        if n is not None and (isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)) or n < 0):
            raise LinearizationError(f"Modes.table: n must be None or an integer >= 0, got {n!r:.60}")
        vibration_only = flag_argument(vibration_only, "Modes.table: vibration_only")
        keep = np.flatnonzero(self.oscillatory) if vibration_only else np.arange(len(self.eigenvalues))
        lines = [f"{'mode':>4}  {'f [Hz]':>12}  {'zeta [%]':>9}  {'f_d [Hz]':>12}  dominant state"]
        for k in keep[:n]:
            z = self.damping[k]
            z = 0.0 if abs(z) < 1e-12 else z  # no "-0"
            lines.append(f"{k + 1:>4}  {self.frequencies[k]:>12.6g}  {'-' if np.isnan(z) else f'{100 * z:.3g}':>9}"
                         f"  {self.damped_frequencies[k]:>12.6g}  {self.dominant(k)}")
        if vibration_only and len(keep) < len(self.eigenvalues):
            lines.append(f"(and {len(self.eigenvalues) - len(keep)} non-oscillatory modes: real eigenvalues)")
        if self.locked:
            lines.append(f"locked: {', '.join(self.locked)}")
        return "\n".join(lines)


def _joints(lin: Linearizer, lockable: bool) -> list[tuple[str, str, str]]:
    """``(joint, drive parameter, coordinate)`` of the revolute and prismatic joints, prismatic ones (linear drives)
    first, then in the model's order; ``lockable``: only those whose drive channel survived the build (a drive
    parameter that the planar assumption fixed to zero, e.g. about a redundant loop direction, cannot carry a
    lock reaction)."""
    variables = {v.name for v in lin.m.variables}
    assumed = (getattr(lin.m, "assumed", {}) or {}) if lockable else {}
    found: dict[str, list[tuple[str, str, str]]] = {".f_drive": [], ".tau_drive": []}
    for name in lin.m.param_names:
        for par, coord in ((".f_drive", ".s"), (".tau_drive", ".phi")):
            joint = name[: -len(par)]
            if name.endswith(par) and joint + coord in variables and name not in assumed:
                found[par].append((joint, name, joint + coord))
    return found[".f_drive"] + found[".tau_drive"]


def _lock_channels(lin: Linearizer, joints: list[str]) -> tuple[list[str], list[str]]:
    """Drive parameters and coordinates of the joints to lock."""
    known = {j: (par, coord) for j, par, coord in _joints(lin, False)}
    for j in joints:
        if j not in known:
            close = difflib.get_close_matches(j, list(known), n=3)
            hint = "did you mean lock='rigid' (a largest independent set of joints)? " if j.strip().lower() == "rigid" \
                else f"did you mean {', '.join(close)}? " if close else (
                f"lockable joints: {', '.join(list(known)[:8])}{' …' if len(known) > 8 else ''}; " if known else "")
            raise LinearizationError(f"cannot lock {j!r}: not a Revolute or Prismatic joint of {lin.m.name} ({hint}a "
                                     "lockable joint has a coordinate phi/s and a drive parameter tau_drive/f_drive)")
    return [known[j][0] for j in joints], [known[j][1] for j in joints]


def _elastic_coordinates(lin: Linearizer) -> list[str]:
    """Names of the elastic (small-motion) coordinates: the variables that components list in their
    ``elastic_coordinates`` attribute (a flexible body's modal coordinates ``q``)."""
    names = {v.name for v in lin.m.variables}
    out = []
    for node in lin.sim.model.walk():
        for var in getattr(type(node), "elastic_coordinates", ()):
            prefix = f"{node.path}.{var}" if node.path else var
            out += [n for n in names if n == prefix or n.startswith(prefix + "[")]
    return sorted(out)


def _eig(A: np.ndarray, basis: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Eigenpairs of ``A`` (restricted to ``basis`` if given), one of each conjugate pair, by frequency."""
    Ar = A if basis is None else basis.T @ A @ basis
    lam, W = np.linalg.eig(Ar) if Ar.size else (np.zeros(0, complex), np.zeros((0, 0), complex))
    V = W if basis is None else basis @ W
    keep = lam.imag >= 0.0  # a real matrix: exact conjugate pairs, real eigenvalues with Im = 0
    lam, V = lam[keep], V[:, keep]
    order = np.lexsort((lam.real, np.abs(lam)))
    lam, V = lam[order], V[:, order]
    if V.size:
        big = np.argmax(np.abs(V), axis=0)
        V = V / V[big, np.arange(V.shape[1])]
    return lam, V


def _rank(M: np.ndarray, scale: float | None = None) -> tuple[int, np.ndarray]:
    """Numerical rank of the rows of ``M`` (relative to ``scale``, default the largest pivot) and the pivot order
    of a pivoted QR of ``Mᵀ`` (independent rows first)."""
    if not M.size:
        return 0, np.arange(M.shape[0])
    _, R, piv = sla.qr(M.T, pivoting=True)
    diag = np.abs(np.diag(R))
    ref = diag.max(initial=0.0) if scale is None else scale
    return int(np.sum(diag > LOCK_RANK_TOL * ref)), piv


def _rigid_rank(lin: Linearizer, point: OperatingPoint, C: np.ndarray) -> tuple[int, np.ndarray]:
    """Rank of joint coordinates ``C`` (rows: sensitivities to the states) on the state directions that leave every
    elastic coordinate unchanged (the joints of a loop closed by flexible links count as in the rigid mechanism),
    and the row order with an independent set first: taken greedily in the given order, so the caller's
    preference (drives first, then the model's order) decides among equivalent sets."""
    elastic = _elastic_coordinates(lin)
    rigid = sla.null_space(lin.outputs(point, elastic)[0], rcond=1e-10) if elastic else np.eye(C.shape[1])
    M = C @ rigid
    scale = float(np.linalg.norm(C, 2)) if C.size else 0.0  # motion the elastic coordinates allow is no rigid DOF
    total, _ = _rank(M, scale)
    chosen: list[int] = []
    for k in range(M.shape[0]):
        if len(chosen) == total:
            break
        if _rank(M[[*chosen, k]], scale)[0] == len(chosen) + 1:
            chosen.append(k)
    rest = [k for k in range(M.shape[0]) if k not in chosen]
    if elastic and any("loop closure" in row for row in lin.m.row_labels):
        warnings.warn(
            f"{lin.m.name}: the rigid degrees of freedom are counted with the elastic coordinates held, at a point "
            f"where loops closed through flexible bodies are deflected; this count ({total}) can miss some of them "
            "(an over-constrained mechanism with flexible links). Check the joints it chose against the mechanism, "
            "or pass the joints to lock by name", AnalysisWarning, stacklevel=3)
    return total, np.array(chosen + rest, dtype=int)


def mobility(model: Any, *, at: Result | None = None, t: float | None = None, params: dict[str, Any] | None = None,
             steady_state: bool = False, starts: dict[str, float] | None = None) -> tuple[int, list[str]]:
    """The mechanism's rigid degrees of freedom at an operating point, and joints that parametrise them.

    The number of independent coordinates among all revolute and prismatic joints (their ``phi`` / ``s``) on the
    constraint manifold, the elastic coordinates held (:func:`modal_analysis`, ``lock="rigid"``): the real
    mobility of an over-constrained mechanism, which Grübler's count misses. Degrees of freedom that no joint
    coordinate expresses (a free-floating body) are not counted.

    Returns
    -------
    int, list of str
        The mobility and a set of that many independent joints.
    """
    sim = as_simulation(model)
    point = operating_point(sim, at=at, t=t, params=params, steady_state=steady_state, starts=starts)
    lin = Linearizer(sim)
    triples = _joints(lin, False)
    joints, coords = [j for j, _, _ in triples], [c for _, _, c in triples]
    if not joints:
        return 0, []
    C, _ = lin.outputs(point, coords)
    rank, piv = _rigid_rank(lin, point, C)
    return rank, [joints[int(k)] for k in piv[:rank]]


def _locked_modes(lin: Linearizer, point: OperatingPoint, joints: list[str] | str
                  ) -> tuple[LinearSystem, np.ndarray, np.ndarray, list[str]]:
    auto = isinstance(joints, str)
    names = [j for j, _, _ in _joints(lin, True)] if auto else list(joints)
    if not names:
        raise LinearizationError(f"lock='rigid': {lin.m.name} has no revolute or prismatic joint")
    params, coords = _lock_channels(lin, names)
    sys = lin.linearize(point, params, coords)
    A, B, C = sys.A, sys.B, sys.C
    G = C @ A @ B
    scale = max(np.abs(G).max(initial=0.0), 1e-300)
    if np.abs(C @ B).max(initial=0.0) > 1e-8 * scale * max(1.0, 1.0 / max(np.abs(A).max(initial=1.0), 1e-300)):
        bad = [names[k] for k in np.flatnonzero(np.abs(C @ B).max(axis=1) > 1e-8 * scale)]
        raise LinearizationError(f"cannot lock {', '.join(bad)}: the joint coordinate responds directly to its drive "
                                 "(it is not a position coordinate of the mechanism at this point)")
    rank, piv = _rigid_rank(lin, point, C) if auto else _rank(G)
    if rank < len(names):
        dependent = [names[k] for k in piv[rank:]]
        if not auto:
            raise LinearizationError(
                f"cannot lock {', '.join(names)} together: {', '.join(dependent)} "
                f"{'is' if len(dependent) == 1 else 'are'} already held by the others (a closed kinematic loop); "
                "lock fewer joints")
        keep = [int(k) for k in piv[:rank]]
        names = [names[k] for k in keep]
        A, B, C = A, B[:, keep], C[keep]
        G = C @ A @ B
    Ac = A - B @ np.linalg.solve(G, C @ A @ A)
    basis = sla.null_space(np.vstack([C, C @ A]), rcond=1e-10)
    lam, V = _eig(Ac, basis)
    return sys, lam, V, names


def modal_analysis(model: Any, *, lock: list[str] | tuple[str, ...] | str | None = None, at: Result | None = None,
                   t: float | None = None, params: dict[str, Any] | None = None, steady_state: bool = False,
                   starts: dict[str, float] | None = None) -> Modes:
    """Natural frequencies, damping ratios and mode shapes of a model at an operating point (module doc).

    Parameters
    ----------
    model : Simulation or Component
        The model.
    lock : list of str or str, optional
        Joints (Revolute / Prismatic component names, each once) held at their operating-point coordinate (a
        single name may be given as a string), or ``"rigid"`` for a largest independent set of them (the
        mechanism's rigid degrees of freedom). Default: free.
    at, t, params, steady_state, starts
        The operating point (:func:`flexlib.analysis.operating_point`).

    Returns
    -------
    Modes

    Examples
    --------
    >>> modes = modal_analysis(model, steady_state=True)  # doctest: +SKIP
    >>> print(modes.table(6))                             # doctest: +SKIP
    """
    lock = _lock_argument(lock)
    sim = as_simulation(model)
    point = operating_point(sim, at=at, t=t, params=params, steady_state=steady_state, starts=starts)
    return _modes(Linearizer(sim), point, lock)


def _lock_argument(lock: Any) -> list[str] | str:
    """``lock`` as ``"rigid"`` or a list of distinct joint names (a single other string is one joint name)."""
    if isinstance(lock, str) and lock == "rigid":
        return lock
    return names_argument(lock, "lock")


def _modes(lin: Linearizer, point: OperatingPoint, lock: list[str] | str) -> Modes:
    if not lock:
        sys = lin.linearize(point, [], [])
        lam, V = _eig(sys.A, None)
        return Modes(lam, V, sys, [])
    sys, lam, V, names = _locked_modes(lin, point, lock)
    return Modes(lam, V, sys, names)


@dataclass
class ModalSweep:
    """Frequencies over a set of operating points.

    Attributes
    ----------
    points : list of str
        Where each row was computed.
    frequencies, damping : ndarray
        ``(n_points, n_modes)``: undamped natural frequency [Hz] and damping ratio [1] of the lowest ``n_modes``
        oscillatory modes at each point (NaN where a point has fewer).
    modes : list of Modes
        The full analysis at each point.
    """

    points: list[str]
    frequencies: np.ndarray
    damping: np.ndarray
    modes: list[Modes]


def modal_sweep(model: Any, *, at: Result | None = None, times: Any = None, poses: list[dict[str, float]] | None = None,
                lock: list[str] | str | None = None, n_modes: int = 6, params: dict[str, Any] | None = None,
                steady_state: bool = True, f_min: float = 0.0, max_damping: float = np.inf) -> ModalSweep:
    """The lowest ``n_modes`` vibration modes over a trajectory or a set of poses.

    Parameters
    ----------
    model : Simulation or Component
        The model (built once for the whole sweep).
    at, times : Result and array_like
        Operating points along a result: its states at each time [s].
    poses : list of dict
        Or static poses: start values (e.g. joint angles, held as initial conditions) and parameter values
        (e.g. a cylinder's ``x_start``) per pose, each solved as a static equilibrium when ``steady_state``
        (default).
    lock, params
        As :func:`modal_analysis`.
    n_modes : int
        Oscillatory modes reported per point, >= 1.
    f_min, max_damping : float
        Report only vibration modes at or above ``f_min`` [Hz] with a damping ratio up to ``max_damping`` [1]
        (e.g. leave out slow closed-loop control modes and the well-damped valve-spool modes of a machine).

    Raises
    ------
    LinearizationError
        Both or neither of ``at`` and ``poses``; ``n_modes`` not an integer >= 1; ``f_min`` not a finite number
        >= 0; ``max_damping`` not a number; ``times`` not a 1-D sequence of finite times within the result; a pose
        that is not a dict; a bad ``lock`` (as :func:`modal_analysis`). An empty ``times`` or ``poses`` gives an
        empty sweep.
    """
    if isinstance(n_modes, (bool, np.bool_)) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
        raise LinearizationError(f"modal_sweep: n_modes must be an integer >= 1, got {n_modes!r:.60}")
    f_min = real_argument(f_min, "modal_sweep: f_min [Hz]")
    max_damping = real_argument(max_damping, "modal_sweep: max_damping [1]", allow_inf=True)
    if f_min < 0.0:
        raise LinearizationError(f"modal_sweep: f_min = {f_min!r} Hz is negative")
    steady_state = flag_argument(steady_state, "modal_sweep: steady_state")
    lock, params = _lock_argument(lock), mapping_argument(params, "modal_sweep: params")
    if (at is None) == (poses is None):
        raise LinearizationError("modal_sweep: give either at=result with times=[...] or poses=[{...}, ...]")
    if at is not None and times is None:
        raise LinearizationError("modal_sweep: at=result needs times=[...] [s]")
    if poses is not None and times is not None:  # the times were ignored
        raise LinearizationError("modal_sweep: times=[...] go with at=result; poses=[...] are static poses without "
                                 "times: give one of the two")
    if at is not None:
        times = _sweep_times(times)
    elif isinstance(poses, (str, Mapping)) or not hasattr(poses, "__iter__"):
        raise LinearizationError(f"modal_sweep: poses must be a list of dicts {{name: value}}, got "
                                 f"{type(poses).__name__} {poses!r:.60}")
    sim = as_simulation(model)
    lin = Linearizer(sim)
    points = _sweep_points(sim, at, times, poses, params, steady_state)
    f = np.full((len(points), n_modes), np.nan)
    z = np.full((len(points), n_modes), np.nan)
    all_modes = []
    for k, point in enumerate(points):
        modes = _modes(lin, point, lock)
        with np.errstate(invalid="ignore"):
            wanted = modes.oscillatory & (modes.frequencies >= f_min) & (modes.damping <= max_damping)
        osc = np.flatnonzero(wanted)[:n_modes]
        f[k, :len(osc)] = modes.frequencies[osc]
        z[k, :len(osc)] = modes.damping[osc]
        all_modes.append(modes)
    return ModalSweep([pt.source for pt in points], f, z, all_modes)


def _sweep_times(times: Any) -> np.ndarray:
    """``modal_sweep``'s ``times`` as a 1-D array of finite times [s]."""
    why = not_a_number(times)
    if why is not None or np.ndim(times) > 1:
        raise LinearizationError(f"modal_sweep: times = {times!r:.80} is "
                                 f"{why or 'not 1-D'}; give a 1-D sequence of times [s] within the result")
    times = np.atleast_1d(np.asarray(times, dtype=float))
    bad = np.flatnonzero(~np.isfinite(times))
    if bad.size:
        raise LinearizationError(f"modal_sweep: times[{int(bad[0])}] = {float(times[bad[0]])!r} s is not finite")
    return times


def _sweep_points(sim: Any, at: Result | None, times: np.ndarray | None, poses: Any, params: dict[str, Any],
                  steady_state: bool) -> list[OperatingPoint]:
    """The operating points of a sweep: the states of result ``at`` at ``times``, or the static ``poses``."""
    if at is not None:
        if not isinstance(at, Result):
            raise LinearizationError(f"modal_sweep: at must be a flexlib Result, got {type(at).__name__}")
        pvec = result_parameters(sim, at, params)
        return [result_point(sim, at, float(tk), pvec) for tk in times]
    points = []
    pnames = set(sim.compiled.param_names)
    for j, pose in enumerate(poses or []):
        pose = mapping_argument(pose, f"modal_sweep: poses[{j}]")
        pars = {**params, **{k: v for k, v in pose.items() if k in pnames}}
        starts = {k: v for k, v in pose.items() if k not in pnames}
        try:
            points.append(operating_point(sim, params=pars, steady_state=steady_state, starts=starts))
        except LinearizationError as exc:
            raise LinearizationError(f"modal_sweep: poses[{j}]: {exc}") from None
    return points
