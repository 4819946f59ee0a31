"""The Modelica Association's reference results of MSL examples (``tests/data/msl``) and the comparison the MSL
example tests make: each signal's largest deviation over its range at the reference's output times."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import flexlib as fl

DATA = Path(__file__).resolve().parents[1] / "data" / "msl"


def reference(name: str) -> dict[str, np.ndarray]:
    """The reference's signals at its distinct output times (an event's second row, the value after it)."""
    with np.load(DATA / f"{name}.npz") as f:
        ref = {k: f[k] for k in f.files}
    t = ref["time"]
    last = np.r_[t[1:] != t[:-1], True]
    return {k: v[last] for k, v in ref.items()}


def worst_deviation(res: fl.Result, ref: dict[str, np.ndarray]) -> dict[str, float]:
    """Per comparison signal: the largest deviation from the reference over the reference's range."""
    t = ref["time"]
    out = {}
    for name, values in ref.items():
        if name == "time":
            continue
        mine = res.value(name, t, side="right")
        out[name] = float(np.max(np.abs(mine - values)) / np.ptp(values))
    return out
