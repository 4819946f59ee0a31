"""Hand statics of the robots by virtual work: generalised forces as the gradient of a closed-form energy."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["energy_gradient"]


def energy_gradient(V: Callable[[np.ndarray], float], x: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """``∂V/∂x`` at ``x`` by central differences of step ``h``: the generalised forces that hold a conservative
    system at rest (principle of virtual work; truncation error ``O(h²)``, about 1e-12 relative here)."""
    x = np.asarray(x, dtype=float)
    out = np.empty(len(x))
    for k in range(len(x)):
        dx = np.zeros(len(x))
        dx[k] = h
        out[k] = (V(x + dx) - V(x - dx)) / (2 * h)
    return out
