"""Stage 4 — initialisation: consistent ``y(t0)``, ``y'(t0)`` from start values and ``fixed`` flags.

The initialisation problem has the unknowns ``y`` and the derivatives of the states, and
the equations ``F(t0, y, y', p) = 0`` plus one equation per initial condition (a fixed
start value, or ``der(x) = 0`` for every state without one in steady-state mode). It must
be square and structurally regular; otherwise the error names the over-specified
conditions or the states left free. It is solved by a damped Newton method on the sparse
CasADi Jacobian (SciPy sparse LU), falling back to SciPy's trust-region least squares.

The same machinery re-initialises after an event: states keep their values, algebraic
variables and derivatives are recomputed.
"""

from __future__ import annotations

import warnings

import casadi as ca
import numpy as np
import scipy.optimize as so
import scipy.sparse as sps
import scipy.sparse.linalg  # noqa: F401  (sps.linalg)

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.structure import culprits, group_by_owner, matching
from flexlib.errors import InitializationError

__all__ = ["Initializer"]


class Initializer:
    """Consistent initial values for one compiled model (functions built lazily, reused)."""

    def __init__(self, model: CompiledModel) -> None:
        self.model = model
        self.diff = np.flatnonzero(model.differential)
        self._init_fns: dict[tuple, tuple[ca.Function, ca.Function]] = {}
        self._reinit_fns: tuple[ca.Function, ca.Function] | None = None

    # -- symbolic set-up ------------------------------------------------------------------------
    def _symbols(self) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX, ca.SX]:
        m = self.model
        t = ca.SX.sym("t")
        y = ca.SX.sym("y", m.n)
        ypd = ca.SX.sym("ypd", len(self.diff))
        yp = ca.SX.zeros(m.n)
        for k, i in enumerate(self.diff):
            yp[i] = ypd[k]
        p = ca.SX.sym("p", m.n_params + m.n_relations)
        return t, y, ypd, yp, p

    def _init_functions(self, active: tuple[int, ...], steady: tuple[int, ...]) -> tuple[ca.Function, ca.Function]:
        key = (active, steady)
        if key not in self._init_fns:
            m = self.model
            t, y, ypd, yp, p = self._symbols()
            vals = ca.SX.sym("vals", len(active))
            F = m.sx_function("res")(t, y, yp, p)
            C = m.sx_function("cond")(t, y, yp, p)
            rows = [F]
            if active:
                rows.append(ca.vertcat(*[C[k] for k in active]) - vals)
            if steady:
                rows.append(ca.vertcat(*[ypd[k] for k in steady]))
            G = ca.vertcat(*rows)
            w = ca.vertcat(y, ypd)
            g = ca.Function("g", [w, ca.vertcat(t, p, vals)], [G])
            jg = ca.Function("jg", [w, ca.vertcat(t, p, vals)], [ca.jacobian(G, w)])
            self._init_fns[key] = (g, jg)
        return self._init_fns[key]

    def _labels(self, active: tuple[int, ...], steady: tuple[int, ...]) -> list[tuple[str, str]]:
        m = self.model
        labels = [(lab.split(":")[0], lab) for lab in m.row_labels]
        labels += [("initial conditions", f"{m.conditions[k][0]} = start value") for k in active]
        labels += [("steady state", f"der({m.y_names[self.diff[k]]}) = 0") for k in steady]
        return labels

    # -- public ---------------------------------------------------------------------------------
    def initial(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                steady_state: bool = False, tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
        """Consistent initial values at ``t0``.

        Parameters
        ----------
        t0 : float
            Initial time [s].
        p : ndarray
            Parameter vector (parameters, then relation values).
        starts : dict
            ``{name: (start, fixed)}`` for every scalar variable (from the model instance).
        steady_state : bool
            Add ``der(x) = 0`` for every state that has no initial condition of its own.
        """
        m = self.model
        cond_vals = np.array([starts.get(name, (val, True))[0] for name, val in m.conditions])
        active = []
        cond_fn = m.function("cond")
        y_guess = self.guess(starts)
        for k, (name, _) in enumerate(m.conditions):
            if m.cond_depends[k]:
                active.append(k)
                continue
            have = float(np.asarray(cond_fn(t0, y_guess, np.zeros(m.n), p)).ravel()[k])
            if abs(have - cond_vals[k]) > 1e-9 * max(1.0, abs(have)):
                raise InitializationError(
                    f"initial condition {name} = {cond_vals[k]:g} contradicts the model, which fixes it to {have:g}")
        steady: list[int] = []
        if steady_state:
            fixed_names = {m.conditions[k][0] for k in active}
            steady = [k for k, i in enumerate(self.diff) if m.y_names[i] not in fixed_names]
        par = np.concatenate([[t0], p, cond_vals[active]])
        w0 = np.concatenate([y_guess, np.zeros(len(self.diff))])
        if steady:
            steady = self._complementary_steady(tuple(active), tuple(steady), w0, par)
        active_t, steady_t = tuple(active), tuple(steady)
        g, jg = self._init_functions(active_t, steady_t)
        self._check_structure(jg, w0, par, active_t, steady_t)
        try:
            w = self._solve(g, jg, w0, par, tol, self._labels(active_t, steady_t))
        except InitializationError as err:
            best = getattr(err, "best", None)
            if best is not None:
                err.point = self._split(best)
            raise
        y, yp = self._split(w)
        return y, self.algebraic_rates(t0, y, yp, p)

    def _complementary_steady(self, active: tuple[int, ...], steady: tuple[int, ...], w0: np.ndarray,
                              par: np.ndarray) -> list[int]:
        """The ``der(x) = 0`` rows that complement the model's own initial conditions.

        Initial equations and fixed start values of algebraic variables (a volume's start
        pressure fixes its stored mass) take the place of some steady-state rows. Rows are
        matched in priority order (model equations, initial conditions, then steady-state rows);
        augmenting paths never unmatch a row, so the steady-state rows left unmatched are exactly
        those the other conditions make redundant.
        """
        _, jg = self._init_functions(active, steady)
        pattern = jg.sparsity_out(0)
        colind, row = pattern.get_ccs()
        inc = sps.csc_matrix((np.ones(len(row)), row, colind), shape=pattern.shape).tocsr()
        row_match, _ = matching(inc, in_order=True)
        first = self.model.n + len(active)
        return [k for j, k in enumerate(steady) if row_match[first + j] >= 0]

    def guess(self, starts: dict[str, tuple[float, bool]]) -> np.ndarray:
        """Start guesses for ``y`` from the model's start values."""
        y = np.zeros(self.model.n)
        for i, sources in enumerate(self.model.start_sources):
            for name, sign in sources:
                val = starts.get(name, (0.0, False))[0]
                if val != 0.0:
                    y[i] = sign * val
                    break
        return y

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
               tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
        """Recompute algebraic variables and derivatives at an event, states held."""
        y_new, yp_new = self._reinit(t, y, yp, p, tol)
        return y_new, self.algebraic_rates(t, y_new, yp_new, p)

    def algebraic_rates(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> np.ndarray:
        """``yp`` with the rates of the algebraic variables filled in (by a consistent solve at ``t + δ``).

        They do not enter the residual, but IDA's predictor uses them on the first step; zeros
        make the error test fail on systems whose algebraic variables move fast.
        """
        alg = np.flatnonzero(~self.model.differential)
        if len(alg) == 0:
            return yp
        delta = 1e-7 * max(1.0, abs(t))
        y2 = y + delta * yp
        try:
            y2, _ = self._reinit(t + delta, y2, yp, p, 1e-12)
        except InitializationError:
            return yp
        out = yp.copy()
        out[alg] = (y2[alg] - y[alg]) / delta
        return out

    def _reinit(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
                tol: float) -> tuple[np.ndarray, np.ndarray]:
        m = self.model
        if self._reinit_fns is None:
            t_s, _, ypd, yp_s, p_s = self._symbols()
            ystate = ca.SX.sym("ystate", len(self.diff))
            alg = np.flatnonzero(~m.differential)
            ya = ca.SX.sym("ya", len(alg))
            yfull = ca.SX.zeros(m.n)
            for k, i in enumerate(self.diff):
                yfull[i] = ystate[k]
            for k, i in enumerate(alg):
                yfull[i] = ya[k]
            F = m.sx_function("res")(t_s, yfull, yp_s, p_s)
            w = ca.vertcat(ya, ypd)
            par = ca.vertcat(t_s, p_s, ystate)
            self._reinit_fns = (ca.Function("g", [w, par], [F]), ca.Function("jg", [w, par], [ca.jacobian(F, w)]))
            self._alg = alg
        g, jg = self._reinit_fns
        w0 = np.concatenate([y[self._alg], yp[self.diff]])
        par = np.concatenate([[t], p, y[self.diff]])
        labels = [(lab.split(":")[0], lab) for lab in m.row_labels]
        w = self._solve(g, jg, w0, par, tol, labels)
        y_new = y.copy()
        y_new[self._alg] = w[:len(self._alg)]
        yp_new = np.zeros(m.n)
        yp_new[self.diff] = w[len(self._alg):]
        return y_new, yp_new

    # -- internals ------------------------------------------------------------------------------
    def _split(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = self.model.n
        y = w[:n].copy()
        yp = np.zeros(n)
        yp[self.diff] = w[n:]
        return y, yp

    def _unknown_names(self) -> list[tuple[str, str]]:
        m = self.model
        names = [(o, nm) for o, nm in zip(m.y_owners, m.y_names, strict=True)]
        names += [(m.y_owners[i], f"der({m.y_names[i]})") for i in self.diff]
        return names

    def _check_structure(self, jg: ca.Function, w0: np.ndarray, par: np.ndarray,
                         active: tuple[int, ...], steady: tuple[int, ...]) -> None:
        spj = jg.sparsity_out(0)
        colind, row = spj.get_ccs()
        inc = sps.csc_matrix((np.ones(len(row)), np.asarray(row), np.asarray(colind)), shape=spj.shape).tocsr()
        n_eq, n_unk = spj.shape
        row_match, col_match = matching(inc)
        if n_eq == n_unk and np.all(row_match >= 0):
            return
        rows, cols = culprits(inc, row_match, col_match)
        labels = self._labels(active, steady)
        unknowns = self._unknown_names()
        n_cond = len(active) + len(steady)
        n_states = len(self.diff)
        states = ", ".join(self.model.y_names[i] for i in self.diff)
        parts = [f"the model has {n_states} states ({states}) and {n_cond} initial conditions"]
        over = [labels[r] for r in rows if r >= self.model.n]
        if rows:
            parts.append("over-specified — these conditions conflict with the equations or each other:\n"
                         + group_by_owner(over or [labels[r] for r in rows]))
        if cols:
            parts.append("under-specified — these unknowns are not determined; add init={...} for states among "
                         "them (or use steady_state=True):\n" + group_by_owner([unknowns[c] for c in cols]))
        kind = "over-specified" if rows and not cols else "under-specified" if cols and not rows else "inconsistent"
        raise InitializationError(f"initial conditions are {kind}: " + "\n".join(parts))

    def _solve(self, g: ca.Function, jg: ca.Function, w0: np.ndarray, par: np.ndarray, tol: float,
               labels: list[tuple[str, str]]) -> np.ndarray:
        def fun(w: np.ndarray) -> np.ndarray:
            return np.asarray(g(w, par)).ravel()

        def jac(w: np.ndarray) -> sps.csc_matrix:
            return sps.csc_matrix(jg(w, par).sparse())

        w = w0.astype(float).copy()
        r = fun(w)
        scale = 1.0
        # damped Newton with sparse LU (fast path for the usual well-posed problem)
        for _ in range(50):
            norm = np.linalg.norm(r, np.inf)
            if norm <= tol * scale:
                return w
            J = jac(w)
            with warnings.catch_warnings():
                warnings.simplefilter("error", sps.linalg.MatrixRankWarning)
                try:
                    step = sps.linalg.spsolve(J, -r)
                except (RuntimeError, sps.linalg.MatrixRankWarning):
                    step = None
            if step is None or not np.all(np.isfinite(step)):  # singular: least-squares (Gauss–Newton) step
                step = sps.linalg.lsqr(J, -r, atol=1e-14, btol=1e-14)[0]
            if not np.all(np.isfinite(step)):
                break
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
        if np.linalg.norm(r, np.inf) <= tol * scale:
            return w
        # robust fallback: trust-region least squares
        big = len(w) > 200

        def fun_finite(x: np.ndarray) -> np.ndarray:  # a non-finite trial point makes the trust region shrink
            rx = fun(x)
            return rx if np.all(np.isfinite(rx)) else np.full_like(rx, 1e150)

        try:
            sol = so.least_squares(fun_finite, w, jac=jac if big else (lambda x: jac(x).toarray()), method="trf",
                                   xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=500,
                                   tr_solver="lsmr" if big else "exact")
            if np.all(np.isfinite(fun(sol.x))):
                w = sol.x
        except ValueError:  # non-finite Jacobian: keep the damped-Newton point for the report
            pass
        r = fun(w)
        if np.linalg.norm(r, np.inf) <= max(tol, 1e-8) * scale:
            return w
        worst = np.argsort(-np.abs(r))[:5]
        lines = "\n".join(f"  |residual| = {abs(r[k]):.3g}  in  {labels[k][1] if k < len(labels) else k}"
                          for k in worst if abs(r[k]) > tol)
        err = InitializationError("could not find consistent initial values; largest residuals:\n" + lines)
        err.best = w  # the best point found, for callers that can change the problem and retry
        raise err
