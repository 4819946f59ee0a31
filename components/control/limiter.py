"""Limit the range of a signal."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, ParameterError, eq, if_else, no_event
from flexlib.core.options import flag

from .interfaces import PartialSISO, check_mirrored_limit, mirror_lower_limit, scalar

__all__ = ["Limiter", "limit"]


def limit(u: Any, upper: Any, lower: Any, strict: bool = False) -> Any:
    """``upper`` if ``u > upper``, ``lower`` if ``u < lower``, else ``u`` (events unless ``strict``)."""
    select = no_event if strict else if_else
    return select(u > upper, upper, select(u < lower, lower, u))


class Limiter(PartialSISO):
    """Limiter: the input passes while ``u_min <= u <= u_max``, otherwise the violated limit.

    .. math::

        y = \\begin{cases} u_{max} & u > u_{max} \\\\ u_{min} & u < u_{min} \\\\ u & \\text{else} \\end{cases}

    Each limit crossing is a state event (the integrator stops exactly at the kink), unless
    ``strict`` is set.

    Parameters
    ----------
    strict : bool
        True to evaluate the limits continuously (MSL ``strict``: ``noEvent``, no events), for
        inputs that must not be stopped at; default False (events).

    Connectors
    ----------
    y : Output [1]
        Limited signal.

    Notes
    -----
    ``u_max >= u_min`` is checked on the instance, at flatten and for values passed to
    ``sim.run(params=...)``.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Nonlinear.Limiter``.
    """

    u_max = Parameter(unit="1", doc="Upper limit of the input signal")
    u_min = Parameter(unit="1", doc="Lower limit of the input signal, <= ``u_max`` (default ``-u_max``, as MSL's)")

    def __init__(self, strict: bool = False, **kw: Any) -> None:
        self._u_min_follows = mirror_lower_limit(kw, "u_max", "u_min")  # MSL's uMin = -uMax
        super().__init__(**kw)
        self.strict = flag(self, "strict", strict)

    def check(self, values: dict) -> None:
        if getattr(self, "_u_min_follows", False):
            check_mirrored_limit(self, values, "u_max", "u_min")
        hi, lo = scalar(values, "u_max"), scalar(values, "u_min")
        if hi is not None and lo is not None and hi < lo:
            raise ParameterError(f"{self.where}: limits must be consistent (u_max >= u_min), but u_max = {hi:g} "
                                 f"< u_min = {lo:g}")

    def equations(self) -> list:
        return [eq(self.y, limit(self.u, self.u_max, self.u_min, self.strict))]
