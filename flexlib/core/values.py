"""Checks of values a user gives: on/off options, real numbers and arrays of them.

A string such as ``'1.6e9'``, a bool, None or a complex number is refused by name rather than converted, so a
mistaken value never becomes a silently different number. The declarations (parameter values, start values),
the component libraries and the analyses share these checks.
"""

from __future__ import annotations

import decimal
import numbers
from typing import Any

import casadi as ca
import numpy as np

__all__ = ["as_bool", "not_a_number", "not_a_scalar", "numeric_array"]


def as_bool(value: Any, what: str, error: type[Exception], *, ints: bool = True) -> bool:
    """An on/off option as a bool: True or False (numpy bools too; with ``ints`` also 0 and 1), never a string, None or
    another number — ``bool("False")`` is True, so such a value would silently switch the option on. Otherwise
    ``error`` naming ``what`` and the value."""
    if isinstance(value, (bool, np.bool_)) or (ints and isinstance(value, (int, np.integer)) and value in (0, 1)):
        return bool(value)
    raise error(f"{what} must be True or False, got {value!r:.80}")


def not_a_scalar(value: Any) -> str | None:
    """Why ``value`` is not one real number (:func:`not_a_number`, or an array), or None if it is."""
    why = not_a_number(value)
    if why is None and np.ndim(value) != 0:
        why = f"an array of shape {np.shape(value)}, not a number"
    return why


def not_a_number(value: Any) -> str | None:
    """Why ``value`` (a scalar or a nested list/array) is not a real number or array of them, or None if it is.

    Refused: strings (``'1.6e9'`` would otherwise be parsed by numpy), booleans (``True`` would be 1.0), None,
    complex numbers, and anything else numpy would only hold as an object.
    """
    if value is None:
        return "None, not a number"
    if isinstance(value, (str, bytes, np.str_, np.bytes_)):
        return "a string, not a number"
    if isinstance(value, (bool, np.bool_)):
        return "a bool, not a number"
    if isinstance(value, (numbers.Real, decimal.Decimal)):
        return None
    if isinstance(value, (complex, np.complexfloating)):
        return "complex, not a real number"
    if isinstance(value, (ca.SX, ca.MX)):
        return "a symbolic expression, not a number"
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):  # ragged nested lists
        return "not a number or a regular array of numbers"
    kind = arr.dtype.kind
    if kind in "iuf":
        if isinstance(value, (list, tuple)) and _has_bool(value):  # numpy reads [1.0, True] as [1.0, 1.0]
            return "a sequence with a bool entry, not only numbers"
        return None
    if kind == "b":
        return "a bool, not a number" if arr.ndim == 0 else "an array of bools, not of numbers"
    if kind in "USa":
        return "a string, not a number" if arr.ndim == 0 else "an array of strings, not of numbers"
    if kind == "c":
        return "complex, not a real number"
    if kind == "O":
        if arr.ndim == 0:
            return f"of type {type(value).__name__}, not a number"
        for item in arr.flat:
            why = not_a_number(item)
            if why is not None:
                return f"an array with an entry {item!r} ({why})"
        return None
    return f"of type {type(value).__name__}, not a number"


def _plain_numbers(seq: list | tuple) -> bool:
    """True if a nested list/tuple holds only Python floats and ints (not bools) and numpy reals."""
    for x in seq:
        t = type(x)
        if t is float or t is int:
            continue
        if t in (list, tuple):
            if not _plain_numbers(x):
                return False
        elif not isinstance(x, (np.floating, np.integer)):
            return False
    return True


def _has_bool(seq: list | tuple) -> bool:
    """True if a nested list/tuple holds a bool anywhere."""
    return any(isinstance(x, (bool, np.bool_)) or (isinstance(x, (list, tuple)) and _has_bool(x)) for x in seq)


def numeric_array(value: Any, what: str, accepted: str, error: type[Exception]) -> np.ndarray:
    """``value`` as a float array, refusing strings, bools, None, complex and other non-numbers.

    Parameters
    ----------
    value : Any
        The value received (a number or a nested list/array of numbers).
    what : str
        How the message names it (``"mass.m: parameter value"``).
    accepted : str
        What is accepted, appended to the message (``"a real number [kg]"``).
    error : type
        The exception class to raise.
    """
    try:
        if (type(value) is np.ndarray and value.dtype.kind in "iuf") or type(value) in (float, int):
            return np.array(value, dtype=float)  # the usual cases: nothing to refuse
        if type(value) in (list, tuple) and _plain_numbers(value):  # a (nested) list of floats and ints
            return np.array(value, dtype=float)
    except (ValueError, OverflowError):  # ragged, or an int beyond the float range (10**400): named below
        pass
    why = not_a_number(value)
    if why is None:
        try:
            return np.array(value, dtype=float)
        except (TypeError, ValueError, OverflowError) as exc:
            why = f"not numeric ({exc})"
    shown = "is None" if value is None else f"{value!r:.80} is {why}"
    raise error(f"{what} {shown}; give {accepted}")
