"""Choice of the frame in which a force element or sensor resolves its vector (MSL ``Types.ResolveInFrame*``).

MSL makes ``resolveInFrame`` an evaluated parameter (it decides which equations are written); here it
is a constructor argument checked by :func:`check_resolve_in_frame`. MSL's extra ``frame_resolve``
connector is not provided: resolve a world-resolved output with a separate block if needed.
"""

from __future__ import annotations

from typing import Any

from flexlib.core.options import remember_option
from flexlib.errors import ModelError

__all__ = ["check_resolve_in_frame"]


def check_resolve_in_frame(component: Any, value: Any, allowed: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of ``allowed``, else raise :class:`~flexlib.ModelError` naming the component."""
    if not isinstance(value, str) or value not in allowed:
        label = component.path or type(component).__name__
        raise ModelError(f"{label}: resolve_in_frame = {value!r} is not one of {', '.join(map(repr, allowed))}")
    remember_option(component, "resolve_in_frame", lambda v: check_resolve_in_frame(component, v, allowed))
    return value
