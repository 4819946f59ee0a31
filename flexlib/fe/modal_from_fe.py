"""Modal data from an FE model: :func:`modal_data_from_fe` reduces it by Craig–Bampton (:mod:`.reduction`) for a
floating body or one attached at a node, and assembles the :class:`~.modal_data.ModalData` — modes per node,
generalised matrices, frequencies, the inertia invariants, section forces and stresses of beam models, geometric
stiffness and static load responses on request, and the provenance of the reduction (SI units).

A body attached at ``reference_node`` is reduced in one of two ways. ``attachment="clamped"``: the reduction runs
on the model clamped there, every mode has zero translation and rotation at the node, and the reference frame
*is* the node's frame (the "tangent frame"). ``attachment="pinned"``: only the node's translations are held, the
three rigid rotations about it are removed (the modes are mass-orthogonal to them: the reference frame turns with
the body's mean rotation about the node, its mean axes), and the node turns elastically. For a body on a hinge,
pinned modes are the hinged body's own modes: the modal equations decouple from the rotation, fewer modes
converge, and the reference frame's angular velocity is the body's gross rotation (what the centrifugal
geometric stiffening needs).
"""

from __future__ import annotations

import datetime as _dt
import math
import numbers
from collections.abc import Sequence
from dataclasses import replace
from typing import Any, Literal

import numpy as np
import scipy.linalg as la

from flexlib.core.values import as_bool
from flexlib.errors import ModalFileError, RunArgumentError

from .arguments import is_int
from .beam import beam_stress_modes, section_force_modes
from .fe_model import FEModel, UnknownNodeError
from .geometric import inertial_load_cases, interface_load_cases, modal_geometric_stiffness
from .invariants import inertia_invariants
from .matrix_checks import check_translational_mass
from .modal_data import ModalData
from .reduction import (
    RIGID_NAMES,
    CraigBamptonResult,
    ReductionMessages,
    craig_bampton_named,
    elastic_static_responses,
    rotations_about,
)

__all__ = ["modal_data_from_fe"]


def modal_data_from_fe(fe: FEModel, interface_nodes: Sequence[int], n_modes: int, *, free: bool = True,
                       orthogonalize: bool = True, title: str = "", creator: str = "flexlib",
                       damping_ratio: np.ndarray | None = None,
                       stress_fibre: tuple[float, float] | None = None,
                       geometric_stiffening: bool = False, support_nodes: Sequence[int] | None = None,
                       reference_node: int | None = None,
                       attachment: Literal["clamped", "pinned"] = "clamped", static_loads: bool = True) -> Any:
    """Reduce an FE model by Craig–Bampton and assemble a :class:`ModalData` (modes per node, generalised
    matrices, frequencies, the nine inertia invariants, body properties and provenance).

    Parameters
    ----------
    fe : FEModel
        FE matrices with node coordinates [m] and DOF map.
    interface_nodes : sequence of int
        Node ids whose six (or fewer) DOFs are the interface (the flexible body's frames).
    n_modes : int
        Number of fixed-interface normal modes.
    free : bool
        The body is unconstrained (floating frame): its six rigid-body modes are removed.
    orthogonalize : bool
        Improved Craig–Bampton (orthonormal modes) rather than the raw basis.
    title, creator : str
        Header text of the modal file.
    damping_ratio : ndarray, optional
        Modal damping ratios [1] per mode of the result, each a fraction of critical damping in ``[0, 1]``;
        default: the frequency rule of
        :func:`~flexlib.fe.selection.default_damping_ratio` when used.
    stress_fibre : (float, float), optional
        Beam models: section fibre ``(y, z)`` [m] at which stress modes are recovered
        (:func:`~flexlib.fe.beam.beam_stress_modes`); beam models always get their
        section-force modes.
    geometric_stiffening : bool
        Beam models: add the modal geometric stiffness of the inertial and interface unit load cases
        (:func:`~flexlib.fe.geometric.modal_geometric_stiffness`).
    support_nodes : sequence of int, optional
        With ``geometric_stiffening``: nodes held for its static load cases; default the first interface node (the
        reference node if given).
    reference_node : int, optional
        Attach the body's reference frame to this node (attached modes). The node becomes the first interface
        node and ``free`` does not apply; the other interface nodes give the constraint (static) modes, as in
        Craig–Bampton. Default: a floating reference frame (``free``).
    attachment : {"clamped", "pinned"}
        With ``reference_node``: the node clamped (the reference frame is the node's frame) or pinned (its
        translations held, the rigid rotations about it removed: the frame follows the body's mean axes); see
        the module docstring.
    static_loads : bool
        Store the body's exact elastic static response to the unit load cases (inertial: ``acc_*``,
        ``alpha_*``, ``omega_**``; interface: ``F{node}_{ux..rz}``) with their modal loads, so that outputs can be
        recovered by the mode-acceleration method (:meth:`ModalData.residual_fields`).

    Returns
    -------
    ModalData
        Body properties from the mass description: mass = I1 [kg], centre of mass = I2 / I1 [m], inertia about
        the body-frame origin = I7 [kg m2].

    Raises
    ------
    RunArgumentError
        An argument that is not what is accepted, named: ``fe`` not an FEModel; a flag not a bool; ``title`` or
        ``creator`` not a string; node ids that are not whole numbers or not in the model (``reference_node`` one
        id); ``n_modes`` not a whole number in range; ``attachment`` not one of its choices, or ``"pinned"``
        without ``reference_node``; ``support_nodes`` without ``geometric_stiffening``; ``stress_fibre`` not two
        numbers; ``damping_ratio`` not one ratio in ``[0, 1]`` per mode; an FE model that cannot be reduced as
        asked (its mass matrix without mass in a rigid translation, an interface that does not hold it, ...).
        For a model read from a file its faults are a :class:`~flexlib.errors.ModalFileError` naming the file.
    """
    _check_options(fe, free, orthogonalize, geometric_stiffening, static_loads, title, creator, stress_fibre)
    interface_nodes, support_nodes = _check_nodes(fe, interface_nodes, n_modes, attachment, reference_node,
                                                  support_nodes, geometric_stiffening)
    held, rigid, interface_nodes, reference_node = _attached(fe, interface_nodes, free, reference_node, attachment)
    names = _messages(held, fe, free and reference_node is None, reference_node, attachment)
    cb = craig_bampton_named(held.M, held.K, held.dofs(interface_nodes), n_modes, rigid, orthogonalize, names)
    _check_reduced(cb, rigid, orthogonalize, reference_node, names)
    settings = {"orthogonalize": orthogonalize, "n_modes": int(n_modes), "reference_node": reference_node,
                "attachment": attachment, "stress_fibre": stress_fibre, "support_nodes": support_nodes,
                "geometric_stiffening": geometric_stiffening, "static_loads": static_loads,
                "free": free and reference_node is None, "damping_ratio": damping_ratio}
    return _assembled(held, cb, interface_nodes, rigid, settings, title, creator)


def _check_nodes(fe: FEModel, interface_nodes: Any, n_modes: Any, attachment: Any, reference_node: Any,
                 support_nodes: Any, geometric_stiffening: bool) -> tuple[list[int], list[int] | None]:
    """The interface and support node ids checked (with ``n_modes`` and the attachment), and a mass matrix that
    carries mass in every rigid translation."""
    func = "modal_data_from_fe"
    interface_nodes = _node_ids(fe, interface_nodes, "interface_nodes")
    if not is_int(n_modes) or n_modes < 0:
        raise RunArgumentError(f"{func}: n_modes must be a whole number >= 0, got {n_modes!r}")
    if attachment not in ("clamped", "pinned"):
        raise RunArgumentError(f"{func}: attachment must be 'clamped' or 'pinned', got {attachment!r}")
    if attachment == "pinned" and reference_node is None:
        raise RunArgumentError(f"{func}: attachment='pinned' says how the reference frame is attached at "
                               "reference_node, which is not given: pass reference_node=<the pin node> (a floating "
                               "body, free=True, has no attachment)")
    if support_nodes is not None:
        if not geometric_stiffening:
            raise RunArgumentError(f"{func}: support_nodes={support_nodes!r} hold the body for the geometric "
                                   "stiffness load cases, which are computed only with geometric_stiffening=True")
        support_nodes = _node_ids(fe, support_nodes, "support_nodes")
    why = check_translational_mass(fe.M, fe.dof_map)
    if why is not None:
        raise (ModalFileError if fe.from_file else RunArgumentError)(f"{func}: {fe.source_label('M')}: {why}")
    return interface_nodes, support_nodes


def _assembled(fe: FEModel, cb: CraigBamptonResult, interface_nodes: list[int], rigid: np.ndarray | None,
               settings: dict[str, Any], title: str, creator: str) -> ModalData:
    """The :class:`ModalData` of a reduction ``cb`` of ``fe``: modes per node, invariants and body properties,
    beam section forces and stresses, geometric stiffness and static load data as ``settings`` ask, the damping
    ratios checked, provenance."""
    stress_fibre, damping_ratio = settings["stress_fibre"], settings["damping_ratio"]
    if damping_ratio is not None:
        damping_ratio = _damping_argument(damping_ratio, cb.omega.size)
    points = fe.mass_points if fe.mass_points is not None else fe.lumped_mass_points()
    inv = inertia_invariants(points, cb.modes)
    geometric, support = None, None
    if settings["geometric_stiffening"]:
        support = list(interface_nodes[:1] if settings["support_nodes"] is None else settings["support_nodes"])
        if not support:
            raise RunArgumentError("modal_data_from_fe: geometric_stiffening needs a support node (no interface "
                                   "nodes and no support_nodes)")
        cases = inertial_load_cases(fe) | interface_load_cases(fe, [k for k in interface_nodes if k not in support])
        geometric = modal_geometric_stiffness(fe, cb.modes, support, cases)
    trans, rot = fe.nodal_fields(cb.modes)
    static = (_static_load_data(fe, cb, interface_nodes, rigid, settings["free"], stress_fibre)
              if settings["static_loads"] else {})
    reference_node = settings["reference_node"]
    provenance = {
        "method": "improved Craig-Bampton (orthonormalised)" if settings["orthogonalize"] else "Craig-Bampton",
        "interface_nodes": interface_nodes,
        "n_interface_dofs": int(fe.dofs(interface_nodes).size),
        "n_fixed_interface_modes": settings["n_modes"],
        "fixed_interface_frequencies_Hz": [float(x) for x in cb.fixed_interface_omega / (2 * math.pi)],
        "n_rigid_modes_removed": int(cb.n_rigid_removed),
        "n_massless_dofs_condensed": int(cb.massless_dofs.size),
        "n_massless_reduced_directions_condensed": int(cb.n_massless_condensed),
        "reference_node": reference_node,
        "attachment": None if reference_node is None else settings["attachment"],
        "n_fe_dofs": int(fe.n_dofs),
        "mass_description": points.description,
        "fe": fe.info,
        "stress_fibre_m": None if stress_fibre is None else [float(v) for v in stress_fibre],
        "geometric_stiffness_support_nodes": None if geometric is None else [int(k) for k in support],
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    return ModalData(
        title=title, creator=creator, mass=float(inv["I1"]), center_of_mass=inv["I2"] / inv["I1"],
        inertia=inv["I7"], node_ids=fe.node_ids, coordinates=fe.nodes, elements=fe.elements,
        interface_nodes=np.asarray(interface_nodes, dtype=np.int64), translational_modes=trans,
        rotational_modes=rot, generalized_mass=cb.generalized_mass, generalized_stiffness=cb.generalized_stiffness,
        frequencies=cb.frequencies, invariants=inv, mass_description=points.description.split(" ")[0],
        damping_ratio=damping_ratio, provenance=provenance,
        section_forces=None if fe.beam is None else section_force_modes(fe, cb.modes),
        stress_modes=None if stress_fibre is None else beam_stress_modes(fe, cb.modes, stress_fibre),
        geometric_stiffness=geometric, **static)


def _check_options(fe: Any, free: Any, orthogonalize: Any, geometric_stiffening: Any, static_loads: Any,
                   title: Any, creator: Any, stress_fibre: Any) -> None:
    """The arguments of :func:`modal_data_from_fe` that need no reduction: ``fe`` an FEModel, the flags bools,
    the header texts strings, ``stress_fibre`` two finite numbers (of a beam model)."""
    func = "modal_data_from_fe"
    if not isinstance(fe, FEModel):
        raise RunArgumentError(f"{func}: argument 'fe' must be an FEModel (from beam_mesh, read_fe, "
                               f"read_matrix_market or an importer), got {type(fe).__name__} {fe!r:.80}")
    flags = (("free", free), ("orthogonalize", orthogonalize), ("geometric_stiffening", geometric_stiffening),
             ("static_loads", static_loads))
    for flag, value in flags:
        as_bool(value, f"{func}: argument {flag!r}", RunArgumentError, ints=False)
    for arg, text in (("title", title), ("creator", creator)):
        if not isinstance(text, str):
            raise RunArgumentError(f"{func}: argument {arg!r} must be a string (header text of the modal file), got "
                                   f"{type(text).__name__} {text!r}")
    if (stress_fibre is not None or geometric_stiffening) and fe.beam is None:
        raise RunArgumentError(f"{func}: stress_fibre and geometric_stiffening need a beam model (beam_mesh)")
    if stress_fibre is not None:
        items = [stress_fibre] if isinstance(stress_fibre, str | bytes) or np.ndim(stress_fibre) == 0 else \
            np.asarray(stress_fibre, dtype=object).ravel().tolist()
        numeric = all(isinstance(v, numbers.Real) and not isinstance(v, bool | np.bool_) for v in items)
        fibre = np.asarray(items, dtype=float) if numeric else np.zeros(0)
        if np.shape(stress_fibre) != (2,) or fibre.shape != (2,) or not np.all(np.isfinite(fibre)):
            raise RunArgumentError(f"{func}: argument 'stress_fibre' must be two finite numbers (y, z) [m], got "
                                   f"{stress_fibre!r}")


def _attached(fe: FEModel, interface_nodes: list[int], free: bool, reference_node: Any,
              attachment: str) -> tuple[FEModel, np.ndarray | None, list[int], int | None]:
    """The model the reduction runs on, its rigid-body fields, the interface nodes (the reference node first) and
    the reference node's id, for a floating body or one attached at ``reference_node``."""
    func = "modal_data_from_fe"
    rigid = fe.rigid_body_modes() if free else None
    if reference_node is not None:
        reference_node = _node_ids(fe, [reference_node], "reference_node", scalar=True)[0]
        centre = fe.nodes[fe.node_index([reference_node])[0]]
        if fe.mass_points is None:  # lumped from the whole M: the held node's mass stays in the invariants
            fe = replace(fe, mass_points=fe.lumped_mass_points())
        if attachment == "clamped":
            fe = fe.constrained([reference_node])
            rigid = None
        else:
            fe = fe.constrained([reference_node], ("ux", "uy", "uz"))
            rigid = rotations_about(fe, centre)
        interface_nodes = [reference_node] + [k for k in interface_nodes if k != reference_node]
    elif free and not interface_nodes:
        raise RunArgumentError(f"{func}: interface_nodes is empty, but a free body (free=True) needs interface nodes "
                               "that fix its rigid-body motion for the Craig–Bampton constraint modes (one node with "
                               "its six DOFs, or three nodes not on a line); give interface_nodes, or attach the body "
                               "with reference_node=")
    return fe, rigid, interface_nodes, reference_node


def _messages(fe: FEModel, given: FEModel, free: bool, reference_node: int | None,
              attachment: str) -> ReductionMessages:
    """How the reduction's errors name things: the node, component and row of the model as ``given`` (before any
    attachment constraint), its file or producer, the rigid modes and the hints for this attachment."""
    rigid_names, rigid_hint = RIGID_NAMES, "pass free=False"
    if reference_node is not None and attachment == "pinned":
        rigid_names = tuple(f"rotation about {a} through node {reference_node}" for a in "xyz")
        rigid_hint = "use attachment='clamped'"
    has = fe.dof_map >= 0
    given_row = np.full(fe.n_dofs, -1, dtype=np.int64)
    given_row[fe.dof_map[has]] = given.dof_map[has]
    return ReductionMessages(func="modal_data_from_fe", label=lambda row: given.dof_label(int(given_row[int(row)])),
                             source=lambda m: fe.source_label(m),
                             error=ModalFileError if fe.from_file else RunArgumentError,
                             interface="interface_nodes" + (f" (with reference_node {reference_node})"
                                                            if reference_node is not None else ""),
                             rigid_names=rigid_names, rigid_hint=rigid_hint,
                             hold_hint="pass free=True for a floating body, or reference_node=" if not free and
                             reference_node is None else "hold the body (reference_node=)")


def _check_reduced(cb: CraigBamptonResult, rigid: np.ndarray | None, orthogonalize: bool,
                   reference_node: int | None, names: ReductionMessages) -> None:
    """The reduced modes carry mass (the raw basis) and, for a held body, stiffness in every mode."""
    func = names.func
    if not orthogonalize:
        e, U = la.eigh(cb.generalized_mass)
        if e.size and e.min() <= 1e-12 * max(float(e.max()), 1e-300):
            raise RunArgumentError(f"{func}: orthogonalize=False keeps the raw Craig–Bampton basis, and a combination "
                                   f"of its modes carries no mass (moving most at {names.largest(cb.modes @ U[:, 0])}: "
                                   "interface DOFs without mass whose constraint modes move no mass, e.g. rotations of "
                                   "a lumped mass without rotary inertia); pass orthogonalize=True, which condenses "
                                   "them statically")
    if rigid is None and orthogonalize and cb.omega.size:
        top = float(np.max(cb.omega)) ** 2
        zero = np.flatnonzero(cb.omega**2 <= 1e-10 * top)
        if zero.size:
            raise RunArgumentError(f"{func}: {zero.size} mode(s) have zero frequency (omega^2 <= 1e-10 x the "
                                   f"largest), moving most at {names.largest(cb.modes[:, zero[0]])}: the FE model is "
                                   "not held, but " + ("free=False: pass free=True (floating frame) or "
                                                       "reference_node=" if reference_node is None else
                                                       f"attached at node {reference_node} it still has a "
                                                       "mechanism"))


def _static_load_data(fe: FEModel, cb: CraigBamptonResult, interface_nodes: list[int], rigid: np.ndarray | None,
                      free: bool, stress_fibre: Any) -> dict[str, Any]:
    """The body's exact elastic static responses to its unit load cases (inertial and interface), with their modal
    loads, section forces and stresses: the ``ModalData`` fields of mode-acceleration recovery."""
    cases = inertial_load_cases(fe) | interface_load_cases(fe, interface_nodes)
    names = list(cases)
    loads = np.column_stack([cases[k] for k in names])
    try:
        u = elastic_static_responses(fe, loads, rigid)
    except RunArgumentError as exc:
        raise RunArgumentError(f"modal_data_from_fe: {exc}; free={free}" + (": pass free=True (floating frame) or "
                                                                           "reference_node=" if not free else "")
                               ) from None
    s_trans, s_rot = fe.nodal_fields(u)
    return {"load_cases": tuple(names), "static_translations": s_trans, "static_rotations": s_rot,
            "static_modal_loads": loads.T @ cb.modes,
            "static_section_forces": None if fe.beam is None else section_force_modes(fe, u),
            "static_stress": None if stress_fibre is None else beam_stress_modes(fe, u, stress_fibre)}


def _damping_argument(value: Any, m: int) -> np.ndarray:
    """``damping_ratio`` of :func:`modal_data_from_fe`: one ratio in [0, 1] (a number, not text or a bool) per mode."""
    func = "modal_data_from_fe"
    accepted = (f"one modal damping ratio per mode ({m} modes), each a fraction of critical damping in [0, 1] "
                "(0.02 for 2 %)")
    if isinstance(value, str | bytes) or np.ndim(value) == 0:
        hint = (f"; for the same ratio on every mode pass np.full({m}, {value!r}), or leave the file's ratios to "
                f"the default rule and give FlexibleBody(..., damping={value!r})") if isinstance(
            value, numbers.Real) and not isinstance(value, bool | np.bool_) else ""
        raise RunArgumentError(f"{func}: argument 'damping_ratio' must be {accepted}, got {value!r}{hint}")
    items = np.asarray(value, dtype=object).ravel().tolist()
    for k, v in enumerate(items):
        if not isinstance(v, numbers.Real) or isinstance(v, bool | np.bool_) or not 0.0 <= float(v) <= 1.0:
            pct = isinstance(v, numbers.Real) and not isinstance(v, bool | np.bool_) and 1.0 < float(v) <= 100.0
            raise RunArgumentError(f"{func}: argument 'damping_ratio'[{k}] is {v!r}: damping_ratio must be "
                                   f"{accepted}" + (f" (a percentage? {float(v):g} % is {float(v) / 100:g})"
                                                    if pct else ""))
    if np.ndim(value) != 1 or len(items) != m:
        raise RunArgumentError(f"{func}: argument 'damping_ratio' has shape {np.shape(value)}, but the reduction "
                               f"gives {m} modes: give {accepted}")
    return np.asarray(items, dtype=float)


def _node_ids(fe: FEModel, value: Any, argument: str, scalar: bool = False) -> list[int]:
    """Node ids given as an argument: whole numbers (not bools or strings), distinct, all in the FE model."""
    func = "modal_data_from_fe"
    if scalar and len(value) == 1 and (isinstance(value[0], Sequence | np.ndarray | range) and
                                       not isinstance(value[0], str | bytes)):
        raise RunArgumentError(f"{func}: argument {argument!r} must be one node id (an int), got {value[0]!r}")
    if isinstance(value, str | bytes) or (not scalar and is_int(value)) or \
            (not scalar and not isinstance(value, Sequence | np.ndarray | range)):
        raise RunArgumentError(f"{func}: argument {argument!r} must be a list of node ids, got {value!r}"
                               + (f" (for one node: [{value}])" if is_int(value) else ""))
    ids = []
    for v in np.asarray(value, dtype=object).ravel():
        if is_int(v) or (isinstance(v, float | np.floating) and float(v).is_integer()):
            ids.append(int(v))
        else:
            raise RunArgumentError(f"{func}: argument {argument!r}: node id {v!r} is not a whole number")
    seen = set()
    for k in ids:
        if k in seen:
            raise RunArgumentError(f"{func}: argument {argument!r} gives node {k} more than once ({ids})")
        seen.add(k)
    known = set(int(k) for k in fe.node_ids)
    missing = [k for k in ids if k not in known]
    if missing:
        raise UnknownNodeError(f"{func}: argument {argument!r}: node {missing[0]} is not in the FE model ("
                               f"{fe.node_ids.size} nodes, ids {int(fe.node_ids.min())}..{int(fe.node_ids.max())}, "
                               f"{fe.source_label()})")
    return ids
