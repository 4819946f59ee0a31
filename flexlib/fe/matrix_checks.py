"""Checks that FE mass and stiffness matrices from a file fit together and can be a structure's: square, finite,
symmetric, of equal size, positive semi-definite as far as cheap necessary conditions tell, a DOF map that gives
every row to one node component, and mass in every rigid translation. Each failure is a
:class:`~flexlib.errors.ModalFileError` naming the file, the matrix and the DOF at fault."""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from flexlib.errors import ModalFileError

from .arguments import COMPONENTS, row_ranges

__all__ = ["check_matrices", "check_semidefinite_pattern", "check_translational_mass", "label_rows"]


def label_rows(dof_map: np.ndarray, node_ids: np.ndarray | None = None) -> Any:
    """A function giving ``"node 7 uz (row 44)"`` for a matrix row, from a DOF map (for messages)."""
    def label(row: int) -> str:  # only called to write a message: search then
        hit = np.argwhere(dof_map == int(row)) if dof_map.ndim == 2 and dof_map.shape[1] == 6 else np.zeros((0, 2))
        if hit.size == 0:
            return f"row {int(row)}"
        p, c = (int(v) for v in hit[0])
        ok = node_ids is not None and p < len(node_ids)
        return f"node {int(node_ids[p]) if ok else p} {COMPONENTS[c]} (row {int(row)})"

    return label


def check_semidefinite_pattern(A: sp.spmatrix, name: str, label: Any) -> str | None:
    """Why a symmetric ``A`` (mass or stiffness) cannot be positive semi-definite, or None: a negative diagonal
    term, or an off-diagonal term larger than the geometric mean of its two diagonal terms (a 2 x 2 principal
    minor below zero), naming the DOFs through ``label(row)``. Necessary conditions only (cheap: one pass over
    the nonzeros); the reduction finds what these miss."""
    A = sp.coo_matrix(A)
    d = np.asarray(A.diagonal(), dtype=float)
    scale = float(np.abs(d).max(initial=0.0)) or 1.0
    neg = np.flatnonzero(d < -1e-12 * scale)
    if neg.size:
        r = int(neg[np.argmin(d[neg])])
        kind = "mass" if name[:1] in "Mm" else "stiffness"
        more = "" if neg.size == 1 else f"; {neg.size} such DOFs"
        return (f"matrix {name!r} has a negative diagonal term {d[r]:.6g} at {label(r)}: a {kind} matrix is positive "
                f"semi-definite (its diagonal >= 0){more}")
    off = A.row != A.col
    if np.any(off):
        i, j, v = A.row[off], A.col[off], np.abs(A.data[off])
        bound = np.sqrt(np.maximum(d[i], 0.0) * np.maximum(d[j], 0.0))
        bad = np.flatnonzero(v > bound * (1 + 1e-8) + 1e-12 * scale)
        if bad.size:
            k = bad[np.argmax(v[bad] - bound[bad])]
            return (f"matrix {name!r} is not positive semi-definite: the term {A.data[off][k]:.6g} at ({label(i[k])}, "
                    f"{label(j[k])}) exceeds the geometric mean {bound[k]:.6g} of their diagonal terms "
                    "(a 2 x 2 principal minor is negative)")
    return None


def check_matrices(path: str | tuple[str, str], M: sp.spmatrix, K: sp.spmatrix, n_nodes: int,
                    dof_map: np.ndarray, names: tuple[str, str] = ("M", "K"), nodes_source: str = "nodes",
                    node_ids: np.ndarray | None = None, default_map: bool = False) -> None:
    """Square, finite, symmetric, positive semi-definite (necessary conditions) matrices of equal size, and a DOF map
    that covers every row once; errors name the file of the matrix at fault (``path``: one file, or the mass and
    stiffness files), the DOF and the node list."""
    files = (path, path) if isinstance(path, str) else path
    both = files[0] if files[0] == files[1] else f"{files[0]}, {files[1]}"
    for name, A, file in zip(names, (M, K), files):
        if A.shape[0] != A.shape[1]:
            raise ModalFileError(f"{file}: matrix {name!r} is not square: shape {A.shape}")
    if M.shape != K.shape:
        raise ModalFileError(f"{both}: matrices {names[0]!r} {M.shape} and {names[1]!r} {K.shape} differ in size")
    dof_map = np.asarray(dof_map)
    label = label_rows(dof_map, node_ids)
    for name, A, file in zip(names, (M, K), files):
        if not np.all(np.isfinite(A.data)):
            coo = sp.coo_matrix(A)
            k = int(np.flatnonzero(~np.isfinite(coo.data))[0])
            raise ModalFileError(f"{file}: matrix {name!r} has non-finite entries (NaN or inf): {coo.data[k]} at "
                                 f"({label(coo.row[k])}, {label(coo.col[k])})")
        asym = abs(A - A.T).max() if A.nnz else 0.0
        scale = abs(A).max() if A.nnz else 1.0
        if asym > 1e-9 * scale:
            D = sp.coo_matrix(abs(A - A.T))
            k = int(np.argmax(D.data))
            raise ModalFileError(f"{file}: matrix {name!r} is not symmetric (max |A - A^T| = {asym:.3g} at "
                                 f"({label(D.row[k])}, {label(D.col[k])}), max |A| = {scale:.3g})")
    n = M.shape[0]
    if dof_map.ndim != 2 or dof_map.shape != (n_nodes, 6):
        raise ModalFileError(f"{both}: 'dof_map' must have shape ({n_nodes}, 6) (one row per node of {nodes_source}, "
                             f"one column per component {' '.join(COMPONENTS)}), got {dof_map.shape}")
    if dof_map.max(initial=-1) >= n:
        p, c = (int(v) for v in np.argwhere(dof_map == dof_map.max())[0])
        raise ModalFileError(f"{both}: 'dof_map' refers to row {dof_map.max()} of a {n}-row matrix (node {p} "
                             f"{COMPONENTS[c]}): {n_nodes} nodes in {nodes_source}" +
                             (f", but {n} rows = {n / 6:g} x 6 (six DOFs per node by the default dof_map): is "
                              "a node too many in the node list, or the matrices' DOF set not six per node "
                              "(pass dof_map)?" if default_map else ""))
    if dof_map.min(initial=-1) < -1:
        p, c = (int(v) for v in np.argwhere(dof_map < -1)[0])
        raise ModalFileError(f"{both}: 'dof_map' holds {int(dof_map[p, c])} at node {p} {COMPONENTS[c]}: rows are "
                             ">= 0, or -1 for a DOF the node does not have")
    used = dof_map[dof_map >= 0]
    values, counts = np.unique(used, return_counts=True)
    if np.any(counts > 1):
        r = int(values[np.argmax(counts > 1)])
        owners = [f"node {int(node_ids[p]) if node_ids is not None else int(p)} {COMPONENTS[c]}"
                  for p, c in np.argwhere(dof_map == r)]
        raise ModalFileError(f"{both}: 'dof_map' gives row {r} to {' and '.join(owners)}: each row is one DOF")
    if values.size != n:
        free = np.setdiff1d(np.arange(n), values)
        hint = ""
        if default_map and n % 6 == 0 and n // 6 > n_nodes:
            hint = (f": by the default dof_map (six rows per node) these are nodes "
                    f"{row_ranges(np.arange(n_nodes, n // 6))}"
                    f" — {n // 6} nodes for the matrices, {n_nodes} in the node list: is a node missing from it?")
        elif default_map:
            hint = f": {n} rows are not six per node — pass dof_map"
        raise ModalFileError(f"{both}: matrix rows {row_ranges(free)} (of {n}) belong to no node in the node list "
                             f"{nodes_source} ({n_nodes} nodes); their mass and stiffness would drop out of the "
                             f"body{hint}")
    for name, A, file in zip(names, (M, K), files):
        why = check_semidefinite_pattern(A, name, label)
        if why is not None:
            raise ModalFileError(f"{file}: {why}")
    why = check_translational_mass(M, dof_map, names[0])
    if why is not None:
        raise ModalFileError(f"{files[0]}: {why}")


def check_translational_mass(M: sp.spmatrix, dof_map: np.ndarray, name: str = "M") -> str | None:
    """Why ``M`` cannot be a mass matrix, or None: a rigid translation ``u`` (all nodes along x, y or z) must carry
    mass, ``u^T M u > 0``; a free body's stiffness matrix gives it none (the mass and stiffness matrices swapped, or
    the same matrix given twice)."""
    M = sp.csr_matrix(M)
    for a, axis in enumerate("xyz"):
        rows = dof_map[:, a][dof_map[:, a] >= 0] if dof_map.ndim == 2 and dof_map.shape[1] == 6 else np.zeros(0)
        if not rows.size:
            continue
        block = M[rows][:, rows]
        scale = float(abs(block).sum())
        mass = float(block.sum())
        if scale > 0 and mass <= 1e-9 * scale:
            return (f"matrix {name!r} gives a rigid translation along {axis} no mass (u^T M u = {mass:.3g}, against "
                    f"{scale:.3g} for the sum of its terms' magnitudes): a mass matrix carries the body's mass in "
                    "every rigid translation, a free body's stiffness matrix none. Are the mass and stiffness "
                    "matrices swapped, or the same matrix given twice?")
    return None
