"""Partial blocks of the signal library (MSL Blocks.Interfaces).

Signals are causal: an ``Output`` is computed by its block, an ``Input`` takes the value
of the output connected to it. Signals are dimensionless (unit ``"1"``); a physical
source interprets the value in SI units.

References
----------
Modelica Standard Library 4.0, ``Modelica.Blocks.Interfaces``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from flexlib import Component, Input, Output, Parameter
from flexlib.errors import ModelError, ParameterError

__all__ = [
    "INIT_TYPES",
    "PartialSI2SO",
    "PartialSISO",
    "PartialSO",
    "PartialSVcontrol",
    "PartialSignalSource",
    "ValueChecks",
    "check_choice",
]

#: Initialisation options of the continuous blocks (MSL ``Modelica.Blocks.Types.Init``: NoInit,
#: SteadyState, InitialState, InitialOutput). ``"no_init"`` writes no initial equation: the
#: model must supply the condition (``init={...}`` or ``run(steady_state=True)``).
INIT_TYPES = ("no_init", "steady_state", "initial_state", "initial_output")


def check_choice(block: Any, option: str, value: Any, choices: tuple) -> Any:
    """Return ``value`` if it is one of ``choices``, else raise a ModelError naming the block."""
    if value not in choices:
        raise ModelError(f"{type(block).__name__}: {option}={value!r} is not one of {', '.join(map(repr, choices))}")
    return value


class ValueChecks:
    """Mixin: parameter values are checked when assigned (:meth:`check_value`) and together
    (:meth:`check_values`) after construction and after every later assignment.

    ``Parameter(min=, max=)`` bounds are also checked at run time; the checks here give clearer
    messages and strict bounds, and hold the relations between parameters (``u_max >= u_min``),
    which values passed to ``sim.run(params=...)`` do not get.
    """

    def __init__(self, **kw: Any) -> None:
        super().__init__(**kw)
        self.__dict__["_values_complete"] = True
        self.check_values()

    def _assign(self, name: str, value: Any) -> None:
        try:
            number = float(value) if np.ndim(value) == 0 else None
        except (TypeError, ValueError):
            number = None  # arrays and bad values: the Parameter's own check reports them
        if number is not None and np.isfinite(number):
            self.check_value(name, number)
        super()._assign(name, value)
        if self.__dict__.get("_values_complete"):
            self.check_values()

    def check_value(self, name: str, value: float) -> None:
        """Raise :class:`~flexlib.ParameterError` if ``value`` is invalid for scalar parameter ``name``."""

    def check_values(self) -> None:
        """Raise :class:`~flexlib.ParameterError` for inconsistent parameter values."""

    def _value_error(self, message: str) -> ParameterError:
        """A ParameterError naming this block (its path once it is part of a model)."""
        return ParameterError(f"{type(self).__name__} {self.path or '(unnamed)'}: {message}")

    def _value(self, name: str) -> float | None:
        """Current value of scalar parameter ``name`` (None if it has no value yet)."""
        v = self.parameter_value(name)
        return None if v is None else float(v)


class PartialSO(Component):
    """Block with a single output ``y``."""

    y = Output(unit="1", doc="Output signal")


class PartialSISO(PartialSO):
    """Block with a single input ``u`` and a single output ``y``."""

    u = Input(unit="1", doc="Input signal")


class PartialSI2SO(PartialSO):
    """Block with two inputs ``u1``, ``u2`` and a single output ``y``."""

    u1 = Input(unit="1", doc="First input signal")
    u2 = Input(unit="1", doc="Second input signal")


class PartialSVcontrol(PartialSO):
    """Controller with a set point ``u_s``, a measurement ``u_m`` and an output ``y`` (MSL SVcontrol)."""

    u_s = Input(unit="1", doc="Set point (reference) signal")
    u_m = Input(unit="1", doc="Measurement (feedback) signal")


class PartialSignalSource(PartialSO):
    """Signal source with an ``offset`` and a ``start_time`` (MSL SignalSource)."""

    offset = Parameter(0.0, unit="1", doc="Offset of the output signal")
    start_time = Parameter(0.0, unit="s", doc="Output = offset for time < start_time")
