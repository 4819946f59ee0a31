"""Dynamic state selection: re-choose the dummy derivatives during a run.

The dummy-derivative selection of stage 3 is made at the start values; it stays valid while
the selected blocks (one per differentiation level) stay regular. A Cartesian pendulum whose
selection was made with ``x`` as the state is singular where it passes the horizontal; a
four-bar mechanism passes through such configurations on every turn.

The monitor evaluates, after every integrator step, each level's block over the candidate
derivatives (a compiled function of the current solution) and compares the smallest singular
value of the selected columns with that of the best selection (the same pivoted-QR rule by
``state_select`` class as at compile time). When the current one falls below ``ratio`` times the
best, the run switches: the selection is made again at the current point, the DAE is assembled
and compiled for it (SX functions, a few milliseconds), every column value (variables and their
derivatives) is carried over by name, the new algebraic part is made consistent, and IDA
restarts. This is Dymola's dynamic state selection in spirit (Mattsson, Olsson, Elmqvist,
"Dynamic selection of states in Dymola", Modelica Workshop 2000), done by restart instead of
by switching inside one residual.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla
from scipy.linalg.lapack import dgesv as _dgesv

from flexlib.compile.codegen import CompiledModel, compile_dae
from flexlib.compile.dummy_derivatives import pick_columns
from flexlib.compile.index_reduction import Structure

__all__ = ["StateSelectionMonitor"]


def _smallest_sv(A: np.ndarray) -> float:
    return float(np.linalg.svd(A, compute_uv=False)[-1]) if A.size else np.inf

#: Levels with at least this many rows solve for the exchange ratio with a sparse LU (SuperLU) instead of a dense
#: one; below it LAPACK's dense solve is faster (``docs/decisions/027-state-selection-check-sparse.md``).
SPARSE_LEVEL_ROWS = 60


class _Level:
    """One differentiation level with a choice: its block of the level Jacobians as rows × candidates.

    ``take`` indexes the level's entries in the nonzeros of ``jlev``, at (``rows``, ``cols``) of the block; the
    candidates whose column is structurally zero never enter the exchange ratio (flexible pump truck: 60 of the 110
    unselected candidates of its 202-row level).
    """

    def __init__(self, n_rows: int, n_cands: int, costs: list[int], selected: list[int], take: np.ndarray,
                 rows: np.ndarray, cols: np.ndarray) -> None:
        self.shape = (n_rows, n_cands)
        self.costs, self.selected = costs, selected
        self.take, self.rows, self.cols = take, rows, cols
        sel = np.asarray(selected, dtype=np.intp)
        in_b = np.isin(cols, sel)
        others = np.setdiff1d(cols, sel)  # the unselected candidates with a structural nonzero
        self.n_others = len(others)
        where = np.full(n_cands, -1, dtype=np.intp)  # candidate -> its column in B (selected) or in N (others)
        where[sel] = np.arange(len(sel))
        where[others] = np.arange(len(others))
        self.sparse = n_rows >= SPARSE_LEVEL_ROWS
        # B = block[:, selected] as CSC (sorted by column, then row), N = block[:, others] dense
        b_take, b_row, b_col = take[in_b], rows[in_b], where[cols[in_b]]
        order = np.lexsort((b_row, b_col))
        self.b_take, self.b_row, self.b_col = b_take[order], b_row[order].astype(np.int32), b_col[order]
        self.b_indptr = np.concatenate([[0], np.cumsum(np.bincount(self.b_col, minlength=len(sel)))]).astype(np.int32)
        self.n_take, self.n_row, self.n_col = take[~in_b], rows[~in_b], where[cols[~in_b]]
        self._B: sps.csc_matrix | None = None

    def dense(self, nz: np.ndarray) -> np.ndarray:
        """The block (rows × all candidates) at the nonzeros ``nz`` of ``jlev``."""
        block = np.zeros(self.shape)
        block[self.rows, self.cols] = nz[self.take]
        return block

    def exchange_ratio(self, nz: np.ndarray) -> float:
        """``max |B⁻¹ N|`` (``B`` the selected columns, ``N`` the other candidates); inf if ``B`` is singular."""
        if not self.n_others:
            return 0.0
        n_rows = self.shape[0]
        N = np.zeros((n_rows, self.n_others))
        N[self.n_row, self.n_col] = nz[self.n_take]
        if n_rows == 1:  # one row: the exchange ratios are quotients of entries
            b = abs(float(nz[self.b_take[0]])) if len(self.b_take) else 0.0
            return float(np.abs(N).max()) / b if b > 0.0 else np.inf
        if self.sparse:
            B = self._B
            if B is None:
                B = self._B = sps.csc_matrix((nz[self.b_take], self.b_row, self.b_indptr), shape=(n_rows, n_rows))
            else:  # the same pattern: only the values change (no constructor checks per call)
                np.take(nz, self.b_take, out=B.data)
            try:
                x = spla.splu(B, permc_spec="COLAMD").solve(N)
            except RuntimeError:  # exactly singular
                return np.inf
            return float(np.abs(x).max())
        B = np.zeros((n_rows, n_rows), order="F")
        B[self.b_row, self.b_col] = nz[self.b_take]
        _, _, x, info = _dgesv(B, N, overwrite_a=True, overwrite_b=True)
        return float(np.abs(x).max()) if info == 0 else np.inf


class StateSelectionMonitor:
    """Watches the conditioning of the dummy-derivative blocks and performs switches.

    The full test (pivoted QR by cost class, then the smallest singular values of the selected and
    of the best block, 0.4–0.5 ms on a 25-row block) runs only when a cheap indicator says the
    selection may have degraded. The indicator is the largest basis-exchange ratio
    ``max |B⁻¹ N|`` of each level (``B`` the selected columns, ``N`` the others; entry ``(i, j)`` is
    the factor by which ``|det|`` grows when selected column ``i`` is swapped for candidate ``j``),
    from one small LU solve. It is evaluated on a schedule, not every step: the next check is placed
    half-way to the time where the indicator's reciprocal, extrapolated linearly from the last two
    checks, would reach the trigger, and at least every ``every`` steps; a step-size collapse
    (IDA's step ``collapse`` times below the step at the last check, the sign of a singular
    iteration matrix) forces a check at once.

    Parameters
    ----------
    rebuild : callable
        Returns the index-reduction :class:`Structure` of the model (stages 1–3), used when the
        compiled model came from the disk cache and has no structure in memory.
    ratio : float
        Switch when the smallest singular value of the selected block drops below ``ratio``
        times that of the best block (hysteresis: a new selection is at least ``1/ratio`` better).
    every : int
        Largest number of steps between two indicator checks while the indicator approaches the
        trigger; while it stays below 1/1.2 of it and does not change at all, the cap doubles at
        every check up to ``16 * every``.
    trigger : float
        Run the full test when the exchange ratio exceeds ``trigger / ratio`` (default 0.75: at the
        default ``ratio`` 0.5, once some swap would grow ``|det|`` 1.5-fold). Near-ties (ratios
        0.9–1.1, common in closed loops) stay below it.
    collapse : float
        A step this many times smaller than the step at the last check forces a check.
    """

    def __init__(self, rebuild: Callable[[], Structure], ratio: float = 0.5, every: int = 64,
                 trigger: float = 0.75, collapse: float = 8.0) -> None:
        self.rebuild = rebuild
        self.ratio = ratio
        self.every = every
        self.trigger = trigger
        self.collapse = collapse
        self._variants: dict[tuple, CompiledModel] = {}
        self._buffers: dict[Any, tuple] = {}
        self._skip = 0
        self._t_next = -np.inf
        self._t_last = np.nan  # time and reciprocal indicators (one per level) of the last check
        self._g_last: list[float] = []
        self._g_raw: list[float] = []
        self._t_prev_step = np.nan
        self._h_ref = 0.0  # step size at the last check
        self._e_ref = trigger / ratio
        self._cap = every
        #: counters for benchmarks: indicator checks, full tests, switches proposed
        self.counts = {"indicator": 0, "full": 0}

    def reset(self) -> None:
        """Forget the schedule (a new run or a new selection)."""
        self._skip = 0
        self._t_next = -np.inf
        self._t_last = self._t_prev_step = np.nan
        self._g_last, self._g_raw = [], []
        self._h_ref = 0.0
        self._e_ref = self.trigger / self.ratio
        self._cap = self.every

    def steps_allowed(self) -> tuple[int, float, float]:
        """How far an integrator may run before :meth:`needs_switch` must see a step: ``(steps, t_next, h_min)``
        — after at most ``steps`` steps, or after the first step that ends at or after ``t_next`` [s] or is
        shorter than ``h_min`` [s] (the steps before it would be skipped: pass their number as ``skipped``)."""
        return self._skip + 1, float(self._t_next), self._h_ref / self.collapse

    def needs_switch(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray, *,
                     skipped: int = 0, h: float | None = None) -> bool:
        """True if a clearly better-conditioned selection exists at this point.

        Cheap unless a check is due (see the class docstring): a due check computes the exchange
        ratio of every level with a choice, and only above the trigger the full test, which compares
        the smallest singular values of the selected block and of the best block (pivoted QR by
        ``state_select`` class, as at compile time) and answers True below ``ratio``.

        Called after every step, or (``skipped`` > 0) after a run of steps bounded by :meth:`steps_allowed`
        of which all but the last were not shown; ``h`` is then the last step's size [s].
        """
        if skipped > 0:
            self._skip = max(self._skip - skipped, 0)
        h = t - self._t_prev_step if h is None else h
        self._t_prev_step = t
        if self._skip > 0 and t < self._t_next and not 0.0 < h * self.collapse < self._h_ref:
            self._skip -= 1
            return False
        if h > 0.0:
            self._h_ref = h
        return self._check(model, t, y, yp, p)

    def _check(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> bool:
        self.counts["indicator"] += 1
        nz = self._jlev(model, t, y, yp, p)
        levels = self._levels(model)
        es = [level.exchange_ratio(nz) for level in levels]
        es = [e if e < np.inf else np.inf for e in es]  # also NaN
        worst = max([1e-12, *es])  # largest exchange ratio over the levels
        if worst > self._e_ref:
            self.counts["full"] += 1
            for level in levels:
                block, costs, selected = level.dense(nz), level.costs, level.selected
                n_rows, n_cands = block.shape
                best = pick_columns(block, list(range(n_cands)), costs, n_rows)
                if best is None or sorted(best) == sorted(selected):
                    continue
                quality = _smallest_sv(block[:, selected]) / max(_smallest_sv(block[:, best]), 1e-300)
                if quality < self.ratio:
                    return True
            # no switch: the next full test once the indicator has grown by another quarter (the bar
            # stays up for this selection: lower values were already judged good enough)
            self._e_ref = 1.25 * worst
        # schedule: the reciprocal g = 1/e falls towards the bar near a singular selection, about linearly in time
        # per level: a tie that never moves must not hide a level that approaches the bar
        # (clamped at 4/bar: far below the bar, changes of a small ratio do not call for checks)
        # (plain floats: a model has a few levels, and numpy's per-call overhead would dominate a check)
        g_trig = 1.0 / self._e_ref
        g_raw = [1.0 / max(e, 1e-12) for e in es]
        g = [min(x, 4.0 * g_trig) for x in g_raw]
        t_next = np.inf
        stationary = False
        if math.isfinite(self._t_last) and t > self._t_last and len(self._g_last) == len(g) == len(self._g_raw):
            dt = t - self._t_last
            rates = [(a - b) / dt for a, b in zip(self._g_last, g, strict=True)]
            closing = [max(gk - g_trig, 0.0) / rk for gk, rk in zip(g, rates, strict=True) if rk > 0.0]
            if closing:
                t_next = t + 0.5 * min(closing)
            stationary = all(abs(a - b) <= 1e-6 * a for a, b in zip(g_raw, self._g_raw, strict=True))
        self._t_last, self._g_last, self._g_raw = t, g, g_raw
        self._t_next = t_next
        g = 1.0 / worst
        # below the bar and not moving at all (e.g. a structural tie of two identical columns): the step
        # cap between checks doubles (to 16 ``every``)
        self._cap = min(2 * self._cap, 16 * self.every) if g > 1.2 * g_trig and stationary else self.every
        self._skip = self._cap - 1 if g > g_trig else 0
        return False

    def _levels(self, model: CompiledModel) -> list[_Level]:
        """The levels with a choice (:class:`_Level`), cached per model."""
        entry = self._buffers.get(("levels", id(model)))
        if entry is None or entry[0] is not model:
            flat = np.asarray(model.function("jlev").sparsity_out(0).find(), dtype=np.intp)  # nonzero -> dense index
            levels, offset = [], 0
            for n_rows, n_cands, costs, selected in model.levels:
                size = n_rows * n_cands
                if n_cands > n_rows:
                    mine = np.flatnonzero((flat >= offset) & (flat < offset + size))
                    local = flat[mine] - offset
                    levels.append(_Level(n_rows, n_cands, costs, selected, mine, local % n_rows, local // n_rows))
                offset += size
            entry = self._buffers[("levels", id(model))] = (model, levels)
        return entry[1]

    def _jlev(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> np.ndarray:
        """The nonzeros of the level Jacobians at a point, through a FunctionBuffer (no per-call conversion)."""
        entry = self._buffers.get(id(model))
        if entry is None or entry[0] is not model:
            fn = model.function("jlev")
            buf, ev = fn.buffer()
            tb, out = np.zeros(1), np.zeros(fn.nnz_out(0))
            buf.set_arg(0, memoryview(tb))
            buf.set_res(0, memoryview(out))
            entry = self._buffers[id(model)] = (model, buf, ev, tb, out)
        _, buf, ev, tb, out = entry
        tb[0] = t
        buf.set_arg(1, memoryview(y))
        buf.set_arg(2, memoryview(yp))
        buf.set_arg(3, memoryview(p))
        ev()
        return out

    def switch(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray,
               p: np.ndarray) -> tuple[CompiledModel, np.ndarray, np.ndarray] | None:
        """A model with a new state selection and the current solution mapped onto it (None: no change)."""
        structure: Structure = model._structure or self.rebuild()
        values = dict(zip(model.col_names, np.asarray(model.function("cols")(t, y, yp, p)).ravel(), strict=True))
        col_names = [name for name in _names(structure)]
        point = structure.point(np.array([values[n] for n in col_names]), t, p)
        dummies, levels = structure.select(point)
        key = tuple(sorted(dummies))
        new = self._variants.get(key)
        if new is None:
            dae = structure.assemble(dummies, levels)
            new = compile_dae(structure.simple.flat, structure.simple, dae, codegen=False)
            self._variants[key] = new
        if new.y_names == model.y_names and np.array_equal(new.differential, model.differential):
            return None
        self.reset()
        y_new = np.array([values[n] for n in new.y_names])
        yp_new = np.zeros(new.n)
        for i in np.flatnonzero(new.differential):
            yp_new[i] = values.get(f"der({new.y_names[i]})", 0.0)
        return new, y_new, yp_new


def _names(structure: Structure) -> list[str]:
    from flexlib.compile.dummy_derivatives import col_name

    return [col_name(c, structure.simple.variables) for c in structure.cols]
