"""PID controller with limited output, anti-windup, set-point weighting and derivative filter."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Input, Parameter, Variable, der, eq, no_event
from flexlib.core.options import flag
from flexlib.errors import ModelError, ParameterError

from .interfaces import INIT_TYPES, PartialSVcontrol, check_choice, check_mirrored_limit, mirror_lower_limit, scalar
from .limiter import limit

__all__ = ["LimPID"]


CONTROLLER_TYPES = ("P", "PI", "PD", "PID")
SMALL = 1e-60  # Modelica.Constants.small
EPS = float(np.finfo(float).eps)


class LimPID(PartialSVcontrol):
    """P, PI, PD or PID controller with output limits and anti-windup (MSL LimPID).

    With ``e = u_s - u_m``, the block of MSL 4.0 written out (``d = 0`` without D, ``xi = 0``
    without I, ``u_ff = 0`` without feed-forward):

    .. math::

        v &= k \\, (w_p u_s - u_m + d + x_i) + k_{ff} u_{ff}, \\qquad y = \\mathrm{lim}(v) \\\\
        T_i \\dot x_i &= e + \\frac{y - v}{k N_i}
            \\qquad\\text{(integrator with anti-windup by back-calculation)} \\\\
        T_f \\dot x_d &= w_d u_s - u_m - x_d, \\qquad d = \\frac{T_d}{T_f}(w_d u_s - u_m - x_d),
            \\qquad T_f = \\max(T_d / N_d, 10^{-14})

    While ``y`` is in its limits ``v = y`` and ``xi`` integrates ``e/Ti``; in a limit the
    feedback ``(y - v)/(k Ni)`` pulls ``v`` back to the limit with the time constant
    ``Ni Ti``. ``Ni`` → ∞ switches the anti-windup off. The limits are state events
    (``strict=True``: no events).

    Parameters
    ----------
    controller_type : str
        ``"P"``, ``"PI"``, ``"PD"`` or ``"PID"`` (default).
    init_type : str
        ``"initial_state"`` (default, as MSL): ``xi = xi_start``, ``xd = xd_start``;
        ``"steady_state"``: ``der(xi) = der(xd) = 0``; ``"initial_output"`` (PI, PID):
        ``k (wp u_s - u_m + d + xi) = y_start`` and ``der(xd) = 0``; ``"no_init"``: none.
    use_feed_forward : bool
        True to add the input ``u_ff`` (times ``k_ff``) before the limiter.
    strict : bool
        True to evaluate the limiter continuously (no events).

    Connectors
    ----------
    u_s : Input [1]
        Set point.
    u_m : Input [1]
        Measurement.
    u_ff : Input [1]
        Feed-forward signal (only if ``use_feed_forward``).
    y : Output [1]
        Limited controller output.

    Notes
    -----
    Values given at construction are checked together (``Ti > 0``, ``Td >= 0``, ``k != 0``,
    ``y_max >= y_min``, ``y_start`` within the limits for ``"initial_output"``), again at flatten and
    for run-time ``params`` (:meth:`check`), naming the block.
    With ``"steady_state"`` the integrator's ``der(xi) = 0`` fixes the control error; it is singular
    when the measurement is fixed by another initial condition (see MSL's documentation).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Continuous.LimPID``; K. J. Åström,
    T. Hägglund, *PID Controllers: Theory, Design, and Tuning*, 2nd ed., ISA 1995, ch. 3.
    """

    k = Parameter(1.0, unit="1", doc="Gain of the controller, nonzero")
    Ti = Parameter(0.5, unit="s", gt=0.0, doc="Time constant of the integrator")
    Td = Parameter(0.1, unit="s", min=0.0, doc="Time constant of the derivative block")
    y_max = Parameter(unit="1", doc="Upper limit of the output")
    y_min = Parameter(unit="1", doc="Lower limit of the output, <= ``y_max`` (default ``-y_max``, as MSL's)")
    wp = Parameter(1.0, unit="1", min=0.0, doc="Set-point weight of the proportional part")
    wd = Parameter(0.0, unit="1", min=0.0, doc="Set-point weight of the derivative part")
    Ni = Parameter(0.9, unit="1", min=100 * EPS, doc="``Ni * Ti`` is the time constant of the anti-windup compensation")
    Nd = Parameter(10.0, unit="1", min=100 * EPS,
                   doc="Derivative filter: ``Td / Nd`` is its time constant (larger: more ideal)")
    k_ff = Parameter(1.0, unit="1", doc="Gain of the feed-forward input (used only with ``use_feed_forward``)")
    xi_start = Parameter(0.0, unit="1", doc='Initial integrator state ``xi`` (init_type ``"initial_state"``)')
    xd_start = Parameter(0.0, unit="1", doc='Initial derivative-filter state ``xd`` (init_type ``"initial_state"``)')
    y_start = Parameter(0.0, unit="1",
                        doc='Initial output before the limiter, ``v - k_ff u_ff`` (init_type ``"initial_output"``)')

    control_error = Variable(unit="1", doc="Control error u_s - u_m")
    xi = Variable(unit="1", state_select="prefer", doc="Integrator state (MSL ``I.y``; 0 without I)")
    xd = Variable(unit="1", state_select="prefer", doc="Derivative-filter state (MSL ``D.x``; 0 without D)")
    y_unlimited = Variable(unit="1", doc="Controller output before the limiter (MSL ``limiter.u``)")

    def __init__(self, controller_type: str = "PID", init_type: str = "initial_state",
                 use_feed_forward: bool = False, strict: bool = False, **kw: Any) -> None:
        check_choice(self, "controller_type", controller_type, CONTROLLER_TYPES)
        check_choice(self, "init_type", init_type, INIT_TYPES)
        if init_type == "initial_output" and "I" not in controller_type:
            raise ModelError(f"LimPID: init_type='initial_output' needs an integrator (PI or PID), "
                             f"not controller_type={controller_type!r}")
        # MSL's yMin = -yMax: not given, y_min follows y_max (checked for run-time values, see check)
        self._y_min_follows = mirror_lower_limit(kw, "y_max", "y_min")
        super().__init__(**kw)
        # controller_type decides the integrator and derivative states (with_I, with_D): fixed once built
        self.controller_type = check_choice(self, "controller_type", controller_type, CONTROLLER_TYPES,
                                            structural=True)
        self.init_type = check_choice(self, "init_type", init_type, INIT_TYPES)
        self.with_I, self.with_D = "I" in controller_type, "D" in controller_type
        self.use_feed_forward = flag(self, "use_feed_forward", use_feed_forward, structural=True)
        self.strict = flag(self, "strict", strict)
        if self.use_feed_forward:
            self.u_ff = Input(unit="1", doc="Feed-forward signal")

    def check(self, values: dict) -> None:
        k = scalar(values, "k")
        if k is not None and abs(k) < SMALL:
            raise ParameterError(f"{self.where}: controller gain k must be non-zero, got {k:g}")
        hi, lo, y0 = scalar(values, "y_max"), scalar(values, "y_min"), scalar(values, "y_start")
        if hi is None or lo is None:
            return
        if getattr(self, "_y_min_follows", False):
            check_mirrored_limit(self, values, "y_max", "y_min")
        if hi < lo:
            raise ParameterError(f"{self.where}: limits must be consistent (y_max >= y_min), but y_max = {hi:g} "
                                 f"< y_min = {lo:g}")
        if getattr(self, "init_type", None) == "initial_output" and y0 is not None and not lo <= y0 <= hi:
            raise ParameterError(f"{self.where}: y_start = {y0:g} is outside the limits y_min = {lo:g} and "
                                 f"y_max = {hi:g}")

    def _derivative(self) -> tuple[Any, Any]:
        """``(der(xd), d)`` of MSL's Derivative block with k = Td, T = Tf (zero gain if Td ≈ 0)."""
        ud = self.wd * self.u_s - self.u_m
        Tf = ca.fmax(self.Td / self.Nd, 1e-14)
        active = ca.fabs(self.Td) >= EPS  # parameters only: no event
        return no_event(active, (ud - self.xd) / Tf, 0.0), no_event(active, self.Td / Tf * (ud - self.xd), 0.0)

    def initial_equations(self) -> list:
        init = self.init_type
        out = []
        if init == "steady_state":
            out += [eq(der(self.xi), 0.0, label="steady integrator")] if self.with_I else []
            out += [eq(der(self.xd), 0.0, label="steady derivative")] if self.with_D else []
        elif init == "initial_state":
            out += [eq(self.xi, self.xi_start, label="xi = xi_start")] if self.with_I else []
            out += [eq(self.xd, self.xd_start, label="xd = xd_start")] if self.with_D else []
        elif init == "initial_output":
            out.append(eq(self.y_unlimited - self._feed_forward(), self.y_start, label="output = y_start"))
            out += [eq(der(self.xd), 0.0, label="steady derivative")] if self.with_D else []
        return out

    def _feed_forward(self) -> Any:
        return self.k_ff * self.u_ff if self.use_feed_forward else 0.0

    def equations(self) -> list:
        e = self.u_s - self.u_m
        eqs = [eq(self.control_error, e)]
        if self.with_D:
            rate, d = self._derivative()
            eqs.append(eq(der(self.xd), rate))
        else:
            d = 0.0
            eqs.append(eq(self.xd, 0.0))
        v = self.y_unlimited
        eqs += [eq(v, self.k * (self.wp * self.u_s - self.u_m + d + self.xi) + self._feed_forward()),
                eq(self.y, limit(v, self.y_max, self.y_min, self.strict))]
        if self.with_I:
            eqs.append(eq(self.Ti * der(self.xi), e + (self.y - v) / (self.k * self.Ni)))
        else:
            eqs.append(eq(self.xi, 0.0))
        return eqs
