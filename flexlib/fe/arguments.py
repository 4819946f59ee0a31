"""Argument checks the FE toolkit shares: numbers (finite reals, not text or bools), three-vectors, node component
names, and row lists written as runs for messages. Each failure is a :class:`~flexlib.errors.RunArgumentError`
naming the function and the argument."""

from __future__ import annotations

import numbers
import os
from typing import Any

import numpy as np

from flexlib.errors import RunArgumentError

__all__ = ["COMPONENTS", "array_kind", "component_list", "is_int", "real_array", "row_ranges", "vector3"]

#: Names of the six components of a node, in ``dof_map`` column order.
COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")


def array_kind(value: Any) -> str:
    """The numpy dtype kind of ``value`` as an array (``"U"`` for text, ``"O"`` for what is not a regular array)."""
    if isinstance(value, str | bytes | os.PathLike):
        return "U"
    try:
        return np.asarray(value).dtype.kind
    except (TypeError, ValueError):
        return "O"


def component_list(components: Any) -> tuple[str, ...]:
    """Component names, each one of :data:`COMPONENTS`; a single string is refused with a hint (it would be read
    letter by letter)."""
    if isinstance(components, str):
        raise RunArgumentError(f"FEModel: components must be a list of names from {list(COMPONENTS)}, got the string "
                               f"{components!r}" + (f" (for one component: [{components!r}])"
                                                    if components in COMPONENTS else ""))
    try:
        names = tuple(components)
    except TypeError:
        raise RunArgumentError(f"FEModel: components must be a list of names from {list(COMPONENTS)}, got "
                               f"{components!r}") from None
    for c in names:
        if c not in COMPONENTS:
            hint = f" (did you mean {c.lower()!r}?)" if isinstance(c, str) and c.lower() in COMPONENTS else ""
            raise RunArgumentError(f"FEModel: unknown component {c!r}; components are {list(COMPONENTS)}{hint}")
    return names


def real_array(func: str, name: str, value: Any, what: str) -> np.ndarray:
    """An array of finite real numbers (not text, bools or complex), naming the argument."""
    if array_kind(value) not in "iuf":
        raise RunArgumentError(f"{func}: argument {name!r} must be {what}, numbers, got {value!r:.80}")
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        raise RunArgumentError(f"{func}: argument {name!r} has non-finite values: {a.ravel()[:6].tolist()}")
    return a


def vector3(func: str, name: str, value: Any, unit: str) -> np.ndarray:
    a = real_array(func, name, value, f"three numbers (x, y, z) {unit}")
    if a.shape != (3,):
        raise RunArgumentError(f"{func}: argument {name!r} must be three numbers (x, y, z) {unit}, got shape "
                               f"{a.shape}: {value!r}")
    return a


def row_ranges(rows: np.ndarray, limit: int = 8) -> str:
    """``"24..29, 31"``: sorted integers as runs (for messages)."""
    rows = np.unique(np.asarray(rows, dtype=np.int64))
    runs: list[str] = []
    start = prev = None
    for r in [*rows.tolist(), None]:
        if r is not None and prev is not None and r == prev + 1:
            prev = r
            continue
        if start is not None:
            runs.append(str(start) if start == prev else f"{start}..{prev}")
        start = prev = r
    return ", ".join(runs[:limit]) + (" ..." if len(runs) > limit else "")


def is_int(value: Any) -> bool:
    """An integer (Python or numpy), not a bool."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)
