"""FE mass and stiffness matrices from commercial FE codes: ANSYS full files and Nastran OP4 / DMIG.

Each reader returns a validated :class:`~flexlib.fe.fe_model.FEModel` (symmetric,
finite, consistent node/DOF map) from which :func:`~flexlib.fe.reduction.craig_bampton`
and :func:`~flexlib.fe.reduction.modal_data_from_fe` build the modal data. The file
formats are read by the FE community's open-source readers, installed as optional extras:

- ANSYS (MAPDL) ``.full`` files through ``ansys-mapdl-reader`` (``pip install flexlib[ansys]``);
- Nastran OUTPUT4 (``.op4``) files and DMIG bulk-data cards through ``pyNastran`` (``pip install flexlib[nastran]``).

FE codes are unit-agnostic: flexlib takes the matrices and coordinates as SI (kg, m, N, rad), so a model built
in another consistent unit system (e.g. t, mm, N) must be converted first (scale ``M`` by the mass unit and
``K`` and the coordinates by the length unit). DOF components map as ANSYS ``UX UY UZ ROTX ROTY ROTZ`` and Nastran
components ``1 2 3 4 5 6`` to flexlib's ``ux uy uz rx ry rz`` (:data:`~.arguments.COMPONENTS`).

References
----------
- Ansys Inc., *Mechanical APDL Programmer's Reference*, "Description of the Full Stiffness-Mass File" (fdfull):
  the full file holds the assembled matrices in the solver ordering with its DOF labels and constraint table,
  but no node coordinates (those are in the results file ``.rst`` or the archive ``.cdb``).
- MSC Software, *MSC Nastran Quick Reference Guide*: bulk data entries DMIG (direct matrix input at grid
  points; ``IFO = 6`` symmetric, one term of each off-diagonal pair), GRID (CP, CD coordinate systems) and
  CORDij; *DMAP Programmer's Guide*: OUTPUT4 (the OP4 format).
"""

from __future__ import annotations

import importlib
import os
import warnings
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import scipy.sparse as sp

from flexlib.errors import ModalFileError, RunArgumentError

from .arguments import COMPONENTS
from .fe_model import FEModel
from .matrix_checks import check_matrices
from .matrix_files import check_file, read_nodes, read_table

__all__ = ["read_ansys_full", "read_nastran_dmig", "read_nastran_op4"]

#: ANSYS DOF reference numbers of the structural nodal DOFs (fdfull: UX=1 ... ROTZ=6) and their names.
ANSYS_DOF_LABELS = {1: "UX", 2: "UY", 3: "UZ", 4: "ROTX", 5: "ROTY", 6: "ROTZ", 7: "AX", 8: "AY", 9: "AZ",
                    10: "VX", 11: "VY", 12: "VZ", 19: "PRES", 20: "TEMP", 21: "VOLT", 22: "MAG"}


def _optional(module: str, extra: str, package: str, reader: str = "this reader", path: Any = None) -> ModuleType:
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        file = "" if path is None else f" ({os.fspath(path)})" if isinstance(path, str | os.PathLike) else ""
        raise ImportError(f"{reader}{file}: {package} is needed for this reader: pip install 'flexlib[{extra}]' "
                          f"({exc}); without it, export the mass and stiffness matrices to Matrix Market and use "
                          "read_matrix_market") from None


def _fe_model(source: str, M: sp.spmatrix, K: sp.spmatrix, nodes: np.ndarray, dof_map: np.ndarray,
              node_ids: np.ndarray, info: dict[str, Any], names: tuple[str, str] = ("M", "K"),
              nodes_source: str = "nodes", default_map: bool = False) -> FEModel:
    """Validate (square, finite, symmetric, positive semi-definite diagonal, every row mapped to one node) and
    build the FEModel; errors name ``source``."""
    M, K = sp.csr_matrix(M, dtype=float), sp.csr_matrix(K, dtype=float)
    if nodes.ndim != 2 or nodes.shape[1] != 3:
        raise ModalFileError(f"{source}: node coordinates must have shape (N, 3), got {nodes.shape}")
    if not np.all(np.isfinite(nodes)):
        k = int(np.argwhere(~np.isfinite(nodes))[0, 0])
        raise ModalFileError(f"{source}: node {int(node_ids[k])} has a non-finite coordinate {nodes[k].tolist()} "
                             f"[m] ({nodes_source})")
    check_matrices(source, M, K, nodes.shape[0], dof_map, names, nodes_source=nodes_source,
                    node_ids=np.asarray(node_ids), default_map=default_map)
    try:
        return FEModel(M, K, nodes, dof_map, node_ids, info=info)
    except ValueError as exc:
        raise ModalFileError(f"{source}: {exc}") from None


def _names(func: str, mass: tuple[str, Any], stiffness: tuple[str, Any]) -> None:
    """The names of the mass and the stiffness matrix in a file: two different strings."""
    for arg, value in (mass, stiffness):
        if not isinstance(value, str) or not value:
            raise RunArgumentError(f"{func}: argument {arg!r} must be the name of a matrix in the file (e.g. 'MAA', "
                                   f"'KAA'), got {value!r}")
    if mass[1] == stiffness[1]:
        raise RunArgumentError(f"{func}: arguments {mass[0]!r} and {stiffness[0]!r} name the same matrix "
                               f"{mass[1]!r}: the mass and the stiffness are two matrices")


def _mirror_triangle(A: sp.spmatrix) -> sp.csr_matrix:
    """The full symmetric matrix from one stored triangle (a matrix with both triangles is returned unchanged)."""
    A = sp.csr_matrix(A)
    lower, upper = sp.tril(A, -1), sp.triu(A, 1)
    if lower.nnz and upper.nnz:
        return A
    return (A + (upper if upper.nnz else lower).T).tocsr()


# --------------------------------------------------------------------------------------------------------- ANSYS
def _ansys_nodes(full_path: str, nodes: Any, reader: ModuleType) -> tuple[np.ndarray, np.ndarray, str]:
    """Node numbers and coordinates for a full file: (ids, xyz, description of the source)."""
    if nodes is None:
        sibling = Path(full_path).with_suffix(".rst")
        if not sibling.is_file():
            raise ValueError(f"read_ansys_full: {full_path} holds no node coordinates (the full file format has "
                             f"none) and there is no result file {sibling.name} beside it: pass nodes= a .rst/.cdb "
                             "path or an array (N, 3) / (N, 4) [node, x, y, z] [m]")
        nodes = sibling
    if isinstance(nodes, str | os.PathLike):
        path = os.fspath(nodes)
        try:
            if Path(path).suffix.lower() in (".cdb", ".dat", ".inp"):
                mesh = reader.Archive(path)
            else:
                mesh = reader.read_binary(path).mesh
            return np.asarray(mesh.nnum, dtype=np.int64), np.asarray(mesh.nodes, dtype=float)[:, :3], path
        except Exception as exc:  # the reader raises bare Exception/RuntimeError for unreadable files
            raise ModalFileError(f"{path}: cannot read node coordinates for {full_path}: {exc}") from None
    table = np.asarray(nodes, dtype=float)
    if table.ndim == 2 and table.shape[1] == 4:
        return table[:, 0].astype(np.int64), table[:, 1:], "array [node, x, y, z]"
    if table.ndim == 2 and table.shape[1] == 3:
        return np.zeros(0, dtype=np.int64), table, "array (N, 3) in ascending node number"
    raise ValueError(f"read_ansys_full: nodes must be a path or an array (N, 3) or (N, 4), got shape {table.shape}")


def read_ansys_full(path: str | os.PathLike[str], *,
                    nodes: str | os.PathLike[str] | np.ndarray | None = None) -> FEModel:
    """Read the mass and stiffness matrices of an ANSYS (MAPDL) ``.full`` file through ``ansys-mapdl-reader``.

    The full file stores the upper triangles of ``K`` and ``M`` in the solver ordering; they are mirrored to the
    full symmetric matrices and renumbered node by node (ascending node number, then ``UX UY UZ ROTX ROTY ROTZ``
    mapped to ``ux uy uz rx ry rz``). DOFs constrained in the ANSYS model (``D`` command) are *removed*: they
    get ``-1`` in ``dof_map`` (held at zero, as :meth:`FEModel.constrained` does) and are listed in
    ``info["constrained"]``; a free-free model has none. The full file has no node coordinates: they come from
    ``nodes``.

    Parameters
    ----------
    path : path
        The ``.full`` file (symmetric matrices, consistent mass; lumped-mass and unsymmetric files are refused).
    nodes : path or array, optional
        Node coordinates [m]: a results file (``.rst``) or an archive (``.cdb``) of the same model, read with
        ``ansys-mapdl-reader``; or an array ``(N, 4)`` of ``[node, x, y, z]``; or ``(N, 3)`` in ascending node
        number of the full file's nodes. Default: the results file ``jobname.rst`` beside the full file.

    Returns
    -------
    FEModel
        ``node_ids`` are the ANSYS node numbers; ``info`` records the file, ANSYS version, jobname, the header's
        unit system and the coordinate source.

    Raises
    ------
    ImportError
        ``ansys-mapdl-reader`` is not installed.
    ModalFileError
        Unreadable or non-full file, a non-structural DOF label, nodes with different DOF sets, matrices that
        are not symmetric or finite, a node without coordinates; the message names the file.
    RunArgumentError
        ``path`` is not a str or os.PathLike.
    """
    if not isinstance(path, str | os.PathLike):
        raise RunArgumentError(f"read_ansys_full: argument 'path' must be a path (str or os.PathLike) to an ANSYS full "
                               f"file, got {type(path).__name__} {path!r:.60}")
    reader = _optional("ansys.mapdl.reader", "ansys", "ansys-mapdl-reader", "read_ansys_full", path)
    name = os.fspath(path)
    full = _open_full_file(name, reader)
    dof_ref, k, m, constrained, labels = _full_file_matrices(name, full)
    _check_dof_labels(name, dof_ref, labels)
    component = labels[dof_ref[:, 1]] - 1
    held = {(int(n), int(d)) for n, d in constrained}
    free = np.array([(int(n), int(d)) not in held for n, d in dof_ref], dtype=bool)
    keep = np.flatnonzero(free)
    K = _mirror_triangle(k)[keep][:, keep]
    M = _mirror_triangle(m)[keep][:, keep]

    node_ids = np.unique(dof_ref[:, 0])
    coordinates, source = _full_file_coordinates(name, nodes, reader, node_ids)
    index = np.searchsorted(node_ids, dof_ref[:, 0])
    dof_map = -np.ones((node_ids.size, 6), dtype=np.int64)
    dof_map[index[keep], component[keep]] = np.arange(keep.size)
    header = full._standard_header if hasattr(full, "_standard_header") else {}
    info = {"source": name, "format": "ANSYS full file", "ansys_version": str(header.get("verstring", "")),
            "jobname": str(header.get("jobname", "")), "units_in_file": str(header.get("units", "")),
            "coordinates": source,
            "constrained": _constraint_groups(constrained, labels)}
    return _fe_model(name, M, K, coordinates, dof_map, node_ids, info, nodes_source=source)


def _open_full_file(name: str, reader: ModuleType) -> Any:
    """The ANSYS full file at ``name`` opened by ``ansys-mapdl-reader``, after checking its record pointers fit
    the file (the reader's compiled parser reads past the end of a truncated file and can abort the process)."""
    if not Path(name).is_file():
        raise ModalFileError(f"{name}: " + ("is a directory, not an ANSYS full file" if Path(name).is_dir() else
                                            "no such ANSYS full file"))
    try:
        full = reader.read_binary(name)
    except Exception as exc:  # the reader raises bare Exception/RuntimeError/struct.error on foreign files
        raise ModalFileError(f"{name}: not readable as an ANSYS binary file: {exc}") from None
    if type(full).__name__ != "FullFile":
        raise ModalFileError(f"{name}: an ANSYS {type(full).__name__}, not a full file (.full)")
    # the header's record pointers are in 4-byte words
    header = getattr(full, "_header", {})
    pointers = {key: int(header[key]) for key in ("ptrSTF", "ptrMAS", "ptrDOF", "ptrEND") if key in header}
    size = Path(name).stat().st_size
    if len(pointers) < 4 or any(not 0 < v <= pointers["ptrEND"] for v in pointers.values()) \
            or 4 * pointers["ptrEND"] > size:
        raise ModalFileError(f"{name}: truncated or damaged full file: record pointers {pointers} (4-byte words) "
                             f"do not fit its {size} bytes")
    return full


def _full_file_matrices(name: str, full: Any) -> tuple[np.ndarray, Any, Any, np.ndarray, np.ndarray]:
    """The full file's DOF reference (node, DOF index) pairs, upper triangles of ``K`` and ``M``, constrained
    (node, DOF index) pairs and the model's DOF labels (its third record)."""
    from ansys.mapdl.reader.common import read_table as ansys_read_table

    with warnings.catch_warnings():  # the reader only warns when a matrix is missing: make that an error here
        warnings.filterwarnings("error", message="Missing (stiffness|mass) matrix")
        try:
            dof_ref, k, m = full.load_km(sort=True)
            constrained = np.asarray(full.const)
            with open(name, "rb") as f:  # third record: the DOF reference numbers of the model's DOF set
                ansys_read_table(f, skip=True)
                ansys_read_table(f, skip=True)
                labels = np.asarray(ansys_read_table(f), dtype=np.int64)
        except Exception as exc:
            raise ModalFileError(f"{name}: cannot read the stiffness and mass matrices: {exc}") from None
    return np.asarray(dof_ref, dtype=np.int64), k, m, constrained, labels


def _check_dof_labels(name: str, dof_ref: np.ndarray, labels: np.ndarray) -> None:
    """Every node carries the model's DOF set, and it holds structural displacements and rotations only."""
    per_node = np.bincount(np.unique(dof_ref[:, 0], return_inverse=True)[1])
    if np.any(per_node != labels.size) or dof_ref[:, 1].max(initial=0) >= labels.size:
        raise ModalFileError(f"{name}: nodes carry different DOF sets ({sorted(set(per_node.tolist()))} DOFs per "
                             f"node, model DOF set {[ANSYS_DOF_LABELS.get(int(v), v) for v in labels]}): export M "
                             "and K with their DOF map to Matrix Market (HBMAT with its mapping file) and use "
                             "read_matrix_market")
    bad = [int(v) for v in labels if not 1 <= v <= 6]
    if bad:
        raise ModalFileError(f"{name}: DOF labels {[ANSYS_DOF_LABELS.get(v, v) for v in bad]} are not structural "
                             "displacements or rotations (UX UY UZ ROTX ROTY ROTZ)")


def _full_file_coordinates(name: str, nodes: Any, reader: ModuleType,
                           node_ids: np.ndarray) -> tuple[np.ndarray, str]:
    """The coordinates [m] of the full file's nodes ``node_ids`` (from ``nodes``, see :func:`read_ansys_full`) and a
    description of their source."""
    ids, xyz, source = _ansys_nodes(name, nodes, reader)
    if ids.size == 0:  # (N, 3) in ascending node number
        if xyz.shape[0] != node_ids.size:
            raise ModalFileError(f"{name}: nodes has {xyz.shape[0]} rows for the full file's {node_ids.size} nodes")
        ids = node_ids
    lookup = {int(i): r for r, i in enumerate(ids)}
    missing = [int(i) for i in node_ids if int(i) not in lookup]
    if missing:
        raise ModalFileError(f"{name}: nodes {missing[:10]}{' ...' if len(missing) > 10 else ''} have no "
                             f"coordinates in {source}")
    return xyz[[lookup[int(i)] for i in node_ids]], source


def _constraint_groups(constrained: np.ndarray, labels: np.ndarray) -> list[dict[str, list[Any]]]:
    """Constrained (node, DOF index) pairs as ``[{"nodes": [...], "components": [...]}]`` (the schema of
    :meth:`FEModel.constrained`), grouping nodes held in the same components."""
    per_node: dict[int, list[str]] = {}
    for node, d in constrained:
        per_node.setdefault(int(node), []).append(COMPONENTS[int(labels[d]) - 1])
    groups: dict[tuple[str, ...], list[int]] = {}
    for node, comps in sorted(per_node.items()):
        groups.setdefault(tuple(sorted(comps, key=COMPONENTS.index)), []).append(node)
    return [{"nodes": nodes, "components": list(comps)} for comps, nodes in groups.items()]


# ------------------------------------------------------------------------------------------------------- Nastran
def read_nastran_op4(path: str | os.PathLike[str], *, mass: str = "MAA", stiffness: str = "KAA",
                     nodes: np.ndarray | str | os.PathLike[str],
                     dof_map: np.ndarray | str | os.PathLike[str] | None = None,
                     node_ids: Sequence[int] | np.ndarray | None = None) -> FEModel:
    """Read a mass and a stiffness matrix from a Nastran OUTPUT4 file (text or binary) through ``pyNastran``.

    An OP4 file holds matrices only: the DOF behind each row (the Nastran a-set order of the DMAP that wrote it)
    and the node coordinates come from the caller, as for :func:`~.fe_model.read_matrix_market`.

    Parameters
    ----------
    path : path
        The ``.op4`` file.
    mass, stiffness : str
        Names of the mass [kg, kg m, kg m2] and stiffness [N/m, N, N m/rad] matrices in the file (e.g. ``MAA``,
        ``KAA`` or ``MHH``/``KHH``).
    nodes : array or path
        Undeformed node coordinates [m], ``(N, 3)`` ``[x, y, z]`` or ``(N, 4)`` ``[grid, x, y, z]`` (a path:
        whitespace/comma separated text).
    dof_map : array (N, 6) or path, optional
        Matrix row of each node's ``(ux, uy, uz, rx, ry, rz)`` (Nastran components 1-6), ``-1`` if absent;
        default six DOFs per node in node order (``6 i + c``).
    node_ids : sequence of int, optional
        Grid ids of the nodes of an ``(N, 3)`` table (default ``0 .. N-1``).

    Raises
    ------
    ImportError
        ``pyNastran`` is not installed.
    ModalFileError
        Unreadable file, a missing or complex matrix, matrices that are not square, symmetric or finite, or a
        DOF map that does not fit them; a "mass" matrix without mass in a rigid translation (the matrices
        swapped); the message names the file and the matrix.
    RunArgumentError
        ``path`` not a path; ``mass`` or ``stiffness`` not a name, or both the same matrix.
    """
    op4 = _optional("pyNastran.op4.op4", "nastran", "pyNastran", "read_nastran_op4", path)
    _names("read_nastran_op4", ("mass", mass), ("stiffness", stiffness))
    name = check_file(path, "a Nastran OUTPUT4 file", "path") if not isinstance(path, str | os.PathLike) \
        else os.fspath(path)
    if not Path(name).is_file():
        raise ModalFileError(f"{name}: " + ("is a directory, not an OP4 file" if Path(name).is_dir() else
                                            "no such OP4 file"))
    check_file(name, "a Nastran OUTPUT4 file", "path")
    try:
        matrices = op4.OP4(debug=False).read_op4(name, precision="double")
    except Exception as exc:  # pyNastran raises assorted errors on malformed files
        raise ModalFileError(f"{name}: not readable as a Nastran OP4 file: {type(exc).__name__}: {exc}") from None
    mats = []
    for label, key in (("mass", mass), ("stiffness", stiffness)):
        if key not in matrices:
            raise ModalFileError(f"{name}: no {label} matrix {key!r} (the file has {sorted(matrices)})")
        entry = matrices[key]
        data = entry[1] if isinstance(entry, tuple) else entry.data  # (form, matrix) in 1.3, Matrix in 1.4
        if isinstance(data, list):
            raise ModalFileError(f"{name}: matrix {key!r} appears more than once")
        A = sp.csr_matrix(data)
        if np.iscomplexobj(A.data):
            raise ModalFileError(f"{name}: matrix {key!r} is complex; a real {label} matrix is needed")
        if A.shape[0] != A.shape[1]:
            raise ModalFileError(f"{name}: matrix {key!r} is not square: shape {A.shape}")
        mats.append(A.astype(float))
    ids, xyz, where = read_nodes(nodes, "nodes", node_ids)
    dmap = np.arange(6 * xyz.shape[0]).reshape(-1, 6) if dof_map is None else read_table(dof_map, "dof_map", np.int64)
    info = {"source": name, "format": "Nastran OUTPUT4", "matrices": [mass, stiffness]}
    return _fe_model(name, mats[0], mats[1], xyz, dmap, ids, info, (mass, stiffness), nodes_source=where,
                     default_map=dof_map is None)


def _dmig_entries(source: str, card: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows (grid, component), columns and real values of a DMIG matrix, checked for form, type and duplicates."""
    name = card.name
    form = int(card.matrix_form if getattr(card, "matrix_form", None) is not None else card.ifo)
    if form not in (1, 2, 6):
        raise ModalFileError(f"{source}: DMIG {name!r} has IFO = {form}; a square (1) or symmetric (6) matrix "
                             "is needed")
    if card.is_complex or int(card.tin) in (3, 4):
        raise ModalFileError(f"{source}: DMIG {name!r} is complex (TIN = {card.tin}); a real matrix is needed")
    rows = np.asarray(card.GCi, dtype=np.int64).reshape(-1, 2)
    cols = np.asarray(card.GCj, dtype=np.int64).reshape(-1, 2)
    values = np.asarray(card.Real, dtype=float)
    for label, gc in (("row", rows), ("column", cols)):
        scalar = gc[(gc[:, 1] < 1) | (gc[:, 1] > 6)]
        if scalar.size:
            raise ModalFileError(f"{source}: DMIG {name!r} {label} (grid {scalar[0, 0]}, component {scalar[0, 1]}) is "
                                 "not a grid component 1-6 (scalar and extra points have no place on a body)")
    pairs = np.hstack([rows, cols])
    if form == 6:  # one term of each off-diagonal pair: (i, j) and (j, i) are the same entry
        pairs = np.where(_before(rows, cols)[:, None], pairs, np.hstack([cols, rows]))
    unique, counts = np.unique(pairs, axis=0, return_counts=True)
    if np.any(counts > 1):
        g = unique[np.argmax(counts > 1)]
        raise ModalFileError(f"{source}: DMIG {name!r} gives the term at (grid {g[0]}, component {g[1]}) x (grid "
                             f"{g[2]}, component {g[3]}) more than once" + (" (both triangles of a symmetric matrix)"
                                                                             if form == 6 else ""))
    return rows, cols, values


def _before(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise (grid, component) ``a <= b`` in lexicographic order."""
    return (a[:, 0] < b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] <= b[:, 1]))


def read_nastran_dmig(bdf_path: str | os.PathLike[str], mass_name: str, stiffness_name: str, *,
                      punch: bool | None = None) -> FEModel:
    """Read mass and stiffness matrices given as DMIG cards, with the GRID coordinates, from a Nastran bulk data
    file through ``pyNastran`` (``read_bdf``).

    DMIG rows and columns are (grid, component 1-6); the DOFs are all those used by either matrix, numbered grid by
    grid (ascending id), then component; the nodes are the grids the matrices use, at their GRID positions in the
    basic system [m] (input systems ``CP`` resolved by pyNastran). Symmetric matrices (``IFO = 6``) give one term
    of each off-diagonal pair and are mirrored. Components are in the grid's displacement system ``CD``: a
    rectangular ``CD`` is rotated to the basic system (``K_basic = T^T K_cd T`` with ``T`` the node's
    direction-cosine blocks); cylindrical or spherical ones are refused.

    Parameters
    ----------
    bdf_path : path
        Bulk data file (or full input deck) with the DMIG and GRID cards (and CORDij the grids refer to).
    mass_name, stiffness_name : str
        Names of the DMIG mass [kg, kg m, kg m2] and stiffness [N/m, N, N m/rad] matrices (e.g. ``MAAX``,
        ``KAAX``).
    punch : bool, optional
        The file is bulk data only (no executive or case control); default: unless it has a ``BEGIN BULK`` line.

    Raises
    ------
    ImportError
        ``pyNastran`` is not installed.
    ModalFileError
        Unreadable file; a missing, complex, non-square or twice-given DMIG; a grid without a GRID card or with
        a curvilinear ``CD``; matrices that are not symmetric or finite; a "mass" matrix without mass in a rigid
        translation (the matrices swapped). The message names the file and the card.
    RunArgumentError
        ``bdf_path`` not a path; ``mass_name`` or ``stiffness_name`` not a name, or both the same DMIG; ``punch``
        not True, False or None.
    """
    bdf = _optional("pyNastran.bdf.bdf", "nastran", "pyNastran", "read_nastran_dmig", bdf_path)
    _names("read_nastran_dmig", ("mass_name", mass_name), ("stiffness_name", stiffness_name))
    if punch is not None and not isinstance(punch, bool | np.bool_):
        raise RunArgumentError(f"read_nastran_dmig: argument 'punch' must be True (bulk data only), False (a full "
                               f"input deck) or None (decided by a BEGIN BULK line), got {punch!r}")
    name = check_file(bdf_path, "a Nastran bulk data file", "bdf_path") if not isinstance(
        bdf_path, str | os.PathLike) else os.fspath(bdf_path)
    model = _read_bulk_data(name, bdf, punch)
    entries = {}
    for label, key in (("mass", mass_name), ("stiffness", stiffness_name)):
        if key not in model.dmig:
            raise ModalFileError(f"{name}: no DMIG {label} matrix {key!r} (DMIG cards: {sorted(model.dmig)})")
        entries[key] = _dmig_entries(name, model.dmig[key])
    dofs = np.unique(np.vstack([gc for rows, cols, _ in entries.values() for gc in (rows, cols)]), axis=0)
    grids = np.unique(dofs[:, 0])
    missing = [int(g) for g in grids if int(g) not in model.nodes]
    if missing:
        raise ModalFileError(f"{name}: DMIG grids {missing[:10]} have no GRID card")
    n = dofs.shape[0]
    index = {(int(g), int(c)): i for i, (g, c) in enumerate(dofs)}
    node_of = np.searchsorted(grids, dofs[:, 0])
    dof_map = -np.ones((grids.size, 6), dtype=np.int64)
    dof_map[node_of, dofs[:, 1] - 1] = np.arange(n)
    nodes = np.array([model.nodes[int(g)].get_position() for g in grids], dtype=float)

    mats = _dmig_matrices(model, entries, index, n)
    T = _cd_rotation(name, model, grids, dof_map)
    if T is not None:
        mats = [(T.T @ A @ T).tocsr() for A in mats]
    info = {"source": name, "format": "Nastran DMIG", "matrices": [mass_name, stiffness_name]}
    return _fe_model(name, mats[0], mats[1], nodes, dof_map, grids.astype(np.int64), info, (mass_name, stiffness_name))


def _read_bulk_data(name: str, bdf: ModuleType, punch: bool | None) -> Any:
    """The Nastran deck at ``name`` read by pyNastran (bulk data only if ``punch``; default: unless it has a
    ``BEGIN BULK`` line), its grids and coordinate systems cross-referenced."""
    try:
        text = Path(name).read_text(errors="replace")
    except OSError as exc:
        raise ModalFileError(f"{name}: cannot read the bulk data file: {exc}") from None
    if not text.strip():
        raise ModalFileError(f"{name}: the bulk data file is empty (no GRID or DMIG cards)")
    if punch is None:
        punch = not any(line.upper().startswith("BEGIN") and "BULK" in line.upper() for line in text.splitlines())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)  # pyNastran 1.3 leaves a probe file handle to the GC
        try:
            model = bdf.read_bdf(name, xref=False, punch=punch, debug=None)
            # only grids and coordinate systems: the deck's elements, properties, loads ... are not needed here
            model.cross_reference(xref_nodes=True, xref_elements=False, xref_properties=False, xref_masses=False,
                                  xref_materials=False, xref_loads=False, xref_constraints=False, xref_aero=False,
                                  xref_sets=False, xref_optimization=False)
        except Exception as exc:  # pyNastran raises assorted errors on malformed decks
            raise ModalFileError(f"{name}: not readable as Nastran bulk data: {type(exc).__name__}: {exc}") from None
    return model


def _dmig_matrices(model: Any, entries: dict[str, tuple[Any, Any, np.ndarray]], index: dict[tuple[int, int], int],
                   n: int) -> list[sp.csr_matrix]:
    """The DMIG matrices (in the order of ``entries``) on the ``n`` DOF rows of ``index`` (grid, component);
    symmetric ones (``IFO = 6``) mirrored."""
    mats = []
    for key, (rows, cols, values) in entries.items():
        r = np.array([index[(int(g), int(c))] for g, c in rows], dtype=np.int64)
        c = np.array([index[(int(g), int(c))] for g, c in cols], dtype=np.int64)
        if int(model.dmig[key].matrix_form) == 6:  # mirror each off-diagonal term
            off = r != c
            r, c = np.concatenate([r, c[off]]), np.concatenate([c, r[off]])
            values = np.concatenate([values, values[off]])
        mats.append(sp.csr_matrix((values, (r, c)), shape=(n, n)))
    return mats


def _cd_rotation(source: str, model: Any, grids: np.ndarray, dof_map: np.ndarray) -> sp.csr_matrix | None:
    """``T`` with ``u_cd = T u_basic`` on the DOFs, or None when every grid's CD is the basic system."""
    n = int(dof_map.max()) + 1
    rows, cols, vals = [], [], []
    rotated = False
    for k, g in enumerate(grids):
        node = model.nodes[int(g)]
        cd = int(node.Cd())
        if cd == 0:
            beta = np.eye(3)
        else:
            coord = model.coords.get(cd)
            if coord is None:
                raise ModalFileError(f"{source}: GRID {int(g)} refers to coordinate system CD = {cd}, which is "
                                     "not defined")
            if coord.Type != "R":
                raise ModalFileError(f"{source}: GRID {int(g)} has a curvilinear displacement system CD = {cd} "
                                     f"({type(coord).__name__}); only rectangular ones are rotated to basic")
            beta = np.asarray(coord.beta(), dtype=float)
            rotated = True
        for block in (slice(0, 3), slice(3, 6)):
            ids = dof_map[k, block]
            if cd != 0 and 0 < (ids >= 0).sum() < 3:
                raise ModalFileError(f"{source}: GRID {int(g)} (CD = {cd}) has only some of its "
                                     f"{'translation' if block.start == 0 else 'rotation'} components in the DMIG; "
                                     "all three are needed to rotate them to the basic system")
            if (ids < 0).all():
                continue
            for i in range(3):
                for j in range(3):
                    if beta[i, j] != 0.0:
                        rows.append(ids[i])
                        cols.append(ids[j])
                        vals.append(beta[i, j])
    if not rotated:
        return None
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
