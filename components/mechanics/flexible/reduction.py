"""Craig–Bampton reduction with the improved (orthonormalised) mode set, and modal data from FE matrices.

The DOFs are split into interface (boundary) DOFs ``b`` and interior DOFs ``i``. The Craig–Bampton basis

    u = [u_b; u_i] = [[I, 0], [Psi_ib, Phi_in]] [q_c; q_n],   Psi_ib = -K_ii^-1 K_ib,

holds the static *constraint modes* (unit displacement of one interface DOF, the others held, interior free;
exact static response to any interface load) and ``n_modes`` *fixed-interface normal modes* ``Phi_in``
(``K_ii phi = omega^2 M_ii phi``, interface held, mass-normalised; shift-invert Lanczos on the sparse LU of
``K_ii``). The reduced matrices ``T^T M T``, ``T^T K T`` are then diagonalised (the improved Craig–Bampton
method used for modal neutral files: solve the reduced eigenproblem), giving mass-orthonormal modes with their
natural frequencies; for a free body the six rigid-body modes are removed first (projected out in the reduced
space, so none of the elastic content is lost), leaving only deformation modes relative to the floating frame.

References
----------
- R. R. Craig, M. C. C. Bampton, "Coupling of substructures for dynamic analyses", *AIAA J.* 6 (1968)
  1313-1319.
- R. R. Craig, A. J. Kurdila, *Fundamentals of Structural Dynamics*, 2nd ed., Wiley 2006, §14.5-14.6.
- MSC Software, *Adams/Flex* documentation, "Craig-Bampton orthonormalization" (the modes of the modal
  neutral file); Z. Zhou et al., MWorks FlexibleBody (seed 000 of issue 10).
"""

from __future__ import annotations

import datetime as _dt
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from .fe_model import FEModel
from .invariants import inertia_invariants

__all__ = ["CraigBamptonResult", "craig_bampton", "elastic_static_responses", "modal_data_from_fe"]

_DENSE_LIMIT = 400  # interior DOFs up to which the fixed-interface eigenproblem is solved densely


@dataclass(frozen=True, eq=False)
class CraigBamptonResult:
    """Result of :func:`craig_bampton`.

    Attributes
    ----------
    modes : ndarray, shape (n, k)
        Mode shapes on the FE DOFs (translations [m], rotations [rad] per unit modal coordinate); with
        ``orthogonalize=True`` mass-orthonormal and ordered by frequency, else the raw Craig–Bampton basis.
    generalized_mass, generalized_stiffness : ndarray, shape (k, k)
        ``modes^T M modes`` [kg] and ``modes^T K modes`` [N/m] (identity and ``diag(omega^2)`` when
        orthogonalised).
    omega : ndarray, shape (k,)
        ``sqrt(K_jj / M_jj)`` of each mode [rad/s] (the natural frequencies when orthogonalised).
    basis : ndarray, shape (n, n_b + n_modes)
        The Craig–Bampton basis ``T`` (constraint modes, then fixed-interface modes) on the FE DOFs.
    fixed_interface_omega : ndarray, shape (n_modes,)
        Natural frequencies of the fixed-interface modes [rad/s].
    interface_dofs : ndarray of int
        The interface DOF rows.
    n_rigid_removed : int
        Rigid-body modes projected out (6 for a free 3D body, 0 if none were given).
    """

    modes: np.ndarray
    generalized_mass: np.ndarray
    generalized_stiffness: np.ndarray
    omega: np.ndarray
    basis: np.ndarray
    fixed_interface_omega: np.ndarray
    interface_dofs: np.ndarray
    n_rigid_removed: int

    @property
    def frequencies(self) -> np.ndarray:
        """``omega / (2 pi)`` [Hz]."""
        return self.omega / (2.0 * math.pi)


def _fixed_interface_modes(Kii: sp.csc_matrix, Mii: sp.csc_matrix, lu: Any, n_modes: int) -> tuple[np.ndarray,
                                                                                                       np.ndarray]:
    ni = Kii.shape[0]
    if n_modes == 0:
        return np.zeros(0), np.zeros((ni, 0))
    if ni <= _DENSE_LIMIT or n_modes >= ni - 1:
        w, V = la.eigh(Kii.toarray(), Mii.toarray())
        w, V = w[:n_modes], V[:, :n_modes]
    else:
        op = sla.LinearOperator((ni, ni), matvec=lu.solve, dtype=float)
        w, V = sla.eigsh(Kii, k=n_modes, M=Mii, sigma=0.0, which="LM", OPinv=op)
        order = np.argsort(w)
        w, V = w[order], V[:, order]
    V = V / np.sqrt(np.einsum("ij,ij->j", V, Mii @ V))
    return w, V


def craig_bampton(M: sp.spmatrix | np.ndarray, K: sp.spmatrix | np.ndarray, interface_dofs: Sequence[int] | np.ndarray,
                  n_modes: int, *, rigid_body_modes: np.ndarray | None = None,
                  orthogonalize: bool = True) -> CraigBamptonResult:
    """Craig–Bampton reduction of ``(M, K)`` with interface DOFs and ``n_modes`` fixed-interface modes.

    Parameters
    ----------
    M, K : sparse or dense (n, n)
        Symmetric mass [kg, kg m, kg m2] and stiffness [N/m, N, N m/rad] matrices.
    interface_dofs : sequence of int
        Rows of the interface (boundary) DOFs, kept exactly by the constraint modes.
    n_modes : int
        Number of fixed-interface normal modes (0: Guyan reduction on the interface).
    rigid_body_modes : ndarray (n, r), optional
        Rigid-body displacement fields of a free body (e.g. :meth:`FEModel.rigid_body_modes`); they are
        projected out of the reduced space before orthogonalisation (requires ``orthogonalize``).
    orthogonalize : bool
        Solve the reduced eigenproblem (improved Craig–Bampton): mass-orthonormal modes with frequencies.

    Returns
    -------
    CraigBamptonResult

    Raises
    ------
    ValueError
        Bad sizes or DOF indices, ``K_ii`` singular (the interface does not restrain the body), rigid-body
        fields that ``K`` does not annihilate, or more modes than interior DOFs.
    """
    M = sp.csr_matrix(M, dtype=float)
    K = sp.csr_matrix(K, dtype=float)
    n = K.shape[0]
    if M.shape != (n, n) or K.shape != (n, n):
        raise ValueError(f"craig_bampton: M {M.shape} and K {K.shape} must be square and of equal size")
    b = np.asarray(interface_dofs, dtype=np.int64).ravel()
    if b.size and (b.min() < 0 or b.max() >= n or len(np.unique(b)) != b.size):
        raise ValueError(f"craig_bampton: interface_dofs must be distinct rows in 0..{n - 1}")
    i = np.setdiff1d(np.arange(n), b)
    if not isinstance(n_modes, int | np.integer) or n_modes < 0 or n_modes > i.size:
        raise ValueError(f"craig_bampton: n_modes must be an integer in 0..{i.size} (interior DOFs), got {n_modes!r}")
    if rigid_body_modes is not None:
        R = np.asarray(rigid_body_modes, dtype=float)
        if R.ndim != 2 or R.shape[0] != n:
            raise ValueError(f"craig_bampton: rigid_body_modes must have shape ({n}, r), got {R.shape}")
        residual = np.abs(K @ R).max() / max(abs(K).max() * np.abs(R).max(), 1e-300)
        if residual > 1e-8:
            raise ValueError(f"craig_bampton: K does not annihilate the rigid-body modes (relative residual "
                             f"{residual:.2e}): the FE model is constrained; pass rigid_body_modes=None "
                             "(modal_data_from_fe: free=False)")
        if np.linalg.matrix_rank(R[b], tol=1e-9 * max(np.abs(R).max(), 1.0)) < R.shape[1]:
            raise ValueError("craig_bampton: the interface DOFs do not restrain all rigid-body motions "
                             "(K_ii is singular); add interface nodes")
        if not orthogonalize:
            raise ValueError("craig_bampton: rigid_body_modes are removed only with orthogonalize=True")
    Kii = K[i][:, i].tocsc()
    Mii = M[i][:, i].tocsc()
    try:
        lu = sla.splu(Kii)
    except RuntimeError as exc:
        raise ValueError(f"craig_bampton: K_ii is singular ({exc}): the interface does not restrain the "
                         "body; add interface DOFs") from None
    Psi = -lu.solve(K[i][:, b].toarray()) if b.size else np.zeros((i.size, 0))
    w, Phi = _fixed_interface_modes(Kii, Mii, lu, int(n_modes))
    if np.any(w <= 0):
        raise ValueError("craig_bampton: K_ii is not positive definite: the interface does not restrain the body")
    T = np.zeros((n, b.size + Phi.shape[1]))
    T[b, np.arange(b.size)] = 1.0
    T[np.ix_(i, np.arange(b.size))] = Psi
    T[np.ix_(i, np.arange(b.size, T.shape[1]))] = Phi
    Mr = T.T @ (M @ T)
    Kr = T.T @ (K @ T)
    Mr, Kr = (Mr + Mr.T) / 2, (Kr + Kr.T) / 2
    n_rigid = 0
    if orthogonalize:
        Q = np.eye(T.shape[1])
        if rigid_body_modes is not None:
            X = np.linalg.solve(Mr, T.T @ (M @ R))  # rigid fields in Craig–Bampton coordinates
            Q = la.null_space(X.T @ Mr)  # the mass-orthogonal complement: deformation only
            n_rigid = T.shape[1] - Q.shape[1]
        _, Y = la.eigh(Q.T @ Kr @ Q, Q.T @ Mr @ Q)
        X = Q @ Y
        modes = T @ X
        Mg, Kg = X.T @ Mr @ X, X.T @ Kr @ X
        Mg, Kg = (Mg + Mg.T) / 2, (Kg + Kg.T) / 2
    else:
        modes, Mg, Kg = T, Mr, Kr
    omega = np.sqrt(np.maximum(np.diag(Kg), 0.0) / np.diag(Mg))
    return CraigBamptonResult(modes, Mg, Kg, omega, T, np.sqrt(w), b, n_rigid)


def modal_data_from_fe(fe: FEModel, interface_nodes: Sequence[int], n_modes: int, *, free: bool = True,
                       orthogonalize: bool = True, title: str = "", creator: str = "flexlib",
                       damping_ratio: np.ndarray | None = None,
                       stress_fibre: tuple[float, float] | None = None,
                       geometric_stiffening: bool = False, support_nodes: Sequence[int] | None = None,
                       reference_node: int | None = None,
                       attachment: Literal["clamped", "pinned"] = "clamped", static_loads: bool = True) -> Any:
    """Reduce an FE model by Craig–Bampton and assemble a :class:`ModalData` (modes per node, generalised
    matrices, frequencies, the nine inertia invariants, body properties and provenance).

    Parameters
    ----------
    fe : FEModel
        FE matrices with node coordinates [m] and DOF map.
    interface_nodes : sequence of int
        Node ids whose six (or fewer) DOFs are the interface (the flexible body's frames).
    n_modes : int
        Number of fixed-interface normal modes.
    free : bool
        The body is unconstrained (floating frame): its six rigid-body modes are removed.
    orthogonalize : bool
        Improved Craig–Bampton (orthonormal modes) rather than the raw basis.
    title, creator : str
        Header text of the modal file.
    damping_ratio : ndarray, optional
        Modal damping ratios [1] per kept mode; default: the frequency rule of
        :func:`~flexlib.components.mechanics.flexible.selection.default_damping_ratio` when used.
    stress_fibre : (float, float), optional
        Beam models: section fibre ``(y, z)`` [m] at which stress modes are recovered
        (:func:`~flexlib.components.mechanics.flexible.beam.beam_stress_modes`); beam models always get their
        section-force modes.
    geometric_stiffening : bool
        Beam models: add the modal geometric stiffness of the inertial and interface unit load cases
        (:func:`~flexlib.components.mechanics.flexible.geometric.modal_geometric_stiffness`).
    support_nodes : sequence of int, optional
        Nodes held for those static load cases; default the first interface node (the reference node if given).
    reference_node : int, optional
        Attach the body's reference frame to this node (attached modes). The node becomes the first interface
        node and ``free`` does not apply; the other interface nodes give the constraint (static) modes, as in
        Craig–Bampton. Default: a floating reference frame (``free``).
    attachment : {"clamped", "pinned"}
        With ``reference_node``: ``"clamped"`` — the reduction runs on the model clamped there, every mode has
        zero translation and rotation at the node, and the reference frame *is* the node's frame (the "tangent
        frame" of seed 001); ``"pinned"`` — only the node's translations are held, the three rigid rotations
        about it are removed (the modes are mass-orthogonal to them: the reference frame turns with the body's
        mean rotation about the node, its mean axes), and the node turns elastically. For a body on a hinge,
        pinned modes are the hinged body's own modes: the modal equations decouple from the rotation, fewer
        modes converge, and the reference frame's angular velocity is the body's gross rotation (what the
        centrifugal geometric stiffening needs).
    static_loads : bool
        Store the body's exact elastic static response to the unit load cases (inertial: ``acc_*``,
        ``alpha_*``, ``omega_**``; interface: ``F{node}_{ux..rz}``) with their modal loads, so that outputs can be
        recovered by the mode-acceleration method (:meth:`ModalData.residual_fields`).

    Returns
    -------
    ModalData
        Body properties from the mass description: mass = I1 [kg], centre of mass = I2 / I1 [m], inertia about
        the body-frame origin = I7 [kg m2].
    """
    from .beam import beam_stress_modes, section_force_modes
    from .modal_data import ModalData

    if (stress_fibre is not None or geometric_stiffening) and fe.beam is None:
        raise ValueError("modal_data_from_fe: stress_fibre and geometric_stiffening need a beam model (beam_mesh)")
    interface_nodes = [int(k) for k in interface_nodes]
    rigid = fe.rigid_body_modes() if free else None
    if attachment not in ("clamped", "pinned"):
        raise ValueError(f"modal_data_from_fe: attachment must be 'clamped' or 'pinned', got {attachment!r}")
    if reference_node is not None:
        reference_node = int(reference_node)
        centre = fe.nodes[fe.node_index([reference_node])[0]]
        if attachment == "clamped":
            fe = fe.constrained([reference_node])
            rigid = None
        else:
            fe = fe.constrained([reference_node], ("ux", "uy", "uz"))
            rigid = _rotations_about(fe, centre)
        interface_nodes = [reference_node] + [k for k in interface_nodes if k != reference_node]
        free = False
    dofs = fe.dofs(interface_nodes)
    cb = craig_bampton(fe.M, fe.K, dofs, n_modes, rigid_body_modes=rigid,
                       orthogonalize=orthogonalize)
    points = fe.mass_points if fe.mass_points is not None else fe.lumped_mass_points()
    inv = inertia_invariants(points, cb.modes)
    geometric = None
    if geometric_stiffening:
        from .geometric import inertial_load_cases, interface_load_cases, modal_geometric_stiffness

        support = list(interface_nodes[:1] if support_nodes is None else support_nodes)
        if not support:
            raise ValueError("modal_data_from_fe: geometric_stiffening needs a support node (no interface nodes)")
        cases = inertial_load_cases(fe) | interface_load_cases(fe, [k for k in interface_nodes if k not in support])
        geometric = modal_geometric_stiffness(fe, cb.modes, support, cases)
    trans, rot = fe.nodal_fields(cb.modes)
    static: dict[str, Any] = {}
    if static_loads:
        from .geometric import inertial_load_cases, interface_load_cases

        cases = inertial_load_cases(fe) | interface_load_cases(fe, interface_nodes)
        names = list(cases)
        loads = np.column_stack([cases[k] for k in names])
        u = elastic_static_responses(fe, loads, rigid)
        s_trans, s_rot = fe.nodal_fields(u)
        static = {"load_cases": tuple(names), "static_translations": s_trans, "static_rotations": s_rot,
                  "static_modal_loads": loads.T @ cb.modes,
                  "static_section_forces": None if fe.beam is None else section_force_modes(fe, u),
                  "static_stress": None if stress_fibre is None else beam_stress_modes(fe, u, stress_fibre)}
    provenance = {
        "method": "improved Craig-Bampton (orthonormalised)" if orthogonalize else "Craig-Bampton",
        "interface_nodes": interface_nodes,
        "n_interface_dofs": int(dofs.size),
        "n_fixed_interface_modes": int(n_modes),
        "fixed_interface_frequencies_Hz": [float(x) for x in cb.fixed_interface_omega / (2 * math.pi)],
        "n_rigid_modes_removed": int(cb.n_rigid_removed),
        "reference_node": reference_node,
        "attachment": None if reference_node is None else attachment,
        "n_fe_dofs": int(fe.n_dofs),
        "mass_description": points.description,
        "fe": fe.info,
        "stress_fibre_m": None if stress_fibre is None else [float(v) for v in stress_fibre],
        "geometric_stiffness_support_nodes": None if geometric is None else [int(k) for k in support],
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    return ModalData(
        title=title, creator=creator, mass=float(inv["I1"]), center_of_mass=inv["I2"] / inv["I1"],
        inertia=inv["I7"], node_ids=fe.node_ids, coordinates=fe.nodes, elements=fe.elements,
        interface_nodes=np.asarray(interface_nodes, dtype=np.int64), translational_modes=trans,
        rotational_modes=rot, generalized_mass=cb.generalized_mass, generalized_stiffness=cb.generalized_stiffness,
        frequencies=cb.frequencies, invariants=inv, mass_description=points.description.split(" ")[0],
        damping_ratio=damping_ratio, provenance=provenance,
        section_forces=None if fe.beam is None else section_force_modes(fe, cb.modes),
        stress_modes=None if stress_fibre is None else beam_stress_modes(fe, cb.modes, stress_fibre),
        geometric_stiffness=geometric, **static)


def elastic_static_responses(fe: FEModel, loads: np.ndarray, rigid: np.ndarray | None = None) -> np.ndarray:
    """Exact elastic static responses ``u = G f`` of a body to load vectors, with inertia relief if it has
    rigid-body modes.

    ``G = sum_k phi_k phi_k^T / omega_k^2`` over *all* elastic eigenmodes of ``(K, M)`` mass-orthogonal to the
    rigid-body modes ``R``, computed without eigenmodes from the sparse saddle-point system
    ``[[K, M R], [R^T M, 0]] [u; lam] = [f; 0]``: the load is balanced by the rigid-body d'Alembert forces
    ``-M R lam`` (inertia relief) and ``u`` is mass-orthogonal to ``R``. Subtracting the kept modes' share gives
    the residual flexibility of the mode-acceleration method (Craig & Kurdila 2006, §10.4 and §14.6).

    Parameters
    ----------
    fe : FEModel
        The model the modes were computed on (after any attachment constraints).
    loads : ndarray (n, C)
        Load vectors on the FE DOFs [N, N m].
    rigid : ndarray (n, r), optional
        Rigid-body modes of ``fe`` (its stiffness null space); ``None`` if ``K`` is nonsingular.

    Returns
    -------
    ndarray (n, C)
        Displacement fields [m, rad].
    """
    loads = np.asarray(loads, dtype=float).reshape(fe.n_dofs, -1)
    K = sp.csc_matrix(fe.K)
    if rigid is None or rigid.shape[1] == 0:
        A, rhs = K, loads
    else:
        MR = sp.csc_matrix(fe.M @ rigid)
        A = sp.bmat([[K, MR], [MR.T, None]], format="csc")
        rhs = np.vstack([loads, np.zeros((rigid.shape[1], loads.shape[1]))])
    try:
        u = np.asarray(sla.splu(A).solve(rhs))[: fe.n_dofs]
    except RuntimeError as exc:
        raise ValueError(f"elastic_static_responses: the FE model ({fe.n_dofs} DOFs) has rigid-body motion that "
                         f"is neither held nor given as rigid-body modes (stiffness singular: {exc})") from None
    if not np.all(np.isfinite(u)):
        raise ValueError("elastic_static_responses: non-finite static response (singular stiffness)")
    return u


def _rotations_about(fe: FEModel, centre: np.ndarray) -> np.ndarray:
    """The three rigid rotation fields ``(n, 3)`` about ``centre`` [m] (unit small rotations about x, y, z)."""
    R = np.zeros((fe.n_dofs, 3))
    arm = fe.nodes - centre
    for a in range(3):
        u = np.cross(np.eye(3)[a], arm)
        for b in range(3):
            rows = fe.dof_map[:, b]
            R[rows[rows >= 0], a] = u[rows >= 0, b]
        rows = fe.dof_map[:, 3 + a]
        R[rows[rows >= 0], a] = 1.0
    return R
