"""Tare: the input re-zeroed at the start of the run."""

from __future__ import annotations

from flexlib import Parameter, Variable, der, eq

from .interfaces import PartialSISO

__all__ = ["Tare"]


class Tare(PartialSISO):
    """Tare: ``y = u − u(t₀) + y_start``, the input re-zeroed at the start to ``y_start``.

    What a transducer zeroed on the machine reports: a measurement taken relative to its value when the run
    starts, offset to a known reading. The start value ``u(t₀)`` is held by the state ``u0`` with
    ``der(u0) = 0`` and the initial equation ``u0 = u``, so the start may be computed by the initialisation (a
    deflected structure at rest, say) and still read ``y_start``.

    Connectors
    ----------
    y : Output [1]
        ``u − u0 + y_start``.

    References
    ----------
    The tare function of measurement amplifiers (zero balance), e.g. HBM QuantumX, "Zero balance / tare".
    Modelica Standard Library 4.0 has no single block for it: ``Modelica.Blocks.Discrete.TriggeredSampler``
    triggered once at the start, then ``Modelica.Blocks.Math.Add`` (``u − u0``) and an offset.
    """

    y_start = Parameter(0.0, unit="1", doc="Output at the start (in the unit of the signal)")
    u0 = Variable(unit="1", doc="Input at the start, held")

    def initial_equations(self) -> list:
        return [eq(self.u0, self.u, label="u0 = u at the start")]

    def equations(self) -> list:
        return [eq(der(self.u0), 0.0), eq(self.y, self.u - self.u0 + self.y_start)]
