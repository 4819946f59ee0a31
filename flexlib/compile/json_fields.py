"""Typed reading of JSON metadata: each value checked for the type it must have, or a ``ValueError`` naming it.

A cache entry's ``model.json`` is read back into a :class:`~flexlib.compile.codegen.CompiledModel` through these
checks (``CompiledModel.from_data``), so a damaged or hand-edited entry is refused by field, never half-loaded.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from flexlib.compile.index_reduction import IndexReport

__all__ = ["expect", "index_report", "levels", "name_number", "plain_dict", "record", "str_list"]


def expect(value: Any, kind: type | tuple[type, ...], what: str) -> Any:
    """``value`` if it is of type ``kind`` (an int is not a bool), else ``ValueError`` naming ``what``."""
    if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
        raise ValueError(f"{what}: expected {kind}, got {type(value).__name__}")
    return value


def str_list(v: Any, what: str) -> list[str]:
    """``v`` if it is a list of str, else ``ValueError`` naming ``what``."""
    if type(v) is not list or not all(type(x) is str for x in v):
        raise ValueError(f"{what}: expected a list of strings")
    return v


def name_number(v: Any, what: str) -> tuple[str, float]:
    """A ``[name, number]`` pair as ``(name, float)``, else ``ValueError`` naming ``what``."""
    if type(v) is not list or len(v) != 2 or type(v[0]) is not str or type(v[1]) not in (int, float):
        raise ValueError(f"{what}: expected a (name, number) pair")
    return v[0], float(v[1])


_RECORD_FIELDS: dict[type, frozenset[str]] = {}
_RECORD_VALUES = (str, bool, int, float, list)


def record(kind: type, v: Any, what: str) -> Any:
    """A dataclass ``kind`` built from a JSON object of some of its fields (plain values only)."""
    names = _RECORD_FIELDS.get(kind)
    if names is None:
        names = _RECORD_FIELDS[kind] = frozenset(f.name for f in dataclasses.fields(kind))
    if type(v) is not dict or not v.keys() <= names:
        raise ValueError(f"{what}: expected a record with keys from {sorted(names)}")
    if not all(type(val) in _RECORD_VALUES for val in v.values()):
        raise ValueError(f"{what}: unexpected value types")
    return kind(**v)


def index_report(v: Any, what: str) -> IndexReport:
    """An :class:`IndexReport` from its JSON object, each field of its type."""
    rep = record(IndexReport, v, what)
    expect(rep.index, int, what)
    rep.differentiated = [(expect(o, str, what), expect(e, str, what), expect(k, int, what))
                          for o, e, k in expect(rep.differentiated, list, what)]
    for name in ("states", "dummy_derivatives", "redundant", "explicit"):
        setattr(rep, name, str_list(getattr(rep, name), what))
    expect(rep.indeterminate, int, what)
    return rep


def levels(v: Any, what: str) -> list[tuple[int, int, list[int], list[int]]]:
    """The state-selection levels: ``[rows, candidates, [costs], [selected]]`` of ints."""
    out = []
    for item in expect(v, list, what):
        nr, nc, costs, sel = expect(item, list, what)
        out.append((expect(nr, int, what), expect(nc, int, what),
                    [expect(c, int, what) for c in expect(costs, list, what)],
                    [expect(c, int, what) for c in expect(sel, list, what)]))
    return out


def plain_dict(v: Any, what: str) -> dict[str, Any]:
    """``v`` if it is a JSON object of str, bool, int, float or None values."""
    for key, val in expect(v, dict, what).items():
        expect(val, (str, bool, int, float, type(None)), f"{what}.{key}")
    return v
