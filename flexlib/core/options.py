"""Constructor options of components: on/off flags checked as bools, and the checks remembered so that an
assignment after construction is checked the same way (:meth:`flexlib.core.component.Node._set_option` reads them)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from flexlib.core.values import as_bool
from flexlib.errors import ParameterError

__all__ = ["flag", "remember_option"]


def flag(node: Any, name: str, value: Any, *, structural: bool = False) -> bool:
    """A structural on/off option of a component (``use_support``, ``strict``, ``use_flange``, ...) as a bool.

    ``bool("False")`` is True, so a string, None or a number other than 0/1 given for a flag would silently switch the
    option on: it is refused with a :class:`~flexlib.errors.ParameterError` naming the component class, the option and
    the value. The option is remembered (:func:`remember_option`): a later ``node.<name> = value`` is checked the same
    way, and refused for a ``structural`` option (one that decided connectors, variables or start values in the
    constructor, such as ``use_support``), which a later assignment could not change.
    """
    on = as_bool(value, f"{type(node).__name__}: {name}", ParameterError)
    remember_option(node, name, lambda v: flag(node, name, v, structural=structural), structural=structural)
    return on


def remember_option(node: Any, name: str, check: Callable[[Any], Any], *, structural: bool = False) -> None:
    """Record how constructor option ``name`` of ``node`` is checked, so that an assignment after construction
    (``limiter.strict = "False"``, ``pid.controller_type = "PI"``) is checked too.

    Parameters
    ----------
    node : Node
        The component.
    name : str
        The attribute the option is stored in.
    check : callable
        ``check(value)`` returns the accepted value or raises an error naming the component class, the option and the
        value (:func:`flag`, ``check_choice``).
    structural : bool
        True if the value decided the component's connectors, variables, start values or other attributes when it
        was built (``use_support`` adds a flange, ``controller_type`` the integrator): assigning another value later
        would be ignored in part, so it is refused, naming the constructor argument to use instead.
    """
    node.__dict__.setdefault("_options", {})[name] = (check, structural)
