"""Continuous, continuously differentiable switching functions (private helper).

Valve characteristics have corners (cracking, full opening). Writing them with ``max`` /
``min`` puts a kink into the residual, and :func:`flexlib.if_else` would make every corner a
state event. Here each corner is rounded by a quadratic fillet of half-width ``h`` centred on
the corner (evaluated with :func:`flexlib.no_event`): the functions are exact outside the
fillets, C1 everywhere and create no events. This is the corner smoothing of Simscape
Fluids' valve blocks (*Smoothing factor*), written with explicit fillets.
"""

from __future__ import annotations

from typing import Any

import casadi as ca

from flexlib import no_event

__all__ = ["smooth_clamp", "smooth_ramp"]


def smooth_ramp(x: Any, h: Any) -> Any:
    """``max(x, 0)`` with the corner rounded on ``[-h, h]``: ``(x + h)**2 / (4 h)`` there."""
    h = ca.fmax(h, 1e-12)  # h = 0: plain corner (the fillet branch is never selected)
    fillet = (x + h) ** 2 / (4.0 * h)
    return no_event(x <= -h, 0.0, no_event(x >= h, x, fillet))


def smooth_clamp(x: Any, lo: Any, hi: Any, h: Any) -> Any:
    """``min(max(x, lo), hi)`` with both corners rounded (exact if ``hi - lo >= 2 h``)."""
    return lo + smooth_ramp(x - lo, h) - smooth_ramp(x - hi, h)
