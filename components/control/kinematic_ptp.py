"""Point-to-point move as fast as the velocity and acceleration limits allow (its acceleration)."""

from __future__ import annotations

import casadi as ca

from flexlib import Parameter, ParameterError, eq, if_else, time

from .interfaces import PartialSO, scalar

__all__ = ["KinematicPTP"]


class KinematicPTP(PartialSO):
    """The acceleration ``y = q̈`` of the fastest move over ``delta_q`` within ``|q̇| ≤ qd_max``, ``|q̈| ≤ qdd_max``.

    Integrated twice (e.g. two :class:`~.integrator.Integrator`) it moves ``q`` by ``delta_q`` from ``start_time``:
    constant acceleration ``qdd_max`` for ``T_a``, a cruise at ``qd_max`` if the move is long enough to reach it, and
    the mirrored deceleration, ending at rest at ``start_time + T_e``::

        T_a1 = sqrt(|delta_q| / qdd_max),   T_a2 = qd_max / qdd_max
        T_a2 >= T_a1 (no cruise):  accelerate for T_a1, decelerate for T_a1, T_e = 2 T_a1
        otherwise:                 accelerate for T_a2, cruise until T_v = |delta_q| / qd_max, T_e = T_v + T_a2

    The switching instants are time events.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.KinematicPTP`` (one distance; MSL's vector form
    synchronises several distances on the slowest).
    """

    delta_q = Parameter(1.0, unit="1", doc="Distance to move")
    qd_max = Parameter(1.0, unit="1", gt=0.0, doc="Maximum speed der(q)")
    qdd_max = Parameter(1.0, unit="1", gt=0.0, doc="Maximum acceleration der(qd)")
    start_time = Parameter(0.0, unit="s", doc="Time instant at which the move starts")

    def check(self, values: dict) -> None:
        if scalar(values, "delta_q") == 0.0:
            raise ParameterError(f"{self.param_label('delta_q')} = 0: the distance to move must be nonzero")

    def equations(self) -> list:
        dist = ca.fabs(self.delta_q)
        sd_max, sdd_max = self.qd_max / dist, self.qdd_max / dist  # path speed and acceleration limits [1/s, 1/s2]
        t_a1, t_a2 = ca.sqrt(1.0 / sdd_max), sd_max / sdd_max
        # no cruise (t_a2 >= t_a1): accelerate for t_a1, brake from t_v = t_a1; else accelerate for t_a2 and brake
        # from t_v = 1/sd_max (> t_a1 exactly then): both are min and max, so no relation of parameters is needed
        t_acc, t_v = ca.fmin(t_a1, t_a2), ca.fmax(t_a1, 1.0 / sd_max)
        t0 = self.start_time
        sdd = if_else(time < t0, 0.0,
                      if_else(time < t_acc + t0, sdd_max,
                              if_else(time < t_v + t0, 0.0, if_else(time < t_v + t_acc + t0, -sdd_max, 0.0))))
        return [eq(self.y, self.delta_q * sdd)]
