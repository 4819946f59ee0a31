"""Finite-element mass and stiffness matrices with their node/DOF map: the :class:`FEModel` record.

An :class:`FEModel` is what a producer of modal data starts from: scipy.sparse mass ``M`` [kg, kg m, kg m2]
and stiffness ``K`` [N/m, N, N m/rad] over a set of DOFs, the undeformed node coordinates [m] and a map
``dof_map[node, component]`` from a node and one of its six components ``(ux, uy, uz, rx, ry, rz)`` (translations
[m], small rotations [rad], in the body frame) to the row of ``M`` and ``K`` (``-1``: the node has no such DOF,
e.g. a constrained one or a solid element's rotation). Any FE code can supply these through
:func:`~flexlib.fe.matrix_files.read_fe` (``.npz``), :func:`~flexlib.fe.matrix_files.read_matrix_market` or the
importers (:mod:`flexlib.fe.importers`); the built-in beam mesher
(:func:`~flexlib.fe.beam.beam_mesh`) produces them directly.

References
----------
- R. D. Cook, D. S. Malkus, M. E. Plesha, R. J. Witt, *Concepts and Applications of Finite Element Analysis*,
  4th ed., Wiley 2002, §2.8 (DOF numbering, assembly) and §11.3 (consistent and lumped mass).
"""

from __future__ import annotations

import numbers
import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from flexlib.errors import ModalFileError, RunArgumentError

from .arguments import COMPONENTS, array_kind, component_list, real_array, row_ranges, vector3

__all__ = ["BeamElements", "FEModel", "MassPoints", "UnknownNodeError", "check_fe", "check_fields",
           "node_id_list"]

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
                problems.append(f"rows {row_ranges(free)} of the {n}-row matrices belong to no node (dof_map maps "
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
            kind = A.dtype.kind if sp.issparse(A) else array_kind(A)
            if kind not in "iuf":
                raise RunArgumentError(f"FEModel: argument {name!r} must be a real matrix (scipy.sparse or a dense "
                                       f"array of numbers), got {type(A).__name__} {A!r:.60}"
                                       + ("; read matrix files with read_fe or read_matrix_market" if kind == "U"
                                          else ""))
            object.__setattr__(self, name, sp.csr_matrix(A, dtype=float))
        for name, integer in (("nodes", False), ("dof_map", True), ("node_ids", True), ("elements", True)):
            value = getattr(self, name)
            kind = array_kind(value)
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
        for i in node_id_list(node_ids, "FEModel: node ids"):
            if int(i) not in lookup:
                raise UnknownNodeError(f"FEModel: no node with id {int(i)} (ids {self.node_ids.min()}.."
                                       f"{self.node_ids.max()}, {self.node_ids.size} nodes)")
            out.append(lookup[int(i)])
        return np.asarray(out, dtype=np.int64)

    def dofs(self, node_ids: Sequence[int] | np.ndarray, components: Sequence[str] = COMPONENTS) -> np.ndarray:
        """DOF rows of the given nodes (by id) and components (names from :data:`COMPONENTS`), skipping absent ones."""
        cols = [COMPONENTS.index(c) for c in component_list(components)]
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
        components = component_list(components)
        fixed = set(self.dofs(node_ids, components).tolist())
        keep = np.array([i for i in range(self.n_dofs) if i not in fixed], dtype=np.int64)
        new_index = -np.ones(self.n_dofs, dtype=np.int64)
        new_index[keep] = np.arange(keep.size)
        dof_map = np.where(self.dof_map >= 0, new_index[np.maximum(self.dof_map, 0)], -1)
        info = dict(self.info)
        info["constrained"] = [*info.get("constrained", []), {"nodes": [int(i) for i in node_id_list(node_ids, "")],
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
        m, d, J = self._point_mass_arguments(func, idx, masses, offsets, inertias)
        k = idx.size
        rows: list[np.ndarray] = []
        cols: list[np.ndarray] = []
        vals: list[np.ndarray] = []
        loads = np.zeros((self.n_dofs, 3))
        base = 0 if self.mass_points is None else self.mass_points.masses.size
        selectors: dict[str, list] = {"rows_t": [], "cols_t": [], "vals_t": [], "rows_r": [], "cols_r": []}
        for j in range(k):
            dof = self.dof_map[idx[j]]
            if np.any(dof[:3] < 0) or ((np.any(d[j]) or np.any(J[j])) and np.any(dof[3:] < 0)):
                raise RunArgumentError(f"{func}: node {int(self.node_ids[idx[j]])} lacks the DOFs the mass needs "
                                       "(translations; rotations for an offset or inertia): attach it before "
                                       "constraining the node")
            N = _rigid_offset_map(d[j])
            block = m[j] * N.T @ N
            block[3:, 3:] += J[j]
            live = np.flatnonzero(dof >= 0)
            rows.append(np.repeat(dof[live], live.size))
            cols.append(np.tile(dof[live], live.size))
            vals.append(block[np.ix_(live, live)].ravel())
            loads[dof[live]] += (m[j] * N.T)[live]
            _point_selector_entries(selectors, 3 * (base + j), N, dof, live)
        add = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                            shape=(self.n_dofs, self.n_dofs)) if k else sp.csr_matrix((self.n_dofs, self.n_dofs))
        M = (self.M + add.tocsr()).tocsr()  # duplicates (several masses on a node) are summed
        points = self.mass_points
        if points is not None:
            points = _appended_mass_points(points, self.nodes[idx] + d, m, J, selectors, self.n_dofs)
        info = dict(self.info)
        info["point_masses"] = [*info.get("point_masses", []),
                                {"count": k, "total_kg": float(m.sum())}]
        unit_loads = None if self.unit_loads is None else self.unit_loads + loads
        return replace(self, M=M, mass_points=points, info=info, unit_loads=unit_loads)

    def _point_mass_arguments(self, func: str, idx: np.ndarray, masses: Any, offsets: Any,
                              inertias: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The masses (k,) [kg], offsets (k, 3) [m] and inertias (k, 3, 3) [kg m2] of :meth:`with_point_masses`,
        checked: one per node, masses >= 0, inertias symmetric positive semidefinite."""
        k = idx.size
        m = real_array(func, "masses", masses, "masses [kg]").reshape(-1)
        if m.shape != (k,):
            raise RunArgumentError(f"{func}: {k} nodes but {m.size} masses (nodes {self.node_ids[idx].tolist()}, "
                                   f"masses {m.tolist()} [kg]): give one mass per node")
        d = np.zeros((k, 3)) if offsets is None else real_array(func, "offsets", offsets, "offsets [m]")
        J = np.zeros((k, 3, 3)) if inertias is None else real_array(func, "inertias", inertias, "inertias [kg m2]")
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
        return m, d, J

    def translation_field(self, vector: Sequence[float]) -> np.ndarray:
        """DOF vector of a uniform translation ``vector`` [m] of all nodes (rotations zero)."""
        vector = vector3("FEModel.translation_field", "vector", vector, "[m]")
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
        return self.gravity_loads() @ vector3("FEModel.gravity_load", "g", g, "[m/s2]")

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
        readable by :func:`~flexlib.fe.matrix_files.read_fe` (atomically: temporary file then ``os.replace``).

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


def _rigid_offset_map(d: np.ndarray) -> np.ndarray:
    """``N = [I, -[d x]]`` (3 x 6): a point at offset ``d`` [m] from a node moves by ``u + theta x d``."""
    N = np.zeros((3, 6))
    N[:, :3] = np.eye(3)
    dx = np.array([[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]], [-d[1], d[0], 0.0]])
    N[:, 3:] = -dx
    return N


def _point_selector_entries(selectors: dict[str, list], row0: int, N: np.ndarray, dof: np.ndarray,
                            live: np.ndarray) -> None:
    """Append a point mass's rows (from ``row0``) of the translational (``N`` on the node's DOFs) and rotational
    (the node's rotations) selectors of :class:`MassPoints`."""
    for a in range(3):
        for c in live:
            if N[a, c] != 0.0:
                selectors["rows_t"].append(row0 + a)
                selectors["cols_t"].append(dof[c])
                selectors["vals_t"].append(N[a, c])
        if dof[3 + a] >= 0:
            selectors["rows_r"].append(row0 + a)
            selectors["cols_r"].append(dof[3 + a])


def _appended_mass_points(points: MassPoints, positions: np.ndarray, m: np.ndarray, J: np.ndarray,
                          selectors: dict[str, list], n_dofs: int) -> MassPoints:
    """``points`` with ``k`` point masses at ``positions`` [m] (masses ``m`` [kg], inertias ``J`` [kg m2]) added,
    their selector rows from :func:`_point_selector_entries`."""
    k = m.size
    shape = (3 * (points.masses.size + k), n_dofs)
    Nt = sp.vstack([points.Nt, sp.csr_matrix((3 * k, n_dofs))]).tocsr() + sp.csr_matrix(
        (selectors["vals_t"], (selectors["rows_t"], selectors["cols_t"])), shape=shape)
    Nr = sp.vstack([points.Nr, sp.csr_matrix((3 * k, n_dofs))]).tocsr() + sp.csr_matrix(
        (np.ones(len(selectors["rows_r"])), (selectors["rows_r"], selectors["cols_r"])), shape=shape)
    return MassPoints(np.vstack([points.positions, positions]), np.concatenate([points.masses, m]),
                      np.concatenate([points.inertias, J]), Nt.tocsr(), Nr.tocsr(),
                      points.description + f" + {k} point masses")


def node_id_list(node_ids: Any, where: str) -> list[int]:
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
    a = real_array(func, name, fields, "displacement or load fields on the FE DOFs")
    if a.ndim not in ndim or a.shape[0] != fe.n_dofs:
        shapes = " or ".join(f"({fe.n_dofs},)" if k == 1 else f"({fe.n_dofs}, k)" for k in ndim)
        raise RunArgumentError(f"{func}: argument {name!r} has shape {a.shape}, expected {shapes}: one row per DOF of "
                               f"the FE model ({fe.n_dofs} DOFs)")
    return a


