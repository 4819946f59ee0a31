"""Argument checks shared by the boom parts (private): errors name the part and the argument."""

from __future__ import annotations

import math
import numbers
from typing import Any

from flexlib.errors import ParameterError

__all__ = ["finite", "positive", "positives"]


def positive(part: str, name: str, value: Any, unit: str, *, allow_zero: bool = False) -> float:
    """``value`` as a finite float > 0 (``>= 0`` with ``allow_zero``); else ``ParameterError`` naming ``part``
    and ``name``."""
    ok = isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or value < 0 or (value == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ParameterError(f"{part}: {name} must be a finite number {bound} [{unit}], got {value!r}")
    return float(value)


def finite(part: str, name: str, value: Any, unit: str) -> float:
    """``value`` as a finite float; else ``ParameterError`` naming ``part`` and ``name``."""
    if not (isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(value)):
        raise ParameterError(f"{part}: {name} must be a finite number [{unit}], got {value!r}")
    return float(value)


def positives(part: str, **arguments: tuple[Any, str]) -> list[float]:
    """:func:`positive` for each ``name=(value, unit)``, in order."""
    return [positive(part, name, value, unit) for name, (value, unit) in arguments.items()]
