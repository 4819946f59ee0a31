"""Sampled blocks in a run: components stepped at fixed instants by code outside the DAE (a co-simulation FMU,
:class:`flexlib.fmi.FMUBlock`).

A sampled block has ``step`` [s], ``sampled_inputs()`` (full names of variables it reads), ``sampled_states()`` (full
names of states it sets: its held outputs, ``der(y) = 0``), ``sample_start(t0)``, ``sample(t, inputs) -> values`` and
``sample_stop()``. The run loop (:mod:`flexlib.solve.loop`) stops the integrator exactly at each sample instant
``t0 + k·step`` (as at a time event), then :meth:`Samplers.due` hands each block due there its inputs and sets its
states to what it returns; the loop makes the point consistent (the event iteration with the states held) and
restarts the integrator.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import ModelError

__all__ = ["Samplers", "sampled_blocks"]


def sampled_blocks(model: Any) -> list[Any]:
    """The sampled blocks of a model instance (components with ``sample_start``), in tree order."""
    return [n for n in model.walk() if callable(getattr(n, "sample_start", None))]


def _selection(model: CompiledModel, rows: np.ndarray) -> ca.Function:
    """``(t, y, y', p) -> the variables rows`` of the model's output function, built once per run (a sample then
    evaluates the blocks' inputs only, not every variable)."""
    out = model.sx_function("out")
    args = [ca.SX.sym(out.name_in(k), out.sparsity_in(k)) for k in range(out.n_in())]
    every = out(*args)
    return ca.Function("sampled_inputs", args, [ca.vertcat(*[every[int(r)] for r in rows]) if len(rows) else
                                                ca.SX(0, 1)])


class Samplers:
    """The sampled blocks of one run and their next instants."""

    def __init__(self, blocks: list[Any], model: CompiledModel, t0: float) -> None:
        names = [v.name for v in model.variables]
        self.blocks, self.model, self.t0 = blocks, model, t0
        self.inputs, self.states = [], []
        for b in blocks:
            missing = [n for n in b.sampled_inputs() if n not in names]
            states = [n for n in b.sampled_states() if n not in model.y_names]
            if missing or states:
                what = missing[0] if missing else states[0]
                raise ModelError(f"{b.path}: sampled block: {what} is not "
                                 f"{'a variable' if missing else 'a state'} of the compiled model")
            self.inputs.append(np.array([names.index(n) for n in b.sampled_inputs()], dtype=int))
            self.states.append(np.array([model.y_names.index(n) for n in b.sampled_states()], dtype=int))
        self.read = _selection(model, np.concatenate([np.zeros(0, dtype=int), *self.inputs]))
        self.at = np.cumsum([0, *(len(i) for i in self.inputs)])  # block k's inputs: read()[at[k]:at[k + 1]]
        self.count = [0] * len(blocks)
        self.samples = 0

    def next_time(self) -> float:
        """The earliest next sample instant [s] (inf without blocks)."""
        return min((self._time(k) for k in range(len(self.blocks))), default=np.inf)

    def _time(self, k: int) -> float:
        return self.t0 + self.count[k] * self.blocks[k].step

    def start(self) -> None:
        for b in self.blocks:
            b.sample_start(self.t0)

    def stop(self) -> None:
        for b in self.blocks:
            b.sample_stop()

    def due(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, list[str]] | None:
        """At ``t`` [s]: each block due samples (its inputs read from ``(y, yp, p)``); the unknowns with the blocks'
        states set, and the paths of the blocks that sampled — or None if none is due."""
        tol = 1e-9 * max(1.0, abs(t))
        due = [k for k in range(len(self.blocks)) if self._time(k) <= t + tol]
        if not due:
            return None
        inputs = np.asarray(self.read(t, y, yp, p), dtype=float).ravel()
        y1 = np.array(y, dtype=float)
        for k in due:
            y1[self.states[k]] = self.blocks[k].sample(t, inputs[self.at[k]:self.at[k + 1]])
            self.count[k] += 1
        self.samples += 1
        return y1, [self.blocks[k].path or type(self.blocks[k]).__name__ for k in due]
