"""Diagnostics that say where: non-finite values, singular Jacobians and failing integrator steps.

The initialisation (stage 4) and the integrator (stage 6) call these helpers only when something has
already failed, to turn a bare "could not converge" into the equations, variables and components that
caused it. Nothing here changes a result.

* :func:`nonfinite_lines` — equations whose residual, and (equation, variable) pairs whose Jacobian
  entry, is NaN or ±Inf at a point (a ``1/x`` at ``x = 0``, ``sqrt`` of a negative number, the
  ``0·∞`` of ``sign(x)·sqrt(|x|)`` differentiated at ``x = 0``).
* :func:`singular_lines` — a numerically singular (scaled) Jacobian: the dependent equations and the
  variables of the null space, grouped by component (rank-revealing SVD / pivoted QR).
* :func:`step_failure_lines` — an integrator failure: non-finite values at the last accepted point and
  at a predicted point a little further on, and the unknowns that change fastest relative to their
  error weight ``rtol·|y| + atol·nominal`` (the ones that dominate IDA's local error test; scikit-sundae
  exposes neither IDA's error weights nor its estimated local errors, so they are recomputed here).

Each returns a list of text lines (empty if nothing was found).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps

from flexlib.compile.structure import group_by_owner

__all__ = ["failure_message", "nonfinite_lines", "row_scale", "singular_lines", "step_failure_lines"]

#: Dense rank analysis (SVD) up to this many unknowns; pivoted QR of the scaled matrix above, up to
#: ``_DENSE_QR_MAX`` (both O(n³): beyond that the analysis would take longer than the failure is worth).
_DENSE_SVD_MAX = 1500
_DENSE_QR_MAX = 3000


def _owner(label: str) -> str:
    return label.split(":")[0] if ":" in label else ""


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def row_scale(J: sps.spmatrix, nominal: np.ndarray) -> np.ndarray:
    """Per-equation scale ``max_j |J_ij|·nominal_j``, at least 1.

    The size a residual of equation ``i`` takes when one of its variables moves by its nominal value.
    The initialisation tests ``|F_i| <= tol·row_scale_i``, so that an equation in Pa with 1e7 Pa terms
    is held to the same relative accuracy as one in metres (round-off of a 1e7 Pa equation is ~1e-9 Pa,
    far above an absolute 1e-10); the floor of 1 keeps small-valued equations at the absolute tolerance.
    """
    A = sps.csr_matrix(J)  # row-wise maxima straight from the CSR arrays (scipy's max(axis=1) costs ~1 ms a call)
    mx = np.zeros(A.shape[0])
    filled = np.diff(A.indptr) > 0
    if A.nnz:
        with np.errstate(invalid="ignore"):
            vals = np.abs(A.data * np.asarray(nominal, dtype=float)[A.indices])
            mx[filled] = np.maximum.reduceat(vals, A.indptr[:-1][filled])
    mx = np.where(np.isfinite(mx), mx, 1.0)
    return np.maximum(mx, 1.0)


def nonfinite_lines(r: np.ndarray, J: sps.spmatrix | None, rows: Sequence[tuple[str, str]],
                    cols: Sequence[tuple[str, str]], w: np.ndarray, where: str, limit: int = 8) -> list[str]:
    """Lines naming non-finite residuals and Jacobian entries.

    Parameters
    ----------
    r : ndarray
        Residual vector at the point.
    J : sparse matrix or None
        Jacobian ``dF/dw`` at the point (non-finite entries are reported).
    rows : sequence of (owner, label)
        One per equation.
    cols : sequence of (owner, name)
        One per unknown.
    w : ndarray
        Values of the unknowns at the point (shown for the variables involved).
    where : str
        Words naming the point ("at the start point", "at t = 0.5 s").
    """
    lines: list[str] = []
    csr = sps.csr_matrix(J) if J is not None else None
    bad_w = [j for j in range(len(w)) if not np.isfinite(w[j])]
    for j in bad_w[:limit]:
        lines.append(f"  variable {cols[j][1]} = {_fmt(w[j])} is not finite {where} "
                     f"(component {cols[j][0] or '(model)'})")
    bad_r = np.flatnonzero(~np.isfinite(r))
    for i in bad_r[:limit]:
        involved = ""
        if csr is not None:
            js = csr.indices[csr.indptr[i]:csr.indptr[i + 1]]
            involved = ", ".join(f"{cols[j][1]} = {_fmt(w[j])}" for j in js[:6])
            involved = f"; its variables: {involved}" if involved else ""
        lines.append(f"  equation {rows[i][1]} evaluates to {_fmt(r[i])} {where}{involved}")
    if len(bad_r) > limit:
        lines.append(f"  … and {len(bad_r) - limit} more equations")
    if csr is not None:
        coo = csr.tocoo()
        bad = np.flatnonzero(~np.isfinite(coo.data))
        bad = [k for k in bad if np.isfinite(r[coo.row[k]])] or list(bad)
        for k in bad[:limit]:
            i, j = int(coo.row[k]), int(coo.col[k])
            lines.append(f"  equation {rows[i][1]}: the derivative with respect to {cols[j][1]} "
                         f"(= {_fmt(w[j])}) is {_fmt(coo.data[k])} — the derivative of this equation with respect "
                         f"to that variable is not finite {where}; regularise the law there (e.g. a laminar "
                         "region around zero flow, a guard against division by zero)")
        if len(bad) > limit:
            lines.append(f"  … and {len(bad) - limit} more non-finite Jacobian entries")
    return lines


def rank_deficiency(J: sps.spmatrix, nominal: np.ndarray, rtol: float = 1e-10) -> tuple[set[int], set[int]]:
    """The dependent equations (rows) and the undetermined variables (columns) of a numerically singular Jacobian;
    two empty sets if it is regular (or above 3000 unknowns).

    The columns are scaled by the nominal values and the rows by their largest entry, then the rank is
    found by SVD (dense, up to 1500 unknowns) or pivoted QR. Equations with a weight above 1e-3 in a left
    null vector are the dependent ones; variables with a weight above 1e-3 in a right null vector are the
    ones the equations fail to determine.
    """
    if J.shape[0] == 0 or J.shape[1] == 0 or max(J.shape) > _DENSE_QR_MAX:
        return set(), set()
    A = sps.csr_matrix(J).toarray().astype(float)
    if not np.all(np.isfinite(A)):
        return set(), set()
    A = A * np.asarray(nominal, dtype=float)[None, :]
    rs = np.abs(A).max(axis=1)
    A = A / np.where(rs > 0, rs, 1.0)[:, None]
    n_r, n_c = A.shape
    dep_rows: set[int] = set(np.flatnonzero(rs == 0).tolist())
    free_cols: set[int] = set(np.flatnonzero(np.abs(A).max(axis=0) == 0).tolist())
    if max(n_r, n_c) <= _DENSE_SVD_MAX:
        U, s, Vt = np.linalg.svd(A)
        tol = rtol * max(s[0], 1e-300) * max(n_r, n_c) if len(s) else 0.0
        rank = int(np.sum(s > tol))
        for k in range(rank, n_r):
            dep_rows.update(np.flatnonzero(np.abs(U[:, k]) > 1e-3).tolist())
        for k in range(rank, n_c):
            free_cols.update(np.flatnonzero(np.abs(Vt[k]) > 1e-3).tolist())
    else:
        _, R, piv = sla.qr(A.T, mode="economic", pivoting=True)
        d = np.abs(np.diag(R))
        rank = int(np.sum(d > rtol * max(d[0], 1e-300))) if len(d) else 0
        dep_rows.update(int(i) for i in piv[rank:])
        _, R, piv = sla.qr(A, mode="economic", pivoting=True)
        d = np.abs(np.diag(R))
        rank_c = int(np.sum(d > rtol * max(d[0], 1e-300))) if len(d) else 0
        free_cols.update(int(j) for j in piv[rank_c:])
    return dep_rows, free_cols


def singular_lines(J: sps.spmatrix, rows: Sequence[tuple[str, str]], cols: Sequence[tuple[str, str]],
                   nominal: np.ndarray, rtol: float = 1e-10) -> list[str]:
    """If the scaled Jacobian is numerically singular, lines naming the dependent equations and the
    variables of its null space, grouped by component; empty if it is regular (or above 3000 unknowns)
    (:func:`rank_deficiency`)."""
    dep_rows, free_cols = rank_deficiency(J, nominal, rtol)
    if not dep_rows and not free_cols:
        return []
    out = ["the Jacobian is numerically singular there (rank-revealing decomposition of the scaled iteration matrix)"]
    if dep_rows:
        out.append("dependent equations:\n" + group_by_owner([(rows[i][0], rows[i][1].split(": ", 1)[-1])
                                                              for i in sorted(dep_rows)]))
    if free_cols:
        out.append("variables they leave undetermined:\n" + group_by_owner([cols[j] for j in sorted(free_cols)]))
    return out


def step_failure_lines(model: Any, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray, rtol: float,
                       atol_vec: np.ndarray, h: float, limit: int = 5) -> list[str]:
    """Why an integrator step from the last accepted point ``(t, y, yp)`` failed.

    1. Non-finite residuals or Jacobian entries at ``(t, y, yp)``, then at predicted points
       ``(t + h, y + h·yp)`` for ``h`` and smaller steps (the division by zero or the square root of
       a negative number that the failed step ran into), naming the equation and its variables; else, if IDA's
       iteration matrix ``dF/dy + dF/dy'/h`` is numerically singular there, the dependent equations.
    2. The unknowns with the largest rate relative to their error weight, ``|y'|/(rtol·|y| + atol_i)``
       (the ones that dominate IDA's local error estimate), grouped by component, with their values.

    Parameters
    ----------
    model : CompiledModel
    p : ndarray
        Parameters and relation values.
    h : float
        Step size to predict with [s] (the last step taken, or a guess).
    """
    res, jac = model.function("res"), model.function("jac")
    n = model.n
    rows = [(_owner(lab), lab) for lab in model.row_labels] or [("", f"row {i}") for i in range(n)]
    cols = list(zip(model.y_owners, model.y_names, strict=True))
    lines: list[str] = []

    def probe(tq: float, yq: np.ndarray, ypq: np.ndarray, where: str) -> list[str]:
        with np.errstate(all="ignore"):
            r = np.asarray(res(tq, yq, ypq, p)).ravel()
            J0 = sps.csc_matrix(jac(tq, yq, ypq, p, 0.0).sparse())
            J1 = sps.csc_matrix(jac(tq, yq, ypq, p, 1.0).sparse())
        out = nonfinite_lines(r, J0, rows, cols, yq, where)
        if not out:  # finite dF/dy; a non-finite dF/dy' entry names der(variable)
            dcols = [(o, f"der({nm})") for o, nm in cols]
            out = nonfinite_lines(r, J1, rows, dcols, ypq, where)
        return out

    lines += probe(t, y, yp, f"at the last accepted point t = {t:.10g} s")
    if not lines and np.all(np.isfinite(yp)):
        for k in range(8):
            hk = h * 0.1**k
            if hk <= 0:
                break
            found = probe(t + hk, y + hk * yp, yp, f"at the predicted point t = {t + hk:.10g} s")
            if found:
                lines += found
                break
    if not lines and n <= _DENSE_SVD_MAX and np.all(np.isfinite(y)) and np.all(np.isfinite(yp)):
        # a singular iteration matrix dF/dy + cj·dF/dy' (an index change, a constraint that loses rank)
        with np.errstate(all="ignore"):
            J = sps.csc_matrix(jac(t, y, yp, p, 1.0 / h).sparse())
        lines += singular_lines(J, rows, cols, np.asarray(model.nominal, dtype=float), rtol=1e-9)
    with np.errstate(all="ignore"):
        weight = rtol * np.abs(y) + np.asarray(atol_vec, dtype=float)
        rate = np.abs(yp) / weight
    rate = np.where(np.isfinite(rate), rate, np.inf)
    order = [int(i) for i in np.argsort(-rate) if rate[i] > 0][:limit]
    if order:
        items = [(cols[i][0], f"{cols[i][1]} = {_fmt(y[i])}, der = {_fmt(yp[i])} "
                 f"({_fmt(rate[i])} error weights/s)") for i in order]
        lines.append("fastest-changing unknowns relative to their error weight rtol·|y| + atol·nominal "
                     "(they dominate the local error test):\n" + group_by_owner(items))
    return lines


def failure_message(head: str, model: Any, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray, traj: Any,
                    rtol: float, atol: float, error_test_all: bool | None = None) -> str:
    """``head`` followed by what failed (:func:`step_failure_lines`): non-finite values at the last accepted point
    ``(t, y, yp)`` or just after it with the equation that produced them, and the unknowns that dominate the local
    error test, by component (``traj``: the run's rows so far, for the last step size; ``error_test_all``: the
    solver's, as for :func:`~flexlib.solve.backends.base.absolute_tolerances`)."""
    from flexlib.solve.backends.base import absolute_tolerances

    times = [tt for tt in traj.t if tt < t]
    h = t - times[-1] if times else 1e-6 * max(1.0, abs(t))
    h = max(h, 1e-12 * max(1.0, abs(t)))
    try:
        lines = step_failure_lines(model, p, t, np.asarray(y, dtype=float), np.asarray(yp, dtype=float), rtol,
                                   absolute_tolerances(model, atol, error_test_all), h)
    except Exception as exc:  # the diagnosis must never hide the failure itself
        lines = [f"(no further diagnosis: {type(exc).__name__}: {exc})"]
    return head + ("\n" + "\n".join(lines) if lines else "")
