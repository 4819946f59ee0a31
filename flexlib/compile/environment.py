"""The environment defaults of the build and run options, read in one place.

Every option of :class:`~flexlib.compile.build_options.BuildOptions` and of the solver objects
(:class:`flexlib.IDA`, :class:`flexlib.CasadiIDAS`) that an environment variable may set has its default read here,
by :func:`env_default`, at the moment an option left None is resolved (:data:`DEFAULTS_FROM` lists them). No other
module reads these variables, and nothing writes them: an option given as a value is passed down to the stage that
uses it.

An on/off switch takes ``1``/``true``/``yes``/``on`` or ``0``/``false``/``no``/``off`` (any case; unset or empty:
its default). Anything else is refused with a :class:`~flexlib.errors.RunArgumentError` naming the variable, its
value and the accepted words, so that ``FLEXLIB_NATIVE=false`` is never read as "on".
"""

from __future__ import annotations

import os
from typing import Any

from flexlib.errors import RunArgumentError

__all__ = ["DEFAULTS_FROM", "FALSE_WORDS", "LINSOL_CHOICES", "TREE_FRAMES", "TRUE_WORDS", "env_default", "env_switch"]

#: Values that switch an option on (compared after ``strip().lower()``).
TRUE_WORDS = ("1", "true", "yes", "on")
#: Values that switch an option off.
FALSE_WORDS = ("0", "false", "no", "off")
#: The choices of ``tree_frames`` (:mod:`flexlib.compile.passes.multibody.tearing`).
TREE_FRAMES = ("auto", "tear", "keep")
#: The choices of the C driver's linear solver (``FLEXLIB_LINSOL``, :func:`flexlib.solve.backends.ida_c.linear_solver`).
LINSOL_CHOICES = ("dense", "superlumt", "klu")

#: The options whose default an environment variable gives: option -> variable (``docs/engine.md``, "Switches").
DEFAULTS_FROM = {
    "zero_geometry": "FLEXLIB_ZERO_GEOMETRY",  # BuildOptions: on unless 0
    "explicit": "FLEXLIB_EXPLICIT",            # BuildOptions: on unless 0; "all"
    "tree_frames": "FLEXLIB_TREE_FRAMES",      # BuildOptions: "auto", "tear" or "keep"
    "native": "FLEXLIB_NATIVE",                # IDA: the C driver where it builds, unless 0
    "linear_solver": "FLEXLIB_LINSOL",         # IDA: "dense", "klu", "superlumt"; unset: by size
    "error_test_all": "FLEXLIB_ERROR_TEST_ALL",  # IDA, CasadiIDAS: off unless 1
}


def env_switch(name: str, default: Any, words: tuple[str, ...] = ()) -> Any:
    """The value of the on/off environment variable ``name``.

    Parameters
    ----------
    name : str
        The variable (``"FLEXLIB_NATIVE"``).
    default : bool
        The value when it is unset or empty.
    words : tuple of str
        Further accepted values (lower case), returned as given (``FLEXLIB_EXPLICIT=all``).

    Returns
    -------
    bool or str
        True or False, or one of ``words``.

    Raises
    ------
    RunArgumentError
        The value is none of the accepted ones; the message names the variable, the value and what is accepted.
    """
    raw = os.environ.get(name)
    if raw is None or not raw.strip():
        return default
    value = raw.strip().lower()
    if value in TRUE_WORDS:
        return True
    if value in FALSE_WORDS:
        return False
    if value in words:
        return value
    accepted = ", ".join([*TRUE_WORDS, *FALSE_WORDS, *words])
    raise RunArgumentError(f"environment variable {name} = {raw!r} is invalid: expected one of {accepted} "
                           f"(unset: {'on' if default else 'off'})")


def env_default(option: str) -> Any:
    """The default of ``option`` (a key of :data:`DEFAULTS_FROM`) as its environment variable gives it now.

    Returns
    -------
    bool, str or None
        ``zero_geometry``, ``native``, ``error_test_all``: True or False (unset: True, True, False);
        ``explicit``: True, False or ``"all"`` (unset: True); ``tree_frames``: ``"auto"``, ``"tear"`` or ``"keep"``
        (unset: ``"auto"``); ``linear_solver``: one of :data:`LINSOL_CHOICES`, or None when unset (the rule by size).

    Raises
    ------
    RunArgumentError
        The variable holds a value the option does not accept (the message names the variable and the value).
    """
    name = DEFAULTS_FROM[option]
    if option in ("zero_geometry", "native"):
        return bool(env_switch(name, True))
    if option == "error_test_all":
        return bool(env_switch(name, False))
    if option == "explicit":
        return env_switch(name, True, ("all",))
    raw = os.environ.get(name, "")
    if option == "tree_frames":
        mode = raw.strip().lower() or "auto"
        if mode not in TREE_FRAMES:
            raise RunArgumentError(f"environment variable {name} = {raw!r}: expected 'auto', 'tear' or 'keep'")
        return mode
    if not raw:  # linear_solver
        return None
    if raw not in LINSOL_CHOICES:
        raise RunArgumentError(f"{name}={raw!r}: expected one of {', '.join(LINSOL_CHOICES)}")
    return raw
