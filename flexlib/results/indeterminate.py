"""The mark of statically indeterminate variables in a result: what it holds, how it is stored, how a read warns.

A rigid mechanism whose loops repeat constraints (a planar four-bar built in 3D, a parallelogram with extra links)
is over-constrained: the build drops the repeated loop rows and sets their reactions to zero
(``flexlib.compile.passes.multibody.redundancy``), and every force or torque that a self-stress of those loops
changes is not determined by the model (``flexlib.compile.passes.multibody.indeterminate``). A result keeps them
as ``Result.indeterminate``: ``{variable name: (dropped loop row, ...)}``. Reading one warns
(:class:`~flexlib.errors.IndeterminateReactionWarning`, once per variable and result), ``Result.summary`` and
``Result.plot`` mark them, and result files store the mark (the attribute ``indeterminate``: JSON, absent in files
written before it, which read as none).
"""

from __future__ import annotations

import json
import os
import sys
import warnings
from collections.abc import Callable, Iterable
from typing import Any

from flexlib.errors import IndeterminateReactionWarning

__all__ = ["FOOTNOTE", "MARK", "decode", "encode", "from_rows", "message", "warn_read"]

#: Appended to a variable's row in ``Result.summary`` and to its legend entry in ``Result.plot``.
MARK = "(indeterminate)"
#: The summary's footnote under a table that holds a marked variable.
FOOTNOTE = (f"{MARK}: statically indeterminate, one admissible load split of the over-constrained rigid model "
            "(result.indeterminate); a Bushing at one of the loop's joints or a flexible link determines it")
_HERE = os.path.dirname(os.path.abspath(__file__)) + os.sep
_ALTERNATIVES = ("For a determinate value make the loop compliant: a Bushing "
                 "(flexlib.components.mechanics.multibody.Bushing) in place of one of the loop's joints, or a "
                 "FlexibleBody for one of its links. result.indeterminate lists every such variable with the dropped "
                 "rows behind it")


def from_rows(indeterminate: dict[str, list[int]], rows: list[str]) -> dict[str, tuple[str, ...]]:
    """The mark of a result: each variable with its dropped loop rows, from a compiled model's
    ``indeterminate`` (indices into ``rows``, the report's dropped rows)."""
    return {name: tuple(rows[k] for k in ks if 0 <= k < len(rows)) for name, ks in indeterminate.items()}


def encode(mark: dict[str, tuple[str, ...]]) -> str:
    """``mark`` as the JSON a result file stores: ``{"rows": [...], "variables": {name: [row index, ...]}}``."""
    rows = list(dict.fromkeys(r for causes in mark.values() for r in causes))
    index = {r: k for k, r in enumerate(rows)}
    return json.dumps({"rows": rows, "variables": {n: [index[r] for r in causes] for n, causes in mark.items()}})


def decode(text: Any, bad: Callable[[str], Exception]) -> dict[str, tuple[str, ...]]:
    """The mark stored by :func:`encode` (None, for a file written before the mark: none); ``bad(problem)`` is the
    exception raised for a damaged attribute."""
    if text is None:
        return {}
    try:
        data = json.loads(text)
        rows, variables = data["rows"], data["variables"]
        if not (isinstance(rows, list) and all(isinstance(r, str) for r in rows) and isinstance(variables, dict)):
            raise TypeError("expected a list of rows and an object of variables")
        return {str(n): tuple(rows[int(k)] for k in ks) for n, ks in variables.items()}
    except (TypeError, ValueError, KeyError, IndexError) as err:
        raise bad(f"the attribute 'indeterminate' is not the mark of indeterminate variables ({err})") from None


def message(model: str, names: list[str], mark: dict[str, tuple[str, ...]]) -> str:
    """The warning for a read of the indeterminate variables ``names`` of a result of ``model``."""
    rows = list(dict.fromkeys(r for n in names for r in mark[n]))
    shown = ", ".join(names[:6]) + (f" and {len(names) - 6} more" if len(names) > 6 else "")
    verb, it = ("is", "it") if len(names) == 1 else ("are", "them")
    behind = (f"the dropped row behind {it}: {rows[0]}" if len(rows) == 1 else
              f"{len(rows)} dropped rows leave {it} free, the first: {rows[0]}" if rows else "")
    return (f"result of {model}: {shown} {verb} statically indeterminate: the rigid mechanism is over-constrained, "
            "so the value depends on which redundant loop rows the build dropped and is one admissible split of the "
            f"load, not a prediction ({behind}). {_ALTERNATIVES}")


def warn_read(model: str, names: Iterable[str], mark: dict[str, tuple[str, ...]], warned: set[str]) -> None:
    """Warn once (per name in ``warned``, updated) that the variables ``names`` read from a result are
    indeterminate; the warning points at the first caller outside ``flexlib/results``."""
    new = [n for n in dict.fromkeys(names) if n in mark and n not in warned]
    if not new:
        return
    warned.update(new)
    level, frame = 1, sys._getframe(0)
    while frame is not None and frame.f_code.co_filename.startswith(_HERE):
        frame, level = frame.f_back, level + 1
    warnings.warn(IndeterminateReactionWarning(message(model, new, mark)), stacklevel=level)

