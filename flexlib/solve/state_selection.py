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

import numpy as np

from flexlib.compile.codegen import CompiledModel, compile_dae
from flexlib.compile.index_reduction import Structure, _pick_columns

__all__ = ["StateSelectionMonitor"]


def _smallest_sv(A: np.ndarray) -> float:
    return float(np.linalg.svd(A, compute_uv=False)[-1]) if A.size else np.inf


class StateSelectionMonitor:
    """Watches the conditioning of the dummy-derivative blocks and performs switches.

    Parameters
    ----------
    rebuild : callable
        Returns the index-reduction :class:`Structure` of the model (stages 1–3), used when the
        compiled model came from the disk cache and has no structure in memory.
    ratio : float
        Switch when the smallest singular value of the selected block drops below ``ratio``
        times that of the best block (hysteresis: a new selection is at least ``1/ratio`` better).
    every : int
        Check every this many steps while the selection is comfortably conditioned (every step once a
        ratio falls below twice ``ratio``).
    """

    def __init__(self, rebuild: Callable[[], Structure], ratio: float = 0.5, every: int = 8) -> None:
        self.rebuild = rebuild
        self.ratio = ratio
        self.every = every
        self._variants: dict[tuple, CompiledModel] = {}
        self._buffers: dict[int, tuple] = {}
        self._skip = 0

    def needs_switch(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> bool:
        """True if a clearly better-conditioned selection exists at this point.

        For each level with a choice, the ratio of the smallest singular values of the selected block
        and of the best block (pivoted QR by ``state_select`` class, as at compile time) is computed.
        Below ``ratio``: switch. While every ratio is above twice ``ratio`` only every ``every``-th step is checked.
        """
        if self._skip > 0:
            self._skip -= 1
            return False
        J = self._jlev(model, t, y, yp, p)
        worst = 1.0
        offset = 0
        for n_rows, n_cands, costs, selected in model.levels:
            block = J[offset:offset + n_rows * n_cands].reshape((n_rows, n_cands), order="F")
            offset += n_rows * n_cands
            if n_cands == n_rows:
                continue
            best = _pick_columns(block, list(range(n_cands)), costs, n_rows)
            if best is None or sorted(best) == sorted(selected):
                continue
            quality = _smallest_sv(block[:, selected]) / max(_smallest_sv(block[:, best]), 1e-300)
            if quality < self.ratio:
                return True
            worst = min(worst, quality)
        self._skip = 0 if worst < min(1.0, 2 * self.ratio) else self.every - 1
        return False

    def _jlev(self, model: CompiledModel, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> np.ndarray:
        """Level Jacobians at a point, through a FunctionBuffer (no per-call conversion)."""
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
        sp = model.function("jlev").sparsity_out(0)
        if sp.is_dense():
            return out
        dense = np.zeros(sp.numel())
        dense[np.asarray(sp.find())] = out
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
        y_new = np.array([values[n] for n in new.y_names])
        yp_new = np.zeros(new.n)
        for i in np.flatnonzero(new.differential):
            yp_new[i] = values.get(f"der({new.y_names[i]})", 0.0)
        return new, y_new, yp_new


def _names(structure: Structure) -> list[str]:
    from flexlib.compile.index_reduction import _col_name

    return [_col_name(c, structure.simple.variables) for c in structure.cols]
