"""On/off switches read from the environment (``FLEXLIB_NATIVE``, ``FLEXLIB_ZERO_GEOMETRY``, ``FLEXLIB_EXPLICIT``,
``FLEXLIB_ERROR_TEST_ALL``), all read by one function.

Each switch takes ``1``/``true``/``yes``/``on`` or ``0``/``false``/``no``/``off`` (any case; unset or empty: its
default). Anything else is refused with a :class:`~flexlib.errors.RunArgumentError` naming the variable, its value
and the accepted words, so that ``FLEXLIB_NATIVE=false`` is never read as "on".
"""

from __future__ import annotations

import os

from flexlib.errors import RunArgumentError

__all__ = ["FALSE_WORDS", "TRUE_WORDS", "env_switch"]

#: Values that switch an option on (compared after ``strip().lower()``).
TRUE_WORDS = ("1", "true", "yes", "on")
#: Values that switch an option off.
FALSE_WORDS = ("0", "false", "no", "off")


def env_switch(name: str, default: bool, words: tuple[str, ...] = ()) -> bool | str:
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
