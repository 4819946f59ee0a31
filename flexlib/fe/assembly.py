"""Joining FE models into one: frames of several beam meshes (a spider of spokes on a tube, a truss), or any FE
models that share nodes (SI units).

:func:`join_models` merges the nodes of the given models that coincide (within ``tol``), shares their DOFs (a
rigid joint: the six components are equal), and adds the matrices, so that a frame built from several straight
:func:`~flexlib.fe.beam.beam_mesh` members is one :class:`~flexlib.fe.fe_model.FEModel` with its mass points and
frame-element data, ready for :func:`~flexlib.fe.modal_from_fe.modal_data_from_fe`.

References
----------
- R. D. Cook, D. S. Malkus, M. E. Plesha, R. J. Witt, *Concepts and Applications of Finite Element Analysis*,
  4th ed., Wiley 2002, §2.8 (DOF numbering and assembly of element matrices into global ones).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from flexlib.errors import RunArgumentError

from .fe_model import BeamElements, FEModel, MassPoints

__all__ = ["join_models"]


def join_models(models: Sequence[FEModel], *, tol: float = 1e-9) -> FEModel:
    """One FE model from several whose coinciding nodes are joined rigidly.

    Nodes of different models closer than ``tol`` become one node, whose DOFs every model at it shares (a
    welded joint); the mass and stiffness matrices, the unit acceleration loads, the mass points and the
    frame-element data are assembled over the joined DOF numbering. Nodes are numbered ``0 .. N-1`` in the order
    of first appearance (the first model's nodes first, in their order).

    Parameters
    ----------
    models : sequence of FEModel
        The parts, at least one, in one body frame [m]; a part's own nodes must not coincide.
    tol : float
        Distance below which two nodes are one [m].

    Returns
    -------
    FEModel
        The joined model; its mass points are the parts' (``"consistent"`` if every part's are, else ``"lumped"``), its
        frame-element data the parts' elements (when every part has them: beam meshes), ``info["parts"]`` the
        parts' provenance.

    Raises
    ------
    RunArgumentError
        ``models`` empty or holding something other than an FEModel, ``tol`` not a finite number > 0, coinciding
        nodes within one part, parts whose element tables differ in width.
    """
    func = "join_models"
    parts = list(models) if isinstance(models, Sequence) and not isinstance(models, str | bytes) else None
    if not parts or not all(isinstance(m, FEModel) for m in parts):
        raise RunArgumentError(f"{func}: argument 'models' must be a non-empty sequence of FEModel, got {models!r:.80}")
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real) or not (math.isfinite(tol) and tol > 0):
        raise RunArgumentError(f"{func}: tol must be a finite distance > 0 m, got {tol!r}")
    nodes, index = _joined_nodes(func, parts, float(tol))
    dof_map = -np.ones((len(nodes), 6), dtype=np.int64)
    for part, where in zip(parts, index, strict=True):
        has = part.dof_map >= 0
        dof_map[where] = np.where(has, 0, dof_map[where])  # mark the components any part has
    live = dof_map >= 0
    dof_map[live] = np.arange(int(live.sum()))
    n = int(live.sum())
    selections = [_selection(part, where, dof_map, n) for part, where in zip(parts, index, strict=True)]
    M = sum((S.T @ part.M @ S for part, S in zip(parts, selections, strict=True)), sp.csr_matrix((n, n)))
    K = sum((S.T @ part.K @ S for part, S in zip(parts, selections, strict=True)), sp.csr_matrix((n, n)))
    loads = sum((S.T @ part.gravity_loads() for part, S in zip(parts, selections, strict=True)), np.zeros((n, 3)))
    widths = {part.elements.shape[1] for part in parts if part.elements.size}
    if len(widths) > 1:
        raise RunArgumentError(f"{func}: the parts' element tables have different widths {sorted(widths)}: join "
                               "models of one element kind (their elements are for drawing)")
    elements = np.vstack([where[part.elements] for part, where in zip(parts, index, strict=True)
                          if part.elements.size] or [np.zeros((0, 2), dtype=np.int64)])
    info: dict[str, Any] = {"producer": "flexlib join_models", "parts": [dict(part.info) for part in parts]}
    return FEModel(M.tocsr(), K.tocsr(), nodes, dof_map, np.arange(len(nodes)), elements,
                   _mass_points(parts, selections), info, unit_loads=loads, beam=_beam(parts, selections))


def _joined_nodes(func: str, parts: list[FEModel], tol: float) -> tuple[np.ndarray, list[np.ndarray]]:
    """The joined nodes (N, 3) [m] and, per part, the joined index of each of its nodes."""
    nodes: list[np.ndarray] = []
    index = []
    for k, part in enumerate(parts):
        where = np.empty(part.nodes.shape[0], dtype=np.int64)
        for i, x in enumerate(part.nodes):
            hit = [j for j, y in enumerate(nodes) if np.linalg.norm(x - y) < tol]
            if hit and hit[0] in where[:i]:
                raise RunArgumentError(f"{func}: nodes {int(part.node_ids[list(where[:i]).index(hit[0])])} and "
                                       f"{int(part.node_ids[i])} of part {k} coincide at {x.tolist()} m: a part's "
                                       "own nodes must be distinct")
            if hit:
                where[i] = hit[0]
            else:
                where[i] = len(nodes)
                nodes.append(np.asarray(x, dtype=float))
        index.append(where)
    return np.array(nodes), index


def _selection(part: FEModel, where: np.ndarray, dof_map: np.ndarray, n: int) -> sp.csr_matrix:
    """``S`` (n_part, n) with ``S[i, j] = 1`` where the part's DOF ``i`` is the joined DOF ``j``."""
    has = part.dof_map >= 0
    rows = part.dof_map[has]
    cols = dof_map[where][has]
    return sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(part.n_dofs, n))


def _mass_points(parts: list[FEModel], selections: list[sp.csr_matrix]) -> MassPoints:
    """The parts' mass points (their own, or lumped from ``M``) on the joined DOFs."""
    points = [part.mass_points if part.mass_points is not None else part.lumped_mass_points() for part in parts]
    kind = "consistent" if all(p.description.startswith("consistent") for p in points) else "lumped"
    return MassPoints(np.vstack([p.positions for p in points]), np.concatenate([p.masses for p in points]),
                      np.concatenate([p.inertias for p in points]),
                      sp.vstack([p.Nt @ S for p, S in zip(points, selections, strict=True)]).tocsr(),
                      sp.vstack([p.Nr @ S for p, S in zip(points, selections, strict=True)]).tocsr(),
                      f"{kind} (joined: {'; '.join(sorted({p.description for p in points}))})")


def _beam(parts: list[FEModel], selections: list[sp.csr_matrix]) -> BeamElements | None:
    """The parts' frame elements on the joined DOFs (``None`` unless every part has them)."""
    if any(part.beam is None for part in parts):
        return None
    dofs = []
    for part, S in zip(parts, selections, strict=True):
        new_index = np.asarray(S.argmax(axis=1)).ravel()  # each part DOF's joined DOF (one 1 per row)
        dofs.append(np.where(part.beam.dofs >= 0, new_index[np.maximum(part.beam.dofs, 0)], -1))
    beams = [part.beam for part in parts]

    def joined(name: str) -> np.ndarray:
        return np.concatenate([getattr(b, name) for b in beams])

    return BeamElements(joined("k_local"), joined("rotation"), np.concatenate(dofs), joined("A"), joined("Iy"),
                        joined("Iz"))
