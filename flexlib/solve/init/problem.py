"""The initialisation problem of a compiled model: its unknowns ``(y, y'_states)``, the rows ``F = 0`` plus one per
initial condition (a fixed start value or initial equation, ``der(x) = 0`` in steady-state mode, a component's default
start where the others leave an unknown free), its structural checks (square and regular, else the over-specified
conditions or the free states are named) and the equilibrium checks of a steady start."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.structure import culprits, group_by_owner, matching, row_jacobian
from flexlib.core.instance_values import DEFAULT_START
from flexlib.errors import InitializationError
from flexlib.solve.init.newton import pattern, solve

__all__ = ["InitProblem"]


class InitProblem:
    """The initialisation rows and their functions for one compiled model (built lazily, reused)."""

    def __init__(self, model: CompiledModel) -> None:
        self.model = model
        self.diff = np.flatnonzero(model.differential)
        self.fns: dict[tuple, tuple[ca.Function, ca.Function]] = {}

    def symbols(self) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX, ca.SX]:
        m = self.model
        t = ca.SX.sym("t")
        y = ca.SX.sym("y", m.n)
        ypd = ca.SX.sym("ypd", len(self.diff))
        yp = ca.SX.zeros(m.n)
        for k, i in enumerate(self.diff):
            yp[i] = ypd[k]
        p = ca.SX.sym("p", m.n_params + m.n_relations)
        return t, y, ypd, yp, p

    def functions(self, active: tuple[int, ...], steady: tuple[int, ...],
                        defaults: tuple[int, ...] = ()) -> tuple[ca.Function, ca.Function]:
        key = (active, steady, defaults)
        if key not in self.fns:
            m = self.model
            t, y, ypd, yp, p = self.symbols()
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
            self.fns[key] = (g, jg)
        return self.fns[key]

    def labels(self, active: tuple[int, ...], steady: tuple[int, ...],
                defaults: tuple[int, ...] = ()) -> list[tuple[str, str]]:
        m = self.model
        labels = [(lab.split(":")[0], lab) for lab in m.row_labels]
        labels += [("initial conditions", f"{m.conditions[k][0]} = start value") for k in active]
        labels += [("steady state", f"der({m.y_names[self.diff[k]]}) = 0") for k in steady]
        labels += [("initial conditions", f"{m.y_names[k]} = default start value") for k in defaults]
        return labels

    def default_starts(self, starts: dict[str, tuple[float, Any]], active: tuple[int, ...],
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
        jg = self.functions(active, steady)[1]
        inc = pattern(jg)
        if int(np.sum(matching(inc)[0] >= 0)) == inc.shape[1]:
            return (), w0  # the conditions given already determine every unknown
        g_all, jg_all = self.functions(active, steady, cands)
        par_all = np.concatenate([par, w0[list(cands)]])
        try:
            point, _ = solve(g_all, jg_all, w0, par_all, tol, self.labels(active, steady, cands),
                             self.unknown_names(), self.nominal_w(), diagnose=False)
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

    def nominal_w(self) -> np.ndarray:
        nom = np.asarray(self.model.nominal, dtype=float)
        return np.concatenate([nom, nom[self.diff]])

    def held_states(self, active: tuple[int, ...]) -> tuple[list[int], list[int]]:
        """Positions (in ``self.diff``) of the states held by an initial condition on that state alone: all of
        them (a fixed start value or a component's initial equation, such as a cylinder's ``x = x_start``),
        and those held by a fixed start value only (the user's ``init``, which equilibrium must respect)."""
        m = self.model
        if not active:
            return [], []
        cond = m.sx_function("cond")
        t, y, _, yp, p = self.symbols()
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

    def check_equilibrium(self, y: np.ndarray, yp: np.ndarray, dropped: list[int], active: tuple[int, ...],
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
        _, jg = self.functions(active, tuple(list(steady) + moving))
        inc = pattern(jg)
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

    def complementary_steady(self, active: tuple[int, ...], steady: tuple[int, ...], w0: np.ndarray,
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
        _, jg = self.functions(active, steady)
        inc = pattern(jg)
        first = self.model.n + len(active)
        order = list(range(len(steady)))
        if n_held and len(steady) > n_held:
            # distances from the held rows that constrain free states (those still matched after F and conditions)
            rm, _ = matching(inc[: first + n_held], in_order=True)
            dist = self.distances(inc, [first + j for j in range(n_held) if rm[first + j] >= 0])
            free = list(range(n_held, len(steady)))
            free.sort(key=lambda j: -dist[int(self.diff[steady[j]])])  # stable: model order among equals
            order = list(range(n_held)) + free
        rows = list(range(first)) + [first + j for j in order]
        row_match, _ = matching(inc[rows], in_order=True)
        kept = {order[j] for j in range(len(order)) if row_match[first + j] >= 0}
        return [k for j, k in enumerate(steady) if j in kept]

    @staticmethod
    def distances(inc: sps.csr_matrix, start_rows: list[int]) -> np.ndarray:
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

    def unknown_names(self) -> list[tuple[str, str]]:
        m = self.model
        names = [(o, nm) for o, nm in zip(m.y_owners, m.y_names, strict=True)]
        names += [(m.y_owners[i], f"der({m.y_names[i]})") for i in self.diff]
        return names

    def check_structure(self, jg: ca.Function, w0: np.ndarray, par: np.ndarray,
                         active: tuple[int, ...], steady: tuple[int, ...], defaults: tuple[int, ...] = ()) -> None:
        inc = pattern(jg)
        n_eq, n_unk = inc.shape
        row_match, col_match = matching(inc)
        if n_eq == n_unk and np.all(row_match >= 0):
            return
        rows, cols = culprits(inc, row_match, col_match)
        labels = self.labels(active, steady, defaults)
        unknowns = self.unknown_names()
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
