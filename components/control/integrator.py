"""Integrator block."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, der, eq

from .interfaces import INIT_TYPES, PartialSISO, check_choice, output_state_start

__all__ = ["Integrator"]


class Integrator(PartialSISO):
    """Output the integral of the input: ``der(y) = k u``, ``y = y_start`` at the start.

    Parameters
    ----------
    init_type : str
        ``"initial_state"`` (default, as MSL's) or ``"initial_output"``: ``y = y_start`` at the start;
        ``"steady_state"``: ``der(y) = 0`` (the input is zero at the start); ``"no_init"``: no initial equation
        (give ``init={"y": ...}`` or run with ``steady_state=True``).

    Connectors
    ----------
    y : Output [1]
        The integral of ``u`` (the state).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Continuous.Integrator`` (without its optional ``reset`` and
    ``set`` inputs).
    """

    k = Parameter(1.0, unit="1", doc="Integrator gain")
    y_start = Parameter(0.0, unit="1", doc="Initial value of the output (= state)")

    def __init__(self, init_type: str = "initial_state", **kw: Any) -> None:
        super().__init__(**kw)
        self.init_type = check_choice(self, "init_type", init_type, INIT_TYPES)

    def initial_equations(self) -> list:
        return output_state_start(self)

    def equations(self) -> list:
        return [eq(der(self.y), self.k * self.u)]
