"""Reading a :class:`~.body.FlexibleBody` back from a run: the checks that a result holds the body as built, the
World's gravity of the run, the cut loads at its frames as amplitudes of the interface unit load cases, and the
exact rotation of a frame from its node's elastic rotation vector (SI units)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from flexlib.errors import (
    EmptyResultError,
    IndeterminateReactionWarning,
    ModalDataWarning,
    ModalFileError,
    ModelError,
    RunArgumentError,
)
from flexlib.fe.arguments import COMPONENTS

from ..multibody.world import World
from .arguments import frame_names

__all__ = ["advise_basis", "cayley_rotation", "check_result", "frame_load_amplitudes", "participation",
           "prefetch_body", "result_gravity"]


def check_result(body: Any, result: Any, func: str, source: str) -> int:
        """The number of rows of ``result``, after checking it holds this body as built: its modal coordinates
        (as many as the body keeps) and its frames."""
        from flexlib.results.result import Result

        where = f"{body.where}.{func}"
        if not isinstance(result, Result):
            raise RunArgumentError(f"{where}: argument 'result' must be a flexlib Result (of Simulation.run or "
                                   f"Result.load), got {type(result).__name__}")
        if not body.path:
            raise RunArgumentError(f"{where}: this FlexibleBody is not part of a model; use the body of the model "
                                   f"that made the result of {result.model}")
        prefix = f"{body.path}."
        own = [n for n in result.names if n.startswith(prefix)]
        if not own:
            raise RunArgumentError(f"{where}: the result of {result.model} holds no variables of {body.path} "
                                   f"({prefix}*): it belongs to another model")
        n_q = sum(1 for n in own if n == f"{prefix}q" or n.startswith(f"{prefix}q["))
        if n_q != body.n_modes:
            raise RunArgumentError(f"{where}: the result of {result.model} holds {n_q} modal coordinates for "
                                   f"{body.path} ({prefix}q), but the body has {body.n_modes} (modes kept from the "
                                   f"{source}): the result belongs to another model (another build of "
                                   "this body); use the body of the model that made it")
        held = {n[len(prefix):].split(".")[0] for n in own if n.startswith(f"{prefix}frame_")}
        names = frame_names(len(body.frame_nodes))
        if set(names) != held:
            raise RunArgumentError(f"{where}: the result of {result.model} holds the frames {sorted(held)} of "
                                   f"{body.path}, but the body has {names} (at nodes {list(body.frame_nodes)}): "
                                   "the result belongs to another model")
        nt = int(np.size(result.t))
        if not nt:
            raise EmptyResultError(f"{where}: the result of {result.model} has no rows; the run is "
                                   f"{result.status}" + (f" ({result.message})" if result.message else ""))
        return nt


def frame_load_amplitudes(body: Any, result: Any, T: np.ndarray) -> dict[str, np.ndarray]:
    """Amplitudes ``F{node}_{component}`` of the interface unit load cases over a result: the cut force [N] and
    torque [N m] on ``body`` at each frame's node, in body axes (``T`` (nt, 3, 3): world to body); a frame at a node
    the modal data hold no static responses for, and that carries load, is a
    :class:`~flexlib.errors.ModalFileError`."""
    d = body.modal_data
    nt = T.shape[0]
    values: dict[str, np.ndarray] = {}
    for node, frame in zip(body.frame_nodes, frame_names(len(body.frame_nodes)), strict=True):
        Tf = np.asarray(result[f"{body.path}.{frame}.T"], dtype=float).reshape(nt, 3, 3, order="F")
        to_body = np.einsum("kij,klj->kil", T, Tf)  # T_body T_frame^T = T_rel^T
        for kind, offset in (("f", 0), ("t", 3)):
            with warnings.catch_warnings():  # a rigid rest of a loop may leave components indeterminate (zero):
                warnings.simplefilter("ignore", IndeterminateReactionWarning)  # the body takes them as the run has
                cut = result[f"{body.path}.{frame}.{kind}"]
            load = np.einsum("kij,kj->ki", to_body, np.asarray(cut, dtype=float).reshape(nt, 3))
            for i in range(3):
                values[f"F{node}_{COMPONENTS[offset + i]}"] = load[:, i]
    carried = {int(k) for k in d.interface_nodes}  # the reduction made load cases for all their free DOFs
    for node, frame in zip(body.frame_nodes, frame_names(len(body.frame_nodes)), strict=True):
        if node not in carried and np.abs(np.column_stack(
                [values[f"F{node}_{c}"] for c in COMPONENTS])).max(initial=0.0) > 0.0:
            raise ModalFileError(f"{body.path}.{frame}: loads at node {node}, but the modal data {d.title!r} "
                                 f"hold no static responses for loads there (its load cases cover the interface "
                                 f"nodes {sorted(carried)}): make node {node} an interface node of the "
                                 "reduction for mode-acceleration recovery")
    return values


def cayley_rotation(theta: np.ndarray) -> np.ndarray:
    """The exact rotation ``T_rel`` (body → node axes) a frame gets from its node's elastic rotation vector.

    The Cayley map of ``a = theta / 2``: ``T_rel = I + 2 (A² − A) / (1 + |a|²)`` with ``A = [a×]``; orthogonal
    for any ``theta`` and ``I − [theta×]`` to first order (the frame equations of :class:`~.body.FlexibleBody`).

    Parameters
    ----------
    theta : ndarray (..., 3)
        Small-rotation vectors [rad] in body axes.

    Returns
    -------
    ndarray (..., 3, 3)
    """
    try:
        bad = isinstance(theta, str | bytes) or np.asarray(theta).dtype.kind not in "iuf"
    except (TypeError, ValueError):
        bad = True
    if bad or np.ndim(theta) == 0 or np.shape(theta)[-1] != 3 or not np.all(np.isfinite(theta)):
        raise RunArgumentError(f"cayley_rotation: argument 'theta' must be finite rotation vectors (..., 3) [rad], got "
                               f"{type(theta).__name__} of shape {np.shape(theta)}: {theta!r:.60}")
    a = np.asarray(theta, dtype=float) / 2
    A = np.zeros((*a.shape[:-1], 3, 3))
    A[..., 0, 1], A[..., 0, 2], A[..., 1, 2] = -a[..., 2], a[..., 1], -a[..., 0]
    A -= np.swapaxes(A, -1, -2)
    k = (2 / (1 + np.einsum("...a,...a->...", a, a)))[..., None, None]
    return np.eye(3) + k * (A @ A - A)


def result_gravity(body: Any, result: Any) -> np.ndarray:
    """The World's gravity vector [m/s2] used in ``result`` (its recorded parameters, else the model's)."""
    worlds = [n for n in body.root.walk() if isinstance(n, World)]
    if len(worlds) != 1:
        raise ModelError(f"{body.path}: the model needs exactly one World (found {len(worlds)})")
    world = worlds[0]
    params = getattr(result, "parameters", {}) or {}

    def value(name: str, shape: int | None) -> np.ndarray:
        default = np.asarray(world.parameter_value(name), dtype=float)
        if shape is None:
            key = f"{world.path}.{name}"
            return np.asarray(params[key][0], dtype=float) if key in params else default
        keys = [f"{world.path}.{name}[{i}]" for i in range(shape)]
        return np.array([params[k][0] for k in keys], dtype=float) if all(k in params for k in keys) else default

    g, n = float(value("g", None)), value("n", 3)
    return g * n / np.linalg.norm(n)


def participation(body: Any, all_modes: Any, amplitudes: np.ndarray, t: np.ndarray, threshold: float,
                  at: float | None) -> Any:
    """The MPF table of the file's modes ``all_modes`` from the body's load-case ``amplitudes`` (nt, C) at times
    ``t``: at the run's most critical instant (``at=None``: the row whose loads give the largest static modal
    response ``Σ (φ_iᵀF/k_i)²`` over all the file's modes) or at the row nearest ``at`` [s] (seed 001 takes the
    instant of the largest loads of its rigid-body run)."""
    from flexlib.fe.selection import participation_from_load_cases

    where = f"{body.where}.participation"
    if all_modes.load_cases is None or all_modes.static_modal_loads is None:
        raise ModalFileError(f"{where}: the modal data hold no static load responses (make them with "
                             "modal_data_from_fe(..., static_loads=True)): the body's loads cannot be projected")
    if at is None:
        k = np.diag(np.asarray(all_modes.generalized_stiffness, dtype=float))
        static = (amplitudes @ all_modes.static_modal_loads) / np.where(k > 0, k, np.inf)
        row = int(np.argmax(np.sum(static**2, axis=1)))
    else:
        if isinstance(at, bool) or not isinstance(at, int | float | np.integer | np.floating) or not np.isfinite(at):
            raise RunArgumentError(f"{where}: at must be a time [s] of the run or None (its most critical instant), "
                                   f"got {at!r}")
        if not t[0] <= float(at) <= t[-1]:
            raise RunArgumentError(f"{where}: at = {at!r} s lies outside the run ({t[0]:g} … {t[-1]:g} s)")
        row = int(np.argmin(np.abs(t - float(at))))
    return participation_from_load_cases(all_modes, amplitudes[row], threshold=threshold)


def advise_basis(body: Any, source: str) -> None:
    """Warn (:class:`~flexlib.errors.ModalDataWarning`, naming the body, the joint and the pinned attachment) when the
    body's clamped-basis reference node sits on a revolute joint that is free about its axis.

    The modal data's basis is clamped (``modal_data_from_fe(..., attachment="clamped")``, the default) at its
    reference node when the node's frame is connected to a ``Revolute``'s frame and to nothing else (a hub body or
    another link on the same frame can take a moment), and the revolute takes no moment about its axis from a
    position: no drive flange, or a flange that only torque sources, dampers and sensors act on (the seed-001 beam's
    bang-bang torque). There the body's own deformation has a slope at the pin that cantilever modes lack;
    hinged-beam modes (``attachment="pinned"``) have it.
    """
    from ..multibody.revolute import Revolute
    from ..rotational.damper import Damper
    from ..rotational.interfaces import PartialAbsoluteSensor, PartialRelativeSensor
    from ..rotational.torque import Torque
    from ..rotational.torque_sensor import TorqueSensor

    provenance = body.modal_data.provenance
    node = provenance.get("reference_node")
    if provenance.get("attachment") != "clamped" or node is None or int(node) not in body.frame_nodes:
        return
    passive = (Torque, Damper, PartialAbsoluteSensor, PartialRelativeSensor, TorqueSensor)
    members = body.frame_at(int(node)).connection_set()
    if len(members) != 1 or not isinstance(members[0]._parent, Revolute):
        return  # another part on the same frame (a hub, a link, a bushing) can take the moment
    joint = members[0]._parent
    axis = joint.axis if joint.use_axis_flange else None
    if axis is None or all(isinstance(c._parent, passive) for c in axis.connection_set()):
        warnings.warn(ModalDataWarning(
            f"{body.where}: the {source} has a clamped basis at its reference node {node}, which sits on the "
            f"free revolute {joint.where} (no moment about its axis): cantilever modes fit a hinged body poorly "
            "(the seed-001 beam's deflection error 12 % instead of 1.5 % with 4 modes); make the data with "
            "modal_data_from_fe(..., attachment='pinned')"), stacklevel=4)


def prefetch_body(body: Any, result: Any) -> None:
    """Evaluate the variables a body's outputs read from ``result`` (its modal coordinates, reference motion and
    frames' orientations and cut loads) in one pass over the rows: a run's result derives them from its stored
    unknowns, column by column otherwise (70 passes for the pump truck's five sections: 4 s instead of 0.3 s)."""
    prefetch = getattr(result, "prefetch", None)
    if prefetch is None or not body.path:
        return
    # every modal body of the model at once: the first body's call makes the one pass, the others find their columns
    names = []
    for node in body.root.walk():
        if type(node) is type(body) and node.path:
            p = f"{node.path}."
            names += [f"{p}q", f"{p}r_0", f"{p}a_0", f"{p}w", f"{p}z"]
            names += [f"{p}{f}.{x}" for f in frame_names(len(node.frame_nodes)) for x in ("T", "f", "t")]
    prefetch(*names)
