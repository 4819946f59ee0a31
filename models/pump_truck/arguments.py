"""Checks of :class:`~models.pump_truck.model.PumpTruck`'s arguments: time tables and flexible-section modes."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from flexlib.errors import ParameterError

from .parameters import PumpTruckParameters

__all__ = ["JOINTS", "check_modes", "check_table"]

#: Joint names: the slewing joint and the five boom joints.
JOINTS = ("slew", "joint1", "joint2", "joint3", "joint4", "joint5")


def check_modes(modes: Any, record: PumpTruckParameters) -> int | dict[int, list[int]]:
    """``PumpTruck(modes=...)`` of a flexible boom: ``"mpf"`` (the selection of
    :func:`~models.pump_truck.flexible.mpf_modes` for ``record``), a count >= 1, or a list of mode indices for every
    section 1–5."""
    if modes == "mpf":
        from .flexible import mpf_modes

        return mpf_modes(record)
    if isinstance(modes, int) and not isinstance(modes, bool):
        if modes < 1:
            raise ParameterError(f"PumpTruck: modes must be at least 1 per section, got {modes!r}")
        return modes
    if not isinstance(modes, Mapping):
        raise ParameterError(f"PumpTruck: modes must be 'mpf', a count or a mapping of section to mode indices, "
                             f"got {modes!r}")
    try:
        out = {int(k): [int(i) for i in v] for k, v in modes.items()}
    except (TypeError, ValueError):
        raise ParameterError(f"PumpTruck: modes must map section numbers 1-5 to lists of mode indices, got "
                             f"{modes!r}") from None
    if sorted(out) != [1, 2, 3, 4, 5]:
        missing = sorted(set(range(1, 6)) - set(out))
        extra = sorted(set(out) - set(range(1, 6)))
        raise ParameterError(f"PumpTruck: modes must give every section 1-5 (missing {missing}, unknown {extra})")
    return out


def check_table(owner: str, spec: Any, n_values: int | None = None) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Check a time table ``{"t": [...], "<joint>": [...], ...}`` and return ``t`` and the columns."""
    if not isinstance(spec, Mapping) or "t" not in spec:
        raise ParameterError(f"PumpTruck: {owner} must be a mapping with a time column 't' and one column per joint")
    t = np.asarray(spec["t"], dtype=float)
    if t.ndim != 1 or t.size < 1 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise ParameterError(f"PumpTruck: {owner}['t'] must be finite, strictly increasing times [s]")
    cols = {}
    for name, col in spec.items():
        if name == "t":
            continue
        if name not in JOINTS:
            raise ParameterError(f"PumpTruck: {owner} has unknown joint {name!r}; joints are {', '.join(JOINTS)}")
        y = np.asarray(col, dtype=float)
        if y.shape != t.shape or not np.all(np.isfinite(y)):
            raise ParameterError(f"PumpTruck: {owner}[{name!r}] needs {t.size} finite values (one per time point)")
        cols[name] = y
    return t, cols
