"""The nonlinear solve of an initialisation or re-initialisation problem ``g(w) = 0``: damped Newton on the sparse
Jacobian (SciPy sparse LU), then trust-region least squares, and on failure a diagnosis that names equations and
variables (non-finite values, the largest scaled residuals, a singular Jacobian)."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import casadi as ca
import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg  # noqa: F401  (sps.linalg)

from flexlib.errors import InitializationError
from flexlib.solve.diagnose import nonfinite_lines, row_scale, singular_lines

__all__ = ["accept", "csc", "pattern", "solve"]

Labels = list[tuple[str, str]]


def solve(g: Any, jg: Any, w0: np.ndarray, par: np.ndarray, tol: float, labels: Labels, cols: Labels,
          nominal: np.ndarray, what: str = "could not find consistent initial values",
          diagnose: bool = True) -> tuple[np.ndarray, Any]:
    """Solve ``g(w, par) = 0`` from ``w0``: damped Newton (sparse LU), then trust-region least squares.

    Newton iterates to the absolute ``tol`` while it makes progress; where it stalls (round-off: an equation
    with 1e7 Pa terms cannot be held to 1e-10 Pa), the point is accepted by a per-equation scaled test
    ``|g_i| <= tol·s_i`` with ``s_i = max(1, max_j |J_ij|·nominal_j)`` (:func:`~flexlib.solve.diagnose.row_scale`):
    relative to the size the equation's terms take when one of its variables moves by its nominal value,
    never stricter than the absolute test. On failure the error names non-finite residuals and Jacobian
    entries, then the equations with the largest scaled residuals and, if the Jacobian is numerically
    singular, the dependent equations and the variables involved (``err.best``: the best point found).

    Returns
    -------
    w : ndarray
        The solution.
    J : sparse matrix or None
        The Jacobian at ``w`` where Newton accepted it there (None otherwise).
    """

    def fun(w: np.ndarray) -> np.ndarray:
        return np.asarray(g(w, par)).ravel()

    def jac(w: np.ndarray) -> sps.csc_matrix:
        return csc(jg(w, par))

    with np.errstate(all="ignore"):
        w, r, J, done = _newton(fun, jac, w0, tol, nominal, diagnose)
        if done:
            return accept(w, r, J, diagnose, labels, cols, what), J
        if np.all(np.isfinite(r)) and _wnorm(r, row_scale(jac(w), nominal)) <= tol:
            return w, None
        w = _least_squares(fun, jac, w)
        r = fun(w)
        J = jac(w)
        s = row_scale(J, nominal)
        if _wnorm(r, s) <= max(tol, 1e-8):
            return w, None
        if not diagnose:  # a trial whose failure the caller discards
            err = InitializationError(f"{what} (trial)")
            err.best = w
            raise err
        # the failure, named
        nf = nonfinite_lines(r, J, labels, cols, w, "at the best point found")
        if not nf and not np.array_equal(w, w0):
            r0 = fun(w0)
            nf = nonfinite_lines(r0, jac(w0), labels, cols, w0, "at the start guesses")
    raise _failure(what, nf, r, s, J, tol, labels, cols, nominal, w)


def _wnorm(r: np.ndarray, s: np.ndarray) -> float:
    return float(np.max(np.abs(r) / s)) if len(r) else 0.0


def _newton(fun: Callable[[np.ndarray], np.ndarray], jac: Callable[[np.ndarray], sps.csc_matrix], w0: np.ndarray,
            tol: float, nominal: np.ndarray, diagnose: bool) -> tuple[np.ndarray, np.ndarray, Any, bool]:
    """Damped Newton with sparse LU (the fast path for the usual well-posed problem): ``(w, r, J, accepted)``.

    It iterates to the absolute tolerance while that makes progress; where it stalls (round-off: a 1e7 Pa equation
    cannot be held to 1e-10 Pa), a point that passes the scaled test with the Jacobian there is accepted as soon as
    a full Newton step from it no longer lowers the residual (no line search spinning on noise)."""
    w = w0.astype(float).copy()
    r = fun(w)
    for _ in range(50):
        norm = np.linalg.norm(r, np.inf)
        J = jac(w) if norm > tol or diagnose else None
        scaled_ok = norm > tol and bool(np.all(np.isfinite(r))) and _wnorm(r, row_scale(J, nominal)) <= tol
        if norm <= tol:
            return w, r, J, True
        step = _step(J, r)
        if step is None:
            break
        if scaled_ok:  # round-off level: one full step, taken only if it lowers the residual
            r_try = fun(w + step)
            if np.all(np.isfinite(r_try)) and np.linalg.norm(r_try, np.inf) < norm:
                w, r = w + step, r_try
                continue
            return w, r, J, True
        lam = 1.0
        while lam > 1e-4:
            w_try = w + lam * step
            r_try = fun(w_try)
            if np.all(np.isfinite(r_try)) and np.linalg.norm(r_try, np.inf) < (1 - 1e-4 * lam) * norm:
                break
            lam *= 0.5
        else:
            break
        w, r = w_try, r_try
    return w, r, None, False


def _step(J: sps.csc_matrix, r: np.ndarray) -> np.ndarray | None:
    """The Newton step ``-J⁻¹ r`` (sparse LU), a least-squares (Gauss–Newton) step where ``J`` is singular, or None."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", sps.linalg.MatrixRankWarning)
        try:
            step = sps.linalg.spsolve(J, -r)
        except (RuntimeError, ValueError, sps.linalg.MatrixRankWarning):
            step = None
    if step is None or not np.all(np.isfinite(step)):
        try:
            step = sps.linalg.lsqr(J, -r, atol=1e-14, btol=1e-14)[0]
        except ValueError:
            return None
    return step if np.all(np.isfinite(step)) else None


def _least_squares(fun: Callable[[np.ndarray], np.ndarray], jac: Callable[[np.ndarray], sps.csc_matrix],
                   w: np.ndarray) -> np.ndarray:
    """The robust fallback: trust-region least squares from ``w`` (``w`` itself if it fails)."""
    big = len(w) > 200

    def fun_finite(x: np.ndarray) -> np.ndarray:  # a non-finite trial point makes the trust region shrink
        rx = fun(x)
        return rx if np.all(np.isfinite(rx)) else np.full_like(rx, 1e150)

    try:
        import scipy.optimize as so  # here: importing it costs 0.35 s, and most starts never get this far

        sol = so.least_squares(fun_finite, w, jac=jac if big else (lambda x: jac(x).toarray()),
                               method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=500,
                               tr_solver="lsmr" if big else "exact")
        if np.all(np.isfinite(fun(sol.x))):
            w = sol.x
    except (ValueError, np.linalg.LinAlgError):  # non-finite Jacobian: keep the Newton point for the report
        pass
    return w


def _failure(what: str, nf: list[str], r: np.ndarray, s: np.ndarray, J: Any, tol: float, labels: Labels,
             cols: Labels, nominal: np.ndarray, w: np.ndarray) -> InitializationError:
    """The error of a failed solve, naming what failed; ``best`` is the best point found, for callers that can
    change the problem and retry."""
    if nf:
        err = InitializationError(f"{what}: non-finite values:\n" + "\n".join(nf))
    else:
        scaled = np.abs(r) / s
        worst = [k for k in np.argsort(-scaled)[:5] if scaled[k] > tol]
        lines = "\n".join(f"  |residual| = {abs(r[k]):.3g} (scale {s[k]:.3g})  in  "
                          f"{labels[k][1] if k < len(labels) else k}" for k in worst)
        msg = f"{what}; largest residuals:\n" + lines
        sing = singular_lines(J, labels, cols, nominal)
        if sing:
            msg += "\n" + "\n".join(sing)
        err = InitializationError(msg)
    err.best = w
    return err


def accept(w: np.ndarray, r: np.ndarray, J: Any, diagnose: bool, labels: Labels, cols: Labels,
           what: str) -> np.ndarray:
    """Return the consistent point ``w``.

    Consistent, but the integrator also needs a finite iteration matrix there: a law whose derivative is not
    finite at the start (sign(dp)·sqrt(|dp|) at dp = 0) is named now, not as an integrator failure at t0
    (with explicit unknowns eliminated, compile/explicit.py, a start is often consistent without a Newton
    step)."""
    if diagnose:
        nf = nonfinite_lines(r, J, labels, cols, w, "at the consistent start")
        if nf:
            err = InitializationError(f"{what}: non-finite values:\n" + "\n".join(nf))
            err.best = w
            raise err
    return w


def csc(J: Any) -> sps.csc_matrix:
    """A Jacobian as CSC: the states-held one already is; a CasADi Function's comes as a sparse DM."""
    return sps.csc_matrix(J if sps.issparse(J) else J.sparse())


def pattern(jg: ca.Function) -> sps.csr_matrix:
    """The sparsity pattern of a Jacobian function's output as a 0/1 matrix (rows: equations, columns: unknowns)."""
    spj = jg.sparsity_out(0)
    colind, row = spj.get_ccs()
    return sps.csc_matrix((np.ones(len(row)), np.asarray(row), np.asarray(colind)), shape=spj.shape).tocsr()
