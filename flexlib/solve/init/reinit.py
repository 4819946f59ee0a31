"""Re-initialisation at an event: the states are held, the algebraic unknowns and the states' derivatives are solved
again from ``F(t, y, y', p) = 0`` (:func:`reinit_point`), and the rates of the algebraic unknowns are estimated for
the integrator's predictor (:func:`algebraic_rates`)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg  # noqa: F401  (sps.linalg)

from flexlib.compile.codegen import AUTO_C_MIN_UNKNOWNS, CompiledModel
from flexlib.solve.init.newton import csc, solve

__all__ = ["StatesHeld", "algebraic_rates", "held_arguments", "held_functions", "reinit_point"]


def held_functions(m: CompiledModel, diff: np.ndarray) -> tuple[Any, Any]:
    """Residual and Jacobian of the event problem with the states held: unknowns ``w = (y_alg, y'_states)``,
    parameters ``(t, p, y_states)``. A large model uses its own ``res``/``jac`` (:class:`StatesHeld`); a small one
    the exact symbolic Jacobian of the held problem, which is cheap to build there."""
    alg = np.flatnonzero(~m.differential)
    if m.n > AUTO_C_MIN_UNKNOWNS:
        held = StatesHeld(m, alg, diff)
        return held, held.jacobian
    t_s = ca.SX.sym("t")
    ypd = ca.SX.sym("ypd", len(diff))
    yp_s = ca.SX.zeros(m.n)
    for k, i in enumerate(diff):
        yp_s[i] = ypd[k]
    p_s = ca.SX.sym("p", m.n_params + m.n_relations)
    ystate = ca.SX.sym("ystate", len(diff))
    ya = ca.SX.sym("ya", len(alg))
    yfull = ca.SX.zeros(m.n)
    for k, i in enumerate(diff):
        yfull[i] = ystate[k]
    for k, i in enumerate(alg):
        yfull[i] = ya[k]
    F = m.sx_function("res")(t_s, yfull, yp_s, p_s)
    w = ca.vertcat(ya, ypd)
    par = ca.vertcat(t_s, p_s, ystate)
    return ca.Function("g", [w, par], [F]), ca.Function("jg", [w, par], [ca.jacobian(F, w)])


def held_arguments(m: CompiledModel, diff: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
                   p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The event problem's unknowns ``w = (y_alg, y'_states)``, its parameters ``(t, p, y_states)`` and the nominal
    values of ``w`` at the point ``(t, y, yp)``."""
    alg = np.flatnonzero(~m.differential)
    nom = np.asarray(m.nominal, dtype=float)
    return (np.concatenate([y[alg], yp[diff]]), np.concatenate([[t], p, y[diff]]),
            np.concatenate([nom[alg], nom[diff]]))


def reinit_point(m: CompiledModel, fns: tuple[Any, Any], diff: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
                 p: np.ndarray, tol: float, diagnose: bool = True) -> tuple[np.ndarray, np.ndarray, Any]:
    """The consistent point at ``t`` [s] with the states of ``y`` held: ``(y, yp, J)`` with ``J`` the held
    problem's Jacobian there (None where the solve did not evaluate it)."""
    g, jg = fns
    alg = np.flatnonzero(~m.differential)
    w0, par, nominal = held_arguments(m, diff, t, y, yp, p)
    labels = [(lab.split(":")[0], lab) for lab in m.row_labels]
    cols = ([(m.y_owners[i], m.y_names[i]) for i in alg] + [(m.y_owners[i], f"der({m.y_names[i]})") for i in diff])
    w, J = solve(g, jg, w0, par, tol, labels, cols, nominal,
                 what=f"could not find consistent values at t = {t:.10g} s (states held)", diagnose=diagnose)
    y_new = y.copy()
    y_new[alg] = w[:len(alg)]
    yp_new = np.zeros(m.n)
    yp_new[diff] = w[len(alg):]
    return y_new, yp_new, J


def algebraic_rates(m: CompiledModel, fns: tuple[Any, Any], diff: np.ndarray, t: float, y: np.ndarray,
                    yp: np.ndarray, p: np.ndarray, jac: sps.spmatrix | None = None) -> np.ndarray:
    """``yp`` with the rates of the algebraic variables filled in, from the consistent point at ``t + δ``.

    They do not enter the residual, but IDA's predictor uses them on the first step; zeros make the error
    test fail on systems whose algebraic variables move fast. The states are moved to ``y + δ·y'`` and the
    held problem (:func:`reinit_point`) is solved at ``t + δ`` by chord steps with its Jacobian at ``t`` (``jac``
    when the caller has it): the guess is ``O(δ)`` off and the Jacobian ``O(δ)`` stale, so two steps leave
    ``O(δ³)``, far below the ``O(δ)`` of the difference quotient itself.
    """
    if m.differential.all():
        return yp
    g, jg = fns
    alg = np.flatnonzero(~m.differential)
    na = len(alg)
    w = np.concatenate([y[alg], yp[diff]])
    delta = 1e-7 * max(1.0, abs(t))
    with np.errstate(all="ignore"):
        try:
            lu = sps.linalg.splu(csc(jac if jac is not None else jg(w, np.concatenate([[t], p, y[diff]]))))
        except RuntimeError:  # singular there: the rates stay as they are
            return yp
        par = np.concatenate([[t + delta], p, y[diff] + delta * yp[diff]])
        w2 = np.concatenate([y[alg] + delta * yp[alg], yp[diff]])
        for _ in range(2):
            r = np.asarray(g(w2, par), dtype=float).ravel()
            step = lu.solve(-r)
            if not np.all(np.isfinite(step)):
                return yp
            w2 += step
    out = yp.copy()
    out[alg] = (w2[:na] - y[alg]) / delta
    return out


class StatesHeld:
    """The event re-initialisation problem ``F(t, y, y') = 0`` with the states held, for :func:`reinit_point`.

    Unknowns ``w = (y_alg, y'_states)``, parameters ``par = (t, p, y_states)``; the rates of the algebraic
    unknowns are zero (they do not enter the residual). Evaluated with the model's own ``res`` and ``jac``
    functions — generated C when the model has it — instead of a symbolic Jacobian built for it: building that
    (``ca.jacobian`` of the whole residual) and evaluating it interpreted took 0.4 s at the one time event of
    the 794-unknown boom proxy (``benchmarks/boom_proxy.py``), more than the 2 s integration's monitor, events
    and result assembly together. ``jac`` is ``∂F/∂y + c·∂F/∂y'``, so the algebraic columns are those of
    ``jac(c = 0)`` and the state columns are ``(jac(c) − jac(0))/c`` with ``c = 2**20``: the cancellation error
    ``eps·|∂F/∂y|/c`` is far below what Newton needs, and the solve is checked on ``F`` itself. Used for models
    with more than ``AUTO_C_MIN_UNKNOWNS`` unknowns; smaller ones keep the exact symbolic Jacobian, which takes
    milliseconds to build there.
    """

    CJ = float(2**20)

    def __init__(self, model: CompiledModel, alg: np.ndarray, diff: np.ndarray) -> None:
        self.model, self.alg, self.diff = model, alg, diff
        # the model Jacobian's CSC nonzeros that make the columns of ∂F/∂w: those of the algebraic columns, then
        # those of the state columns (gathered once; each evaluation is then two C calls and two gathers)
        colind = np.asarray(model.jac_colind)
        row = np.asarray(model.jac_row)
        take = [np.arange(colind[c], colind[c + 1]) for c in np.concatenate([alg, diff]).astype(int)]
        self._take_alg = np.concatenate(take[:len(alg)] or [np.zeros(0, int)]).astype(int)
        self._take_diff = np.concatenate(take[len(alg):] or [np.zeros(0, int)]).astype(int)
        self._rows = np.concatenate([row[self._take_alg], row[self._take_diff]]).astype(np.int32)
        self._colptr = np.concatenate([[0], np.cumsum([len(k) for k in take])]).astype(np.int32)
        self._shape = (model.n, len(alg) + len(diff))

    def _point(self, w: np.ndarray, par: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
        m, na = self.model, len(self.alg)
        n_p = m.n_params + m.n_relations
        y, yp = np.zeros(m.n), np.zeros(m.n)
        y[self.alg] = w[:na]
        y[self.diff] = par[1 + n_p:]
        yp[self.diff] = w[na:]
        return float(par[0]), y, yp, par[1:1 + n_p]

    def __call__(self, w: np.ndarray, par: np.ndarray) -> np.ndarray:
        """Residual ``F`` at ``w``."""
        return np.asarray(self.model.function("res")(*self._point(w, par))).ravel()

    def jacobian(self, w: np.ndarray, par: np.ndarray) -> sps.csc_matrix:
        """``∂F/∂w`` (CSC): algebraic columns ``∂F/∂y_alg``, then state columns ``∂F/∂y'_states``."""
        t, y, yp, p = self._point(w, par)
        jac = self.model.function("jac")
        j0 = np.asarray(jac(t, y, yp, p, 0.0).nonzeros(), dtype=float)
        jc = np.asarray(jac(t, y, yp, p, self.CJ).nonzeros(), dtype=float)
        data = np.concatenate([j0[self._take_alg], (jc[self._take_diff] - j0[self._take_diff]) / self.CJ])
        J = sps.csc_matrix((data, self._rows.copy(), self._colptr.copy()), shape=self._shape)  # pruned below
        J.eliminate_zeros()  # the ∂F/∂y pattern of the state columns: no entries of ∂F/∂y'
        return J
