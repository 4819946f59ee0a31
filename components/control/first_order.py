"""First-order transfer function block (one pole)."""

from __future__ import annotations

from typing import Any

from flexlib import Parameter, ParameterError, der, eq

from .interfaces import INIT_TYPES, PartialSISO, check_choice, output_state_start, scalar

__all__ = ["FirstOrder"]


class FirstOrder(PartialSISO):
    """First-order lag ``y = k / (T s + 1) u``: ``der(y) = (k u - y) / T``.

    Parameters
    ----------
    init_type : str
        ``"initial_state"`` (default) or ``"initial_output"``: ``y = y_start`` at the start;
        ``"steady_state"``: ``der(y) = 0``; ``"no_init"``: no initial equation (give
        ``init={"y": ...}`` or run with ``steady_state=True``).

    Connectors
    ----------
    y : Output [1]
        Output signal (the state).

    Notes
    -----
    MSL's default ``initType`` is NoInit, which Modelica tools resolve with the start value
    ``y_start``; flexlib asks for complete initial conditions, so the default here is
    ``"initial_state"``, the same start.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Continuous.FirstOrder``.
    """

    k = Parameter(1.0, unit="1", doc="Gain")
    T = Parameter(unit="s", doc="Time constant, nonzero")
    y_start = Parameter(0.0, unit="1", doc="Initial value of the output (= state)")

    def __init__(self, init_type: str = "initial_state", **kw: Any) -> None:
        super().__init__(**kw)
        self.init_type = check_choice(self, "init_type", init_type, INIT_TYPES)

    def check(self, values: dict) -> None:
        if scalar(values, "T") == 0.0:
            raise ParameterError(f"{self.param_label('T')} = 0: time constant T must be != 0")

    def initial_equations(self) -> list:
        return output_state_start(self)

    def equations(self) -> list:
        return [eq(der(self.y), (self.k * self.u - self.y) / self.T)]
