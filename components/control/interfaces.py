"""Partial blocks of the signal library (MSL Blocks.Interfaces).

Signals are causal: an ``Output`` is computed by its block, an ``Input`` takes the value
of the output connected to it. Signals are dimensionless (unit ``"1"``); a physical
source interprets the value in SI units.

References
----------
Modelica Standard Library 4.0, ``Modelica.Blocks.Interfaces``.
"""

from __future__ import annotations

from flexlib import Component, Input, Output, Parameter

__all__ = ["PartialSI2SO", "PartialSISO", "PartialSO", "PartialSignalSource"]


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


class PartialSignalSource(PartialSO):
    """Signal source with an ``offset`` and a ``start_time`` (MSL SignalSource)."""

    offset = Parameter(0.0, unit="1", doc="Offset of the output signal")
    start_time = Parameter(0.0, unit="s", doc="Output = offset for time < start_time")
