"""Finite-element mass and stiffness matrices with their node/DOF map, and their files (``.npz``, Matrix Market).

An :class:`FEModel` is what a producer of modal data starts from: scipy.sparse mass ``M`` [kg, kg m, kg m2]
and stiffness ``K`` [N/m, N, N m/rad] over a set of DOFs, the undeformed node coordinates [m] and a map
``dof_map[node, component]`` from a node and one of its six components ``(ux, uy, uz, rx, ry, rz)`` (translations
[m], small rotations [rad], in the body frame) to the row of ``M`` and ``K`` (``-1``: the node has no such DOF,
e.g. a constrained one or a solid element's rotation). Any FE code can supply these through
:func:`read_fe` (``.npz``) or :func:`read_matrix_market`; the built-in beam mesher
(:func:`~flexlib.components.mechanics.flexible.beam.beam_mesh`) produces them directly.

References
----------
- R. D. Cook, D. S. Malkus, M. E. Plesha, R. J. Witt, *Concepts and Applications of Finite Element Analysis*,
  4th ed., Wiley 2002, §2.8 (DOF numbering, assembly) and §11.3 (consistent and lumped mass).
- Matrix Market exchange format: R. F. Boisvert, R. Pozo, K. Remington, *The Matrix Market Exchange Formats:
  Initial Design*, NISTIR 5935, 1996 (read with :func:`scipy.io.mmread`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import scipy.io
import scipy.sparse as sp

from flexlib.errors import ModalFileError

__all__ = ["COMPONENTS", "BeamElements", "FEModel", "MassPoints", "read_fe", "read_matrix_market"]

#: Names of the six components of a node, in ``dof_map`` column order.
COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")


@dataclass(frozen=True, eq=False)
class MassPoints:
    """A mass description as points: the nine inertia invariants are sums over these points.

    For a *lumped* description the points are the FE nodes with their nodal masses and inertias; for a
    *consistent* one they are the Gauss points of the elements, weighted so that the sums integrate the
    element's density exactly (see :func:`~flexlib.components.mechanics.flexible.invariants.inertia_invariants`).

    Parameters
    ----------
    positions : ndarray, shape (P, 3)
        Undeformed positions in the body frame [m].
    masses : ndarray, shape (P,)
        Point masses [kg].
    inertias : ndarray, shape (P, 3, 3)
        Point rotational inertia tensors in body axes [kg m2] (rotary inertia of the section or node).
    Nt, Nr : scipy.sparse matrix, shape (3 P, n_dofs)
        Interpolation from the FE DOFs to the translation [m] and small rotation [rad] of each point
        (rows ``3 p .. 3 p + 2``).
    description : str
        ``"consistent"`` or ``"lumped"`` plus how it was made (goes to the modal file's provenance).
    """

    positions: np.ndarray
    masses: np.ndarray
    inertias: np.ndarray
    Nt: sp.csr_matrix
    Nr: sp.csr_matrix
    description: str

    def drop_dofs(self, keep: np.ndarray) -> MassPoints:
        """The same points on a subset ``keep`` of the DOFs (the others are held at zero)."""
        return replace(self, Nt=self.Nt[:, keep].tocsr(), Nr=self.Nr[:, keep].tocsr())


@dataclass(frozen=True, eq=False)
class BeamElements:
    """Per-element data of frame elements, for recovering section forces and stresses from displacements.

    Parameters
    ----------
    k_local : ndarray, shape (E, 12, 12)
        Element stiffness in local axes [N/m, N, N m].
    rotation : ndarray, shape (E, 3, 3)
        Rows: the element's local x, y, z axes in the body frame [1].
    dofs : ndarray of int, shape (E, 12)
        Global DOF rows of the element's 12 DOFs (``-1``: held at zero).
    A, Iy, Iz : ndarray, shape (E, 2)
        Section area [m2] and second moments [m4] at the element's two ends.
    """

    k_local: np.ndarray
    rotation: np.ndarray
    dofs: np.ndarray
    A: np.ndarray
    Iy: np.ndarray
    Iz: np.ndarray

    def drop_dofs(self, new_index: np.ndarray) -> BeamElements:
        """The same elements after a DOF renumbering (``new_index[old] = new`` or ``-1``)."""
        dofs = np.where(self.dofs >= 0, new_index[np.maximum(self.dofs, 0)], -1)
        return replace(self, dofs=dofs)


@dataclass(frozen=True, eq=False)
class FEModel:
    """Sparse FE mass and stiffness matrices with node coordinates and the node/DOF map.

    Parameters
    ----------
    M, K : scipy.sparse.csr_matrix, shape (n, n)
        Symmetric mass [kg, kg m, kg m2] and stiffness [N/m, N, N m/rad] matrices.
    nodes : ndarray, shape (N, 3)
        Undeformed node coordinates in the body frame [m].
    dof_map : ndarray of int, shape (N, 6)
        Row of ``M``/``K`` of each node's ``(ux, uy, uz, rx, ry, rz)``; ``-1`` where the node has none.
    node_ids : ndarray of int, shape (N,)
        User-facing node numbers (default ``0 .. N-1``).
    elements : ndarray of int, shape (E, k)
        Connectivity as indices into ``nodes`` (for drawing; ``(0, 2)`` if unknown).
    mass_points : MassPoints or None
        Mass description for the inertia invariants; ``None``: lumped from ``M`` (:meth:`lumped_mass_points`).
    unit_loads : ndarray, shape (n, 3), optional
        Consistent nodal loads [N, N m] of a unit uniform acceleration field along x, y, z [m/s2] (``M`` times
        the rigid translation fields of the unconstrained model); default computed from ``M``. Kept through
        :meth:`constrained`, where ``M`` alone would miss the mass coupled to the removed DOFs.
    beam : BeamElements, optional
        Frame-element data (from the beam mesher) for section forces and stresses.
    info : dict
        Provenance (mesher settings, source file) as JSON-serialisable values.
    """

    M: sp.csr_matrix
    K: sp.csr_matrix
    nodes: np.ndarray
    dof_map: np.ndarray
    node_ids: np.ndarray
    elements: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    mass_points: MassPoints | None = None
    info: dict[str, Any] = field(default_factory=dict)
    unit_loads: np.ndarray | None = None
    beam: BeamElements | None = None

    def __post_init__(self) -> None:
        n = self.M.shape[0]
        problems = []
        if self.M.shape != (n, n) or self.K.shape != (n, n):
            problems.append(f"M {self.M.shape} and K {self.K.shape} must be square and of equal size")
        if self.nodes.ndim != 2 or self.nodes.shape[1] != 3:
            problems.append(f"nodes must have shape (N, 3), got {self.nodes.shape}")
        if self.dof_map.shape != (self.nodes.shape[0], 6):
            problems.append(f"dof_map must have shape (N, 6) = {(self.nodes.shape[0], 6)}, got {self.dof_map.shape}")
        elif self.dof_map.size:
            used = self.dof_map[self.dof_map >= 0]
            if used.size and (used.max() >= n or len(np.unique(used)) != used.size):
                problems.append("dof_map rows must be distinct and below the matrix size")
        if self.node_ids.shape != (self.nodes.shape[0],) or len(np.unique(self.node_ids)) != self.node_ids.size:
            problems.append("node_ids must be one distinct id per node")
        if problems:
            raise ValueError("FEModel: " + "; ".join(problems))

    @property
    def n_dofs(self) -> int:
        """Number of DOFs (rows of ``M``)."""
        return int(self.M.shape[0])

    def node_index(self, node_ids: Sequence[int] | np.ndarray) -> np.ndarray:
        """Indices into ``nodes`` of the given node ids; a clear error names an unknown id."""
        lookup = {int(i): k for k, i in enumerate(self.node_ids)}
        out = []
        for i in np.atleast_1d(np.asarray(node_ids)).ravel():
            if int(i) not in lookup:
                raise KeyError(f"FEModel: no node with id {int(i)} (ids {self.node_ids.min()}..{self.node_ids.max()})")
            out.append(lookup[int(i)])
        return np.asarray(out, dtype=np.int64)

    def dofs(self, node_ids: Sequence[int] | np.ndarray, components: Sequence[str] = COMPONENTS) -> np.ndarray:
        """DOF rows of the given nodes (by id) and components (names from :data:`COMPONENTS`), skipping absent ones."""
        cols = [COMPONENTS.index(c) for c in components]
        rows = self.dof_map[self.node_index(node_ids)][:, cols].ravel()
        return rows[rows >= 0]

    def nodal_fields(self, fields: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Displacement fields ``(n_dofs, k)`` on the DOFs as nodal translations and rotations ``(k, N, 3)`` each
        [m, rad] (zero where a DOF is absent or held)."""
        fields = np.asarray(fields, dtype=float)
        trans = np.zeros((fields.shape[1], self.nodes.shape[0], 3))
        rot = np.zeros_like(trans)
        for c in range(6):
            rows = self.dof_map[:, c]
            has = rows >= 0
            (trans if c < 3 else rot)[:, has, c % 3] = fields[rows[has]].T
        return trans, rot

    def dof_fields(self, translations: np.ndarray, rotations: np.ndarray) -> np.ndarray:
        """The inverse of :meth:`nodal_fields`: nodal translations and rotations ``(k, N, 3)`` [m, rad] as fields
        ``(n_dofs, k)`` on this model's DOFs (values at held DOFs are dropped)."""
        out = np.zeros((self.n_dofs, np.shape(translations)[0]))
        for c in range(6):
            rows = self.dof_map[:, c]
            has = rows >= 0
            out[rows[has], :] = np.asarray(translations if c < 3 else rotations)[:, has, c % 3].T
        return out

    def rigid_body_modes(self) -> np.ndarray:
        """The six rigid-body displacement fields ``(n, 6)``: unit translations along x, y, z [m] and unit small
        rotations about the body-frame x, y, z axes through the origin [rad] (``u = theta x s``)."""
        R = np.zeros((self.n_dofs, 6))
        for a in range(3):
            e = np.eye(3)[a]
            rows = self.dof_map[:, a]
            R[rows[rows >= 0], a] = 1.0
            u = np.cross(e, self.nodes)  # rotation about e_a
            for b in range(3):
                rows = self.dof_map[:, b]
                R[rows[rows >= 0], 3 + a] = u[rows >= 0, b]
            rows = self.dof_map[:, 3 + a]
            R[rows[rows >= 0], 3 + a] = 1.0
        return R

    def constrained(self, node_ids: Sequence[int] | np.ndarray, components: Sequence[str] = COMPONENTS) -> FEModel:
        """The model with the given node components held at zero (their DOFs removed), e.g. a clamped end."""
        fixed = set(self.dofs(node_ids, components).tolist())
        keep = np.array([i for i in range(self.n_dofs) if i not in fixed], dtype=np.int64)
        new_index = -np.ones(self.n_dofs, dtype=np.int64)
        new_index[keep] = np.arange(keep.size)
        dof_map = np.where(self.dof_map >= 0, new_index[np.maximum(self.dof_map, 0)], -1)
        info = dict(self.info)
        info["constrained"] = [*info.get("constrained", []), {"nodes": [int(i) for i in np.atleast_1d(node_ids)],
                                                              "components": list(components)}]
        loads = self.gravity_loads()[keep]
        return replace(self, M=self.M[keep][:, keep].tocsr(), K=self.K[keep][:, keep].tocsr(), dof_map=dof_map,
                       mass_points=None if self.mass_points is None else self.mass_points.drop_dofs(keep), info=info,
                       unit_loads=loads, beam=None if self.beam is None else self.beam.drop_dofs(new_index))

    def with_point_masses(self, node_ids: Sequence[int] | np.ndarray, masses: Sequence[float] | np.ndarray,
                          offsets: Sequence[Sequence[float]] | np.ndarray | None = None,
                          inertias: Sequence[Any] | np.ndarray | None = None) -> FEModel:
        """The model with rigid point masses attached to nodes (non-structural mass: a pipe, a hose, a bracket).

        Each mass ``m`` sits at ``offset`` ``d`` from its node and moves rigidly with it: its displacement is
        ``u + theta x d = [I, -[d x]] (u, theta)``, so it adds ``N^T m N + [0, I]^T J [0, I]`` to the node's
        6 x 6 block of ``M`` (Nastran's ``CONM2`` with an offset) and joins the mass points the inertia
        invariants sum over.

        Parameters
        ----------
        node_ids : sequence of int
            Node (ids) each mass is attached to (a node may carry several).
        masses : sequence of float
            Masses [kg], >= 0.
        offsets : array_like (k, 3), optional
            Position of each mass relative to its node, body axes [m]; default 0. A nonzero offset needs the
            node's three rotations.
        inertias : array_like (k, 3, 3), optional
            Rotational inertia of each mass about its own centre, body axes [kg m2] (symmetric, positive
            semidefinite); default 0.

        Returns
        -------
        FEModel

        Raises
        ------
        ValueError
            Unknown node, negative or non-finite mass, wrong shapes, an offset on a node without rotations.
        """
        idx = self.node_index(node_ids)
        k = idx.size
        m = np.asarray(masses, dtype=float).reshape(-1)
        d = np.zeros((k, 3)) if offsets is None else np.asarray(offsets, dtype=float).reshape(k, 3)
        J = np.zeros((k, 3, 3)) if inertias is None else np.asarray(inertias, dtype=float).reshape(k, 3, 3)
        if m.shape != (k,):
            raise ValueError(f"FEModel.with_point_masses: {k} nodes but {m.size} masses")
        for name, a in (("masses", m), ("offsets", d), ("inertias", J)):
            if not np.all(np.isfinite(a)):
                raise ValueError(f"FEModel.with_point_masses: argument {name!r} has non-finite values")
        if np.any(m < 0):
            raise ValueError(f"FEModel.with_point_masses: negative mass {float(m[m < 0][0])!r} kg at node "
                             f"{int(self.node_ids[idx[np.argmax(m < 0)]])}")
        if np.abs(J - J.transpose(0, 2, 1)).max(initial=0.0) > 1e-12 * max(np.abs(J).max(initial=0.0), 1.0) or \
                np.any(np.linalg.eigvalsh((J + J.transpose(0, 2, 1)) / 2) < -1e-12 * max(np.abs(J).max(initial=0.0),
                                                                                         1.0)):
            raise ValueError("FEModel.with_point_masses: inertias must be symmetric positive semidefinite")
        rows_t, rows_r, cols_t, cols_r, vals_t = [], [], [], [], []
        add = sp.lil_matrix((self.n_dofs, self.n_dofs))
        loads = np.zeros((self.n_dofs, 3))
        base = 0 if self.mass_points is None else self.mass_points.masses.size
        for j in range(k):
            dof = self.dof_map[idx[j]]
            if np.any(dof[:3] < 0) or ((np.any(d[j]) or np.any(J[j])) and np.any(dof[3:] < 0)):
                raise ValueError(f"FEModel.with_point_masses: node {int(self.node_ids[idx[j]])} lacks the DOFs the "
                                 "mass needs (translations; rotations for an offset or inertia): attach it before "
                                 "constraining the node")
            N = np.zeros((3, 6))
            N[:, :3] = np.eye(3)
            dx = np.array([[0.0, -d[j, 2], d[j, 1]], [d[j, 2], 0.0, -d[j, 0]], [-d[j, 1], d[j, 0], 0.0]])
            N[:, 3:] = -dx
            block = m[j] * N.T @ N
            block[3:, 3:] += J[j]
            live = np.flatnonzero(dof >= 0)
            add[np.ix_(dof[live], dof[live])] += block[np.ix_(live, live)]
            loads[dof[live]] += (m[j] * N.T)[live]
            for a in range(3):
                for c in live:
                    if N[a, c] != 0.0:
                        rows_t.append(3 * (base + j) + a)
                        cols_t.append(dof[c])
                        vals_t.append(N[a, c])
                if dof[3 + a] >= 0:
                    rows_r.append(3 * (base + j) + a)
                    cols_r.append(dof[3 + a])
        M = (self.M + add.tocsr()).tocsr()
        points = self.mass_points
        if points is not None:
            shape = (3 * (base + k), self.n_dofs)
            Nt = sp.vstack([points.Nt, sp.csr_matrix((3 * k, self.n_dofs))]).tocsr() + sp.csr_matrix(
                (vals_t, (rows_t, cols_t)), shape=shape)
            Nr = sp.vstack([points.Nr, sp.csr_matrix((3 * k, self.n_dofs))]).tocsr() + sp.csr_matrix(
                (np.ones(len(rows_r)), (rows_r, cols_r)), shape=shape)
            points = MassPoints(np.vstack([points.positions, self.nodes[idx] + d]),
                                np.concatenate([points.masses, m]), np.concatenate([points.inertias, J]),
                                Nt.tocsr(), Nr.tocsr(), points.description + f" + {k} point masses")
        info = dict(self.info)
        info["point_masses"] = [*info.get("point_masses", []),
                                {"count": k, "total_kg": float(m.sum())}]
        unit_loads = None if self.unit_loads is None else self.unit_loads + loads
        return replace(self, M=M, mass_points=points, info=info, unit_loads=unit_loads)

    def translation_field(self, vector: Sequence[float]) -> np.ndarray:
        """DOF vector of a uniform translation ``vector`` [m] of all nodes (rotations zero)."""
        out = np.zeros(self.n_dofs)
        for a in range(3):
            rows = self.dof_map[:, a]
            out[rows[rows >= 0]] = vector[a]
        return out

    def gravity_loads(self) -> np.ndarray:
        """Consistent nodal loads ``(n, 3)`` [N, N m] of unit uniform accelerations along x, y, z [m/s2]."""
        if self.unit_loads is not None:
            return self.unit_loads
        return np.column_stack([self.M @ self.translation_field(np.eye(3)[a]) for a in range(3)])

    def gravity_load(self, g: Sequence[float]) -> np.ndarray:
        """Consistent nodal load vector [N, N m] of the body's weight in a uniform field ``g`` [m/s2]: ``M u_g``
        with ``u_g`` the uniform translation ``g`` of the unconstrained model (exact for shape functions that
        reproduce rigid translation), restricted to the remaining DOFs."""
        return self.gravity_loads() @ np.asarray(g, dtype=float)

    def lumped_mass_points(self) -> MassPoints:
        """Lumped mass description from ``M``: each node's mass is the row sum of the translational block of
        ``M`` in each direction, averaged over x, y, z (mass-conserving); nodal inertias are the rotational
        diagonal blocks of ``M`` (Cook et al. §11.3, row-sum lumping). Where row sums give a negative nodal mass
        (corner nodes of quadratic solid elements, e.g. 20-node hexahedra), the translational diagonal of ``M``
        scaled to the same total mass per direction is used instead (HRZ lumping: E. Hinton, T. Rock,
        O. C. Zienkiewicz, *Earthquake Eng. Struct. Dyn.* 4 (1976) 245-249; Cook et al. §11.3)."""
        N = self.nodes.shape[0]
        masses = np.zeros(N)
        diagonal = np.zeros(N)
        inertias = np.zeros((N, 3, 3))
        M = self.M.tocsr()
        for a in range(3):
            rows = self.dof_map[:, a]
            has = rows >= 0
            trans = np.zeros(self.n_dofs)
            trans[rows[has]] = 1.0
            row_sums = M[rows[has]] @ trans
            masses[has] += row_sums / 3.0
            d = np.asarray(M.diagonal())[rows[has]]
            if d.sum() > 0:
                diagonal[has] += d * (row_sums.sum() / d.sum()) / 3.0
        rule = "translational row sums of M per node"
        if np.any(masses < 0):
            masses, rule = diagonal, "HRZ: translational diagonal of M scaled to the row-sum total (row sums < 0)"
        for a in range(3):
            for b in range(3):
                ra, rb = self.dof_map[:, 3 + a], self.dof_map[:, 3 + b]
                both = (ra >= 0) & (rb >= 0)
                inertias[both, a, b] = np.asarray(M[ra[both], rb[both]]).ravel()
        return MassPoints(self.nodes.copy(), masses, inertias, self._selector(range(3)), self._selector(range(3, 6)),
                          f"lumped ({rule}, rotational diagonal blocks)")

    def _selector(self, components: range) -> sp.csr_matrix:
        N = self.nodes.shape[0]
        rows, cols = [], []
        for p in range(N):
            for k, c in enumerate(components):
                if self.dof_map[p, c] >= 0:
                    rows.append(3 * p + k)
                    cols.append(self.dof_map[p, c])
        return sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(3 * N, self.n_dofs))

    def write_npz(self, path: str | os.PathLike[str]) -> None:
        """Write ``M``, ``K`` (CSR parts), ``nodes``, ``dof_map``, ``node_ids`` and ``elements`` to a ``.npz``
        readable by :func:`read_fe` (atomically: temporary file then ``os.replace``)."""
        path = Path(path)
        tmp = path.with_name(path.name + ".tmp.npz")
        arrays: dict[str, np.ndarray] = {"nodes": self.nodes, "dof_map": self.dof_map, "node_ids": self.node_ids,
                                         "elements": self.elements}
        for name, A in (("M", self.M), ("K", self.K)):
            A = sp.csr_matrix(A)
            arrays.update({f"{name}_data": A.data, f"{name}_indices": A.indices, f"{name}_indptr": A.indptr,
                           f"{name}_shape": np.asarray(A.shape)})
        try:
            np.savez(tmp, **arrays)
            os.replace(tmp, path)
        finally:
            if tmp.exists():
                tmp.unlink()


def _check_matrices(path: str, M: sp.spmatrix, K: sp.spmatrix, n_nodes: int, dof_map: np.ndarray,
                    names: tuple[str, str] = ("M", "K")) -> None:
    for name, A in zip(names, (M, K)):
        if A.shape[0] != A.shape[1]:
            raise ModalFileError(f"{path}: matrix {name!r} is not square: shape {A.shape}")
        if not np.all(np.isfinite(A.data)):
            raise ModalFileError(f"{path}: matrix {name!r} has non-finite entries (NaN or inf)")
        asym = abs(A - A.T).max() if A.nnz else 0.0
        scale = abs(A).max() if A.nnz else 1.0
        if asym > 1e-9 * scale:
            raise ModalFileError(f"{path}: matrix {name!r} is not symmetric (max |A - A^T| = {asym:.3g}, "
                                 f"max |A| = {scale:.3g})")
    if M.shape != K.shape:
        raise ModalFileError(f"{path}: matrices {names[0]!r} {M.shape} and {names[1]!r} {K.shape} differ in size")
    if dof_map.shape != (n_nodes, 6):
        raise ModalFileError(f"{path}: 'dof_map' must have shape ({n_nodes}, 6), got {dof_map.shape}")
    if dof_map.max(initial=-1) >= M.shape[0]:
        raise ModalFileError(f"{path}: 'dof_map' refers to row {dof_map.max()} of a {M.shape[0]}-row matrix")


def read_table(value: Any, label: str, dtype: type) -> np.ndarray:
    """An array given directly, or read from a whitespace/comma separated text file (``label`` names it in errors)."""
    if isinstance(value, str | os.PathLike):
        try:
            text = Path(value).read_text().replace(",", " ")
            return np.atleast_2d(np.loadtxt(text.splitlines(), dtype=dtype))
        except (OSError, ValueError) as exc:
            raise ModalFileError(f"{os.fspath(value)}: cannot read {label!r}: {exc}") from None
    return np.asarray(value, dtype=dtype)


def read_fe(path: str | os.PathLike[str]) -> FEModel:
    """Read an FE model from a ``.npz`` with arrays ``M_data, M_indices, M_indptr, M_shape`` (and the same for
    ``K``; CSR parts as written by :meth:`FEModel.write_npz`) or dense ``M`` and ``K``, plus ``nodes`` (N, 3) [m],
    ``dof_map`` (N, 6) and optionally ``node_ids`` and ``elements``.

    Raises
    ------
    ModalFileError
        Missing, unreadable or inconsistent file; the message names the file and the array.
    """
    name = os.fspath(path)
    try:
        data = np.load(name, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise ModalFileError(f"{name}: cannot read FE matrices: {exc}") from None
    with data:
        def get(key: str) -> np.ndarray:
            if key not in data.files:
                raise ModalFileError(f"{name}: array {key!r} is missing (has {sorted(data.files)})")
            value = data[key]
            if not np.issubdtype(value.dtype, np.number):
                raise ModalFileError(f"{name}: array {key!r} must be numeric, got dtype {value.dtype}")
            return value

        mats = {}
        for key in ("M", "K"):
            if key in data.files:
                mats[key] = sp.csr_matrix(get(key).astype(float))
            else:
                shape = tuple(int(s) for s in get(f"{key}_shape"))
                mats[key] = sp.csr_matrix((get(f"{key}_data").astype(float), get(f"{key}_indices"),
                                           get(f"{key}_indptr")), shape=shape)
        nodes = get("nodes").astype(float)
        dof_map = get("dof_map").astype(np.int64)
        node_ids = get("node_ids").astype(np.int64) if "node_ids" in data.files else np.arange(nodes.shape[0])
        elements = get("elements").astype(np.int64) if "elements" in data.files else np.zeros((0, 2), np.int64)
    if nodes.ndim != 2 or nodes.shape[1] != 3 or not np.all(np.isfinite(nodes)):
        raise ModalFileError(f"{name}: 'nodes' must be finite with shape (N, 3), got {nodes.shape}")
    _check_matrices(name, mats["M"], mats["K"], nodes.shape[0], dof_map)
    try:
        return FEModel(mats["M"], mats["K"], nodes, dof_map, node_ids, elements, info={"source": name})
    except ValueError as exc:
        raise ModalFileError(f"{name}: {exc}") from None


def read_matrix_market(mass: str | os.PathLike[str], stiffness: str | os.PathLike[str],
                       nodes: np.ndarray | str | os.PathLike[str],
                       dof_map: np.ndarray | str | os.PathLike[str] | None = None) -> FEModel:
    """Read ``M`` and ``K`` from Matrix Market files (any FE code can export them) with the node coordinates
    [m] and DOF map as arrays or whitespace/comma separated text files.

    Parameters
    ----------
    mass, stiffness : path
        ``.mtx`` files of the mass [kg, kg m, kg m2] and stiffness [N/m, N, N m/rad] matrices.
    nodes : array (N, 3) or path
        Undeformed node coordinates [m].
    dof_map : array (N, 6) or path, optional
        Matrix row of each node's ``(ux, uy, uz, rx, ry, rz)``, ``-1`` if absent; default six DOFs per node in
        node order (``6 i + c``).

    Raises
    ------
    ModalFileError
        A file is missing or unreadable, or the matrices and maps do not fit together.
    """
    mats = []
    for label, p in (("M", mass), ("K", stiffness)):
        try:
            mats.append(sp.csr_matrix(scipy.io.mmread(os.fspath(p))).astype(float))
        except (OSError, ValueError) as exc:
            raise ModalFileError(f"{os.fspath(p)}: cannot read matrix {label!r} as Matrix Market: {exc}") from None

    xyz = read_table(nodes, "nodes", float)
    dmap = (np.arange(6 * xyz.shape[0]).reshape(-1, 6) if dof_map is None else read_table(dof_map, "dof_map", np.int64))
    source = os.fspath(stiffness)
    _check_matrices(source, mats[0], mats[1], xyz.shape[0], dmap)
    try:
        return FEModel(mats[0], mats[1], xyz, dmap, np.arange(xyz.shape[0]),
                       info={"source": [os.fspath(mass), os.fspath(stiffness)]})
    except ValueError as exc:
        raise ModalFileError(f"{source}: {exc}") from None
