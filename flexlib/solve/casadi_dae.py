"""The compiled model as CasADi's IDAS integrator sees it (used by :mod:`flexlib.solve.casadi_runner`).

Two pieces of the ``casadi-idas`` backend that depend only on the compiled model: :func:`compiled_residual`, the
residual evaluated by the model's generated C with its sparse Jacobian supplied in C (CasADi differentiates an
external function only through a ``jac_<name>`` companion), and :func:`fill_reducing_order`, the COLAMD order
of the integrator's unknowns and rows that keeps its LU factors sparse. Measurements: the module docstring of
:mod:`flexlib.solve.casadi_runner` and ``benchmarks/README.md``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import warnings
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np
import scipy.sparse as sps
from scipy.sparse.linalg import splu

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import CacheWarning

__all__ = ["compiled_residual", "fill_reducing_order", "unknowns_from_xz"]


def unknowns_from_xz(n: int, x_idx: np.ndarray, z_idx: np.ndarray, z_w: np.ndarray, xd: Any, z: Any,
                     sym: Any = ca.SX) -> tuple[Any, Any, Any]:
    """``y``, ``y'`` (zero in the algebraic entries) and ``y'`` of the differential entries in ``x`` order, from the
    integrator's differential states ``xd`` (the ``y`` entries ``x_idx``) and algebraic ``z`` (the ``y`` entries
    ``z_idx``: their derivative where ``z_w``, else themselves), by permutation (:func:`fill_reducing_order`'s
    orders)."""
    nd, nz = len(x_idx), len(z_idx)
    pos_x, pos_zw, pos_za = np.full(n, -1), np.full(n, -1), np.full(n, -1)
    pos_x[x_idx] = np.arange(nd)
    pos_zw[z_idx[z_w]] = np.flatnonzero(z_w)
    pos_za[z_idx[~z_w]] = np.flatnonzero(~z_w)
    xz = ca.vertcat(xd, z)
    y_sel = [int(k) for k in np.where(pos_x >= 0, pos_x, nd + pos_za)]
    y = xz[y_sel] if n else sym(0, 1)
    w = z[[int(k) for k in pos_zw[x_idx]]] if nd else sym(0, 1)  # dx_d/dt, in x order
    zw = ca.vertcat(z, sym(1, 1))  # index nz: a structural zero for the algebraic entries' y'
    yp = zw[[int(k) if k >= 0 else nz for k in pos_zw]] if n else sym(0, 1)
    return y, yp, w


def fill_reducing_order(model: CompiledModel, sx: ca.Function) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                          np.ndarray]:
    """Orders of ``x``, ``z`` and the residual rows that keep the fill-in of the integrator's LU low.

    The integrator factorises the Jacobian of ``[dx/dτ − ode; alg]`` with respect to ``[x; z]``. Its
    structure is built here from the residual's patterns (``∂F/∂y``, ``∂F/∂y'``) and ordered by COLAMD
    (SuperLU's, through ``scipy.sparse.linalg.splu`` on random values); the differential entries of ``x`` and
    the entries of ``z`` (derivatives ``w`` and algebraic ``y``, interleaved) keep the order COLAMD gives their
    columns, the residual rows the order of SuperLU's row pivots (fill-in measured:
    ``docs/decisions/019-casadi-idas-backend.md``).

    Returns
    -------
    x_idx, z_idx, z_w, rows
        ``y`` entries of ``x`` (after ``T``); ``y`` entries of ``z`` with ``z_w`` True where the entry is the
        derivative of that ``y`` entry; residual rows in ``alg`` order.
    """
    n = model.n
    diff = np.asarray(model.differential, dtype=bool)
    d_idx, a_idx = np.flatnonzero(diff), np.flatnonzero(~diff)
    nd = len(d_idx)
    if n == 0:
        return d_idx, a_idx, np.zeros(0, dtype=bool), np.arange(0)
    # columns: x entries 0..nd-1, then z entries: w (nd of them), then the algebraic y (na)
    col_x = np.full(n, -1)
    col_x[d_idx] = np.arange(nd)
    col_z = np.full(n, -1)
    col_z[d_idx] = nd + np.arange(nd)
    col_z[a_idx] = 2 * nd + np.arange(len(a_idx))
    rows_, cols_ = [np.arange(nd), np.arange(nd)], [np.arange(nd), nd + np.arange(nd)]  # dx/dτ = u·w rows
    cy, ry = sx.jac_sparsity(0, 1).get_ccs()
    cyp, ryp = sx.jac_sparsity(0, 2).get_ccs()
    for colind, row, target in ((cy, ry, None), (cyp, ryp, col_z)):
        row = np.asarray(row, dtype=int)
        col = np.repeat(np.arange(n), np.diff(np.asarray(colind)))
        if target is None:  # ∂F/∂y: x columns for differential, z columns for algebraic entries
            c = np.where(diff[col], col_x[col], col_z[col])
        else:  # ∂F/∂y': the w columns (algebraic entries have no y' in this form)
            keep = diff[col]
            row, c = row[keep], col_z[col[keep]]
        rows_.append(nd + row)
        cols_.append(c)
    r, c = np.concatenate(rows_), np.concatenate(cols_)
    N = nd + n
    A = sps.csc_matrix((np.random.default_rng(0).uniform(1.0, 2.0, len(r)), (r, c)), shape=(N, N))
    try:
        lu = splu(A, permc_spec="COLAMD")
    except RuntimeError:  # structurally singular: keep the natural order
        return d_idx, np.concatenate([d_idx, a_idx]), np.arange(n) < nd, np.arange(n)
    rank_c, rank_r = np.asarray(lu.perm_c), np.asarray(lu.perm_r)
    x_idx = d_idx[np.argsort(rank_c[:nd], kind="stable")]
    zc = np.argsort(rank_c[nd:], kind="stable")  # z columns (0..n-1: w first, then algebraic) in order
    z_w = zc < nd
    z_idx = np.where(z_w, d_idx[np.minimum(zc, max(nd - 1, 0))] if nd else 0, a_idx[np.maximum(zc - nd, 0)]
                     if len(a_idx) else 0)
    rows = np.argsort(rank_r[nd:], kind="stable")
    return x_idx, z_idx.astype(int), z_w, rows


def compiled_residual(model: CompiledModel) -> ca.Function | None:
    """The residual ``F(t, y, y', p)`` evaluated by the model's compiled library, with its Jacobian in C.

    ``ca.external`` functions have derivatives (and a sparse Jacobian pattern) only if their library also
    holds ``jac_<name>``; the model's library has ``flexlib_res`` and ``flexlib_jac`` (``∂F/∂y + cj·∂F/∂y'``)
    only. A small companion library (CasADi-generated C, compiled by gcc in ~0.1 s CPU, once per model and
    process, in a private temporary directory removed once the library is loaded) is therefore linked
    against it and adds ``jac_flexlib_res``: ``∂F/∂y`` is ``flexlib_jac`` at ``cj = 0``, ``∂F/∂y'`` the
    difference of its values at ``cj = 1`` and ``cj = 0``, each on its own structural pattern (from the SX
    residual). The derivatives with respect to ``t`` and ``p`` are structural zeros: the integrator
    differentiates only with respect to its states, and the normalised time ``T`` is predicted exactly by
    IDAS (``dT/dτ`` is the constant ``u``), so its column does not change the Newton iteration.
    ``flexlib_res`` itself is found through the companion's dependency on the model's library. Returns None
    if the model has no compiled library in use or no C compiler.
    """
    if model.library is None and getattr(model, "library_pending", None) is not None:
        model.function("res")  # adopts a library gcc has finished in the background
    cc = shutil.which("gcc") or shutil.which("cc")
    if model.library is None or cc is None:
        return None
    model.function("res")  # checks the library against its manifest (drops it, with a warning, if damaged)
    if model.library is None:
        return None
    n, npar = model.n, model.n_params + model.n_relations
    jac_e = model.function("jac")
    sx = model.sx_function("res")
    t, y, yp, p = ca.MX.sym("t"), ca.MX.sym("y", n), ca.MX.sym("yp", n), ca.MX.sym("p", npar)
    out = ca.MX.sym("out_res", ca.Sparsity(n, 1))
    J0 = jac_e(t, y, yp, p, 0.0)
    J1 = jac_e(t, y, yp, p, 1.0)
    jy = ca.project(J0, sx.jac_sparsity(0, 1))
    jyp = ca.project(J1 - J0, sx.jac_sparsity(0, 2))
    jac = ca.Function("jac_flexlib_res", [t, y, yp, p, out], [ca.MX(n, 1), jy, jyp, ca.MX(n, npar)],
                      ["t", "y", "yp", "p", "out_res"], ["jac_res_t", "jac_res_y", "jac_res_yp", "jac_res_p"])
    work = Path(tempfile.mkdtemp(prefix="flexlib-casadi-idas-"))
    cg = ca.CodeGenerator("jac_flexlib_res.c")
    cg.add(jac)
    cg.generate(str(work) + os.sep)
    lib = Path(model.library)
    shim = work / "jac_flexlib_res.so"
    done = subprocess.run([cc, "-O1", "-shared", "-fPIC", str(work / "jac_flexlib_res.c"), "-o", str(shim),
                           f"-L{lib.parent}", f"-l:{lib.name}", f"-Wl,-rpath,{lib.parent}"],
                          capture_output=True, text=True, check=False)
    try:
        if done.returncode != 0:
            warnings.warn(f"casadi-idas: the Jacobian companion of {model.library} did not compile "
                          f"({done.stderr.strip()[:200]}); using the symbolic residual", CacheWarning, stacklevel=3)
            return None
        return ca.external("flexlib_res", str(shim))  # loaded now: the files can go
    finally:
        shutil.rmtree(work, ignore_errors=True)
