"""FE matrix files read into an :class:`~flexlib.fe.fe_model.FEModel`: the ``.npz`` archive of
:meth:`FEModel.write_npz <flexlib.fe.fe_model.FEModel.write_npz>` (:func:`read_fe`), Matrix Market ``.mtx`` files
with node and DOF tables (:func:`read_matrix_market`), and the text tables of nodes and DOF maps the importers share
(:func:`read_nodes`, :func:`read_table`). Every reader checks the matrices (:mod:`.matrix_checks`) and names the
file at fault.

References
----------
- Matrix Market exchange format: R. F. Boisvert, R. Pozo, K. Remington, *The Matrix Market Exchange Formats:
  Initial Design*, NISTIR 5935, 1996 (read with :func:`scipy.io.mmread`).
"""

from __future__ import annotations

import os
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import scipy.io
import scipy.sparse as sp

from flexlib.errors import ModalFileError, RunArgumentError

from .arguments import array_kind
from .fe_model import FEModel
from .matrix_checks import check_matrices

__all__ = ["check_file", "read_fe", "read_matrix_market", "read_nodes", "read_table"]

#: What :func:`read_fe` reads, and the readers of the other FE matrix formats (for error messages).
_FORMATS = ("read_fe reads a .npz archive (FEModel.write_npz: CSR parts M_data/M_indices/M_indptr/M_shape and "
            "the same for K, or dense M and K, with nodes and dof_map); Matrix Market .mtx files: "
            "read_matrix_market(mass, stiffness, nodes, dof_map); Nastran: read_nastran_op4 / read_nastran_dmig; "
            "ANSYS .full: read_ansys_full")


def _text_table(path: str, label: str) -> np.ndarray:
    """A whitespace/comma separated table of numbers from a text file (``#`` comments), as float."""
    p = Path(path)
    if p.is_dir():
        raise ModalFileError(f"{path}: {label!r} is a directory, not a table file")
    try:
        text = p.read_text().replace(",", " ")
    except FileNotFoundError:
        raise ModalFileError(f"{path}: cannot read {label!r}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ModalFileError(f"{path}: cannot read {label!r}: {exc}") from None
    lines = [ln.split("#", 1)[0] for ln in text.splitlines()]
    rows = [(k + 1, ln.split()) for k, ln in enumerate(lines) if ln.strip()]
    if not rows:
        raise ModalFileError(f"{path}: {label!r} is empty (no rows of numbers)")
    width = len(rows[0][1])
    for line, fields in rows:
        if len(fields) != width:
            raise ModalFileError(f"{path}: {label!r} line {line} has {len(fields)} columns, line {rows[0][0]} has "
                                 f"{width}")
        for f in fields:
            try:
                float(f)
            except ValueError:
                raise ModalFileError(f"{path}: {label!r} line {line}: {f!r} is not a number (a header line? start "
                                     "it with #)") from None
    return np.array([[float(f) for f in fields] for _, fields in rows], dtype=float)


def read_table(value: Any, label: str, dtype: type) -> np.ndarray:
    """An array given directly, or read from a whitespace/comma separated text file (``label`` names it in errors);
    integer tables must hold whole numbers."""
    if isinstance(value, str | os.PathLike):
        where = os.fspath(value)
        table = _text_table(where, label)
    else:
        where = f"argument {label!r}"
        if isinstance(value, bool) or value is None:
            raise RunArgumentError(f"{where} must be an array or a path, got {value!r}")
        kind = array_kind(value)
        if kind in "USb":  # numbers are not read out of strings: a table of text is a mistake (or a file's content)
            raise RunArgumentError(f"{where} must be an array of numbers or a path to a table, got "
                                   f"{'bools' if kind == 'b' else 'text'}: {value!r:.80}")
        try:
            table = np.asarray(value, dtype=float)
        except (TypeError, ValueError) as exc:
            raise RunArgumentError(f"{where} must be an array of numbers or a path to a table: {exc}") from None
        if table.ndim == 1 and table.size in (3, 4, 6) and label != "node_ids":
            table = table[None, :]
    error = ModalFileError if isinstance(value, str | os.PathLike) else RunArgumentError
    if np.issubdtype(dtype, np.integer):
        bad = ~np.isfinite(table) | (table != np.round(table))
        if np.any(bad):
            at = tuple(int(v) for v in np.argwhere(bad)[0])
            raise error(f"{where}: {label!r} must hold whole numbers, got {float(table[at])!r} at (row, column) "
                        f"{at if len(at) > 1 else at[0]}")
        return table.astype(np.int64)
    return table.astype(dtype)


def read_nodes(value: Any, label: str = "nodes",
               node_ids: Sequence[int] | np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, str]:
    """Node coordinates [m] as an array or text table ``(N, 3)`` ``[x, y, z]`` or ``(N, 4)`` ``[id, x, y, z]``:
    ``(ids, xyz, description)``; finite coordinates and distinct whole-number ids, each error naming the node and
    the table (a file: :class:`~flexlib.errors.ModalFileError`; an array: :class:`~flexlib.errors.RunArgumentError`).
    ``node_ids`` gives the ids of an ``(N, 3)`` table (default ``0 .. N-1``)."""
    table = read_table(value, label, float)
    file = isinstance(value, str | os.PathLike)
    where = os.fspath(value) if file else f"argument {label!r}"
    error = ModalFileError if file else RunArgumentError
    if table.ndim != 2 or table.shape[1] not in (3, 4) or table.shape[0] == 0:
        raise error(f"{where}: {label!r} must be a table (N, 3) [x, y, z] or (N, 4) [id, x, y, z] [m], got shape "
                    f"{table.shape}")
    xyz = table[:, -3:]
    if table.shape[1] == 4:
        if node_ids is not None:
            raise RunArgumentError(f"{where}: {label!r} has an id column and node_ids is given too: give one")
        raw = table[:, 0]
        bad = ~np.isfinite(raw) | (raw != np.round(raw))
        if np.any(bad):
            k = int(np.argmax(bad))
            raise error(f"{where}: {label!r} row {k}: node id {float(raw[k])!r} is not a whole number (columns: id, "
                        "x, y, z)")
        ids = raw.astype(np.int64)
    elif node_ids is None:
        ids = np.arange(xyz.shape[0], dtype=np.int64)
    else:
        ids = read_table(node_ids, "node_ids", np.int64).ravel()
        if ids.size != xyz.shape[0]:
            raise RunArgumentError(f"argument 'node_ids' has {ids.size} ids for the {xyz.shape[0]} nodes of {where}")
    values, counts = np.unique(ids, return_counts=True)
    if np.any(counts > 1):
        dup = int(values[np.argmax(counts > 1)])
        rows = np.flatnonzero(ids == dup).tolist()
        raise error(f"{where}: node id {dup} appears {len(rows)} times (rows {rows}): ids must be distinct")
    bad = ~np.isfinite(xyz)
    if np.any(bad):
        k = int(np.argwhere(bad)[0, 0])
        raise error(f"{where}: node {int(ids[k])} (row {k}) has a non-finite coordinate {xyz[k].tolist()} [m]")
    return ids, xyz, where


def check_file(path: Any, what: str, argument: str) -> str:
    """The path as a string, checked to be an existing, non-empty regular file (errors name it)."""
    if not isinstance(path, str | os.PathLike):
        raise RunArgumentError(f"argument {argument!r} must be a path (str or os.PathLike) to {what}, got "
                               f"{type(path).__name__} {path!r}")
    name = os.fspath(path)
    p = Path(name)
    if p.is_dir():
        raise ModalFileError(f"{name}: is a directory, not {what} (argument {argument!r})")
    if not p.exists():
        raise ModalFileError(f"{name}: no such file ({what}, argument {argument!r})")
    if p.stat().st_size == 0:
        raise ModalFileError(f"{name}: the file is empty ({what}, argument {argument!r})")
    return name


class _Archive:
    """The arrays of an open ``.npz`` FE model archive, each read and checked once (messages name the file)."""

    def __init__(self, name: str, data: Any) -> None:
        self.name, self.data = name, data

    def get(self, key: str) -> np.ndarray:
        """Array ``key``: present, readable, real numbers."""
        name, data = self.name, self.data
        if key not in data.files:
            raise ModalFileError(f"{name}: array {key!r} is missing (has {sorted(data.files)}); {_FORMATS}")
        try:
            value = data[key]
        except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
            raise ModalFileError(f"{name}: array {key!r} cannot be read: {exc}") from None
        if not np.issubdtype(value.dtype, np.number) or np.issubdtype(value.dtype, np.complexfloating):
            raise ModalFileError(f"{name}: array {key!r} must be real numbers, got dtype {value.dtype}")
        return value

    def whole(self, key: str, value: np.ndarray) -> np.ndarray:
        """``value`` (array ``key``) as integers: whole numbers only."""
        if not np.issubdtype(value.dtype, np.integer):
            bad = ~np.isfinite(value) | (value != np.round(value))
            if np.any(bad):
                raise ModalFileError(f"{self.name}: array {key!r} must hold whole numbers, got "
                                     f"{float(value.ravel()[np.argmax(bad.ravel())])!r}")
        return value.astype(np.int64)

    def matrix(self, key: str) -> sp.csr_matrix:
        """Matrix ``key`` (``"M"`` or ``"K"``): dense, or from its CSR parts."""
        name, get, whole = self.name, self.get, self.whole
        if key in self.data.files:
            dense = get(key)
            if dense.ndim != 2:
                raise ModalFileError(f"{name}: array {key!r} must be a 2-D matrix, got shape {dense.shape}")
            return sp.csr_matrix(dense.astype(float))
        shape = whole(f"{key}_shape", get(f"{key}_shape")).ravel()
        if shape.size != 2 or np.any(shape < 0):
            raise ModalFileError(f"{name}: array '{key}_shape' must be two sizes (rows, columns), got "
                                 f"{shape.tolist()}")
        try:
            A = sp.csr_matrix((get(f"{key}_data").astype(float), whole(f"{key}_indices", get(f"{key}_indices")),
                               whole(f"{key}_indptr", get(f"{key}_indptr"))), shape=(int(shape[0]), int(shape[1])))
            A.check_format(full_check=True)
        except (ValueError, TypeError, IndexError) as exc:
            raise ModalFileError(f"{name}: the CSR arrays {key}_data, {key}_indices, {key}_indptr, "
                                 f"{key}_shape do not form a matrix: {exc}") from None
        return A


def _open_archive(name: str) -> Any:
    """The ``.npz`` at ``name`` opened with :func:`numpy.load`; another format is refused naming its reader."""
    with open(name, "rb") as f:
        magic = f.read(6)
    if not zipfile.is_zipfile(name):
        kind = ("a single numpy array (.npy)" if magic == b"\x93NUMPY" else
                "a Matrix Market file" if magic.startswith(b"%%Matr") else "not a .npz (zip) archive")
        raise ModalFileError(f"{name}: {kind}, not an FE model archive: {_FORMATS}")
    try:
        return np.load(name, allow_pickle=False)
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise ModalFileError(f"{name}: cannot read FE matrices: {exc}") from None


def _archive_node_ids(name: str, nodes: np.ndarray, node_ids: np.ndarray | None, elements: np.ndarray) -> np.ndarray:
    """The archive's node ids (default ``0 .. N-1``), after checking its nodes, ids and elements fit together."""
    if nodes.ndim != 2 or nodes.shape[1] != 3:
        raise ModalFileError(f"{name}: 'nodes' must have shape (N, 3) [m], got {nodes.shape}")
    if node_ids is None:
        node_ids = np.arange(nodes.shape[0])
    elif node_ids.size != nodes.shape[0]:
        raise ModalFileError(f"{name}: 'node_ids' has {node_ids.size} ids for {nodes.shape[0]} nodes")
    values, counts = np.unique(node_ids, return_counts=True)
    if np.any(counts > 1):
        raise ModalFileError(f"{name}: 'node_ids' gives id {int(values[np.argmax(counts > 1)])} to "
                             f"{int(counts.max())} nodes: ids must be distinct")
    if not np.all(np.isfinite(nodes)):
        k = int(np.argwhere(~np.isfinite(nodes))[0, 0])
        raise ModalFileError(f"{name}: 'nodes': node {int(node_ids[k])} (row {k}) has a non-finite coordinate "
                             f"{nodes[k].tolist()} [m]")
    if elements.size and (elements.ndim != 2 or elements.min() < 0 or elements.max() >= nodes.shape[0]):
        raise ModalFileError(f"{name}: 'elements' must be rows of node indices 0..{nodes.shape[0] - 1}, got "
                             f"shape {elements.shape} with values {elements.min()}..{elements.max()}")
    return node_ids


def read_fe(path: str | os.PathLike[str]) -> FEModel:
    """Read an FE model from a ``.npz`` with arrays ``M_data, M_indices, M_indptr, M_shape`` (and the same for
    ``K``; CSR parts as written by :meth:`FEModel.write_npz`) or dense ``M`` and ``K``, plus ``nodes`` (N, 3) [m],
    ``dof_map`` (N, 6) and optionally ``node_ids`` and ``elements``.

    Raises
    ------
    ModalFileError
        Missing, unreadable or inconsistent file, or another format (a ``.npy`` array, Matrix Market, ...: the
        message says which reader takes it); the message names the file and the array.
    """
    name = check_file(path, "an FE model .npz archive", "path")
    data = _open_archive(name)
    with data:
        archive = _Archive(name, data)
        mats = {key: archive.matrix(key) for key in ("M", "K")}
        nodes = archive.get("nodes").astype(float)
        dof_map = archive.whole("dof_map", archive.get("dof_map"))
        node_ids = archive.whole("node_ids", archive.get("node_ids")).ravel() if "node_ids" in data.files else None
        elements = (archive.whole("elements", archive.get("elements")) if "elements" in data.files
                    else np.zeros((0, 2), np.int64))
    node_ids = _archive_node_ids(name, nodes, node_ids, elements)
    check_matrices(name, mats["M"], mats["K"], nodes.shape[0], dof_map, nodes_source=f"{name} 'nodes'",
                   node_ids=node_ids)
    try:
        return FEModel(mats["M"], mats["K"], nodes, dof_map, node_ids, elements, info={"source": name})
    except ValueError as exc:
        raise ModalFileError(f"{name}: {exc}") from None


def _read_mtx(path: Any, label: str, argument: str) -> sp.csr_matrix:
    """One real matrix from a Matrix Market file (coordinate or array; general or symmetric)."""
    name = check_file(path, f"a Matrix Market file of matrix {label!r}", argument)
    try:
        field_, symmetry = scipy.io.mminfo(name)[4:]
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise ModalFileError(f"{name}: cannot read matrix {label!r} as Matrix Market (argument {argument!r}): "
                             f"{exc}") from None
    if field_ not in ("real", "integer", "double"):
        raise ModalFileError(f"{name}: matrix {label!r} is a Matrix Market {field_!r} matrix"
                             + (" (a sparsity pattern without values)" if field_ == "pattern" else "")
                             + "; a real matrix is needed")
    if symmetry not in ("general", "symmetric"):
        raise ModalFileError(f"{name}: matrix {label!r} is declared {symmetry!r}; a mass or stiffness matrix is "
                             "symmetric ('general' or 'symmetric')")
    try:
        A = scipy.io.mmread(name)
    except (OSError, ValueError, IndexError, UnicodeDecodeError) as exc:
        raise ModalFileError(f"{name}: cannot read matrix {label!r} as Matrix Market (argument {argument!r}): "
                             f"{exc}") from None
    return sp.csr_matrix(A, dtype=float)


def read_matrix_market(mass: str | os.PathLike[str], stiffness: str | os.PathLike[str],
                       nodes: np.ndarray | str | os.PathLike[str],
                       dof_map: np.ndarray | str | os.PathLike[str] | None = None) -> FEModel:
    """Read ``M`` and ``K`` from Matrix Market files (any FE code can export them) with the node coordinates
    [m] and DOF map as arrays or whitespace/comma separated text files.

    Parameters
    ----------
    mass, stiffness : path
        ``.mtx`` files of the mass [kg, kg m, kg m2] and stiffness [N/m, N, N m/rad] matrices (coordinate or
        array format, real or integer, general or symmetric). A lumped (diagonal) mass matrix may leave
        rotational DOFs without mass (no rotary inertia): the reduction condenses them statically.
    nodes : array or path
        Undeformed node coordinates [m]: a table ``(N, 3)`` ``[x, y, z]`` (node ids ``0 .. N-1``) or ``(N, 4)``
        ``[id, x, y, z]`` (``#`` starts a comment in a file).
    dof_map : array (N, 6) or path, optional
        Matrix row of each node's ``(ux, uy, uz, rx, ry, rz)``, ``-1`` if absent; default six DOFs per node in
        node order (``6 i + c``). Every matrix row must belong to one node's component.

    Raises
    ------
    ModalFileError
        A file is missing, empty, a directory or not Matrix Market; a matrix is complex, a pattern, not square,
        not symmetric, not finite or not positive semi-definite (a negative diagonal term); the matrices and
        maps do not fit together (a row that belongs to no node); one file given as both, or a mass matrix without
        mass in a rigid translation (the files swapped). The message names the file at fault.
    RunArgumentError
        ``nodes`` or ``dof_map`` given as an array that is not a table of numbers.
    """
    M = _read_mtx(mass, "M", "mass")
    K = _read_mtx(stiffness, "K", "stiffness")
    files = (os.fspath(mass), os.fspath(stiffness))
    if os.path.samefile(*files):
        raise ModalFileError(f"{files[0]}: given as both the mass and the stiffness file (arguments 'mass' and "
                             "'stiffness'): M and K are two matrices, from two files")
    ids, xyz, where = read_nodes(nodes, "nodes")
    default = dof_map is None
    dmap = np.arange(6 * xyz.shape[0]).reshape(-1, 6) if default else read_table(dof_map, "dof_map", np.int64)
    check_matrices(files, M, K, xyz.shape[0], dmap, nodes_source=where, node_ids=ids, default_map=default)
    try:
        return FEModel(M, K, xyz, dmap, ids, info={"source": list(files)})
    except ValueError as exc:
        raise ModalFileError(f"{files[1]}: {exc}") from None
