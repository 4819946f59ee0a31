"""Finite-element mass and stiffness matrices with their node/DOF map, and their files (``.npz``, Matrix Market).

An :class:`FEModel` is what a producer of modal data starts from: scipy.sparse mass ``M`` [kg, kg m, kg m2]
and stiffness ``K`` [N/m, N, N m/rad] over a set of DOFs, the undeformed node coordinates [m] and a map
``dof_map[node, component]`` from a node and one of its six components ``(ux, uy, uz, rx, ry, rz)`` (translations
[m], small rotations [rad], in the body frame) to the row of ``M`` and ``K`` (``-1``: the node has no such DOF,
e.g. a constrained one or a solid element's rotation). Any FE code can supply these through
:func:`read_fe` (``.npz``) or :func:`read_matrix_market`; the built-in beam mesher
(:func:`~flexlib.fe.beam.beam_mesh`) produces them directly.

References
----------
- R. D. Cook, D. S. Malkus, M. E. Plesha, R. J. Witt, *Concepts and Applications of Finite Element Analysis*,
  4th ed., Wiley 2002, §2.8 (DOF numbering, assembly) and §11.3 (consistent and lumped mass).
- Matrix Market exchange format: R. F. Boisvert, R. Pozo, K. Remington, *The Matrix Market Exchange Formats:
  Initial Design*, NISTIR 5935, 1996 (read with :func:`scipy.io.mmread`).
"""

from __future__ import annotations

import numbers
import os
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import scipy.io
import scipy.sparse as sp

from flexlib.errors import ModalFileError, RunArgumentError

__all__ = ["COMPONENTS", "BeamElements", "FEModel", "MassPoints", "UnknownNodeError", "check_fe",
           "check_fields", "check_translational_mass", "read_fe", "read_matrix_market", "read_nodes"]

#: Names of the six components of a node, in ``dof_map`` column order.
COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")

#: What :func:`read_fe` reads, and the readers of the other FE matrix formats (for error messages).
_FORMATS = ("read_fe reads a .npz archive (FEModel.write_npz: CSR parts M_data/M_indices/M_indptr/M_shape and "
            "the same for K, or dense M and K, with nodes and dof_map); Matrix Market .mtx files: "
            "read_matrix_market(mass, stiffness, nodes, dof_map); Nastran: read_nastran_op4 / read_nastran_dmig; "
            "ANSYS .full: read_ansys_full")


class UnknownNodeError(RunArgumentError, KeyError):
    """A node id that the FE model does not have (a :class:`~flexlib.errors.RunArgumentError` and a ``KeyError``)."""

    def __str__(self) -> str:  # KeyError would show the repr of the message
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True, eq=False)
class MassPoints:
    """A mass description as points: the nine inertia invariants are sums over these points.

    For a *lumped* description the points are the FE nodes with their nodal masses and inertias; for a
    *consistent* one they are the Gauss points of the elements, weighted so that the sums integrate the
    element's density exactly (see :func:`~flexlib.fe.invariants.inertia_invariants`).

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
        self._normalise()
        n = self.M.shape[0]
        problems = []
        if self.M.shape != (n, n) or self.K.shape != (n, n):
            problems.append(f"M {self.M.shape} and K {self.K.shape} must be square and of equal size")
        if self.nodes.ndim != 2 or self.nodes.shape[1] != 3:
            problems.append(f"nodes must have shape (N, 3), got {self.nodes.shape}")
        elif not np.all(np.isfinite(self.nodes)):
            row = int(np.argwhere(~np.isfinite(self.nodes))[0, 0])
            problems.append(f"node {row} has a non-finite coordinate {self.nodes[row].tolist()} [m]")
        if self.dof_map.shape != (self.nodes.shape[0], 6):
            problems.append(f"dof_map must have shape (N, 6) = {(self.nodes.shape[0], 6)}, got {self.dof_map.shape}")
        elif self.dof_map.size:
            used = self.dof_map[self.dof_map >= 0]
            if np.any(self.dof_map < -1):
                problems.append(f"dof_map holds {int(self.dof_map.min())}: rows are >= 0, or -1 for an absent DOF")
            elif used.size and (used.max() >= n or len(np.unique(used)) != used.size):
                problems.append("dof_map rows must be distinct and below the matrix size")
            elif used.size != n and not (self.M.shape != (n, n) or self.K.shape != (n, n)):
                free = np.setdiff1d(np.arange(n), used)
                problems.append(f"rows {_ranges(free)} of the {n}-row matrices belong to no node (dof_map maps "
                                f"{used.size} rows): their mass and stiffness would be lost from the body")
        if self.node_ids.shape != (self.nodes.shape[0],) or len(np.unique(self.node_ids)) != self.node_ids.size:
            problems.append("node_ids must be one distinct id per node")
        if problems:
            raise RunArgumentError("FEModel: " + "; ".join(problems))

    def _normalise(self) -> None:
        """The fields as the methods use them: CSR matrices of floats, float node coordinates, integer maps and ids
        (a dense matrix or a list of lists is taken as given); anything else is a
        :class:`~flexlib.errors.RunArgumentError` naming the field."""
        for name in ("M", "K"):
            A = getattr(self, name)
            if sp.issparse(A) and A.format == "csr" and A.dtype.kind == "f":
                continue
            kind = A.dtype.kind if sp.issparse(A) else _kind(A)
            if kind not in "iuf":
                raise RunArgumentError(f"FEModel: argument {name!r} must be a real matrix (scipy.sparse or a dense "
                                       f"array of numbers), got {type(A).__name__} {A!r:.60}"
                                       + ("; read matrix files with read_fe or read_matrix_market" if kind == "U"
                                          else ""))
            object.__setattr__(self, name, sp.csr_matrix(A, dtype=float))
        for name, integer in (("nodes", False), ("dof_map", True), ("node_ids", True), ("elements", True)):
            value = getattr(self, name)
            kind = _kind(value)
            if kind not in "iuf":
                raise RunArgumentError(f"FEModel: argument {name!r} must be an array of "
                                       f"{'whole ' if integer else ''}numbers, got {type(value).__name__} "
                                       f"{value!r:.60}")
            a = np.asarray(value)
            if integer and kind == "f":
                bad = ~np.isfinite(a) | (a != np.round(a))
                if np.any(bad):
                    raise RunArgumentError(f"FEModel: argument {name!r} must hold whole numbers, got "
                                           f"{float(a[bad][0])!r}")
            a = a.astype(np.int64 if integer else float, copy=False)
            if a is not value:
                object.__setattr__(self, name, a)

    def dof_label(self, row: int) -> str:
        """``"node 7 uz (row 44)"``: the node id and component of a matrix row (for messages)."""
        hit = np.argwhere(self.dof_map == int(row))
        if hit.size == 0:
            return f"row {int(row)}"
        p, c = (int(v) for v in hit[0])
        return f"node {int(self.node_ids[p])} {COMPONENTS[c]} (row {int(row)})"

    def source_label(self, matrix: str = "K") -> str:
        """Where the model (its ``"M"`` or ``"K"``) came from, for messages: the file, or the producer."""
        source = self.info.get("source")
        if isinstance(source, list | tuple) and len(source) == 2:  # Matrix Market: [mass file, stiffness file]
            return str(source[0 if matrix == "M" else 1])
        if source:
            return str(source)
        return f"FE model from {self.info['producer']}" if self.info.get("producer") else "FE model (in memory)"

    @property
    def from_file(self) -> bool:
        """The model was read from a file (``info["source"]``)."""
        return bool(self.info.get("source"))

    @property
    def n_dofs(self) -> int:
        """Number of DOFs (rows of ``M``)."""
        return int(self.M.shape[0])

    def node_index(self, node_ids: Sequence[int] | np.ndarray) -> np.ndarray:
        """Indices into ``nodes`` of the given node ids; a clear error names an unknown id."""
        lookup = {int(i): k for k, i in enumerate(self.node_ids)}
        out = []
        for i in _node_id_list(node_ids, "FEModel: node ids"):
            if int(i) not in lookup:
                raise UnknownNodeError(f"FEModel: no node with id {int(i)} (ids {self.node_ids.min()}.."
                                       f"{self.node_ids.max()}, {self.node_ids.size} nodes)")
            out.append(lookup[int(i)])
        return np.asarray(out, dtype=np.int64)

    def dofs(self, node_ids: Sequence[int] | np.ndarray, components: Sequence[str] = COMPONENTS) -> np.ndarray:
        """DOF rows of the given nodes (by id) and components (names from :data:`COMPONENTS`), skipping absent ones."""
        cols = [COMPONENTS.index(c) for c in _component_list(components)]
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
        components = _component_list(components)
        fixed = set(self.dofs(node_ids, components).tolist())
        keep = np.array([i for i in range(self.n_dofs) if i not in fixed], dtype=np.int64)
        new_index = -np.ones(self.n_dofs, dtype=np.int64)
        new_index[keep] = np.arange(keep.size)
        dof_map = np.where(self.dof_map >= 0, new_index[np.maximum(self.dof_map, 0)], -1)
        info = dict(self.info)
        info["constrained"] = [*info.get("constrained", []), {"nodes": [int(i) for i in _node_id_list(node_ids, "")],
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
        RunArgumentError
            (a ``ValueError``) Unknown node, a mass that is not a number >= 0 (text, a bool, NaN), ``offsets`` or
            ``inertias`` of the wrong shape, an inertia that is not symmetric positive semidefinite, an offset on
            a node without rotations; the message names the argument.
        """
        func = "FEModel.with_point_masses"
        idx = self.node_index(node_ids)
        k = idx.size
        m = _real_array(func, "masses", masses, "masses [kg]").reshape(-1)
        if m.shape != (k,):
            raise RunArgumentError(f"{func}: {k} nodes but {m.size} masses (nodes {self.node_ids[idx].tolist()}, "
                                   f"masses {m.tolist()} [kg]): give one mass per node")
        d = np.zeros((k, 3)) if offsets is None else _real_array(func, "offsets", offsets, "offsets [m]")
        J = np.zeros((k, 3, 3)) if inertias is None else _real_array(func, "inertias", inertias, "inertias [kg m2]")
        for name, a, shape in (("offsets", d, (k, 3)), ("inertias", J, (k, 3, 3))):
            if a.shape != shape and a.size != int(np.prod(shape)):
                raise RunArgumentError(f"{func}: argument {name!r} has shape {a.shape}, expected {shape} (one per "
                                       f"mass)")
        d, J = d.reshape(k, 3), J.reshape(k, 3, 3)
        if np.any(m < 0):
            raise RunArgumentError(f"{func}: negative mass {float(m[m < 0][0])!r} kg at node "
                                   f"{int(self.node_ids[idx[np.argmax(m < 0)]])}")
        if np.abs(J - J.transpose(0, 2, 1)).max(initial=0.0) > 1e-12 * max(np.abs(J).max(initial=0.0), 1.0) or \
                np.any(np.linalg.eigvalsh((J + J.transpose(0, 2, 1)) / 2) < -1e-12 * max(np.abs(J).max(initial=0.0),
                                                                                         1.0)):
            raise RunArgumentError(f"{func}: argument 'inertias' must be symmetric positive semidefinite 3 x 3 "
                                   "tensors [kg m2]")
        rows_t, rows_r, cols_t, cols_r, vals_t = [], [], [], [], []
        add = sp.lil_matrix((self.n_dofs, self.n_dofs))
        loads = np.zeros((self.n_dofs, 3))
        base = 0 if self.mass_points is None else self.mass_points.masses.size
        for j in range(k):
            dof = self.dof_map[idx[j]]
            if np.any(dof[:3] < 0) or ((np.any(d[j]) or np.any(J[j])) and np.any(dof[3:] < 0)):
                raise RunArgumentError(f"{func}: node {int(self.node_ids[idx[j]])} lacks the DOFs the mass needs "
                                       "(translations; rotations for an offset or inertia): attach it before "
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
        vector = _vector3("FEModel.translation_field", "vector", vector, "[m]")
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
        return self.gravity_loads() @ _vector3("FEModel.gravity_load", "g", g, "[m/s2]")

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
        readable by :func:`read_fe` (atomically: temporary file then ``os.replace``).

        Raises
        ------
        RunArgumentError
            ``path`` is not a str or os.PathLike.
        ModalFileError
            The file cannot be written (a missing directory, no permission); the message names it and nothing is
            left behind.
        """
        if not isinstance(path, str | os.PathLike):
            raise RunArgumentError(f"FEModel.write_npz: argument 'path' must be a path (str or os.PathLike) of the "
                                   f".npz to write, got {type(path).__name__} {path!r}")
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
        except OSError as exc:
            raise ModalFileError(f"{path}: cannot write the FE model archive: {exc}") from None
        finally:
            if tmp.exists():
                tmp.unlink()


def _kind(value: Any) -> str:
    """The numpy dtype kind of ``value`` as an array (``"U"`` for text, ``"O"`` for what is not a regular array)."""
    if isinstance(value, str | bytes | os.PathLike):
        return "U"
    try:
        return np.asarray(value).dtype.kind
    except (TypeError, ValueError):
        return "O"


def _node_id_list(node_ids: Any, where: str) -> list[int]:
    """Node ids as ints: whole numbers (ints, or floats without a fraction, as FE tables give them); a string, a bool
    or a fractional number is a :class:`UnknownNodeError` naming it (``where``: the caller, for the message)."""
    items = np.atleast_1d(np.asarray(node_ids, dtype=object)).ravel().tolist() if not isinstance(
        node_ids, str | bytes) else [node_ids]
    out = []
    for i in items:
        if isinstance(i, bool | np.bool_) or not isinstance(i, numbers.Real) or not float(i).is_integer():
            digits = isinstance(i, str) and i.strip().lstrip("-").isdigit()
            hint = f" (write {int(i)}, without quotes)" if digits else ""
            raise UnknownNodeError(f"{where or 'FEModel'}: node id {i!r} ({type(i).__name__}) is not a node id: ids "
                                   f"are whole numbers{hint}")
        out.append(int(i))
    return out


def _component_list(components: Any) -> tuple[str, ...]:
    """Component names, each one of :data:`COMPONENTS`; a single string is refused with a hint (it would be read
    letter by letter)."""
    if isinstance(components, str):
        raise RunArgumentError(f"FEModel: components must be a list of names from {list(COMPONENTS)}, got the string "
                               f"{components!r}" + (f" (for one component: [{components!r}])"
                                                    if components in COMPONENTS else ""))
    try:
        names = tuple(components)
    except TypeError:
        raise RunArgumentError(f"FEModel: components must be a list of names from {list(COMPONENTS)}, got "
                               f"{components!r}") from None
    for c in names:
        if c not in COMPONENTS:
            hint = f" (did you mean {c.lower()!r}?)" if isinstance(c, str) and c.lower() in COMPONENTS else ""
            raise RunArgumentError(f"FEModel: unknown component {c!r}; components are {list(COMPONENTS)}{hint}")
    return names


def _real_array(func: str, name: str, value: Any, what: str) -> np.ndarray:
    """An array of finite real numbers (not text, bools or complex), naming the argument."""
    if _kind(value) not in "iuf":
        raise RunArgumentError(f"{func}: argument {name!r} must be {what}, numbers, got {value!r:.80}")
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        raise RunArgumentError(f"{func}: argument {name!r} has non-finite values: {a.ravel()[:6].tolist()}")
    return a


def check_fe(func: str, fe: Any, *, beam: bool = False) -> FEModel:
    """``fe`` an :class:`FEModel` (from ``beam_mesh`` if ``beam``), else a :class:`~flexlib.errors.RunArgumentError`
    naming the function."""
    if not isinstance(fe, FEModel):
        raise RunArgumentError(f"{func}: argument 'fe' must be an FEModel (beam_mesh, read_fe, read_matrix_market or "
                               f"an importer), got {type(fe).__name__} {fe!r:.60}")
    if beam and fe.beam is None:
        raise RunArgumentError(f"{func}: the FE model has no frame-element data (not from beam_mesh)")
    return fe


def check_fields(func: str, fe: Any, fields: Any, name: str = "modes", *, ndim: tuple[int, ...] = (2,),
                 beam: bool = False) -> np.ndarray:
    """``fe`` an :class:`FEModel` (from ``beam_mesh`` if ``beam``) and ``fields`` finite numbers with one row per DOF
    of it, of ``ndim`` dimensions: the arguments of the building blocks (section forces, static responses, geometric
    stiffness), each error a :class:`~flexlib.errors.RunArgumentError` naming the function and the argument."""
    check_fe(func, fe, beam=beam)
    a = _real_array(func, name, fields, "displacement or load fields on the FE DOFs")
    if a.ndim not in ndim or a.shape[0] != fe.n_dofs:
        shapes = " or ".join(f"({fe.n_dofs},)" if k == 1 else f"({fe.n_dofs}, k)" for k in ndim)
        raise RunArgumentError(f"{func}: argument {name!r} has shape {a.shape}, expected {shapes}: one row per DOF of "
                               f"the FE model ({fe.n_dofs} DOFs)")
    return a


def _vector3(func: str, name: str, value: Any, unit: str) -> np.ndarray:
    a = _real_array(func, name, value, f"three numbers (x, y, z) {unit}")
    if a.shape != (3,):
        raise RunArgumentError(f"{func}: argument {name!r} must be three numbers (x, y, z) {unit}, got shape "
                               f"{a.shape}: {value!r}")
    return a


def _ranges(rows: np.ndarray, limit: int = 8) -> str:
    """``"24..29, 31"``: sorted integers as runs (for messages)."""
    rows = np.unique(np.asarray(rows, dtype=np.int64))
    runs: list[str] = []
    start = prev = None
    for r in [*rows.tolist(), None]:
        if r is not None and prev is not None and r == prev + 1:
            prev = r
            continue
        if start is not None:
            runs.append(str(start) if start == prev else f"{start}..{prev}")
        start = prev = r
    return ", ".join(runs[:limit]) + (" ..." if len(runs) > limit else "")


def _label_rows(dof_map: np.ndarray, node_ids: np.ndarray | None = None) -> Any:
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


def _check_matrices(path: str | tuple[str, str], M: sp.spmatrix, K: sp.spmatrix, n_nodes: int,
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
    label = _label_rows(dof_map, node_ids)
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
                    f"{_ranges(np.arange(n_nodes, n // 6))}"
                    f" — {n // 6} nodes for the matrices, {n_nodes} in the node list: is a node missing from it?")
        elif default_map:
            hint = f": {n} rows are not six per node — pass dof_map"
        raise ModalFileError(f"{both}: matrix rows {_ranges(free)} (of {n}) belong to no node in the node list "
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
        kind = _kind(value)
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


def _check_file(path: Any, what: str, argument: str) -> str:
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
    name = _check_file(path, "an FE model .npz archive", "path")
    with open(name, "rb") as f:
        magic = f.read(6)
    if not zipfile.is_zipfile(name):
        kind = ("a single numpy array (.npy)" if magic == b"\x93NUMPY" else
                "a Matrix Market file" if magic.startswith(b"%%Matr") else "not a .npz (zip) archive")
        raise ModalFileError(f"{name}: {kind}, not an FE model archive: {_FORMATS}")
    try:
        data = np.load(name, allow_pickle=False)
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise ModalFileError(f"{name}: cannot read FE matrices: {exc}") from None
    with data:
        def get(key: str) -> np.ndarray:
            if key not in data.files:
                raise ModalFileError(f"{name}: array {key!r} is missing (has {sorted(data.files)}); {_FORMATS}")
            try:
                value = data[key]
            except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
                raise ModalFileError(f"{name}: array {key!r} cannot be read: {exc}") from None
            if not np.issubdtype(value.dtype, np.number) or np.issubdtype(value.dtype, np.complexfloating):
                raise ModalFileError(f"{name}: array {key!r} must be real numbers, got dtype {value.dtype}")
            return value

        def whole(key: str, value: np.ndarray) -> np.ndarray:
            if not np.issubdtype(value.dtype, np.integer):
                bad = ~np.isfinite(value) | (value != np.round(value))
                if np.any(bad):
                    raise ModalFileError(f"{name}: array {key!r} must hold whole numbers, got "
                                         f"{float(value.ravel()[np.argmax(bad.ravel())])!r}")
            return value.astype(np.int64)

        mats = {}
        for key in ("M", "K"):
            if key in data.files:
                dense = get(key)
                if dense.ndim != 2:
                    raise ModalFileError(f"{name}: array {key!r} must be a 2-D matrix, got shape {dense.shape}")
                mats[key] = sp.csr_matrix(dense.astype(float))
            else:
                shape = whole(f"{key}_shape", get(f"{key}_shape")).ravel()
                if shape.size != 2 or np.any(shape < 0):
                    raise ModalFileError(f"{name}: array '{key}_shape' must be two sizes (rows, columns), got "
                                         f"{shape.tolist()}")
                try:
                    mats[key] = sp.csr_matrix((get(f"{key}_data").astype(float),
                                               whole(f"{key}_indices", get(f"{key}_indices")),
                                               whole(f"{key}_indptr", get(f"{key}_indptr"))),
                                              shape=(int(shape[0]), int(shape[1])))
                    mats[key].check_format(full_check=True)
                except (ValueError, TypeError, IndexError) as exc:
                    raise ModalFileError(f"{name}: the CSR arrays {key}_data, {key}_indices, {key}_indptr, "
                                         f"{key}_shape do not form a matrix: {exc}") from None
        nodes = get("nodes").astype(float)
        dof_map = whole("dof_map", get("dof_map"))
        node_ids = whole("node_ids", get("node_ids")).ravel() if "node_ids" in data.files else None
        elements = whole("elements", get("elements")) if "elements" in data.files else np.zeros((0, 2), np.int64)
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
    _check_matrices(name, mats["M"], mats["K"], nodes.shape[0], dof_map, nodes_source=f"{name} 'nodes'",
                    node_ids=node_ids)
    try:
        return FEModel(mats["M"], mats["K"], nodes, dof_map, node_ids, elements, info={"source": name})
    except ValueError as exc:
        raise ModalFileError(f"{name}: {exc}") from None


def _read_mtx(path: Any, label: str, argument: str) -> sp.csr_matrix:
    """One real matrix from a Matrix Market file (coordinate or array; general or symmetric)."""
    name = _check_file(path, f"a Matrix Market file of matrix {label!r}", argument)
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
    _check_matrices(files, M, K, xyz.shape[0], dmap, nodes_source=where, node_ids=ids, default_map=default)
    try:
        return FEModel(M, K, xyz, dmap, ids, info={"source": list(files)})
    except ValueError as exc:
        raise ModalFileError(f"{files[1]}: {exc}") from None
