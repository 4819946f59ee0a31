"""Reductions: what a study keeps of each run, computed where the run happened (a worker), so that only numbers come
back. Each is a small picklable record ``reduction(result) -> float``; any function of a
:class:`~flexlib.Result` to a float is one too (it must be importable by the workers: defined in a module, not in
``__main__`` of a script run on a remote cluster)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

__all__ = ["Final", "Maximum", "Minimum", "Peak", "Reduction"]


class Reduction(Protocol):
    """``reduction(result) -> float``."""

    def __call__(self, result: Any) -> float: ...


@dataclass(frozen=True)
class Peak:
    """The largest magnitude of ``signal`` over the run (its SI unit): ``max |x(t)|``; for a vector signal (a hinge
    force ``joint2.frame_b.f``) the largest Euclidean norm of its elements."""

    signal: str

    def __call__(self, result: Any) -> float:
        x = np.asarray(result[self.signal], dtype=float)
        return float(np.max(np.linalg.norm(x.reshape(len(x), -1), axis=1)))


@dataclass(frozen=True)
class Maximum:
    """The largest value of the scalar ``signal`` over the run (its SI unit)."""

    signal: str

    def __call__(self, result: Any) -> float:
        return float(np.max(result[self.signal]))


@dataclass(frozen=True)
class Minimum:
    """The smallest value of the scalar ``signal`` over the run (its SI unit)."""

    signal: str

    def __call__(self, result: Any) -> float:
        return float(np.min(result[self.signal]))


@dataclass(frozen=True)
class Final:
    """The value of the scalar ``signal`` at the end of the run (its SI unit)."""

    signal: str

    def __call__(self, result: Any) -> float:
        return float(np.asarray(result[self.signal])[-1])
