"""VTK output of flexible bodies for ParaView: the deformed mesh of one body over time (:func:`write_vtk_series`),
a whole machine — every flexible body and stick figures of the rigid parts — from a run (:func:`write_model_vtk`),
and the atomic writer of a series of meshio meshes with its collection file (:func:`write_series`).

The fields come from :mod:`.output` (a body's :class:`~flexlib.fe.ModalData` and the time series of its motion,
``q(t)``, ``r_0(t)``, ``T(t)``; ``FlexibleBody.motion(result)`` gives them).

References
----------
- Kitware, *VTK File Formats* (XML ``UnstructuredGrid`` ``.vtu`` and the ``.pvd`` collection); ParaView's
  ``.series`` file format (JSON ``{"file-series-version": "1.0", "files": [{"name", "time"}]}``).
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import uuid
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.errors import ResultFileError, RunArgumentError

from .modal_data import ModalData
from .output import (
    FIELDS,
    body_series,
    check_scale,
    data_label,
    deformed_positions,
    field_values,
    motion_series,
    node_displacements,
)

__all__ = ["output_path", "write_model_vtk", "write_series", "write_vtk_series"]


_ELEMENT_CELLS = {2: "line", 3: "line3", 4: "tetra", 8: "hexahedron", 10: "tetra10", 20: "hexahedron20"}


_FACE_CELLS = {3: "triangle", 4: "quad", 6: "triangle6", 8: "quad8"}


def _cell_type(func: str, arg: str, value: Any) -> None:
    """``element_type`` / ``face_type``: None or the name of a meshio cell type."""
    try:
        from meshio._mesh import topological_dimension as known
    except ImportError:  # another meshio layout: its writer names an unknown type
        known = None
    if value is not None and (not isinstance(value, str) or (known is not None and value not in known)):
        raise RunArgumentError(f"{func}: argument {arg!r} must be a meshio cell type (e.g. 'line', 'triangle', "
                               f"'quad', 'tetra', 'hexahedron'), got {value!r}")


def output_path(func: str, path: Any) -> Path:
    """An output path: a str or os.PathLike (else a :class:`~flexlib.errors.RunArgumentError` naming ``func``)."""
    if not isinstance(path, str | os.PathLike):
        raise RunArgumentError(f"{func}: argument 'path' must be a file path (str or os.PathLike), got "
                               f"{type(path).__name__} {path!r:.60}")
    return Path(path)


def _cells(data: ModalData, element_type: str | None, face_type: str | None, func: str) -> list[tuple[str, np.ndarray]]:
    _cell_type(func, "element_type", element_type)
    _cell_type(func, "face_type", face_type)
    cells: list[tuple[str, np.ndarray]] = []
    for arg, conn, given, table in (("element_type", data.elements, element_type, _ELEMENT_CELLS),
                                    ("face_type", data.faces, face_type, _FACE_CELLS)):
        if conn is None or conn.shape[0] == 0:
            continue
        kind = given or table.get(conn.shape[1])
        if kind is None:
            raise RunArgumentError(f"{func}: {data_label(data)} has cells of {conn.shape[1]} nodes: pass {arg} "
                                   f"(a meshio cell type) to say what they are")
        cells.append((kind, np.asarray(conn, dtype=np.int64)))
    if not cells:  # no connectivity: draw the nodes
        cells.append(("vertex", np.arange(data.n_nodes, dtype=np.int64)[:, None]))
    return cells


def _collection_kind(path: Path, func: str = "write_vtk_series") -> str:
    if path.suffix == ".pvd":
        return "pvd"
    if path.name.endswith(".vtu.series"):
        return "series"
    raise RunArgumentError(f"{func}: argument 'path' {str(path)!r} must end in '.pvd' (ParaView data "
                           "collection, XML) or '.vtu.series' (ParaView file series, JSON)")


def write_vtk_series(path: str | os.PathLike[str], data: ModalData, times: Any, q: Any, r_0: Any, T: Any, *,
                     fields: Sequence[str] | None = None, scale: float = 1.0, element_type: str | None = None,
                     face_type: str | None = None, loads: Any = None) -> Path:
    """Write the deformed body over time as VTK unstructured grids (one ``.vtu`` per instant, meshio) and a
    ParaView collection file giving each file's time.

    The frames go to a directory ``<collection name>.d/`` beside the collection file, referenced by relative
    names. Writing is atomic: everything is written under temporary names in the target directory, then the
    frame directory and finally the collection file are renamed into place, so an interrupted or failed write
    never leaves a collection that refers to a half-written series (a previous series at the same path stays
    intact until the new one is complete).

    Parameters
    ----------
    path : str or PathLike
        Collection file: ``*.pvd`` (VTK data collection, XML) or ``*.vtu.series`` (ParaView JSON series).
    data : ModalData
        The body's modal data; cells from ``elements`` (lines for beams) and ``faces`` if present.
    times : array_like (nt,)
        Time of each instant [s], non-decreasing.
    q : array_like (nt, M)
        Modal coordinates [1].
    r_0 : array_like (nt, 3) or (3,)
        Origin of the floating frame, world axes [m].
    T : array_like (nt, 3, 3) or (3, 3)
        Orientation of the floating frame, world to body.
    fields : sequence of str, optional
        Point data to write, from ``"displacement"`` (elastic displacement vector in world axes [m] and its
        magnitude ``displacement_magnitude``), ``"rotation"`` (elastic rotation vector in world axes [rad]),
        ``"von_mises"`` [Pa] and ``"stress"`` (``sxx..szx`` in body axes [Pa]); default ``displacement`` and,
        if the data has stress modes, ``von_mises``. ``node_id`` is always written.
    scale : float
        Magnification of the elastic displacement in the written point positions (fields stay true).
    element_type, face_type : str, optional
        meshio cell types of ``elements`` / ``faces`` where the node count is ambiguous (default by count:
        elements 2 ``line``, 3 ``line3``, 4 ``tetra``, 8 ``hexahedron``; faces 3 ``triangle``, 4 ``quad``).
    loads : array_like (nt, C), optional
        Amplitudes of the data's unit load cases (``body.load_amplitudes(result)``): the deformation recovered by
        the mode-acceleration method, as :func:`~flexlib.fe.node_displacements`; default plain modal superposition
        (``q`` alone carries no loads; :func:`~flexlib.fe.write_model_vtk` recovers a model's bodies by default).

    Returns
    -------
    Path
        The collection file.

    Raises
    ------
    RunArgumentError
        Bad shapes or values of ``times``, ``q``, ``r_0``, ``T``; an unknown field; a bad ``path`` suffix.
    ModalFileError
        ``von_mises`` or ``stress`` requested and the data has no stress modes.
    ResultFileError
        The files cannot be written (the message names the path); nothing is left behind.
    """
    import meshio

    func = "write_vtk_series"
    path = output_path(func, path)
    _collection_kind(path)  # checks the suffix before any work
    s = motion_series(func, data, times, q, r_0, T, scale, loads)
    data = s["data"]
    fields = _field_names(fields, data, func)
    _cells(data, element_type, face_type, func)  # the cell types before any work
    point_fields = _point_fields(s, fields, func)
    cells = _cells(data, element_type, face_type, func)
    node_id = np.asarray(data.node_ids, dtype=np.int64)

    def mesh(k: int) -> Any:
        point_data = {"node_id": node_id} | {f: np.ascontiguousarray(v[k]) for f, v in point_fields.items()}
        return meshio.Mesh(np.ascontiguousarray(s["points"][k]), cells, point_data=point_data)

    return write_series(path, s["t"], mesh, func)


def _field_names(fields: Any, data: ModalData, func: str) -> Sequence[str]:
    """The fields to write: given (one name or a list), else displacement and, with stress modes, von Mises."""
    if fields is None:
        return ("displacement",) + (("von_mises",) if data.stress_modes is not None else ())
    if isinstance(fields, str):
        return (fields,)
    if not isinstance(fields, Sequence) or not all(isinstance(f, str) for f in fields):
        raise RunArgumentError(f"{func}: argument 'fields' must be a field name or a list of them, from "
                               f"{list(FIELDS)}, got {fields!r}")
    return fields


def _point_fields(s: dict[str, Any], fields: Sequence[str], func: str) -> dict[str, np.ndarray]:
    """The point data of each instant: the fields by name (stress by component, displacement with its
    magnitude)."""
    point_fields: dict[str, np.ndarray] = {}
    for name in fields:
        values = field_values(s, name, func)
        if name == "stress":
            for c, comp in enumerate(("sxx", "syy", "szz", "sxy", "syz", "szx")):
                point_fields[f"stress_{comp}"] = values[..., c]
        else:
            point_fields[name] = values
            if name == "displacement":
                point_fields["displacement_magnitude"] = np.linalg.norm(values, axis=-1)
    return point_fields


def write_series(path: str | os.PathLike[str], times: np.ndarray, mesh: Any, func: str = "write_series") -> Path:
    """Write one meshio mesh per instant (``mesh(k)`` for ``k`` in ``range(len(times))``) as ``.vtu`` files and a
    ParaView collection (``*.pvd`` or ``*.vtu.series``), atomically (see :func:`write_vtk_series`).

    Parameters
    ----------
    path : str or PathLike
        Collection file.
    times : ndarray (nt,)
        Time of each instant [s].
    mesh : callable
        ``mesh(k) -> meshio.Mesh`` of instant ``k``.
    func : str
        Name for error messages.

    Returns
    -------
    Path
        The collection file.
    """
    import meshio

    path = output_path(func, path)
    kind = _collection_kind(path, func)
    stem = path.name[: -len(".vtu.series")] if kind == "series" else path.stem
    frames_dir = path.name + ".d"
    names = [f"{frames_dir}/{stem}_{k:06d}.vtu" for k in range(len(times))]
    parent = path.parent
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".tmp", dir=parent))
    except OSError as exc:
        raise ResultFileError(f"{func}: cannot write the VTK series {str(path)!r}: {exc}") from None
    final_dir = parent / frames_dir
    old: Path | None = None
    swapped = False
    try:
        (tmp / frames_dir).mkdir()
        for k, name in enumerate(names):
            meshio.write(tmp / name, mesh(k), file_format="vtu")
        collection = tmp / path.name
        if kind == "pvd":
            _write_pvd(collection, names, times)
        else:
            collection.write_text(json.dumps({"file-series-version": "1.0", "files": [
                {"name": n, "time": float(t)} for n, t in zip(names, times)]}, indent=1))
        if final_dir.exists() or final_dir.is_symlink():  # keep the old series readable until the swap
            old = parent / f".{frames_dir}.{uuid.uuid4().hex[:8]}.old"
            os.replace(final_dir, old)
        os.replace(tmp / frames_dir, final_dir)
        swapped = True
        os.replace(collection, path)
    except OSError as exc:
        if swapped:  # the collection was not replaced: take the new frames out again
            os.replace(final_dir, tmp / frames_dir)
        if old is not None:  # and put the previous series back
            os.replace(old, final_dir)
            old = None
        raise ResultFileError(f"{func}: cannot write the VTK series {str(path)!r}: {exc}") from None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    return path


def _write_pvd(path: Path, names: Sequence[str], times: np.ndarray) -> None:
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    for name, t in zip(names, times):
        ET.SubElement(coll, "DataSet", timestep=repr(float(t)), group="", part="0", file=name)
    ET.indent(root)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)


def write_model_vtk(path: str | os.PathLike[str], model: Any, result: Any, *,
                    lines: dict[str, Sequence[str]] | None = None, scale: float = 1.0, stride: int = 1) -> Path:
    """Write a whole machine over time as one VTK series: every FlexibleBody's deformed mesh and stick figures of
    the rigid parts, for ParaView.

    Parameters
    ----------
    path : str or PathLike
        Collection file (``*.pvd`` or ``*.vtu.series``).
    model : flexlib.Model
        The model the result belongs to (its FlexibleBody components are found by walking it).
    result : Result
        The run.
    lines : mapping of str to sequence of str, optional
        Stick figures of rigid parts: a name and the frame paths (``"joint1.frame_b"``) a polyline joins through
        their origins ``r_0``.
    scale : float
        Magnification of the elastic displacements (drawing only).
    stride : int
        Write every ``stride``-th row of the result (a long run on a fine grid), the last row always.

    Returns
    -------
    Path
        The collection file. Point data: ``part`` (0, 1, … in the order: flexible bodies by path, then
        ``lines``), ``displacement_magnitude`` [m] (elastic, zero on rigid parts). The bodies' deformation is
        recovered by the mode-acceleration method where their modal data allow (:mod:`flexlib.fe.output`).

    Raises
    ------
    RunArgumentError
        No flexible body and no lines, an unknown frame path, a line of fewer than two frames, a bad suffix,
        ``scale`` not a finite number, a ``model`` or ``result`` of the wrong type, a result of another model
        (:meth:`FlexibleBody.motion`).
    ResultFileError
        The files cannot be written (nothing is left behind).
    """
    import meshio

    func = "write_model_vtk"
    path = output_path(func, path)
    _collection_kind(path, func)
    scale = check_scale(func, scale)
    _check_model_arguments(func, model, result, lines, stride)
    t_all = np.asarray(result.t, dtype=float)
    rows = np.unique(np.append(np.arange(0, t_all.size, stride), t_all.size - 1)) if t_all.size else np.zeros(0, int)
    parts = _body_parts(model, result, rows, scale, func) + _line_parts(result, lines, rows, t_all.size, func)
    if not parts:
        raise RunArgumentError(f"{func}: nothing to draw: the model has no FlexibleBody and no lines were given")

    def mesh(k: int) -> Any:
        points, mags, ids, cells, offset = [], [], [], {}, 0
        for i, (pts, u, part_cells) in enumerate(parts):
            points.append(pts[k])
            mags.append(u[k])
            ids.append(np.full(pts.shape[1], i, dtype=np.int64))
            for kind, conn in part_cells:
                cells.setdefault(kind, []).append(conn + offset)
            offset += pts.shape[1]
        return meshio.Mesh(np.ascontiguousarray(np.vstack(points)),
                           [(kind, np.vstack(c)) for kind, c in cells.items()],
                           point_data={"part": np.concatenate(ids), "displacement_magnitude": np.concatenate(mags)})

    return write_series(path, t_all[rows], mesh, func)


#: One part of a machine's VTK series: points (nt, n, 3) [m], displacement magnitudes (nt, n) [m], meshio cells.
_Part = tuple[np.ndarray, np.ndarray, list[tuple[str, np.ndarray]]]


def _check_model_arguments(func: str, model: Any, result: Any, lines: Any, stride: Any) -> None:
    """``stride`` a positive integer, ``model`` a flexlib component, ``result`` a Result, each line a list of at
    least two frame paths."""
    from flexlib.core.component import Component
    from flexlib.results.result import Result

    if isinstance(stride, bool | np.bool_) or not isinstance(stride, int | np.integer) or stride < 1:
        raise RunArgumentError(f"{func}: stride must be a positive integer, got {stride!r}")
    if not isinstance(model, Component):
        raise RunArgumentError(f"{func}: argument 'model' must be the flexlib model the result belongs to, got "
                               f"{type(model).__name__}")
    if not isinstance(result, Result):
        raise RunArgumentError(f"{func}: argument 'result' must be a flexlib Result (of Simulation.run or "
                               f"Result.load), got {type(result).__name__}")
    for name, frames in (lines or {}).items():
        if (isinstance(frames, str) or not isinstance(frames, Sequence) or len(frames) < 2
                or not all(isinstance(f, str) for f in frames)):
            raise RunArgumentError(f"{func}: line {name!r} must be a list of at least two frame paths (e.g. "
                                   f"['joint1.frame_b', 'joint2.frame_a']), got {frames!r}")


def _body_parts(model: Any, result: Any, rows: np.ndarray, scale: float, func: str) -> list[_Part]:
    """The deformed mesh of every FlexibleBody of ``model`` (by path) at the result's ``rows``."""
    from flexlib.components.mechanics.flexible.body import FlexibleBody

    parts: list[_Part] = []
    bodies = sorted((c for c in model.walk() if isinstance(c, FlexibleBody)), key=lambda c: c.path)
    for body in bodies:  # the deformation recovered by default (mode acceleration, flexlib.fe.output)
        data, q, loads, r_0, T = body_series(func, body, result, None)
        loads = None if loads is None else loads[rows]
        pts = deformed_positions(data, q[rows], r_0[rows], T[rows], scale=scale, loads=loads)
        u = np.linalg.norm(node_displacements(data, q[rows], loads=loads), axis=-1) if data.n_modes \
            else np.zeros(pts.shape[:2])
        parts.append((pts, u, _cells(data, None, None, func)))
    return parts


def _line_parts(result: Any, lines: Any, rows: np.ndarray, n_all: int, func: str) -> list[_Part]:
    """Stick figures: each line's polyline through the origins ``r_0`` of its frames at the result's ``rows``."""
    parts: list[_Part] = []
    nt = rows.size
    for name, frames in (lines or {}).items():
        try:
            pts = np.stack([np.asarray(result[f"{frame}.r_0"], dtype=float).reshape(n_all, 3)[rows]
                            for frame in frames], 1)
        except Exception as exc:  # ResultKeyError: say which line and frame
            raise RunArgumentError(f"{func}: line {name!r}: {exc}") from None
        n = len(frames)
        parts.append((pts, np.zeros((nt, n)), [("line", np.column_stack([np.arange(n - 1), np.arange(1, n)]))]))
    return parts
