"""Craig–Bampton reduction with the improved (orthonormalised) mode set, and exact elastic static responses.

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
  neutral file); Z. Zhou et al., MWorks FlexibleBody.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from flexlib.core.values import as_bool
from flexlib.errors import RunArgumentError

from .arguments import is_int
from .fe_model import FEModel, check_fields
from .matrix_checks import check_semidefinite_pattern

__all__ = ["RIGID_NAMES", "CraigBamptonResult", "ReductionMessages", "craig_bampton", "craig_bampton_named",
           "elastic_static_responses", "rotations_about"]

_DENSE_LIMIT = 400  # massive interior DOFs up to which the fixed-interface eigenproblem is solved densely
_MASSLESS = 1e-14  # a diagonal mass term below this fraction of the largest one is no mass (a lumped export's 0)
RIGID_NAMES = ("translation along x", "translation along y", "translation along z", "rotation about x",
                "rotation about y", "rotation about z")


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
    massless_dofs : ndarray of int
        Rows without mass (zero diagonal of ``M``, e.g. the rotations of a lumped mass without rotary inertia):
        statically condensed in the fixed-interface modes.
    n_massless_condensed : int
        Directions of the reduced space without mass (e.g. an interface rotation whose constraint mode moves no
        mass) condensed statically before orthogonalisation: ``k = n_b + n_modes - n_rigid_removed -
        n_massless_condensed`` modes remain.
    """

    modes: np.ndarray
    generalized_mass: np.ndarray
    generalized_stiffness: np.ndarray
    omega: np.ndarray
    basis: np.ndarray
    fixed_interface_omega: np.ndarray
    interface_dofs: np.ndarray
    n_rigid_removed: int
    massless_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    n_massless_condensed: int = 0

    @property
    def frequencies(self) -> np.ndarray:
        """``omega / (2 pi)`` [Hz]."""
        return self.omega / (2.0 * math.pi)


@dataclass(frozen=True)
class ReductionMessages:
    """How errors of a reduction name things: the function, the DOF rows, the matrices' source and the class."""

    func: str = "craig_bampton"
    label: Callable[[int], str] = lambda row: f"row {int(row)}"
    source: Callable[[str], str] = lambda matrix: f"argument {matrix!r}"
    error: type[Exception] = RunArgumentError
    interface: str = "interface_dofs"
    rigid_names: tuple[str, ...] = RIGID_NAMES
    rigid_hint: str = "pass rigid_body_modes=None"
    hold_hint: str = "hold the body (FEModel.constrained) or give rigid_body_modes"

    def matrix_error(self, matrix: str, text: str) -> Exception:
        return self.error(f"{self.source(matrix)}: {text} ({self.func})")

    def largest(self, fieldv: np.ndarray) -> str:
        return self.label(int(np.argmax(np.abs(fieldv))))


def _fixed_interface_modes(K: sp.csr_matrix, M: sp.csr_matrix, i: np.ndarray, massless: np.ndarray, lu: Any,
                           n_modes: int, names: ReductionMessages) -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``n_modes`` modes of ``K_ii phi = omega^2 M_ii phi`` (interface held), mass-normalised, as fields on the
    interior DOFs ``i``. Interior DOFs without mass are condensed statically (exactly: their rows of the
    eigenproblem have no inertia, ``K_zm phi_m + K_zz phi_z = 0``), leaving ``(K_mm - K_mz K_zz^-1 K_zm) phi_m =
    omega^2 M_mm phi_m`` on the massive ones (Guyan 1965; Cook et al. 2002 §11.6, exact for massless DOFs)."""
    ni = i.size
    zmask = massless[i]
    pos_m, pos_z = np.flatnonzero(~zmask), np.flatnonzero(zmask)
    im, iz = i[pos_m], i[pos_z]
    if n_modes == 0:
        return np.zeros(0), np.zeros((ni, 0))
    Kmm, Mmm = K[im][:, im].tocsc(), M[im][:, im].tocsc()
    lu_z = None
    if iz.size:
        Kzm = K[iz][:, im].tocsc()
        try:
            lu_z = sla.splu(K[iz][:, iz].tocsc())
        except RuntimeError:
            raise _unheld(K, iz, names) or names.matrix_error(
                "K", "the interior DOFs without mass (no mass on the diagonal of M, e.g. rotations of a lumped mass) "
                     "form a mechanism with the interface held: their stiffness matrix K_zz is singular") from None
    nm = im.size
    try:
        if nm <= _DENSE_LIMIT or n_modes >= nm - 1:
            A = Kmm.toarray()
            if lu_z is not None:
                A = A - Kzm.T.toarray() @ lu_z.solve(Kzm.toarray())
            w, V = la.eigh((A + A.T) / 2, Mmm.toarray(), subset_by_index=[0, n_modes - 1])
        else:
            if lu_z is None:
                A, op = Kmm, sla.LinearOperator((nm, nm), matvec=lu.solve, dtype=float)
            else:
                def kc(x: np.ndarray) -> np.ndarray:
                    x = np.ravel(x)
                    return Kmm @ x - Kzm.T @ lu_z.solve(np.asarray(Kzm @ x))

                def kc_inv(x: np.ndarray) -> np.ndarray:  # the Schur complement's inverse is the mm block of K_ii^-1
                    y = np.zeros(ni)
                    y[pos_m] = np.ravel(x)
                    return lu.solve(y)[pos_m]

                A = sla.LinearOperator((nm, nm), matvec=kc, dtype=float)
                op = sla.LinearOperator((nm, nm), matvec=kc_inv, dtype=float)
            w, V = sla.eigsh(A, k=n_modes, M=Mmm, sigma=0.0, which="LM", OPinv=op)
            order = np.argsort(w)
            w, V = w[order], V[:, order]
    except la.LinAlgError as exc:
        found = re.search(r"leading minor of order (\d+)", str(exc))
        where = f": the first failing leading minor is at {names.label(im[int(found.group(1)) - 1])}" if found else ""
        raise names.matrix_error("M", f"the mass matrix on the interior DOFs is not positive definite{where} (a "
                                      "negative or singular mass combination; massless DOFs must have zero rows)"
                                 ) from None
    except (sla.ArpackError, sla.ArpackNoConvergence) as exc:
        raise names.matrix_error("M", f"the fixed-interface eigenproblem failed ({exc}): M is not positive "
                                      "semi-definite or K not positive definite on the interior") from None
    mass = np.einsum("ij,ij->j", V, Mmm @ V)
    if not np.all(np.isfinite(mass)) or np.any(mass <= 0):
        k = int(np.argmax(~np.isfinite(mass) | (mass <= 0)))
        raise names.matrix_error("M", f"the mass matrix is not positive semi-definite: a fixed-interface mode has "
                                      f"mass {mass[k]:.3g}, moving most at "
                                      f"{names.largest(_embed(V[:, k], im, M.shape[0]))}")
    V = V / np.sqrt(mass)
    Phi = np.zeros((ni, n_modes))
    Phi[pos_m] = V
    if lu_z is not None:
        Phi[pos_z] = -lu_z.solve(np.asarray(Kzm @ V))
    return w, Phi


def _embed(v: np.ndarray, rows: np.ndarray, n: int) -> np.ndarray:
    out = np.zeros(n)
    out[rows] = v
    return out


def _unheld(K: sp.csr_matrix, rows: np.ndarray, names: ReductionMessages) -> Exception | None:
    """The error for DOFs among ``rows`` without any stiffness (an unconnected DOF: a file problem), or None."""
    diag = np.abs(K.diagonal())[rows]
    scale = float(np.abs(K.diagonal()).max(initial=0.0)) or 1.0
    loose = rows[diag <= 1e-14 * scale]
    if not loose.size:
        return None
    return names.matrix_error("K", f"{names.label(int(loose[0]))} has no stiffness at all (a zero row of K"
                                   + (f"; {loose.size} such DOFs" if loose.size > 1 else "") + "): an unconnected "
                                   "DOF — leave it out of the DOF map (-1), or connect it")


def _checked_matrices(M: Any, K: Any, names: ReductionMessages) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """``M`` and ``K`` as CSR matrices of floats: square, of equal size, finite, symmetric, and positive
    semi-definite as far as :func:`~.matrix_checks.check_semidefinite_pattern` tells."""
    func = names.func
    mats = []
    for label, A in (("M", M), ("K", K)):
        try:
            A = sp.csr_matrix(A, dtype=float)
        except (TypeError, ValueError) as exc:
            raise RunArgumentError(f"{func}: argument {label!r} must be a real matrix (sparse or dense): "
                                   f"{exc}") from None
        mats.append(A)
    M, K = mats
    n = K.shape[0]
    if M.shape != (n, n) or K.shape != (n, n):
        raise RunArgumentError(f"{func}: M {M.shape} and K {K.shape} must be square and of equal size")
    for label, A in (("M", M), ("K", K)):
        coo = A.tocoo()
        bad = ~np.isfinite(coo.data)
        if np.any(bad):
            k = int(np.argmax(bad))
            raise names.matrix_error(label, f"matrix {label!r} has a non-finite entry {coo.data[k]} at "
                                            f"({names.label(coo.row[k])}, {names.label(coo.col[k])})")
        asym = abs(A - A.T).max() if A.nnz else 0.0
        if asym > 1e-9 * (abs(A).max() if A.nnz else 1.0):
            D = sp.coo_matrix(abs(A - A.T))
            k = int(np.argmax(D.data))
            raise names.matrix_error(label, f"matrix {label!r} is not symmetric: |A - A^T| = {asym:.3g} at "
                                            f"({names.label(D.row[k])}, {names.label(D.col[k])})")
        why = check_semidefinite_pattern(A, label, names.label)
        if why is not None:
            raise names.matrix_error(label, why)
    return M, K


def _interface_rows(interface_dofs: Any, n: int, names: ReductionMessages) -> np.ndarray:
    """The interface DOF rows: whole numbers in ``0..n-1``, each once."""
    func = names.func
    try:
        b = np.asarray(interface_dofs).ravel()
        if b.size and not (np.issubdtype(b.dtype, np.integer) or
                           (np.issubdtype(b.dtype, np.floating) and np.all(b == np.round(b)))):
            raise TypeError
        b = b.astype(np.int64)
    except (TypeError, ValueError):
        raise RunArgumentError(f"{func}: argument {names.interface!r} must be integer DOF rows, got "
                               f"{interface_dofs!r}") from None
    if b.size and (b.min() < 0 or b.max() >= n):
        raise RunArgumentError(f"{func}: {names.interface} must be rows in 0..{n - 1}, got "
                               f"{int(b.min() if b.min() < 0 else b.max())}")
    if len(np.unique(b)) != b.size:
        values, counts = np.unique(b, return_counts=True)
        raise RunArgumentError(f"{func}: {names.interface} give {names.label(int(values[np.argmax(counts > 1)]))} "
                               "more than once")
    return b


def _without_massless(M: sp.csr_matrix, names: ReductionMessages) -> tuple[sp.csr_matrix, np.ndarray]:
    """``M`` with the rows and columns of its massless DOFs (diagonal below ``_MASSLESS`` of the largest) set to
    exact zeros, and the mask of those DOFs."""
    diag_m = np.asarray(M.diagonal())
    if not np.any(diag_m > 0):
        raise names.matrix_error("M", "the mass matrix has no mass at all (zero diagonal)")
    massless = diag_m <= _MASSLESS * diag_m.max()
    if np.any(massless):  # zero rows exactly (check_semidefinite_pattern bounds their off-diagonal terms)
        keep = sp.diags((~massless).astype(float))
        M = (keep @ M @ keep).tocsr()
        M.eliminate_zeros()
    return M, massless


def _rigid_modes(rigid_body_modes: Any, K: sp.csr_matrix, b: np.ndarray, orthogonalize: bool,
                 names: ReductionMessages) -> np.ndarray:
    """The rigid-body fields ``(n, r)``: numbers, annihilated by ``K``, each moving some interface DOF."""
    func, n = names.func, K.shape[0]
    try:
        if isinstance(rigid_body_modes, str | bytes) or np.asarray(rigid_body_modes).dtype.kind not in "iuf":
            raise TypeError
        R = np.asarray(rigid_body_modes, dtype=float)
    except (TypeError, ValueError):
        raise RunArgumentError(f"{func}: rigid_body_modes must be an array ({n}, r) of displacement fields "
                               f"(numbers; e.g. FEModel.rigid_body_modes()), got {rigid_body_modes!r:.60}"
                               ) from None
    if not np.all(np.isfinite(R)):
        raise RunArgumentError(f"{func}: rigid_body_modes has non-finite values")
    if R.ndim != 2 or R.shape[0] != n:
        raise RunArgumentError(f"{func}: rigid_body_modes must have shape ({n}, r), got {R.shape}")
    KR = K @ R
    residual = np.abs(KR).max() / max(abs(K).max() * np.abs(R).max(), 1e-300)
    if residual > 1e-8:
        row, col = np.unravel_index(int(np.argmax(np.abs(KR))), KR.shape)
        what = names.rigid_names[col] if col < len(names.rigid_names) else f"rigid mode {col}"
        raise names.matrix_error("K", f"K does not annihilate the rigid-body modes: the {what} leaves a "
                                      f"relative residual {residual:.2e}, largest at {names.label(int(row))}; "
                                      "either the FE model "
                                      f"is held there (constrained), then {names.rigid_hint}, or K is damaged "
                                      "at that DOF")
    if np.linalg.matrix_rank(R[b], tol=1e-9 * max(np.abs(R).max(), 1.0)) < R.shape[1]:
        loose = la.null_space(R[b]) if b.size else np.eye(R.shape[1])
        coeff = np.abs(loose[:, 0])
        k = int(np.argmax(coeff))
        what = names.rigid_names[k] if k < len(names.rigid_names) else "a rigid motion"
        raise RunArgumentError(f"{func}: the interface DOFs do not restrain all rigid-body motions of the free "
                               f"body ({names.interface}: {b.size} DOFs; the {what} moves none of them), so K_ii "
                               "is singular: the "
                               "constraint modes need interface DOFs that fix the body — one node with its six "
                               "DOFs, or three nodes not on a line; add interface nodes")
    if not orthogonalize:
        raise RunArgumentError(f"{func}: rigid_body_modes are removed only with orthogonalize=True")
    return R


def _check_fixed_interface_stiffness(w: np.ndarray, Phi: np.ndarray, Kii: sp.csc_matrix, M: sp.csr_matrix,
                                     i: np.ndarray, names: ReductionMessages) -> None:
    """Every fixed-interface mode has positive stiffness: a negative one is a damaged ``K``, a zero one an
    interface that does not restrain the body."""
    if not np.any(w <= 0):
        return
    k = int(np.argmax(w <= 0))
    fieldv = _embed(Phi[:, k], i, M.shape[0])
    scale = float(np.abs(Kii.diagonal()).max()) / float(max(np.asarray(M.diagonal())[i].max(initial=0.0), 1e-300))
    if w[k] < -1e-9 * scale:
        raise names.matrix_error("K", f"K is not positive semi-definite: a fixed-interface mode has negative "
                                      f"stiffness (omega^2 = {w[k]:.3g} rad2/s2), largest at "
                                      f"{names.largest(fieldv)} — a negative or mis-signed stiffness term there")
    raise RunArgumentError(f"{names.func}: K_ii is not positive definite: a fixed-interface mode has zero stiffness "
                           f"(omega^2 = {w[k]:.3g}), moving most at {names.largest(fieldv)}: the "
                           f"{names.interface} do not restrain the body (a mechanism); add interface DOFs, or "
                           f"{names.hold_hint}")


def _orthonormalised(Mr: np.ndarray, Kr: np.ndarray, T: np.ndarray, M: sp.csr_matrix, R: np.ndarray | None,
                     names: ReductionMessages) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, int]:
    """The improved Craig–Bampton modes of the reduced ``(Mr, Kr)`` on basis ``T``: massless directions condensed,
    rigid fields ``R`` projected out, the reduced eigenproblem solved. Returns the modes, their generalised mass
    and stiffness, and the numbers of rigid modes removed and massless directions condensed."""
    P, n_condensed = _massive_subspace(Mr, Kr, T, R, names)
    T2, Mr2, Kr2 = T @ P, P.T @ Mr @ P, P.T @ Kr @ P
    Mr2, Kr2 = (Mr2 + Mr2.T) / 2, (Kr2 + Kr2.T) / 2
    Q = np.eye(T2.shape[1])
    n_rigid = 0
    if R is not None:
        X = np.linalg.solve(Mr2, T2.T @ (M @ R))  # rigid fields in the reduced coordinates
        Q = la.null_space(X.T @ Mr2)  # the mass-orthogonal complement: deformation only
        n_rigid = T2.shape[1] - Q.shape[1]
    try:
        _, Y = la.eigh(Q.T @ Kr2 @ Q, Q.T @ Mr2 @ Q)
    except la.LinAlgError as exc:
        raise names.matrix_error("M", f"the reduced mass matrix is not positive definite ({exc})") from None
    X = Q @ Y
    Mg, Kg = X.T @ Mr2 @ X, X.T @ Kr2 @ X
    return T2 @ X, (Mg + Mg.T) / 2, (Kg + Kg.T) / 2, n_rigid, n_condensed


def craig_bampton_named(M: Any, K: Any, interface_dofs: Any, n_modes: Any, rigid_body_modes: Any,
                        orthogonalize: bool, names: ReductionMessages) -> CraigBamptonResult:
    """:func:`craig_bampton`, its errors naming things as ``names`` says (the function, DOFs, file, class)."""
    func = names.func
    as_bool(orthogonalize, f"{func}: argument 'orthogonalize'", RunArgumentError, ints=False)
    M, K = _checked_matrices(M, K, names)
    n = K.shape[0]
    b = _interface_rows(interface_dofs, n, names)
    M, massless = _without_massless(M, names)
    i = np.setdiff1d(np.arange(n), b)
    n_massive = int(np.count_nonzero(~massless[i]))
    if not is_int(n_modes) or not 0 <= n_modes <= n_massive:
        extra = f" (of the {i.size} interior DOFs, {i.size - n_massive} have no mass and no modes)" \
            if n_massive < i.size else " (interior DOFs)"
        raise RunArgumentError(f"{func}: n_modes must be an integer in 0..{n_massive}{extra}, got "
                               f"{n_modes!r}")
    n_modes = int(n_modes)
    R = None if rigid_body_modes is None else _rigid_modes(rigid_body_modes, K, b, orthogonalize, names)
    Kii = K[i][:, i].tocsc()
    try:
        lu = sla.splu(Kii) if i.size else None
    except RuntimeError:
        raise _unheld(K, i, names) or RunArgumentError(
            f"{func}: K_ii is singular with the {names.interface} held ({b.size} DOFs): a mechanism (motion without "
            f"strain energy) remains — the interface does not restrain the body; add interface DOFs, or "
            f"{names.hold_hint}") from None
    Psi = -lu.solve(K[i][:, b].toarray()) if b.size and i.size else np.zeros((i.size, b.size))
    w, Phi = _fixed_interface_modes(K, M, i, massless, lu, n_modes, names)
    _check_fixed_interface_stiffness(w, Phi, Kii, M, i, names)
    T = np.zeros((n, b.size + Phi.shape[1]))
    T[b, np.arange(b.size)] = 1.0
    T[np.ix_(i, np.arange(b.size))] = Psi
    T[np.ix_(i, np.arange(b.size, T.shape[1]))] = Phi
    Mr = T.T @ (M @ T)
    Kr = T.T @ (K @ T)
    Mr, Kr = (Mr + Mr.T) / 2, (Kr + Kr.T) / 2
    if orthogonalize:
        modes, Mg, Kg, n_rigid, n_condensed = _orthonormalised(Mr, Kr, T, M, R, names)
    else:
        modes, Mg, Kg, n_rigid, n_condensed = T, Mr, Kr, 0, 0
    d = np.diag(Mg)
    omega = np.sqrt(np.maximum(np.diag(Kg), 0.0) / np.where(d > 0, d, np.inf))
    return CraigBamptonResult(modes, Mg, Kg, omega, T, np.sqrt(w), b, n_rigid, np.flatnonzero(massless),
                              n_condensed)


def _massive_subspace(Mr: np.ndarray, Kr: np.ndarray, T: np.ndarray, R: np.ndarray | None,
                      names: ReductionMessages) -> tuple[np.ndarray, int]:
    """A basis ``P`` of the reduced coordinates without the massless directions, condensed statically (Guyan on
    the reduced matrices: a direction ``z`` without mass follows the others through ``Z^T Kr (P q) = 0``, which
    is exact for it), and how many were condensed; ``P = I`` if ``Mr`` is positive definite."""
    e, U = la.eigh(Mr)
    scale = float(max(e.max(initial=0.0), 1e-300))
    if e.min(initial=0.0) < -1e-9 * scale:
        raise names.matrix_error("M", f"the mass matrix is not positive semi-definite: the reduced mass has a negative "
                                      f"eigenvalue {e.min():.3g} (of {scale:.3g}), its motion largest at "
                                      f"{names.largest(T @ U[:, 0])}")
    zero = e <= 1e-12 * scale
    if not np.any(zero):
        return np.eye(Mr.shape[0]), 0
    Z, Um = U[:, zero], U[:, ~zero]
    Kzz = Z.T @ Kr @ Z
    Kzz = (Kzz + Kzz.T) / 2
    ek, Vk = la.eigh(Kzz)
    if ek.min() <= 1e-10 * max(float(np.abs(Kr).max()), 1e-300):
        fieldv = T @ (Z @ Vk[:, 0])
        what = ""
        if R is not None:
            c, *_ = np.linalg.lstsq(R, fieldv, rcond=None)
            if np.abs(R @ c - fieldv).max() <= 1e-6 * np.abs(fieldv).max():
                k = int(np.argmax(np.abs(c)))
                what = (f" — the rigid-body {names.rigid_names[k] if k < len(names.rigid_names) else 'motion'}: all "
                        "the mass lies on its axis and M gives no rotary inertia about it (a line of lumped masses "
                        "without rotary inertia); give the nodes rotary inertia (FEModel.with_point_masses(..., "
                        "inertias=...) or a consistent mass), or attach the body (reference_node)")
        raise names.matrix_error("M", f"a motion has neither mass nor stiffness (largest at {names.largest(fieldv)})"
                                      f"{what}")
    return Um - Z @ np.linalg.solve(Kzz, Z.T @ Kr @ Um), int(np.count_nonzero(zero))


def craig_bampton(M: sp.spmatrix | np.ndarray, K: sp.spmatrix | np.ndarray, interface_dofs: Sequence[int] | np.ndarray,
                  n_modes: int, *, rigid_body_modes: np.ndarray | None = None,
                  orthogonalize: bool = True) -> CraigBamptonResult:
    """Craig–Bampton reduction of ``(M, K)`` with interface DOFs and ``n_modes`` fixed-interface modes.

    DOFs without mass (a zero diagonal term of ``M``: the rotations of a lumped mass matrix without rotary
    inertia, a common FE export) have no inertia, so their rows of the eigenproblem are static equilibrium:
    interior ones are condensed statically in the fixed-interface modes (Guyan condensation, exact for massless
    DOFs), and reduced directions without mass (an interface rotation whose constraint mode moves no mass) are
    condensed the same way before orthogonalisation. The constraint modes are unchanged, so static interface
    responses stay exact.

    Parameters
    ----------
    M, K : sparse or dense (n, n)
        Symmetric positive semi-definite mass [kg, kg m, kg m2] and stiffness [N/m, N, N m/rad] matrices.
    interface_dofs : sequence of int
        Rows of the interface (boundary) DOFs, kept exactly by the constraint modes.
    n_modes : int
        Number of fixed-interface normal modes (0: Guyan reduction on the interface); at most the number of
        interior DOFs with mass.
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
    RunArgumentError
        Bad sizes, DOF indices or ``n_modes``; ``orthogonalize`` not a bool; ``rigid_body_modes`` not an array of
        numbers of the right shape; the interface does not restrain the body (``K_ii`` singular or
        with a zero-frequency mode, naming the DOF that moves); rigid-body fields that ``K`` does not annihilate;
        a matrix that is not finite, symmetric or positive semi-definite (a negative diagonal term, an
        off-diagonal term above its diagonal terms, a negative-stiffness or negative-mass mode), naming the DOF.
    """
    return craig_bampton_named(M, K, interface_dofs, n_modes, rigid_body_modes, orthogonalize, ReductionMessages())


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
    func = "elastic_static_responses"
    loads = check_fields(func, fe, loads, "loads", ndim=(1, 2)).reshape(fe.n_dofs, -1)
    if rigid is not None:
        rigid = check_fields(func, fe, rigid, "rigid")
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
        raise RunArgumentError(f"elastic_static_responses: the FE model ({fe.n_dofs} DOFs) has rigid-body motion "
                               f"that is neither held nor given as rigid-body modes (stiffness singular: {exc})"
                               ) from None
    if not np.all(np.isfinite(u)):
        raise RunArgumentError("elastic_static_responses: non-finite static response (singular stiffness)")
    return u


def rotations_about(fe: FEModel, centre: np.ndarray) -> np.ndarray:
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
