"""The arguments of :class:`~.body.FlexibleBody` checked and turned into what its equations use: the kept modes
(count, indices, frequency cut-off), the frames' nodes, modal damping ratios, start values of the modal coordinates,
and their nominal sizes. Each failure is a :class:`~flexlib.errors.ModelError` (or
:class:`~flexlib.errors.ParameterError` for ``zeta``) that names the argument and says what is accepted."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from flexlib.errors import ModelError, ParameterError, RunArgumentError
from flexlib.fe.modal_data import ModalData
from flexlib.fe.modal_schema import LOAD_CASE_NAMES
from flexlib.fe.selection import ParticipationTable, planar_modes, select_modes

__all__ = ["check_stiffening_data", "check_zeta", "choose_modes", "damping_ratios", "deferred_arguments", "flag",
           "frame_names", "frame_nodes", "is_int", "is_real", "modal_nominals", "modal_source", "modal_start"]


def modal_source(modal_data: Any) -> tuple[ModalData, str]:
    """The modal data (read and validated once from a path) and how messages name them: ``"modal file 'arm.h5'"``
    or ``"modal data 'arm'"``."""
    if isinstance(modal_data, ModalData):
        title = modal_data.title
        return modal_data, f"modal data {title!r}" if title else "modal data (untitled)"
    if isinstance(modal_data, str | os.PathLike):
        return ModalData.read(modal_data), f"modal file {os.fspath(modal_data)!r}"
    raise ModelError(f"FlexibleBody: modal_data must be a ModalData or the path of a modal file (str or "
                     f"Path), got {modal_data!r} ({type(modal_data).__name__})")


def deferred_arguments(kwargs: dict[str, Any]) -> dict[str, Any]:
    """``zeta``, ``init``, ``guess`` and ``state_select`` taken out of ``kwargs`` (the body applies them once its
    variables exist); the last three must be dicts."""
    deferred = {k: kwargs.pop(k) for k in ("zeta", "init", "guess", "state_select") if k in kwargs}
    for kind in ("init", "guess", "state_select"):
        given = deferred.get(kind)
        if given is not None and not isinstance(given, Mapping):
            accepted = ("{variable: 'always' | 'prefer' | 'default' | 'avoid' | 'never'}" if kind == "state_select"
                        else "{variable name: start value}, e.g. {'q': np.zeros(n_modes)}")
            raise ModelError(f"FlexibleBody: {kind} must be a dict {accepted}, got {type(given).__name__} "
                             f"{given!r:.60}")
    return deferred


def check_stiffening_data(cls: str, data: ModalData, source: str) -> None:
    """``geometric_stiffening=True`` needs the data's ``/geometric_stiffness`` with at least one load case."""
    if data.geometric_stiffness is None:
        raise ModelError(f"{cls}: geometric_stiffening=True, but the {source} has no "
                         "'/geometric_stiffness' (build it with modal_data_from_fe(..., "
                         "geometric_stiffening=True))")
    if not data.geometric_stiffness:
        raise ModelError(f"{cls}: geometric_stiffening=True, but the group "
                         f"'/geometric_stiffness' of the {source} holds no load case (expected "
                         f"{LOAD_CASE_NAMES}): no stiffening term could be added")


def modal_nominals(data: ModalData) -> tuple[float, float]:
    """Nominal sizes of the modal coordinates [1] and rates [1/s]: the ``q`` that deflects the body by 1e-3 of its
    size (small elastic deformation), and that ``q`` oscillating at the lowest modal frequency. They scale the
    integrator's absolute tolerance and the loop-redundancy rank test
    (``flexlib.compile.passes.multibody.redundancy``)."""
    size = float(np.linalg.norm(np.ptp(data.coordinates, axis=0))) or 1.0
    shape = float(np.abs(data.translational_modes).max())
    if not shape > 0:  # rotation-only modes
        shape = float(np.abs(data.rotational_modes).max()) * size
    q_nom = 1e-3 * size / shape if shape > 0 else 1.0
    f = data.frequencies[data.frequencies > 0]
    return q_nom, q_nom * 2 * np.pi * (float(f.min()) if f.size else 1.0)


def is_int(value: Any) -> bool:
    """A Python or numpy integer, not a bool."""
    return isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_)


def is_real(value: Any) -> bool:
    """A Python or numpy real number, not a bool."""
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool | np.bool_)


def flag(name: str, value: Any, accepted: str = "True or False") -> bool:
    """A FlexibleBody switch: a bool (Python or numpy)."""
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise ModelError(f"FlexibleBody: {name} must be {accepted}, got {value!r} ({type(value).__name__})")


def _int_list(name: str, value: Any, what: str, example: str) -> list[int]:
    """``value`` as a list of ints: a list, tuple, range or 1-D integer array whose items are all integers."""
    if isinstance(value, str | bytes | Mapping) or not isinstance(value, Sequence | np.ndarray | range):
        raise ModelError(f"FlexibleBody: {name} must be {what}, got {value!r} ({type(value).__name__}); "
                         f"for example {example}")
    if isinstance(value, np.ndarray):
        if value.ndim != 1:
            raise ModelError(f"FlexibleBody: {name} must be a flat list of {what}, got an array of shape "
                             f"{value.shape}")
        items = value.tolist()
    else:
        items = list(value)
    for k, item in enumerate(items):
        if not is_int(item):
            hint = ""
            if isinstance(item, float | np.floating) and float(item).is_integer():
                hint = f" (write {int(item)})"
            elif isinstance(item, str) and item.strip().lstrip("-").isdigit():
                hint = f" (write {int(item)}, without quotes)"
            raise ModelError(f"FlexibleBody: {name}[{k}] is {item!r} ({type(item).__name__}): {name} must be "
                             f"{what}{hint}")
    return [int(i) for i in items]


def frame_nodes(data: ModalData, frames: Any, source: str) -> list[int]:
    """The node ids of the frames: given, else the file's interface nodes; at least one, distinct, in the file."""
    if frames is None:
        nodes = [int(n) for n in data.interface_nodes]
        if not nodes:
            raise ModelError(f"FlexibleBody: no frames: the {source} has no interface nodes ('/interface/node_ids' "
                             f"is empty); pass frames=[node ids] (nodes {int(data.node_ids.min())}.."
                             f"{int(data.node_ids.max())})")
        return nodes
    nodes = _int_list("frames", frames, "a list of node ids (ints)", "frames=[0, 6]")
    if not nodes:
        iface = [int(n) for n in data.interface_nodes]
        raise ModelError(f"FlexibleBody: frames is empty: a flexible body needs at least one frame (frame_a) to be "
                         f"connected; pass node ids, e.g. frames={iface or [int(data.node_ids[0])]}, or leave "
                         f"frames out for the interface nodes of the {source} {iface}")
    if len(set(nodes)) != len(nodes):
        twice = sorted({n for n in nodes if nodes.count(n) > 1})
        raise ModelError(f"FlexibleBody: frames {nodes} name a node twice (node {twice[0]}); each node gets at most "
                         "one frame")
    for node in nodes:
        try:
            data.node_index(node)
        except KeyError:
            raise ModelError(f"FlexibleBody: frames: node {node} is not in the {source} (nodes "
                             f"{int(data.node_ids.min())}..{int(data.node_ids.max())})") from None
    return nodes


def _ratio(where: str, value: Any) -> float:
    """A modal damping ratio: a real number in [0, 1]."""
    accepted = "a modal damping ratio in [0, 1] (a fraction of critical damping: 0.02 for 2 %)"
    if not is_real(value):
        raise ModelError(f"FlexibleBody: {where} must be {accepted}, got {value!r} ({type(value).__name__})")
    v = float(value)
    if not 0.0 <= v <= 1.0:  # NaN fails too
        hint = f" (a percentage? {v:g} % is {v / 100:g})" if 1.0 < v <= 100.0 else ""
        raise ModelError(f"FlexibleBody: {where} must be {accepted}, got {v!r}{hint}")
    return v


def damping_ratios(zeta: np.ndarray, damping: Any) -> np.ndarray:
    """The modal damping ratios of the kept modes: ``zeta`` (file or default rule) with ``damping`` applied."""
    m = zeta.size
    if damping is None:
        return zeta
    if isinstance(damping, np.ndarray) and damping.ndim == 0:
        damping = damping.item()
    if isinstance(damping, Mapping):
        if damping and not m:
            raise ModelError(f"FlexibleBody: damping given for modes {sorted(damping, key=str)}, but no modes are "
                             "kept")
        for mode, value in damping.items():
            if not is_int(mode):
                raise ModelError(f"FlexibleBody: damping: key {mode!r} ({type(mode).__name__}) must be the index "
                                 f"(int) of a kept mode, 0..{m - 1}")
            if not 0 <= mode < m:
                raise ModelError(f"FlexibleBody: damping given for mode {mode}, but {m} modes are kept (indices "
                                 f"0..{m - 1} into the kept modes)")
            zeta[int(mode)] = _ratio(f"damping[{mode}]", value)
        return zeta
    if is_real(damping):
        zeta[:] = _ratio("damping", damping)
        return zeta
    if isinstance(damping, str | bytes) or not isinstance(damping, Sequence | np.ndarray):
        raise ModelError(f"FlexibleBody: damping must be a modal damping ratio for every kept mode (e.g. 0.02), one "
                         f"per kept mode ({m}) or {{mode: ratio}}, got {damping!r} ({type(damping).__name__})")
    values = list(damping.tolist() if isinstance(damping, np.ndarray) else damping)
    nested = any(isinstance(v, Sequence | np.ndarray) and not isinstance(v, str) for v in values)
    if nested or len(values) != m:
        raise ModelError(f"FlexibleBody: damping has {len(values)} {'nested ' if nested else ''}values, but {m} "
                         "modes are kept: give one ratio per kept mode, one number for all, or {mode: ratio}")
    for k, value in enumerate(values):
        zeta[k] = _ratio(f"damping[{k}]", value)
    return zeta


def check_zeta(value: Any, m: int) -> None:
    """``zeta`` given directly: numbers (not text or bools), one per kept mode (the parameter checks the bounds)."""
    items = np.asarray(value, dtype=object).ravel().tolist() if not isinstance(value, str | bytes) else [value]
    for item in items:
        if not is_real(item):
            raise ParameterError(f"FlexibleBody: zeta must be modal damping ratios (numbers in [0, 1]), one per kept "
                                 f"mode ({m}), got {value!r} (an item {item!r} of type {type(item).__name__})")
    if not m and items:
        raise ParameterError(f"FlexibleBody: zeta has {len(items)} values, but no modes are kept (zeta is absent "
                             "for the rigid body)")


def modal_start(kind: str, name: str, value: Any, m: int) -> np.ndarray:
    """A start value of the modal coordinates ``q`` [1] or rates ``qd`` [1/s]: finite numbers, one per kept mode."""
    where = f"FlexibleBody: {kind}[{name!r}]"
    items = [value] if isinstance(value, str | bytes) or np.ndim(value) == 0 else np.asarray(
        value, dtype=object).ravel().tolist()
    for item in items:
        if not is_real(item):
            raise ModelError(f"{where} must be numbers, one per kept mode ({m}), got {value!r} (an item {item!r} of "
                             f"type {type(item).__name__})")
    if np.ndim(value) != 1 or len(items) != m:
        raise ModelError(f"{where} has shape {np.shape(value)}, but {m} modes are kept: give one value per kept "
                         f"mode, e.g. {kind}={{{name!r}: np.zeros({m})}}")
    out = np.array(items, dtype=float)
    if not np.all(np.isfinite(out)):
        raise ModelError(f"{where} has a non-finite value {float(out[~np.isfinite(out)][0])!r} at index "
                         f"{int(np.flatnonzero(~np.isfinite(out))[0])}")
    return out


def choose_modes(data: ModalData, modes: Any, max_frequency: Any, source: str, plane: Any = None) -> ModalData:
    """The kept modes: ``modes`` (None, an int count, a list of indices or a participation table), ``plane`` and
    ``max_frequency`` (module rules)."""
    n = data.n_modes
    if plane is not None:
        try:
            planar = planar_modes(data, plane)
        except RunArgumentError as err:
            raise ModelError(f"FlexibleBody: {str(err).removeprefix('planar_modes: ')}") from None
        if is_int(modes) and not isinstance(modes, bool | np.bool_) and int(modes) > len(planar):
            raise ModelError(f"FlexibleBody: modes={int(modes)} asks for the {int(modes)} lowest modes in the "
                             f"{plane!r} plane, but the {source} has only {len(planar)} ({planar})")
        if modes is None or (is_int(modes) and not isinstance(modes, bool | np.bool_) and int(modes) >= 0):
            count = len(planar) if modes is None else int(modes)
            return choose_modes(data, planar[:count], max_frequency, source)
        raise ModelError(f"FlexibleBody: plane={plane!r} selects among the lowest modes: give modes as a count "
                         f"(e.g. modes=4, plane={plane!r}) or None, got modes={modes!r}")
    if isinstance(modes, ParticipationTable):
        if len(modes.rows) != n:
            raise ModelError(f"FlexibleBody: the participation table has {len(modes.rows)} modes, the {source} {n}: "
                             "make it from this body's modal data (FlexibleBody.participation)")
        modes = modes.kept
    accepted = ("an int count of the lowest modes (e.g. modes=4) or a list of mode indices into the file's "
                f"modes 0..{n - 1} (e.g. modes=[0, 2])")
    if max_frequency is not None:
        if not is_real(max_frequency) or not float(max_frequency) >= 0.0:
            raise ModelError(f"FlexibleBody: max_frequency must be a frequency [Hz] >= 0, got {max_frequency!r} "
                             f"({type(max_frequency).__name__})")
        max_frequency = float(max_frequency)
    idx: list[int] = []
    if modes is None or is_int(modes):
        if modes is not None and int(modes) < 0:
            raise ModelError(f"FlexibleBody: modes must be >= 0, got {modes} (a count of the lowest modes; 0 for the "
                             "rigid body)")
        if modes is not None and int(modes) > n:
            raise ModelError(f"FlexibleBody: modes={int(modes)} asks for the {int(modes)} lowest modes, but the "
                             f"{source} has only {n}")
        if modes is None and max_frequency is None:
            return data
        out = select_modes(data, count=None if modes is None else int(modes), max_frequency=max_frequency)
    else:
        if isinstance(modes, bool | np.bool_):
            raise ModelError(f"FlexibleBody: modes={modes!r} is a bool; modes must be {accepted}")
        if isinstance(modes, str):
            hint = ""
            if modes.strip().isdigit():
                k = int(modes)
                hint = f"; write modes={k} for the {k} lowest modes, or modes=[{k}] for the mode of index {k}"
            raise ModelError(f"FlexibleBody: modes={modes!r} is a string; modes must be {accepted}{hint}")
        if isinstance(modes, float | np.floating):
            hint = f"; write modes={int(modes)}" if float(modes).is_integer() else ""
            raise ModelError(f"FlexibleBody: modes={modes!r} is a float; modes must be {accepted}{hint}")
        idx = _int_list("modes", modes, accepted, "modes=[0, 2]")
        twice = sorted({i for i in idx if idx.count(i) > 1})
        if twice:
            raise ModelError(f"FlexibleBody: modes {idx} name mode {twice[0]} twice; each mode is kept once")
        bad = [i for i in idx if not 0 <= i < n]
        if bad:
            raise ModelError(f"FlexibleBody: modes {bad} are not in the {source} ({n} modes: 0..{n - 1})")
        out = data.select(idx)
        if max_frequency is not None:
            out = select_modes(out, max_frequency=max_frequency)
    rigid_asked = modes is not None and (int(modes) == 0 if is_int(modes) else not idx)
    if max_frequency is not None and n and not out.n_modes and not rigid_asked:
        raise ModelError(f"FlexibleBody: max_frequency={max_frequency:g} Hz keeps no mode of the {source} (lowest "
                         f"{float(data.frequencies.min()):.4g} Hz); pass modes=0 for a rigid body")
    return out


_LETTERS = "abcdefghijklmnopqrstuvwxyz"


def frame_names(n: int) -> list[str]:
    """Connector names of ``n`` frames: ``frame_a``, ``frame_b``, … (``frame_z``, then ``frame_26``, …)."""
    if not is_int(n) or n < 0:
        raise RunArgumentError(f"frame_names: n must be a number of frames (an int >= 0), got {n!r}")
    return [f"frame_{_LETTERS[i]}" if i < len(_LETTERS) else f"frame_{i}" for i in range(n)]
