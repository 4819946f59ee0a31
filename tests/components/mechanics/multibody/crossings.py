"""Zero crossings of a sampled signal, for the period measurements of the pendulum tests (a helper, not tests)."""

from __future__ import annotations

import numpy as np


def upward_crossings(t: np.ndarray, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """Upward zero crossings by cubic Hermite interpolation between output points."""
    out = []
    for k in np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0)):
        h = t[k + 1] - t[k]
        p0, p1, m0, m1 = x[k], x[k + 1], xd[k] * h, xd[k + 1] * h
        roots = np.roots([2 * p0 - 2 * p1 + m0 + m1, -3 * p0 + 3 * p1 - 2 * m0 - m1, m0, p0])
        real = [r.real for r in roots if abs(r.imag) < 1e-12 and -1e-9 <= r.real <= 1 + 1e-9]
        out.append(t[k] + h * real[0])
    return np.array(out)
