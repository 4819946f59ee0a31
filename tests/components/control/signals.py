"""Helpers shared by the control-block tests (not tests)."""

from __future__ import annotations

import numpy as np

import flexlib as fl


def right_values(res: fl.Result, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Time points and values, keeping the right (post-event) value at an event time."""
    keep = np.ones(len(res.t), dtype=bool)
    keep[:-1] = res.t[1:] != res.t[:-1]
    return res.t[keep], res[name][keep]
