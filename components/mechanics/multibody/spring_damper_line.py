"""Linear spring and damper in parallel along the line between two frames (MSL ``SpringDamperParallel``)."""

from __future__ import annotations

from flexlib import Parameter, Variable, der, eq

from .line_force_base import LineForceBase

__all__ = ["SpringDamperLine"]


class SpringDamperLine(LineForceBase):
    """Massless linear spring and damper in parallel between the origins of frame_a and frame_b.

    ``f = c·(length − s_unstretched) + d·der(length)`` is the tension (positive pulls the frames
    together); frame_a receives ``+e_rel_0·f``, frame_b ``−e_rel_0·f``, no torques. Equivalent to a
    :class:`~.line_force.LineForce` with a translational ``SpringDamper`` between its flanges. The length is
    regularised below ``s_small`` (see :class:`~.line_force_base.LineForceBase`).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.Forces.SpringDamperParallel``.
    """

    c = Parameter(unit="N/m", min=0.0, doc="Spring constant")
    d = Parameter(0.0, unit="N.s/m", min=0.0, doc="Damping constant")
    s_unstretched = Parameter(0.0, unit="m", min=0.0, doc="Unstretched spring length")
    f = Variable(unit="N", doc="Tension (positive pulls the frames together)")

    def equations(self) -> list:
        return [*super().equations(), *self.line_force_equations(self.f, self.f),
                eq(self.f, self.c * (self.length - self.s_unstretched) + self.d * der(self.length))]
