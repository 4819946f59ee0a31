"""What the commands of :mod:`flexlib.cli` share: one-line errors, options given once, the console and number
format, warnings on stderr."""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from typing import Any

import click
from rich.console import Console

from flexlib.errors import FlexlibError

__all__ = ["fmt", "friendly", "new_console", "once", "once_option", "one_line", "say"]


def one_line(err: BaseException) -> str:
    """The message of ``err`` on one line (its class name if it has none)."""
    return " ".join(str(err).split()) or type(err).__name__


def friendly(func: Callable[..., Any]) -> Callable[..., Any]:
    """Turn flexlib's errors (and bad values) into a one-line ``Error: ...`` with exit code 1."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except click.ClickException:
            raise
        except (FlexlibError, ValueError, OSError, LookupError) as err:
            raise click.ClickException(one_line(err)) from None

    return wrapper


def new_console() -> Console:
    """A rich console that prints labels as written (no markup, no highlighting)."""
    return Console(highlight=False, markup=False)  # "[s]" in labels is text, not a style


def once(ctx: click.Context, param: click.Parameter, values: tuple[Any, ...]) -> Any:
    """The value of an option that takes one (``None`` if not given); given twice with different values it is
    refused, naming both (click would silently keep the last)."""
    if len(set(values)) > 1:
        shown = " and ".join(repr(v) for v in dict.fromkeys(values))
        raise click.BadParameter(f"given {len(values)} times ({shown}); give it once", ctx=ctx, param=param)
    return values[0] if values else None


def once_option(*decls: str, **kwargs: Any) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``click.option`` of an option that takes one value: repeating it with another value is an error."""
    return click.option(*decls, multiple=True, callback=once, **kwargs)


def say(kind: str, text: str) -> None:
    """A ``Warning:`` or ``Note:`` line on stderr, after what was printed on stdout (one line, not folded)."""
    sys.stdout.flush()
    click.echo(f"{kind}: {' '.join(text.split())}", err=True)


def fmt(x: float) -> str:
    """A number in a table: six significant digits."""
    return f"{x:.6g}"
