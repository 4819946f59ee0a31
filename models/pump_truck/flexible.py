"""Flexible boom sections: each section's beam mesh, its Craig–Bampton modal data, and modal files cached by content.

A section ``j`` (1–N, N = 4 … 6 the record's sections; the 42 m boom's 1–5) is a uniform steel box (the record's
``b``, ``h`` and wall thickness) meshed along its axis by :func:`~flexlib.fe.beam_mesh` from its root pin (x = 0) to
the next pin (x = length), with nodes at every station where something attaches (:func:`attachment_points`). The
delivery pipe rides on top as non-structural mass: point masses on the nodes (each node's share of ``mass_per_m``
times its tributary length), offset ``h/2 + pipe.offset`` above the axis
(:meth:`~flexlib.fe.FEModel.with_point_masses`; Nastran's ``CONM2``); its mass, centre
of mass and inertia are those of :func:`models.pump_truck.statics.mass_properties` (the pipe lumped at the nodes).
The end hose is a point mass at the last section's tip pin, as in the rigid model.
The reduction is Craig–Bampton with the attachment nodes as interface
(their static constraint modes) plus fixed-interface normal modes, orthonormalised, with the reference frame
pinned at the root (the hinged section's own modes: the frame carries the rotation about the root pin), and the
static load responses for mode-acceleration recovery.

Attachment points (section frame: origin at the root pin, ``x`` to the next pin, ``y`` up when horizontal) come
from the record: the drive bracket ``c`` of the section's own joint (joint 1: direct cylinder; 2–N: the link's
bracket), and on sections 1 … N−1 the next joint's lever pivot ``P`` and cylinder housing ``H`` (given in that
joint's frame, whose origin is this section's tip). Points off the axis — or beyond its ends, like a link bracket
on a horn behind the root pin — are reached from the nearest axis node (the station, clamped to the section) by a
rigid offset in the model (``FixedTranslation``), as a stiff bracket would carry them.

References
----------
R. R. Craig, M. C. C. Bampton, *AIAA J.* 6 (1968) 1313–1319; seed 000 (the boom's flexible sections
as Craig–Bampton bodies); MSC Nastran Quick Reference Guide, ``CONM2`` (offset concentrated mass).
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.errors import IndeterminateReactionWarning
from flexlib.fe import FEModel, ModalData, beam_mesh, box, modal_data_from_fe
from flexlib.fe.geometric import inertial_load_amplitudes

from .parameters import PumpTruckParameters

__all__ = ["MPF_POSES_DEG", "PIN_POINTS", "attachment_points", "mpf_modes", "rigid_section_loads", "section_fe",
           "section_modal_data", "static_section_loads", "unfolding_poses"]

#: Default number of beam elements per section.
N_ELEMENTS = 48
#: Fixed-interface normal modes of the reduction (the kept modes are chosen from the reduced set).
N_FIXED_MODES = 12


def attachment_points(record: PumpTruckParameters, j: int) -> dict[str, tuple[float, float]]:
    """Where section ``j`` (1–N) carries pins, in its section frame [m].

    Returns
    -------
    dict
        ``root`` (its own joint's pin, the origin), ``bracket`` (its own drive's bracket ``c``), ``tip`` (the next
        joint's pin, or the hose hanger on the last section N) and, on sections 1 … N−1, ``lever_pivot`` and
        ``housing`` of the next joint's lever-and-link drive.
    """
    N = record.n_sections
    if not 1 <= j <= N:
        raise ValueError(f"attachment_points: section number must be 1..{N}, got {j!r}")
    L = record.sections[j - 1].length
    points = {"root": (0.0, 0.0), "bracket": tuple(float(v) for v in record.drive(j).c), "tip": (L, 0.0)}
    if j < N:
        nxt = record.drive(j + 1)
        points["lever_pivot"] = (L + float(nxt.P[0]), float(nxt.P[1]))
        points["housing"] = (L + float(nxt.H[0]), float(nxt.H[1]))
    return points


def station_node(x: np.ndarray, node_ids: np.ndarray, position: float, length: float) -> int:
    """Id of the node at the station of an attachment at ``position`` [m] along the axis (the nearest of the
    nodes at ``x`` [m]; a point beyond an end belongs to the end node)."""
    return int(node_ids[np.argmin(np.abs(x - min(max(position, 0.0), length)))])


def section_fe(record: PumpTruckParameters, j: int, n_elements: int = N_ELEMENTS) -> tuple[FEModel, dict[str, int]]:
    """Beam FE model of section ``j`` (1–N) with its pipe as offset point masses (the last section: and the end hose
    at its tip).

    Returns
    -------
    fe : FEModel
        Nodes along body ``x`` from the root pin; node ids ``0 .. n``.
    nodes : dict of str to int
        The node id at each attachment point's station (:func:`attachment_points`).
    """
    sec = record.sections[j - 1]
    L = sec.length
    points = attachment_points(record, j)
    fe = beam_mesh((0.0, 0.0, 0.0), (L, 0.0, 0.0), n_elements, box(sec.b, sec.h, sec.t(record.steel.rho)),
                   E=record.steel.E, rho=record.steel.rho, rotary_inertia=True,
                   nodes_at=sorted({min(max(x, 0.0), L) for x, _ in points.values()}))
    x = fe.nodes[:, 0]
    tributary = np.zeros(x.size)
    dx = np.diff(x)
    tributary[:-1] += dx / 2
    tributary[1:] += dx / 2
    mu = record.pipe.mass_per_m
    offset = [0.0, sec.h / 2 + record.pipe.offset, 0.0]
    fe = fe.with_point_masses(fe.node_ids, mu * tributary, offsets=np.tile(offset, (x.size, 1)))
    if j == record.n_sections:
        fe = fe.with_point_masses([int(fe.node_ids[-1])], [record.hose.mass])
    nodes = {name: station_node(x, fe.node_ids, px, L) for name, (px, _py) in points.items()}
    return fe, nodes


def section_modal_data(record: PumpTruckParameters, j: int, *, n_elements: int = N_ELEMENTS,
                       n_fixed_modes: int = N_FIXED_MODES, cache: bool = True) -> tuple[ModalData, dict[str, int]]:
    """Craig–Bampton modal data of section ``j`` (module docstring), read from the cache when the record's data for
    this section, the mesh and the reduction settings are unchanged.

    Parameters
    ----------
    record : PumpTruckParameters
        The machine's design record.
    j : int
        Section number 1–N.
    n_elements : int
        Beam elements.
    n_fixed_modes : int
        Fixed-interface normal modes of the reduction.
    cache : bool
        Read and write the modal file under ``$FLEXLIB_CACHE_DIR/pump_truck`` (default cache directory of
        flexlib), named by the SHA-256 of everything it depends on.

    Returns
    -------
    data : ModalData
        All modes of the reduction (select with ``FlexibleBody(modes=...)``).
    nodes : dict of str to int
        Interface node id of each attachment point.
    """
    key = json.dumps({"section": asdict(record.sections[j - 1]), "steel": asdict(record.steel),
                      "pipe": asdict(record.pipe), "hose": asdict(record.hose) if j == record.n_sections else None,
                      "points": attachment_points(record, j), "n_elements": n_elements,
                      "n_fixed_modes": n_fixed_modes, "version": 1}, sort_keys=True, default=str)
    digest = hashlib.sha256(key.encode()).hexdigest()[:24]
    path = _cache_dir() / f"section{j}-{digest}.h5"
    if cache and path.exists():
        data = ModalData.read(path)
        L = record.sections[j - 1].length
        return data, {name: station_node(data.coordinates[:, 0], data.node_ids, px, L)
                      for name, (px, _py) in attachment_points(record, j).items()}
    fe, nodes = section_fe(record, j, n_elements)
    interface = sorted(set(nodes.values()))
    data = modal_data_from_fe(fe, interface, n_fixed_modes, reference_node=nodes["root"], attachment="pinned",
                              title=f"pump-truck boom section {j}", creator="models.pump_truck.flexible")
    if cache:
        path.parent.mkdir(parents=True, exist_ok=True)
        data.write(path)
    return data, nodes


def _source_hash(*modules: Any) -> str:
    """SHA-256 of the pump-truck package's, the boom parts', the component library's and the engine's Python
    sources and of the packages defining ``modules`` (what the rigid loads depend on)."""
    import inspect

    import flexlib
    import flexlib.components
    import flexlib.models.boom

    h = hashlib.sha256()
    roots = {Path(__file__).resolve().parent, Path(flexlib.__file__).resolve().parent,
             Path(flexlib.components.__file__).resolve().parent, Path(flexlib.models.boom.__file__).resolve().parent,
             *(Path(inspect.getfile(m)).resolve().parent for m in modules)}
    for path in sorted(p for root in roots for p in root.rglob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:24]


def _cache_dir() -> Path:
    from flexlib.compile.cache import cache_dir

    return Path(os.environ.get("FLEXLIB_CACHE_DIR") or cache_dir()) / "pump_truck"


#: The rigid model's pin names (``PumpTruck._section``) and the attachment points they are.
PIN_POINTS = {"C": "bracket", "P_next": "lever_pivot", "H_next": "housing"}


def rigid_section_loads(result: Any, record: PumpTruckParameters, j: int,
                        data: ModalData | None = None) -> np.ndarray:
    """Amplitudes of section ``j``'s unit load cases in a run of the *rigid* boom, for the MPF method.

    The section's frame is its root joint's ``frame_b``; its loads are those a FlexibleBody in its place would get
    (:meth:`~flexlib.components.mechanics.flexible.FlexibleBody.load_amplitudes`): ``acc_*`` = ``T (a_0 − g)``
    of the section body, ``alpha_*`` / ``omega_**`` from its angular acceleration and velocity, and at each pin the
    force its rigid offset carries (``section{j}.pin_{pin}.frame_b``), moved to the pin's axis node (moment plus
    offset × force), the tip's (``section{j}.tip.frame_b``) and the root joint's reaction on the section.

    Parameters
    ----------
    result : Result
        A run of :class:`~models.pump_truck.model.PumpTruck` (rigid).
    record : PumpTruckParameters
        Its design record.
    j : int
        Section number 1–N.
    data : ModalData, optional
        The section's modal data (default :func:`section_modal_data`).

    Returns
    -------
    ndarray (nt, C)
        Amplitudes in the order of ``data.load_cases``.
    """
    if data is None:
        data, _ = section_modal_data(record, j)
    nt = len(result.t)
    x = data.coordinates[:, 0]
    L = record.sections[j - 1].length
    T = np.asarray(result[f"joint{j}.frame_b.T"], dtype=float).reshape(nt, 3, 3, order="F")
    g = np.array([0.0, -record.g, 0.0])
    a_0 = np.asarray(result[f"section{j}.body.a_0"], dtype=float).reshape(nt, 3)
    w = np.asarray(result[f"section{j}.body.w_a"], dtype=float).reshape(nt, 3)
    z = np.asarray(result[f"section{j}.body.z_a"], dtype=float).reshape(nt, 3)
    values = inertial_load_amplitudes(np.einsum("kij,kj->ki", T, a_0 - g), z, w)
    points = attachment_points(record, j)
    frames = [(f"section{j}.tip", (L, 0.0))] + [(f"section{j}.pin_{pin}", points[name])
                                                for pin, name in PIN_POINTS.items() if name in points]

    def cut(name: str) -> np.ndarray:
        # the rigid boom's linkages are over-constrained out of their plane: the out-of-plane components are
        # statically indeterminate, zero in the run (the dropped rows'), and taken as zero here
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IndeterminateReactionWarning)
            return np.asarray(result[name], dtype=float).reshape(nt, 3)

    for path, (px, py) in frames:
        if f"{path}.frame_b.f[0]" not in result.names:
            continue
        _pin_load(values, data, L, (px, py), cut(f"{path}.frame_b.f"), cut(f"{path}.frame_b.t"))
    _add_node_load(values, station_node(x, data.node_ids, 0.0, L), -cut(f"joint{j}.frame_b.f"),
                   -cut(f"joint{j}.frame_b.t"))
    zero = np.zeros(nt)
    return np.column_stack([np.broadcast_to(values.get(c, zero), (nt,)) for c in data.load_cases])


def _add_node_load(values: dict, node: int, F: np.ndarray, M: np.ndarray) -> None:
    """Add force ``F`` [N] and moment ``M`` [N.m] (``(nt, 3)``, section axes) to node ``node``'s load cases."""
    for i, comp in enumerate(("ux", "uy", "uz")):
        key = f"F{node}_{comp}"
        values[key] = values.get(key, 0.0) + F[:, i]
    for i, comp in enumerate(("rx", "ry", "rz")):
        key = f"F{node}_{comp}"
        values[key] = values.get(key, 0.0) + M[:, i]


def _pin_load(values: dict, data: ModalData, L: float, point: tuple[float, float], F: np.ndarray,
              M: np.ndarray) -> None:
    """A load at ``point`` [m] (section frame) moved to its station's axis node (moment plus offset × force), as the
    pin's rigid offset carries it."""
    node = station_node(data.coordinates[:, 0], data.node_ids, point[0], L)
    offset = np.array([point[0], point[1], 0.0]) - data.coordinates[data.node_index(node)]
    _add_node_load(values, node, F, M + np.cross(offset, F))


def static_section_loads(record: PumpTruckParameters, j: int, pose: Sequence[float],
                         data: ModalData | None = None) -> np.ndarray:
    """Amplitudes of section ``j``'s unit load cases with the boom held at rest in ``pose``, from the free-body
    statics (:func:`~models.pump_truck.free_body.free_body_statics`), without building a model.

    The same loads as :func:`rigid_section_loads` of the rigid boom at rest there (within 4e-14 of the largest amplitude
    at the MPF poses; tested to 1e-9): ``acc_*`` the section's weight (``T (0 − g)`` in its axes; no angular velocity or
    acceleration at rest), at each pin — the root joint's hinge, the bracket of its own drive (the link's, or cylinder
    1's rod), the next joint's hinge, lever pivot and cylinder housing — the force the neighbouring body exerts there (a
    pin carries no moment in the boom's plane), moved to the pin's axis node.

    Parameters
    ----------
    record : PumpTruckParameters
        The design record (its pipe state is the load).
    j : int
        Section number 1–N.
    pose : sequence of N + 1 floats
        Slew (ignored: it turns the boom's plane, not its loads) and joint angles q1 … qN [deg].
    data : ModalData, optional
        The section's modal data (default :func:`section_modal_data`).

    Returns
    -------
    ndarray (1, C)
        Amplitudes in the order of ``data.load_cases``.
    """
    from .free_body import free_body_statics

    if data is None:
        data, _ = section_modal_data(record, j)
    N = record.n_sections
    if not 1 <= j <= N or len(pose) != N + 1:
        raise ValueError(f"static_section_loads: section 1..{N} and a pose of {N + 1} angles [deg] (slew, q1 … qN) "
                         f"expected, got section {j!r} and {len(pose)} angles")
    statics = free_body_statics(record, np.radians(np.asarray(pose, dtype=float)[1:]))
    c, s = np.cos(statics["theta"][j - 1]), np.sin(statics["theta"][j - 1])

    def section_axes(F_world: np.ndarray) -> np.ndarray:  # a world (turret-plane) force in section j's axes
        return np.array([[c * F_world[0] + s * F_world[1], -s * F_world[0] + c * F_world[1], 0.0]])

    values = inertial_load_amplitudes(section_axes(np.array([0.0, record.g])), np.zeros((1, 3)), np.zeros((1, 3)))
    pins = statics["pins"]
    on_section = [("root", statics["F_hinge"][j - 1]), ("bracket", -pins["R1"] if j == 1 else pins[f"C{j}"])]
    if j < N:
        on_section += [("tip", -statics["F_hinge"][j]), ("lever_pivot", -pins[f"P{j + 1}"]),
                       ("housing", -pins[f"H{j + 1}"])]
    points = attachment_points(record, j)
    L = record.sections[j - 1].length
    for name, F in on_section:
        _pin_load(values, data, L, points[name], section_axes(F), np.zeros((1, 3)))
    zero = np.zeros(1)
    return np.column_stack([np.broadcast_to(values.get(k, zero), (1,)) for k in data.load_cases])


def unfolding_poses(fold: Sequence[float], working: Sequence[float]) -> tuple[tuple[float, ...], ...]:
    """The poses [deg] (slew, q1 … qN) of an unfolding from ``fold`` to ``working``: the fold, then joint 1, 2, …, N
    moved in turn to the working pose (the last is the working pose), then the extended horizontal boom (the poses
    whose static loads select the sections' modes, :func:`mpf_modes`)."""
    fold, working = tuple(map(float, fold)), tuple(map(float, working))
    stations = [fold] + [(fold[0], *working[1:k + 1], *fold[k + 1:]) for k in range(1, len(fold))]
    return (*stations, (0.0,) * len(fold))


#: Poses [deg] (slew, q1 … q5) of the 42 m boom whose static loads select the sections' modes (:func:`mpf_modes`):
#: the transport fold, the stations of the unfolding (each joint in turn moved to the working pose), the working pose
#: and the extended horizontal boom (:func:`unfolding_poses` of its transport fold and working pose).
MPF_POSES_DEG = (
    (0.0, 0.0, 176.0, -176.0, 176.0, -176.0),
    (0.0, 50.0, 176.0, -176.0, 176.0, -176.0),
    (0.0, 50.0, 10.0, -176.0, 176.0, -176.0),
    (0.0, 50.0, 10.0, -30.0, 176.0, -176.0),
    (0.0, 50.0, 10.0, -30.0, 20.0, -176.0),
    (0.0, 50.0, 10.0, -30.0, 20.0, -40.0),
    (0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
)


def mpf_modes(record: PumpTruckParameters, *, threshold: float = 0.01, max_modes: int = 8,
              poses: Sequence[Sequence[float]] | None = None, cache: bool = True,
              model: Callable[..., Any] | None = None) -> dict[int, list[int]]:
    """Each section's modes chosen by the modal participation factor method (seed 001).

    The loads on each section in the rigid boom's static equilibrium at ``poses``, filled as the record says — from
    the free-body statics of the record (:func:`static_section_loads`, no model built), or from static starts of a
    rigid machine ``model`` (:func:`rigid_section_loads`; the same loads to 4e-14 for the record's own mechanics,
    :class:`~models.pump_truck.held.HeldBoom`) — give each mode's
    static amplitude ``q_i = φ_iᵀ F / k_i``; a mode is kept if at some pose it reaches ``threshold`` of the largest
    (:func:`~flexlib.fe.participation_from_load_cases`) and moves the section in its
    plane (:func:`flexlib.fe.planar_modes`, ``"xy"``: the boom's loads and loops are planar); of those, the
    ``max_modes`` with the largest shares, in frequency order.

    Parameters
    ----------
    record : PumpTruckParameters
        The design record.
    threshold : float
        Share of the largest static modal amplitude a kept mode reaches at some pose [1].
    max_modes : int
        Most modes kept per section.
    poses : sequence of sequences of N + 1 floats, optional
        Poses [deg] (slew, q1 … qN) whose loads are used (default :data:`MPF_POSES_DEG`, the 42 m boom's; another
        machine gives its own, e.g. :func:`unfolding_poses` of its fold and working pose).
    cache : bool
        Read and write the selection under ``$FLEXLIB_CACHE_DIR/pump_truck`` (keyed by everything it depends on).
    model : callable, optional
        A rigid machine ``model(record, pose=..., slewing=False)``, section ``j`` as ``section{j}`` on ``joint{j}``,
        whose static starts give the loads (for example :class:`~models.pump_truck.held.HeldBoom`: PumpTruck's
        mechanics, cylinders locked). Default: the free-body statics of the record (a linkage the record describes;
        a machine of other mechanics gives its own model).

    Returns
    -------
    dict of int to list of int
        Section number (1–N) to mode indices into :func:`section_modal_data`.
    """
    import flexlib as fl
    from flexlib.fe import participation_from_load_cases, planar_modes

    poses = MPF_POSES_DEG if poses is None else poses
    if not 0.0 < threshold <= 1.0 or int(max_modes) < 1:
        raise ValueError(f"mpf_modes: threshold must be in (0, 1] and max_modes >= 1, got {threshold!r}, "
                         f"{max_modes!r}")
    sections = range(1, record.n_sections + 1)
    datas = {j: section_modal_data(record, j, cache=cache)[0] for j in sections}
    key = json.dumps({"record": asdict(record), "modal": {j: d.content_hash() for j, d in datas.items()},
                      "threshold": threshold, "max_modes": int(max_modes),
                      "poses": [list(map(float, p)) for p in poses], "version": 3,
                      "model": "free-body" if model is None else f"{model.__module__}.{model.__qualname__}",
                      # the loads come from the statics' or the rigid model's code: a change of it selects anew
                      "code": _source_hash(*[m for m in (model,) if m is not None]), "flexlib": fl.__version__},
                     sort_keys=True, default=str)
    path = _cache_dir() / f"mpf-{hashlib.sha256(key.encode()).hexdigest()[:24]}.json"
    if cache and path.exists():
        try:
            return {int(j): [int(k) for k in v] for j, v in json.loads(path.read_text())["modes"].items()}
        except (ValueError, KeyError, TypeError):
            pass  # a damaged file: select again and replace it
    rows = _static_loads(record, datas, poses, model)
    chosen: dict[int, list[int]] = {}
    for j, data in datas.items():
        table = participation_from_load_cases(data, rows[j], threshold=threshold)
        candidates = [k for k in planar_modes(data, "xy") if k in set(table.kept)]
        best = sorted(candidates, key=lambda k: -table.shares[k])[: int(max_modes)]
        chosen[j] = sorted(best, key=lambda k: data.frequencies[k])
    if cache:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".json.part")
        tmp.write_text(json.dumps({"modes": chosen, "threshold": threshold, "max_modes": int(max_modes)}))
        os.replace(tmp, path)
    return chosen


def _static_loads(record: PumpTruckParameters, datas: dict[int, ModalData], poses: Sequence[Sequence[float]],
                  model: Callable[..., Any] | None) -> dict[int, np.ndarray]:
    """Each section's load-case amplitudes at rest in ``poses`` (one row per pose): from the free-body statics
    (``model`` None) or from static starts of ``model`` (:func:`mpf_modes`)."""
    import flexlib as fl

    if model is None:
        return {j: np.vstack([static_section_loads(record, j, pose, data) for pose in poses])
                for j, data in datas.items()}
    rows: dict[int, list[np.ndarray]] = {j: [] for j in datas}
    sim = None
    for pose in poses:
        # static starts (no integration) on one build (the pose is a start value) in CasADi's VM (no C library)
        machine = model(record, pose=pose, slewing=False)
        sim = fl.Simulation(machine, codegen=False) if sim is None else sim.with_model(machine)
        result = sim.initialize()
        for j, data in datas.items():
            rows[j].append(rigid_section_loads(result, record, j, data)[:1])
    return {j: np.vstack(r) for j, r in rows.items()}
