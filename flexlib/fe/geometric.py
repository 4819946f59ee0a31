"""Geometric (stress) stiffening data: modal geometric stiffness matrices per unit load case.

A linear modal body lacks the stiffening of a beam under axial load (the centrifugal stiffening of a rotating
blade, the softening of a compressed link). Following Wallrapp & Schwertassek, the stress state of the body is
written as a superposition of unit load cases — the d'Alembert body forces of the frame's translational
acceleration (3), angular acceleration (3) and the centrifugal field of its angular velocity (6 products
``omega_a omega_b``), and unit forces and moments at the interface nodes (6 per node) — each solved statically
on the FE model held at its support node(s). Each case's element axial forces give the geometric stiffness
``K_G`` of the FE model, projected on the modes: ``G_k = Phi^T K_G,k Phi``. A flexible body then adds
``sum_k c_k(t) G_k`` to its modal stiffness, with ``c_k`` the current accelerations, angular velocity products
and interface loads.

The frame element's geometric stiffness for a constant axial force ``P`` (tension positive) is the consistent
one of McGuire, Gallagher & Ziemian (2000), eq. 9.19, without the end-moment terms: bending blocks
``P/(30 L) [[36, 3L, -36, 3L], [3L, 4L^2, -3L, -L^2], ...]``, axial ``P/L``, torsion ``P Ip/(A L)``; the element's
``P`` is its (constant) axial force of the static solution, exact at the element midpoint for a linearly
varying axial load.

References
----------
- O. Wallrapp, R. Schwertassek, "Representation of geometric stiffening in multibody system simulation",
  *Int. J. Numer. Methods Eng.* 32 (1991) 1833-1850.
- W. McGuire, R. H. Gallagher, R. D. Ziemian, *Matrix Structural Analysis*, 2nd ed., Wiley 2000, §9.3,
  eq. 9.19.
- J. S. Przemieniecki, *Theory of Matrix Structural Analysis*, McGraw-Hill 1968, ch. 15 (geometric stiffness).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from .arguments import COMPONENTS
from .beam import section_force_modes
from .fe_model import FEModel, check_fe, check_fields

__all__ = [
    "geometric_stiffness_matrix",
    "inertial_load_amplitudes",
    "inertial_load_cases",
    "interface_load_cases",
    "modal_geometric_stiffness",
]

_AXES = "xyz"


def _local_kg(L: np.ndarray, P: np.ndarray, A: np.ndarray, Ip: np.ndarray) -> np.ndarray:
    """Local geometric stiffness ``(E, 12, 12)`` [N/m, N, N m] of frame elements of lengths ``L`` [m] under axial
    forces ``P`` [N] (tension positive), areas ``A`` [m2] and polar moments ``Ip`` [m4]."""
    L, P = np.asarray(L, dtype=float)[:, None, None], np.asarray(P, dtype=float)[:, None, None]
    k = np.zeros((L.shape[0], 12, 12))
    one = np.ones_like(L)
    b = P / (30.0 * L) * np.block([[36 * one, 3 * L, -36 * one, 3 * L], [3 * L, 4 * L**2, -3 * L, -(L**2)],
                                   [-36 * one, -3 * L, 36 * one, -3 * L], [3 * L, -(L**2), -3 * L, 4 * L**2]])
    iy = [1, 5, 7, 11]  # (v, rz): x-y plane
    k[:, iy[0]:iy[0] + 1, 0:0] = 0.0
    k[np.ix_(range(L.shape[0]), iy, iy)] += b
    iz = [2, 4, 8, 10]  # (w, -ry): x-z plane
    sign = np.array([1, -1, 1, -1])
    k[np.ix_(range(L.shape[0]), iz, iz)] += b * np.outer(sign, sign)
    ax = np.array([[1.0, -1.0], [-1.0, 1.0]])
    k[np.ix_(range(L.shape[0]), [0, 6], [0, 6])] += P / L * ax
    ratio = (np.asarray(Ip, dtype=float) / np.asarray(A, dtype=float))[:, None, None]
    k[np.ix_(range(L.shape[0]), [3, 9], [3, 9])] += P * ratio / L * ax
    return k


def geometric_stiffness_matrix(fe: FEModel, displacement: np.ndarray) -> sp.csr_matrix:
    """Geometric stiffness ``K_G`` [N/m, N, N m] of a beam model in the stress state of a static ``displacement``.

    Parameters
    ----------
    fe : FEModel
        A model from :func:`~flexlib.fe.beam.beam_mesh` (possibly constrained).
    displacement : ndarray (n,)
        Static displacement field [m, rad] whose element axial forces load the elements.
    """
    displacement = check_fields("geometric_stiffness_matrix", fe, displacement, "displacement", ndim=(1,), beam=True)
    b = fe.beam
    P = section_force_modes(fe, displacement[:, None])[0, :, :, 0].mean(axis=1)
    lengths = np.linalg.norm(fe.nodes[fe.elements[:, 1]] - fe.nodes[fe.elements[:, 0]], axis=1)
    kl = _local_kg(lengths, P, b.A.mean(axis=1), (b.Iy + b.Iz).mean(axis=1))
    T = np.einsum("ij,eab->eiajb", np.eye(4), b.rotation).reshape(-1, 12, 12)  # blockdiag(R, R, R, R)
    kg = np.einsum("eji,ejk,ekl->eil", T, kl, T)
    rows = np.repeat(b.dofs, 12, axis=1).ravel()
    cols = np.tile(b.dofs, (1, 12)).ravel()
    keep = (rows >= 0) & (cols >= 0)
    n = fe.n_dofs
    K = sp.csr_matrix((kg.ravel()[keep], (rows[keep], cols[keep])), shape=(n, n))
    return (K + K.T) / 2


def inertial_load_cases(fe: FEModel) -> dict[str, np.ndarray]:
    """Consistent nodal loads [N, N m] of the d'Alembert body forces of the body frame's unit motions.

    Returns
    -------
    dict of str to ndarray (n,)
        ``acc_x, acc_y, acc_z``: frame acceleration 1 m/s2 (body force ``-rho e_a``);
        ``alpha_x, alpha_y, alpha_z``: angular acceleration 1 rad/s2 (``-rho e_a x s``);
        ``omega_xx, omega_yy, omega_zz``: centrifugal field of ``omega_a^2 = 1 rad2/s2`` (``rho (s - s_a e_a)``);
        ``omega_xy, omega_yz, omega_zx``: the cross terms, per unit ``omega_a omega_b`` (``-rho (s_b e_a +
        s_a e_b)``). Integrated over the mass points (exact for the consistent beam description).
    """
    check_fe("inertial_load_cases", fe)
    pts = fe.mass_points if fe.mass_points is not None else fe.lumped_mass_points()
    s = pts.positions
    eye = np.eye(3)
    fields: dict[str, np.ndarray] = {}
    for a, name in enumerate(_AXES):
        fields[f"acc_{name}"] = -np.broadcast_to(eye[a], s.shape)
    for a, name in enumerate(_AXES):
        fields[f"alpha_{name}"] = -np.cross(eye[a], s)
    for a, name in enumerate(_AXES):
        fields[f"omega_{name}{name}"] = s - s[:, [a]] * eye[a]
    for a, b in ((0, 1), (1, 2), (2, 0)):
        fields[f"omega_{_AXES[a]}{_AXES[b]}"] = -(s[:, [b]] * eye[a] + s[:, [a]] * eye[b])
    return {k: pts.Nt.T @ (pts.masses[:, None] * v).ravel() for k, v in fields.items()}


def interface_load_cases(fe: FEModel, nodes: Sequence[int]) -> dict[str, np.ndarray]:
    """Unit nodal loads at the given nodes: ``F{node}_{ux..rz}`` is 1 N (translations) or 1 N m (rotations)
    on that DOF, body axes."""
    out: dict[str, np.ndarray] = {}
    for node in nodes:
        for comp in COMPONENTS:
            dof = fe.dofs([node], [comp])
            if dof.size:
                f = np.zeros(fe.n_dofs)
                f[dof] = 1.0
                out[f"F{int(node)}_{comp}"] = f
    return out


def modal_geometric_stiffness(fe: FEModel, modes: np.ndarray, support_nodes: Sequence[int],
                              load_cases: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Modal geometric stiffness ``G_k = Phi^T K_G(u_k) Phi`` [N/m per unit modal coordinate and unit load] of
    each load case, with ``u_k`` its static solution on the model held (all six DOFs) at ``support_nodes``.

    Parameters
    ----------
    fe : FEModel
        Unconstrained beam model (the same DOFs as ``modes``).
    modes : ndarray (n, M)
        Mode shapes on the FE DOFs.
    support_nodes : sequence of int
        Node ids held for the static load cases (where the body is attached: its reactions balance the loads).
    load_cases : mapping of str to ndarray (n,)
        Load vectors [N, N m] per unit load, e.g. :func:`inertial_load_cases` and :func:`interface_load_cases`.

    Returns
    -------
    dict of str to ndarray (M, M)
        Symmetric modal geometric stiffness per case.
    """
    modes = check_fields("modal_geometric_stiffness", fe, modes, beam=True)
    held = fe.constrained(support_nodes)
    keep = np.setdiff1d(np.arange(fe.n_dofs), fe.dofs(support_nodes))
    lu = sla.splu(held.K.tocsc())
    modes = np.asarray(modes, dtype=float)
    out = {}
    for name, f in load_cases.items():
        f = np.asarray(f, dtype=float)
        if f.shape != (fe.n_dofs,):
            raise ValueError(f"modal_geometric_stiffness: load case {name!r} has shape {f.shape}, "
                             f"expected ({fe.n_dofs},)")
        u = np.zeros(fe.n_dofs)
        u[keep] = lu.solve(f[keep])
        G = modes.T @ (geometric_stiffness_matrix(fe, u) @ modes)
        out[name] = (G + G.T) / 2
    return out


def inertial_load_amplitudes(alpha: np.ndarray, z: np.ndarray, w: np.ndarray) -> dict[str, np.ndarray]:
    """Amplitudes of the inertial unit load cases (:func:`inertial_load_cases`) of a reference frame
    with origin acceleration less gravity ``alpha`` [m/s2], angular acceleration ``z`` [rad/s2] and angular
    velocity ``w`` [rad/s], all (nt, 3) in body axes: ``acc_*``, ``alpha_*``, ``omega_aa`` = ``w_a²``,
    ``omega_ab`` = ``w_a w_b``."""
    axes = "xyz"
    values: dict[str, np.ndarray] = {}
    for a in range(3):
        values[f"acc_{axes[a]}"] = alpha[:, a]
        values[f"alpha_{axes[a]}"] = z[:, a]
        values[f"omega_{axes[a]}{axes[a]}"] = w[:, a] ** 2
    for a, b in ((0, 1), (1, 2), (2, 0)):
        values[f"omega_{axes[a]}{axes[b]}"] = w[:, a] * w[:, b]
    return values
