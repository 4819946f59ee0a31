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
from typing import Any

import casadi as ca
import numpy as np
import scipy.linalg as sla
import scipy.optimize as so
import scipy.sparse as sps
import scipy.sparse.linalg  # noqa: F401  (sps.linalg)

from flexlib.compile.codegen import AUTO_C_MIN_UNKNOWNS, CompiledModel, compile_dae
from flexlib.compile.structure import culprits, group_by_owner, matching, row_jacobian
from flexlib.core.instance_values import DEFAULT_START
from flexlib.errors import InitializationError, ParameterError
from flexlib.solve.diagnose import nonfinite_lines, row_scale, singular_lines

__all__ = ["Initializer"]


class Initializer:
    """Consistent initial values for one compiled model (functions built lazily, reused)."""

    def __init__(self, model: CompiledModel, structure: Any = None) -> None:
        self.model = model
        #: callable giving the model's index-reduction structure (``Build.structure``): a failure of a model with
        #: explicit algebraics eliminated is diagnosed on the DAE that keeps them (see :meth:`initial`)
        self._structure = structure
        self.diff = np.flatnonzero(model.differential)
        self._init_fns: dict[tuple, tuple[ca.Function, ca.Function]] = {}
        self._reinit_fns: tuple[Any, Any] | None = None
        self._last_jac: Any = None  # the Jacobian at the point the last _solve accepted (None: not evaluated)

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

    def _init_functions(self, active: tuple[int, ...], steady: tuple[int, ...],
                        defaults: tuple[int, ...] = ()) -> tuple[ca.Function, ca.Function]:
        key = (active, steady, defaults)
        if key not in self._init_fns:
            m = self.model
            t, y, ypd, yp, p = self._symbols()
            vals = ca.SX.sym("vals", len(active) + len(defaults))
            F = m.sx_function("res")(t, y, yp, p)
            C = m.sx_function("cond")(t, y, yp, p)
            rows = [F]
            if active:
                rows.append(ca.vertcat(*[C[k] for k in active]) - vals[:len(active)])
            if steady:
                rows.append(ca.vertcat(*[ypd[k] for k in steady]))
            if defaults:
                rows.append(ca.vertcat(*[y[k] for k in defaults]) - vals[len(active):])
            G = ca.vertcat(*rows)
            w = ca.vertcat(y, ypd)
            g = ca.Function("g", [w, ca.vertcat(t, p, vals)], [G])
            jg = ca.Function("jg", [w, ca.vertcat(t, p, vals)], [row_jacobian(G, w)])  # dense rows in reverse mode
            self._init_fns[key] = (g, jg)
        return self._init_fns[key]

    def _labels(self, active: tuple[int, ...], steady: tuple[int, ...],
                defaults: tuple[int, ...] = ()) -> list[tuple[str, str]]:
        m = self.model
        labels = [(lab.split(":")[0], lab) for lab in m.row_labels]
        labels += [("initial conditions", f"{m.conditions[k][0]} = start value") for k in active]
        labels += [("steady state", f"der({m.y_names[self.diff[k]]}) = 0") for k in steady]
        labels += [("initial conditions", f"{m.y_names[k]} = default start value") for k in defaults]
        return labels

    def _default_starts(self, starts: dict[str, tuple[float, Any]], active: tuple[int, ...],
                        steady: tuple[int, ...], w0: np.ndarray, par: np.ndarray,
                        tol: float) -> tuple[tuple[int, ...], np.ndarray]:
        """The unknowns whose ``"default"`` start values the initial system needs (``Component.set_start``), and
        the point to start the square solve from.

        If the equations, initial conditions and steady-state rows leave unknowns undetermined, the system with
        *every* default row ``y_k = start`` is solved first in the least-squares sense (consistent unless a
        default conflicts with the model); at that point, in the model's order, each default row independent of
        the others' and of the Jacobian's rows is taken: ``e_k`` with a component in the null space not spanned
        by the rows taken before. Numeric, at a consistent point, not structural: a modal coordinate that a
        joint locks appears in the loop rows, and its default row is not taken."""
        m = self.model
        cands = tuple(k for k, name in enumerate(m.y_names) if starts.get(name, (0.0, False))[1] == DEFAULT_START)
        if not cands:
            return (), w0
        jg = self._init_functions(active, steady)[1]
        inc = _pattern(jg)
        if int(np.sum(matching(inc)[0] >= 0)) == inc.shape[1]:
            return (), w0  # the conditions given already determine every unknown
        g_all, jg_all = self._init_functions(active, steady, cands)
        par_all = np.concatenate([par, w0[list(cands)]])
        try:
            point = self._solve(g_all, jg_all, w0, par_all, tol, self._labels(active, steady, cands),
                                self._unknown_names(), self._nominal_w(), diagnose=False)
        except InitializationError as err:
            best = getattr(err, "best", None)
            point = w0 if best is None else best
        with np.errstate(all="ignore"):
            J = np.asarray(ca.DM(jg(point, par)).full())
        J = np.nan_to_num(J, nan=0.0, posinf=0.0, neginf=0.0)
        col_scale = np.maximum(np.abs(J).max(axis=0), 1e-300)
        N = sla.null_space(J / col_scale, rcond=1e-10)  # null space in scaled unknowns
        chosen: list[int] = []
        basis = np.zeros((0, N.shape[1]))
        for k in cands:
            if len(chosen) == N.shape[1]:
                break
            v = N[k].copy()
            if basis.shape[0]:
                v -= basis.T @ (basis @ v)
            norm = float(np.linalg.norm(v))
            if norm > 1e-5:  # the null space's rows are O(1) where free, round-off (1e-8 and below) where not
                basis = np.vstack([basis, v / norm])
                chosen.append(k)
        point = point.copy()
        point[list(chosen)] = w0[list(chosen)]  # the default rows hold exactly at the start of the square solve
        return tuple(chosen), point

    # -- public ---------------------------------------------------------------------------------
    def initial(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                steady_state: bool = False, tol: float = 1e-10, diagnose: bool = True) -> tuple[np.ndarray, np.ndarray]:
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

        A failure of a model whose explicit algebraics were eliminated (``report.explicit``) is diagnosed
        again on the DAE that keeps them, so the message names the equations and variables as written
        (``x + y = 1`` and ``2x + 2y = 3`` both, not their combination).
        """
        try:
            return self._initial(t0, p, starts, steady_state, tol, diagnose)
        except InitializationError:
            full = self._full_model() if diagnose else None
            if full is None:
                raise
            Initializer(full).initial(t0, p, starts, steady_state, tol, diagnose)
            raise  # the full DAE initialises: the reduced model's own message stands

    def _full_model(self) -> CompiledModel | None:
        """The model compiled without the explicit-algebraics stage (None if it has none or no structure)."""
        if not self.model.report.explicit or self._structure is None:
            return None
        structure = self._structure()
        dummies, levels = structure.select()
        dae = structure.assemble(dummies, levels, explicit=False)
        return compile_dae(structure.simple.flat, structure.simple, dae, codegen=False)

    def _initial(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                 steady_state: bool = False, tol: float = 1e-10, diagnose: bool = True
                 ) -> tuple[np.ndarray, np.ndarray]:
        m = self.model
        self._check_finite(p, starts)
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
                if ": " in name and " #" in name:  # an initial equation of time and parameters only
                    raise InitializationError(
                        f"initial equation {name.rsplit(' #', 1)[0]} involves no unknown (only time and parameters) "
                        f"and does not hold at the start t = {t0:g} s: its residual there is {have:g}")
                raise InitializationError(
                    f"initial condition {name} = {cond_vals[k]:g} contradicts the model, which fixes it to {have:g}")
        steady: list[int] = []
        held: list[int] = []
        par = np.concatenate([[t0], p, cond_vals[active]])
        w0 = np.concatenate([y_guess, np.zeros(len(self.diff))])
        if steady_state and len(self.diff):
            # der(x) = 0 for every state; those of states held by an initial condition come first (the start
            # value says where the equilibrium is sought, and free states take the values that make it one);
            # a state held by a fixed start value must then be at rest (checked below), one held by a
            # component's initial equation may start away from equilibrium (a partial steady state)
            held, by_start = self._held_states(tuple(active))
            cand = held + [k for k in range(len(self.diff)) if k not in held]
            steady = self._complementary_steady(tuple(active), tuple(cand), w0, par, len(held))
            held = by_start
        active_t, steady_t = tuple(active), tuple(steady)
        defaults, w0 = self._default_starts(starts, active_t, steady_t, w0, par, tol)
        if defaults:
            par = np.concatenate([par, y_guess[list(defaults)]])
        g, jg = self._init_functions(active_t, steady_t, defaults)
        self._check_structure(jg, w0, par, active_t, steady_t, defaults)
        try:
            w = self._solve(g, jg, w0, par, tol, self._labels(active_t, steady_t, defaults), self._unknown_names(),
                            self._nominal_w(), diagnose=diagnose)
        except InitializationError as err:
            best = getattr(err, "best", None)
            if best is not None:
                err.point = self._split(best)
            raise
        y, yp = self._split(w)
        if held:
            self._check_equilibrium(y, yp, [k for k in held if k not in steady], active_t, steady_t,
                                    cond_vals[list(active_t)])
        return y, self.algebraic_rates(t0, y, yp, p)

    def _check_finite(self, p: np.ndarray, starts: dict[str, tuple[float, bool]]) -> None:
        """Parameters and start values must be finite (a NaN would only show as an unnamed failure later)."""
        m = self.model
        bad = [f"{name} = {v!r} [{unit}]" for name, v, unit in zip(m.param_names, p[:m.n_params], m.param_units,
                                                                     strict=True) if not np.isfinite(v)]
        if bad:
            raise ParameterError("parameter values must be finite; not finite: " + ", ".join(bad[:12])
                                 + (f" … and {len(bad) - 12} more" if len(bad) > 12 else ""))
        bad = []
        for name, (val, fixed) in starts.items():
            try:
                finite = bool(np.all(np.isfinite(np.asarray(val, dtype=float))))
            except (TypeError, ValueError):
                finite = False
            if not finite:
                bad.append(f"{name} = {val!r}{' (fixed)' if fixed else ''}")
        if bad:
            raise InitializationError("start values must be finite; not finite: " + ", ".join(bad[:12])
                                      + (f" … and {len(bad) - 12} more" if len(bad) > 12 else ""))

    def _nominal_w(self) -> np.ndarray:
        nom = np.asarray(self.model.nominal, dtype=float)
        return np.concatenate([nom, nom[self.diff]])

    def _held_states(self, active: tuple[int, ...]) -> tuple[list[int], list[int]]:
        """Positions (in ``self.diff``) of the states held by an initial condition on that state alone: all of
        them (a fixed start value or a component's initial equation, such as a cylinder's ``x = x_start``),
        and those held by a fixed start value only (the user's ``init``, which equilibrium must respect)."""
        m = self.model
        if not active:
            return [], []
        cond = m.sx_function("cond")
        t, y, _, yp, p = self._symbols()
        C = cond(t, y, yp, p)
        sp = ca.jacobian_sparsity(ca.vertcat(*[C[k] for k in active]), y)
        colind, row = sp.get_ccs()
        cols_of: dict[int, list[int]] = {}
        for j in range(sp.size2()):
            for r in row[colind[j]:colind[j + 1]]:
                cols_of.setdefault(int(r), []).append(j)
        pos = {int(i): k for k, i in enumerate(self.diff)}
        held: list[int] = []
        by_start: list[int] = []
        for r, k in enumerate(active):
            cols = cols_of.get(r, [])
            if len(cols) != 1 or cols[0] not in pos:
                continue
            state = pos[cols[0]]
            if state not in held:
                held.append(state)
            name = m.conditions[k][0]
            if not (": " in name and " #" in name) and state not in by_start:  # not an initial equation
                by_start.append(state)
        return held, by_start

    def _check_equilibrium(self, y: np.ndarray, yp: np.ndarray, dropped: list[int], active: tuple[int, ...],
                           steady: tuple[int, ...], cond_vals: np.ndarray) -> None:
        """``steady_state=True``: a state held by a fixed start value whose ``der(x) = 0`` could not be imposed
        must still be at rest; otherwise name the fixed start values that prevent the equilibrium."""
        m = self.model
        moving = []
        for k in dropped:
            i = int(self.diff[k])
            if abs(yp[i]) > 1e-6 * max(abs(float(m.nominal[i])), abs(y[i])):
                moving.append(k)
        if not moving:
            return
        # which fixed conditions stand in the way: give the der(x) = 0 row priority over them and see which
        # conditions the (in-order) matching then leaves unmatched
        _, jg = self._init_functions(active, tuple(list(steady) + moving))
        inc = _pattern(jg)
        n, na, ns = m.n, len(active), len(steady)
        culprit_names: list[str] = []
        lines = []
        for j, k in enumerate(moving):
            dropped_row = n + na + ns + j
            for c in range(na) if na <= 60 else []:
                # condition c stands in the way if, matched after everything else, it is the one left over
                order = [*range(n), dropped_row, *(n + q for q in range(na) if q != c), *range(n + na, n + na + ns),
                         n + c]
                row_match, _ = matching(inc[order], in_order=True)
                if row_match[-1] < 0:
                    name, value = m.conditions[active[c]][0], float(np.asarray(cond_vals)[c])
                    text = (f"{name.rsplit(' #', 1)[0]} (initial equation)" if ": " in name and " #" in name
                            else f"{name} = {value:g} (fixed start value)")
                    if text not in culprit_names:
                        culprit_names.append(text)
            i = int(self.diff[k])
            lines.append(f"  der({m.y_names[i]}) = {yp[i]:.6g} at the start (component {m.y_owners[i] or '(model)'})")
        conds = ", ".join(culprit_names) or "the fixed start values"
        raise InitializationError(
            "steady_state=True: no equilibrium with the fixed start values; these states would not be at rest:\n"
            + "\n".join(lines) + f"\nconflicting conditions (freeing any one of them allows it): {conds}. Leave one of "
            "them free (not fixed) so that the equilibrium can choose it, or run without steady_state=True.")

    def _complementary_steady(self, active: tuple[int, ...], steady: tuple[int, ...], w0: np.ndarray,
                              par: np.ndarray, n_held: int = 0) -> list[int]:
        """The ``der(x) = 0`` rows that complement the model's own initial conditions.

        Initial equations and fixed start values of algebraic variables (a volume's start
        pressure fixes its stored mass) take the place of some steady-state rows. Rows are
        matched in priority order (model equations, initial conditions, then steady-state rows);
        augmenting paths never unmatch a row, so the steady-state rows left unmatched are exactly
        those the other conditions make redundant.

        The first ``n_held`` steady rows belong to states held by a fixed start value (a boom angle):
        their equilibrium (the torque balance) is matched first, and then the free states' rows from the
        farthest to the nearest (graph distance in the incidence from the held rows), so that the rows
        given up are those of the free states nearest to the held ones — the chambers of the cylinder
        that holds the boom, not the supply behind the valve.
        """
        _, jg = self._init_functions(active, steady)
        inc = _pattern(jg)
        first = self.model.n + len(active)
        order = list(range(len(steady)))
        if n_held and len(steady) > n_held:
            # distances from the held rows that constrain free states (those still matched after F and conditions)
            rm, _ = matching(inc[: first + n_held], in_order=True)
            dist = self._distances(inc, [first + j for j in range(n_held) if rm[first + j] >= 0])
            free = list(range(n_held, len(steady)))
            free.sort(key=lambda j: -dist[int(self.diff[steady[j]])])  # stable: model order among equals
            order = list(range(n_held)) + free
        rows = list(range(first)) + [first + j for j in order]
        row_match, _ = matching(inc[rows], in_order=True)
        kept = {order[j] for j in range(len(order)) if row_match[first + j] >= 0}
        return [k for j, k in enumerate(steady) if j in kept]

    @staticmethod
    def _distances(inc: sps.csr_matrix, start_rows: list[int]) -> np.ndarray:
        """Breadth-first distance (in row–column steps) of every column from ``start_rows``; inf if unreachable."""
        csc = inc.tocsc()
        dist = np.full(inc.shape[1], np.inf)
        seen_rows = set(start_rows)
        frontier = list(start_rows)
        d = 0
        while frontier:
            d += 1
            cols = set()
            for r in frontier:
                for c in inc.indices[inc.indptr[r]:inc.indptr[r + 1]]:
                    if dist[c] == np.inf:
                        dist[c] = d
                        cols.add(int(c))
            frontier = []
            for c in cols:
                for r in csc.indices[csc.indptr[c]:csc.indptr[c + 1]]:
                    if int(r) not in seen_rows:
                        seen_rows.add(int(r))
                        frontier.append(int(r))
        return dist

    def guess(self, starts: dict[str, tuple[float, bool]]) -> np.ndarray:
        """Start guesses for ``y`` from the model's start values."""
        y = np.zeros(self.model.n)
        guesses = self.model.start_guesses  # build-time guesses (kept tree frames) where no start is given
        for i, sources in enumerate(self.model.start_sources):
            for name, sign in sources:
                val = starts.get(name, (0.0, False))[0]
                if val != 0.0:
                    y[i] = sign * val
                    break
            else:
                if guesses:
                    y[i] = guesses.get(self.model.y_names[i], 0.0)
        return y

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
               tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
        """Recompute algebraic variables and derivatives at an event, states held."""
        y_new, yp_new = self._reinit(t, y, yp, p, tol)
        return y_new, self.algebraic_rates(t, y_new, yp_new, p, self._last_jac)

    def algebraic_rates(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
                        jac: sps.spmatrix | None = None) -> np.ndarray:
        """``yp`` with the rates of the algebraic variables filled in, from the consistent point at ``t + δ``.

        They do not enter the residual, but IDA's predictor uses them on the first step; zeros make the error
        test fail on systems whose algebraic variables move fast. The states are moved to ``y + δ·y'`` and the
        held problem (:meth:`_reinit`) is solved at ``t + δ`` by chord steps with its Jacobian at ``t`` (``jac``
        when the caller has it): the guess is ``O(δ)`` off and the Jacobian ``O(δ)`` stale, so two steps leave
        ``O(δ³)``, far below the ``O(δ)`` of the difference quotient itself.
        """
        if self.model.differential.all():
            return yp
        g, jg = self._held_functions()
        alg = self._alg
        na = len(alg)
        w = np.concatenate([y[alg], yp[self.diff]])
        delta = 1e-7 * max(1.0, abs(t))
        with np.errstate(all="ignore"):
            try:
                lu = sps.linalg.splu(_csc(jac if jac is not None else jg(w, np.concatenate([[t], p, y[self.diff]]))))
            except RuntimeError:  # singular there: the rates stay as they are
                return yp
            par = np.concatenate([[t + delta], p, y[self.diff] + delta * yp[self.diff]])
            w2 = np.concatenate([y[alg] + delta * yp[alg], yp[self.diff]])
            for _ in range(2):
                r = np.asarray(g(w2, par), dtype=float).ravel()
                step = lu.solve(-r)
                if not np.all(np.isfinite(step)):
                    return yp
                w2 += step
        out = yp.copy()
        out[alg] = (w2[:na] - y[alg]) / delta
        return out

    def _held_functions(self) -> tuple[Any, Any]:
        """Residual and Jacobian of the event problem with the states held (:meth:`_reinit`)."""
        m = self.model
        if self._reinit_fns is None:
            alg = np.flatnonzero(~m.differential)
            self._alg = alg
            if m.n > AUTO_C_MIN_UNKNOWNS:
                # a large model: its own res/jac (C when it has it), no symbolic Jacobian (_StatesHeld)
                held = _StatesHeld(m, alg, self.diff)
                self._reinit_fns = (held, held.jacobian)
            else:  # small model: the symbolic Jacobian of the held problem is cheap to build and exact
                t_s, _, ypd, yp_s, p_s = self._symbols()
                ystate = ca.SX.sym("ystate", len(self.diff))
                ya = ca.SX.sym("ya", len(alg))
                yfull = ca.SX.zeros(m.n)
                for k, i in enumerate(self.diff):
                    yfull[i] = ystate[k]
                for k, i in enumerate(alg):
                    yfull[i] = ya[k]
                F = m.sx_function("res")(t_s, yfull, yp_s, p_s)
                w = ca.vertcat(ya, ypd)
                par = ca.vertcat(t_s, p_s, ystate)
                self._reinit_fns = (ca.Function("g", [w, par], [F]),
                                    ca.Function("jg", [w, par], [ca.jacobian(F, w)]))
        return self._reinit_fns

    def _reinit(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
                tol: float, diagnose: bool = True) -> tuple[np.ndarray, np.ndarray]:
        m = self.model
        g, jg = self._held_functions()
        w0 = np.concatenate([y[self._alg], yp[self.diff]])
        par = np.concatenate([[t], p, y[self.diff]])
        labels = [(lab.split(":")[0], lab) for lab in m.row_labels]
        nom = np.asarray(m.nominal, dtype=float)
        cols = ([(m.y_owners[i], m.y_names[i]) for i in self._alg]
                + [(m.y_owners[i], f"der({m.y_names[i]})") for i in self.diff])
        w = self._solve(g, jg, w0, par, tol, labels, cols, np.concatenate([nom[self._alg], nom[self.diff]]),
                        what=f"could not find consistent values at t = {t:.10g} s (states held)", diagnose=diagnose)
        y_new = y.copy()
        y_new[self._alg] = w[:len(self._alg)]
        yp_new = np.zeros(m.n)
        yp_new[self.diff] = w[len(self._alg):]
        return y_new, yp_new

    def consistent_start(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                         steady: bool) -> tuple[np.ndarray, np.ndarray]:
        """Consistent ``y(t0)``, ``y'(t0)`` together with the relation values in ``p`` (updated in place).

        Relations start from their values at the start guesses and are iterated to agree with the solution;
        when the branch chosen by the guesses has no solution (a limiter's guess on the wrong side), the
        relations are re-evaluated at the best point found, then switched one at a time
        (:meth:`start_by_flipping`), before the failure is reported.
        """
        m = self.model
        n_par = m.n_params
        y, yp = self.guess(starts), np.zeros(m.n)
        if m.n_relations:
            with np.errstate(all="ignore"):
                z = np.asarray(m.function("ind")(t0, y, yp, p)).ravel()
            ab = np.asarray(m.function("tev")(p)).reshape(-1, 2)
            for k, rel in enumerate(m.relations):
                if rel.time_event and z[k] == 0.0:
                    p[n_par + k] = float(ab[k, 0] > 0)
                else:
                    p[n_par + k] = float(rel.value(z[k]))
        failed: InitializationError | None = None
        for _ in range(20):
            try:
                y, yp = self.initial(t0, p, starts, steady)
                failed = None
            except InitializationError as err:
                failed = err
                # no solution with these relation values: re-evaluate the relations at the best point
                # found (the start guesses may lie on the wrong side of a limiter) and try again
                point = getattr(err, "point", None)
                if not m.n_relations or point is None or np.size(point[0]) != m.n or np.size(point[1]) != m.n:
                    raise  # (a point of the full system, before explicit eliminations, is not this model's)
                with np.errstate(all="ignore"):
                    z = np.asarray(m.function("ind")(t0, point[0], point[1], p)).ravel()
                flipped = False
                for k, rel in enumerate(m.relations):
                    v = float(rel.value(z[k]))
                    if not rel.time_event and v != p[n_par + k]:
                        p[n_par + k], flipped = v, True
                if not flipped:
                    return self.start_by_flipping(t0, p, starts, steady, err)
                continue
            if not m.n_relations:
                break
            z = np.asarray(m.function("ind")(t0, y, yp, p)).ravel()
            changed = False
            for k, rel in enumerate(m.relations):
                if rel.time_event:
                    continue
                v = float(rel.value(z[k]))
                if v != p[n_par + k]:
                    p[n_par + k], changed = v, True
            if not changed:
                break
        if failed is not None:
            raise failed
        return y, yp

    def start_by_flipping(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]], steady: bool,
                          err: InitializationError, most: int = 16) -> tuple[np.ndarray, np.ndarray]:
        """Try the start with one state relation switched at a time (a start guess on the wrong side of a
        limiter gives a branch without solution); accept a switch whose solution agrees with it, else raise
        ``err`` (the failure of the unswitched problem, with its diagnosis)."""
        m = self.model
        n_par = m.n_params
        state_rel = [k for k, rel in enumerate(m.relations) if not rel.time_event][:most]
        for k in state_rel:
            trial = p.copy()
            trial[n_par + k] = 1.0 - trial[n_par + k]
            try:
                y, yp = self.initial(t0, trial, starts, steady, diagnose=False)
            except InitializationError:
                continue
            z = np.asarray(m.function("ind")(t0, y, yp, trial)).ravel()
            if all(float(m.relations[j].value(z[j])) == trial[n_par + j] for j in state_rel):
                p[:] = trial
                return y, yp
        raise err

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
                         active: tuple[int, ...], steady: tuple[int, ...], defaults: tuple[int, ...] = ()) -> None:
        inc = _pattern(jg)
        n_eq, n_unk = inc.shape
        row_match, col_match = matching(inc)
        if n_eq == n_unk and np.all(row_match >= 0):
            return
        rows, cols = culprits(inc, row_match, col_match)
        labels = self._labels(active, steady, defaults)
        unknowns = self._unknown_names()
        n_cond = len(active) + len(steady) + len(defaults)
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

    def _accept(self, w: np.ndarray, r: np.ndarray, J: Any, diagnose: bool, labels: list[tuple[str, str]],
                cols: list[tuple[str, str]], what: str) -> np.ndarray:
        """Return the consistent point ``w`` (its Jacobian ``J`` kept for :meth:`algebraic_rates`).

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
        self._last_jac = J
        return w

    def _solve(self, g: Any, jg: Any, w0: np.ndarray, par: np.ndarray, tol: float,
               labels: list[tuple[str, str]], cols: list[tuple[str, str]], nominal: np.ndarray,
               what: str = "could not find consistent initial values", diagnose: bool = True) -> np.ndarray:
        """Solve ``g(w) = 0`` from ``w0``: damped Newton (sparse LU), then trust-region least squares.

        Newton iterates to the absolute ``tol`` while it makes progress; where it stalls (round-off: an equation
        with 1e7 Pa terms cannot be held to 1e-10 Pa), the point is accepted by a per-equation scaled test
        ``|g_i| <= tol·s_i`` with ``s_i = max(1, max_j |J_ij|·nominal_j)`` (:func:`~flexlib.solve.diagnose.row_scale`):
        relative to the size the equation's terms take when one of its variables moves by its nominal value,
        never stricter than the absolute test. On failure the error names non-finite residuals and Jacobian
        entries, then the equations with the largest scaled residuals and, if the Jacobian is numerically
        singular, the dependent equations and the variables involved.
        """
        def fun(w: np.ndarray) -> np.ndarray:
            return np.asarray(g(w, par)).ravel()

        def jac(w: np.ndarray) -> sps.csc_matrix:
            return _csc(jg(w, par))

        def wnorm(r: np.ndarray, s: np.ndarray) -> float:
            return float(np.max(np.abs(r) / s)) if len(r) else 0.0

        w = w0.astype(float).copy()
        self._last_jac = None
        with np.errstate(all="ignore"):
            r = fun(w)
            # damped Newton with sparse LU (fast path for the usual well-posed problem). It iterates to the absolute
            # tolerance while that makes progress; where it stalls (round-off: a 1e7 Pa equation cannot be held
            # to 1e-10 Pa), a point that passes the scaled test with the Jacobian there is accepted as soon as a
            # full Newton step from it no longer lowers the residual (no line search spinning on noise)
            for _ in range(50):
                norm = np.linalg.norm(r, np.inf)
                J = jac(w) if norm > tol or diagnose else None
                scaled_ok = norm > tol and bool(np.all(np.isfinite(r))) and wnorm(r, row_scale(J, nominal)) <= tol
                if norm <= tol:
                    return self._accept(w, r, J, diagnose, labels, cols, what)
                with warnings.catch_warnings():
                    warnings.simplefilter("error", sps.linalg.MatrixRankWarning)
                    try:
                        step = sps.linalg.spsolve(J, -r)
                    except (RuntimeError, ValueError, sps.linalg.MatrixRankWarning):
                        step = None
                if step is None or not np.all(np.isfinite(step)):  # singular: least-squares (Gauss–Newton) step
                    try:
                        step = sps.linalg.lsqr(J, -r, atol=1e-14, btol=1e-14)[0]
                    except ValueError:
                        break
                if not np.all(np.isfinite(step)):
                    break
                if scaled_ok:  # round-off level: one full step, taken only if it lowers the residual
                    r_try = fun(w + step)
                    if np.all(np.isfinite(r_try)) and np.linalg.norm(r_try, np.inf) < norm:
                        w, r = w + step, r_try
                        continue
                    return self._accept(w, r, J, diagnose, labels, cols, what)
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
            if np.all(np.isfinite(r)) and wnorm(r, row_scale(jac(w), nominal)) <= tol:
                return w
            # robust fallback: trust-region least squares
            big = len(w) > 200

            def fun_finite(x: np.ndarray) -> np.ndarray:  # a non-finite trial point makes the trust region shrink
                rx = fun(x)
                return rx if np.all(np.isfinite(rx)) else np.full_like(rx, 1e150)

            try:
                sol = so.least_squares(fun_finite, w, jac=jac if big else (lambda x: jac(x).toarray()),
                                       method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=500,
                                       tr_solver="lsmr" if big else "exact")
                if np.all(np.isfinite(fun(sol.x))):
                    w = sol.x
            except (ValueError, np.linalg.LinAlgError):  # non-finite Jacobian: keep the Newton point for the report
                pass
            r = fun(w)
            J = jac(w)
            s = row_scale(J, nominal)
            if wnorm(r, s) <= max(tol, 1e-8):
                return w
            if not diagnose:  # a trial whose failure the caller discards
                err = InitializationError(f"{what} (trial)")
                err.best = w
                raise err
            # the failure, named
            nf = nonfinite_lines(r, J, labels, cols, w, "at the best point found")
            if not nf and not np.array_equal(w, w0):
                r0 = fun(w0)
                nf = nonfinite_lines(r0, jac(w0), labels, cols, w0, "at the start guesses")
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
        err.best = w  # the best point found, for callers that can change the problem and retry
        raise err


class _StatesHeld:
    """The event re-initialisation problem ``F(t, y, y') = 0`` with the states held, for :meth:`Initializer._reinit`.

    Unknowns ``w = (y_alg, y'_states)``, parameters ``par = (t, p, y_states)``; the rates of the algebraic unknowns are
    zero (they do not enter the residual). Evaluated with the model's own ``res`` and ``jac`` functions — generated C
    when the model has it — instead of a symbolic Jacobian built for it
    (``docs/decisions/028-event-reinitialisation-cost.md``). ``jac`` is ``∂F/∂y + c·∂F/∂y'``, so the algebraic columns
    are those of ``jac(c = 0)`` and the state columns are ``(jac(c) − jac(0))/c`` with ``c = 2**20``: the cancellation
    error ``eps·|∂F/∂y|/c`` is far below what Newton needs, and the solve is checked on ``F`` itself. Used for models
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


def _csc(J: Any) -> sps.csc_matrix:
    """A Jacobian as CSC: the states-held one already is; a CasADi Function's comes as a sparse DM."""
    return sps.csc_matrix(J if sps.issparse(J) else J.sparse())


def _pattern(jg: ca.Function) -> sps.csr_matrix:
    """The sparsity pattern of a Jacobian function's output as a 0/1 matrix (rows: equations, columns: unknowns)."""
    spj = jg.sparsity_out(0)
    colind, row = spj.get_ccs()
    return sps.csc_matrix((np.ones(len(row)), np.asarray(row), np.asarray(colind)), shape=spj.shape).tocsr()
