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

from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.linalg.lapack import dgesv as _dgesv

from flexlib.compile.codegen import CompiledModel, compile_dae
from flexlib.compile.index_reduction import Structure, _pick_columns

__all__ = ["StateSelectionMonitor"]


def _smallest_sv(A: np.ndarray) -> float:
    return float(np.linalg.svd(A, compute_uv=False)[-1]) if A.size else np.inf


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
        self._g_last = self._g_raw = np.zeros(0)
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
        self._g_last = self._g_raw = np.zeros(0)
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
        J = self._jlev(model, t, y, yp, p)
        worst = 1e-12  # largest exchange ratio over the levels
        es = []
        blocks = []
        for shape, offset, costs, selected, sel, others in self._levels(model):
            block = J[offset:offset + shape[0] * shape[1]].reshape(shape, order="F")
            if not len(others):
                e = 0.0
            elif shape[0] == 1:  # one row: the exchange ratios are quotients of entries
                b = abs(block[0, sel[0]])
                e = float(np.abs(block[0, others]).max()) / b if b > 0.0 else np.inf
            else:
                _, _, x, info = _dgesv(block[:, sel], block[:, others], overwrite_a=True, overwrite_b=True)
                e = float(np.abs(x).max()) if info == 0 else np.inf
            if not e < np.inf:  # also NaN
                e = np.inf
            worst = max(worst, e)
            es.append(e)
            blocks.append((block, costs, selected))
        if worst > self._e_ref:
            self.counts["full"] += 1
            for block, costs, selected in blocks:
                n_rows, n_cands = block.shape
                best = _pick_columns(block, list(range(n_cands)), costs, n_rows)
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
        g_trig = 1.0 / self._e_ref
        g_raw = 1.0 / np.maximum(np.array(es), 1e-12)
        g = np.minimum(g_raw, 4.0 * g_trig)
        t_next = np.inf
        stationary = False
        if np.isfinite(self._t_last) and t > self._t_last and len(self._g_last) == len(g) == len(self._g_raw):
            rate = (self._g_last - g) / (t - self._t_last)
            closing = rate > 0.0
            if np.any(closing):
                t_next = t + 0.5 * float(np.min(np.maximum(g[closing] - g_trig, 0.0) / rate[closing]))
            stationary = bool(np.all(np.abs(g_raw - self._g_raw) <= 1e-6 * g_raw))
        self._t_last, self._g_last, self._g_raw = t, g, g_raw
        self._t_next = t_next
        g = 1.0 / worst
        # below the bar and not moving at all (e.g. a structural tie of two identical columns): the step
        # cap between checks doubles (to 16 ``every``)
        self._cap = min(2 * self._cap, 16 * self.every) if g > 1.2 * g_trig and stationary else self.every
        self._skip = self._cap - 1 if g > g_trig else 0
        return False

    def _levels(self, model: CompiledModel) -> list[tuple]:
        """Per level with a choice: block shape, offset in the level Jacobians, cost classes, selected
        columns (list and index array) and the other candidates (index array); cached per model."""
        entry = self._buffers.get(("levels", id(model)))
        if entry is None or entry[0] is not model:
            levels, offset = [], 0
            # candidates whose column of the level Jacobian is structurally zero never enter the exchange ratio
            # (flexible pump truck: 60 of the 110 unselected candidates of its 202-row level)
            sp = model.function("jlev").sparsity_out(0)
            structural = np.zeros(sp.numel(), dtype=bool)
            structural[np.asarray(sp.find(), dtype=np.intp)] = True
            for n_rows, n_cands, costs, selected in model.levels:
                if n_cands > n_rows:
                    nonzero = structural[offset:offset + n_rows * n_cands].reshape((n_rows, n_cands), order="F").any(0)
                    others = np.array([k for k in range(n_cands) if k not in selected and nonzero[k]], dtype=np.intp)
                    levels.append(((n_rows, n_cands), offset, costs, selected, np.asarray(selected, dtype=np.intp),
                                   others))
                offset += n_rows * n_cands
            entry = self._buffers[("levels", id(model))] = (model, levels)
        return entry[1]

    def _jlev(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> np.ndarray:
        """Level Jacobians at a point, through a FunctionBuffer (no per-call conversion)."""
        entry = self._buffers.get(id(model))
        if entry is None or entry[0] is not model:
            fn = model.function("jlev")
            buf, ev = fn.buffer()
            tb, out = np.zeros(1), np.zeros(fn.nnz_out(0))
            buf.set_arg(0, memoryview(tb))
            buf.set_res(0, memoryview(out))
            sp = fn.sparsity_out(0)
            scatter = None if sp.is_dense() else (np.asarray(sp.find()), np.zeros(sp.numel()))
            entry = self._buffers[id(model)] = (model, buf, ev, tb, out, scatter)
        _, buf, ev, tb, out, scatter = entry
        tb[0] = t
        buf.set_arg(1, memoryview(y))
        buf.set_arg(2, memoryview(yp))
        buf.set_arg(3, memoryview(p))
        ev()
        if scatter is None:
            return out
        idx, dense = scatter
        dense[idx] = out
        return dense

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
    from flexlib.compile.index_reduction import _col_name

    return [_col_name(c, structure.simple.variables) for c in structure.cols]
