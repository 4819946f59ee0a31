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

from flexlib import Component, Input, Output, Parameter, der, eq
from flexlib.core.options import remember_option
from flexlib.errors import ModelError, ParameterError

__all__ = [
    "INIT_TYPES",
    "PartialSI2SO",
    "PartialSISO",
    "PartialSO",
    "PartialSVcontrol",
    "PartialSignalSource",
    "check_choice",
    "check_mirrored_limit",
    "mirror_lower_limit",
    "output_state_start",
    "scalar",
]

#: Initialisation options of the continuous blocks (MSL ``Modelica.Blocks.Types.Init``: NoInit,
#: SteadyState, InitialState, InitialOutput). ``"no_init"`` writes no initial equation: the
#: model must supply the condition (``init={...}`` or ``run(steady_state=True)``).
INIT_TYPES = ("no_init", "steady_state", "initial_state", "initial_output")


def check_choice(block: Any, option: str, value: Any, choices: tuple, *, structural: bool = False) -> Any:
    """Return ``value`` if it is one of the strings ``choices``, else raise a ModelError naming the block.

    The option is remembered (:func:`flexlib.core.component.remember_option`): a later ``block.<option> = value`` is
    checked the same way, and refused if ``structural`` (the value decided the block's variables when it was built).
    """
    if not isinstance(value, str) or value not in choices:
        raise ModelError(f"{type(block).__name__}: {option}={value!r} is not one of {', '.join(map(repr, choices))}")
    remember_option(block, option, lambda v: check_choice(block, option, v, choices, structural=structural),
                    structural=structural)
    return value


def scalar(values: dict[str, Any], name: str) -> float | None:
    """Scalar parameter ``name`` from the ``values`` given to :meth:`~flexlib.Component.check` (None if absent)."""
    v = values.get(name)
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


def mirror_lower_limit(kw: dict[str, Any], upper: str, lower: str) -> bool:
    """MSL's ``lower = -upper`` default (``yMin = -yMax``, ``uMin = -uMax``): when the constructor's keywords ``kw``
    give ``upper`` but not ``lower``, set ``lower`` to ``-upper`` in ``kw`` and return True (the block then checks
    with :func:`check_mirrored_limit` that later values keep it so). A value that is not a real number is left to the
    parameter check, which names it."""
    if lower in kw or upper not in kw:
        return False
    value = kw[upper]
    if isinstance(value, bool | str):
        return False
    try:
        number = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    if not np.all(np.isfinite(number)):
        return False
    kw[lower] = -number
    return True


def check_mirrored_limit(block: Any, values: dict, upper: str, lower: str) -> None:
    """A block whose ``lower`` follows ``-upper`` (:func:`mirror_lower_limit`) refuses values that part them (a
    run-time ``upper`` alone would leave the built ``lower`` behind), naming both and how to change them."""
    hi, lo = scalar(values, upper), scalar(values, lower)
    if hi is not None and lo is not None and lo != -hi:
        raise ParameterError(f"{block.where}: {lower} was not given, so it is -{upper} (MSL's default), but {upper} = "
                             f"{hi:g} and {lower} = {lo:g}: change both together ({lower} = {-hi:g}), or build the "
                             f"block with {lower} to set it apart")


def output_state_start(block: Any) -> list:
    """The initial equations of a block whose output ``y`` is its state (``FirstOrder``, ``Integrator``), by its
    ``init_type``: ``y = y_start`` (``"initial_state"``, ``"initial_output"``), ``der(y) = 0`` (``"steady_state"``),
    none (``"no_init"``)."""
    if block.init_type == "steady_state":
        return [eq(der(block.y), 0.0, label="steady state")]
    if block.init_type in ("initial_state", "initial_output"):
        return [eq(block.y, block.y_start, label="y = y_start")]
    return []
