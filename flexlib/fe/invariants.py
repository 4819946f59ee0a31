"""The nine inertia invariants of the floating frame of reference formulation with modal superposition.

With the mass description as points ``p`` (masses ``m_p`` [kg], rotational inertias ``J_p`` [kg m2], undeformed
positions ``s_p`` [m] in the body frame, translational mode shapes ``Phi_p`` (3 x M) [m per unit modal
coordinate] and rotational mode shapes ``Phi*_p`` (3 x M) [rad per unit modal coordinate]), and ``a~`` the
cross-product matrix of ``a``::

    I1 = sum m_p                                         (1)       total mass
    I2 = sum m_p s_p                                     (3)       first moment of mass
    I3 = sum m_p Phi_p                                   (3, M)
    I4 = sum m_p s~_p Phi_p + J_p Phi*_p                 (3, M)
    I5[j] = sum m_p phi~_pj Phi_p                        (M, 3, M) phi_pj: column j of Phi_p
    I6 = sum m_p Phi_p^T Phi_p + Phi*_p^T J_p Phi*_p     (M, M)    generalised (modal) mass
    I7 = sum m_p s~_p^T s~_p + J_p                       (3, 3)    inertia tensor about the body-frame origin
    I8[j] = sum m_p s~_p^T phi~_pj                       (M, 3, 3)
    I9[j, k] = sum m_p phi~_pj^T phi~_pk                 (M, M, 3, 3)

so that the inertia tensor of the deformed body about the origin is ``I7 + sum_j q_j (I8[j] + I8[j]^T) +
sum_jk q_j q_k I9[j, k]`` and its first moment ``I2 + I3 q``. For a *lumped* description the points are the FE
nodes; for a *consistent* one they are element Gauss points whose weights integrate the density exactly, so the
sums are the volume integrals of the continuum (the nodal rotational inertia terms appear in I4, I6 and I7 only,
as in the references).

References
----------
- A. A. Shabana, *Dynamics of Multibody Systems*, 3rd ed., Cambridge University Press 2005, ch. 5
  (§5.4-5.6: inertia shape integrals of the floating frame of reference formulation).
- R. Schwertassek, O. Wallrapp, *Dynamik flexibler Mehrkörpersysteme*, Vieweg 1999, ch. 6 (inertia
  integrals and the standard input data).
- MSC Software, *Adams/Flex: Theory of Flexible Bodies* (after Ottarsson, "Modal Flexibility Method in
  ADAMS/FLEX"), inertia invariants 1-9.
"""

from __future__ import annotations

import numpy as np

from flexlib.errors import RunArgumentError

from .fe_model import MassPoints

__all__ = ["INVARIANT_NAMES", "inertia_invariants", "invariant_shapes"]

INVARIANT_NAMES = ("I1", "I2", "I3", "I4", "I5", "I6", "I7", "I8", "I9")


def invariant_shapes(n_modes: int) -> dict[str, tuple[int, ...]]:
    """Array shape of each invariant for ``n_modes`` modes."""
    m = n_modes
    return {"I1": (), "I2": (3,), "I3": (3, m), "I4": (3, m), "I5": (m, 3, m), "I6": (m, m), "I7": (3, 3),
            "I8": (m, 3, 3), "I9": (m, m, 3, 3)}


def inertia_invariants(points: MassPoints, modes: np.ndarray) -> dict[str, np.ndarray]:
    """The nine invariants (module docstring) of the mode shapes ``modes`` (n_dofs, M) on the FE DOFs.

    Parameters
    ----------
    points : MassPoints
        Mass description (positions [m], masses [kg], inertias [kg m2], interpolation from the DOFs).
    modes : ndarray, shape (n_dofs, M)
        Mode shapes on the FE DOFs (translations [m], rotations [rad] per unit modal coordinate).

    Returns
    -------
    dict of str to ndarray
        ``I1`` .. ``I9`` in SI units (kg, kg m, kg m2 per power of the modal coordinates).
    """
    if not isinstance(points, MassPoints):
        raise RunArgumentError(f"inertia_invariants: argument 'points' must be MassPoints (FEModel.mass_points or "
                               f"FEModel.lumped_mass_points()), got {type(points).__name__}")
    n = points.Nt.shape[1]
    try:
        bad = isinstance(modes, str | bytes) or np.asarray(modes).dtype.kind not in "iuf"
    except (TypeError, ValueError):
        bad = True
    if bad or np.ndim(modes) != 2 or np.shape(modes)[0] != n or not np.all(np.isfinite(modes)):
        raise RunArgumentError(f"inertia_invariants: argument 'modes' must be finite mode shapes ({n}, M) on the DOFs "
                               f"of the mass points, got {type(modes).__name__} of shape {np.shape(modes)}")
    modes = np.asarray(modes, dtype=float)
    m = points.masses
    P = m.size
    M = modes.shape[1]
    Pt = (points.Nt @ modes).reshape(P, 3, M)
    Pr = (points.Nr @ modes).reshape(P, 3, M)
    J = points.inertias
    s = points.positions
    # second moments as matrix products (no P x M x M intermediates):
    # C[a, j, b, k] = sum m Phi[a, j] Phi[b, k],  D[x, b, k] = sum m s[x] Phi[b, k],  S[x, y] = sum m s[x] s[y]
    flat = Pt.reshape(P, 3 * M)
    C = ((flat * m[:, None]).T @ flat).reshape(3, M, 3, M)
    D = ((s * m[:, None]).T @ flat).reshape(3, 3, M)
    S = (s * m[:, None]).T @ s
    eye = np.eye(3)
    eps = np.zeros((3, 3, 3))  # Levi-Civita symbol
    eps[0, 1, 2] = eps[1, 2, 0] = eps[2, 0, 1] = 1.0
    eps[0, 2, 1] = eps[2, 1, 0] = eps[1, 0, 2] = -1.0
    # a~^T b~ = (a . b) I - b a^T ;  (a~ b)_c = eps_cxy a_x b_y
    dotC = np.einsum("ajak->jk", C)
    inv = {
        "I1": np.asarray(m.sum()),
        "I2": m @ s,
        "I3": np.einsum("p,pam->am", m, Pt),
        "I4": np.einsum("cxy,xyk->ck", eps, D) + np.einsum("pab,pbm->am", J, Pr),
        "I5": np.einsum("cxy,xjyk->jck", eps, C),
        "I6": dotC + np.einsum("pam,pab,pbn->mn", Pr, J, Pr, optimize=True),
        "I7": np.trace(S) * eye - S.T + J.sum(axis=0),
        "I8": np.einsum("ab,xxj->jab", eye, D) - np.einsum("abj->jba", D),
        "I9": np.einsum("jk,ab->jkab", dotC, eye) - np.einsum("bjak->jkab", C),
    }
    for name in ("I6", "I7"):
        inv[name] = (inv[name] + inv[name].T) / 2
    return {k: np.array(v, dtype=float, order="C") for k, v in inv.items()}
