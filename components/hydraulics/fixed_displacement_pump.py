"""Fixed-displacement pump."""

from __future__ import annotations

from typing import Any

from ._pump import DisplacementParameters, PartialPump

__all__ = ["FixedDisplacementPump"]


class FixedDisplacementPump(DisplacementParameters, PartialPump):
    """Fixed-displacement pump driven by a speed signal or a rotational flange.

    Volume flow delivered from the suction ``port_a`` to the pressure ``port_b`` (counted at
    the suction density, i.e. the mass per revolution is ``rho(p_a) * D * 2 pi``) and shaft
    torque, with ``dp = p_b - p_a``:

    .. math::

        q = \\eta_v D \\omega - C_{leak}\\,\\Delta p, \\qquad
        \\dot m = \\rho(p_a)\\, q, \\qquad \\tau = \\frac{D\\,\\Delta p}{\\eta_m}

    ``eta_v`` is a constant volumetric efficiency (flow loss proportional to speed) and
    ``C_leak`` a laminar leakage coefficient (loss proportional to pressure, Hopsan's
    ``C_q,leak``); use either or both. The laws hold for pumping (``w >= 0``, ``dp >= 0``);
    efficiencies are not inverted in motoring quadrants.

    Notes
    -----
    ``D``, ``eta_v`` and ``eta_m`` must be > 0 (checked at construction, at flatten and for run-time
    ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Fixed-Displacement Pump (IL)* block documentation.
    Hopsan component library, *Fixed Displacement Pump* (``HydraulicFixedDisplacementPump``).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §6.2 (pump and motor equations).
    """

    def displacement(self) -> Any:
        return self.D
