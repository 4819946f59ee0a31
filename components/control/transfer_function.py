"""Linear single-input single-output transfer function."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Parameter, Variable, der, eq, no_event
from flexlib.core.values import numeric_array
from flexlib.errors import ParameterError

from .interfaces import INIT_TYPES, PartialSISO, check_choice

__all__ = ["TransferFunction"]


class TransferFunction(PartialSISO):
    """Transfer function ``y = b(s)/a(s) u`` in controller canonical form.

    .. math::

        y = \\frac{b_0 s^{n_b-1} + \\dots + b_{n_b-1}}{a_0 s^{n_a-1} + \\dots + a_{n_a-1}} u

    With ``nx = len(a) - 1`` states ``x`` (scaled internally by ``a_end = a[-1]`` as MSL does:
    ``x_scaled = a_end * x``): ``a[0] der(x_scaled[0]) = -a[1:] . x_scaled + a_end u``,
    ``der(x_scaled[i]) = x_scaled[i-1]``, ``y = (bb[1:] - d a[1:]) . x_scaled / a_end + d u``
    with ``bb`` = ``b`` padded with leading zeros to the length of ``a`` and ``d = bb[0]/a[0]``.

    Parameters
    ----------
    b : array_like
        Numerator coefficients, highest power of ``s`` first (``2 s + 3`` is ``[2, 3]``) [1];
        ``len(b) <= len(a)`` (proper).
    a : array_like
        Denominator coefficients, highest power first [1]; ``a[0] != 0``.
    x_start : array_like
        Initial states ``x`` (``init_type="initial_state"``), default zeros [1].
    init_type : str
        ``"initial_state"`` (default): ``x = x_start``; ``"steady_state"``: ``der(x) = 0``;
        ``"initial_output"``: ``y = y_start`` and ``der(x[1:]) = 0``; ``"no_init"``: none.

    Variables
    ---------
    x : 1
        States of the controller canonical form, ``x[-1]`` the lowest derivative.
    x_scaled : 1
        ``a_end * x``, the integrated states.

    Notes
    -----
    ``b`` and ``a`` are parameters (tunable at run time, ``params={"tf.a": [...]}``); their
    lengths are structural. MSL's default ``initType`` is NoInit (tools then use ``x_start``);
    here it is ``"initial_state"``, the same start. ``len(a) == 1`` is a static gain.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Continuous.TransferFunction``.
    """

    y_start = Parameter(0.0, unit="1", doc='Initial value of the output (init_type ``"initial_output"``)')

    def __init__(self, b: Any = (1.0,), a: Any = (1.0,), x_start: Any = None,
                 init_type: str = "initial_state", init: dict | None = None, guess: dict | None = None,
                 state_select: dict | None = None, **kw: Any) -> None:
        super().__init__(**kw)  # x is declared below, so init/guess/state_select on it are applied afterwards
        name = type(self).__name__
        b, a = (np.atleast_1d(numeric_array(v, f"{name}: {k}", "a vector of real numbers (highest power of s first)",
                                            ParameterError)) for k, v in (("b", b), ("a", a)))
        if b.ndim != 1 or a.ndim != 1 or len(b) == 0 or len(a) == 0:
            raise ParameterError(f"{name}: b and a must be non-empty vectors, got {b!r} and {a!r}")
        if len(b) > len(a):
            raise ParameterError(f"{name}: transfer function is not proper: len(b) = {len(b)} > len(a) = {len(a)}")
        self.init_type = check_choice(self, "init_type", init_type, INIT_TYPES)
        self.nx = len(a) - 1
        self.b = Parameter(unit="1", shape=len(b), doc="Numerator coefficients, highest power of s first")
        self.a = Parameter(unit="1", shape=len(a), doc="Denominator coefficients, highest power of s first")
        self.b, self.a = b, a
        if self.nx:
            self.x_start = Parameter(unit="1", shape=self.nx, doc="Initial states x")
            self.x_start = np.zeros(self.nx) if x_start is None else x_start
            self.x = Variable(unit="1", shape=self.nx, doc="States in controller canonical form")
            self.x_scaled = Variable(unit="1", shape=self.nx, state_select="prefer", doc="Scaled states a_end * x")
        elif x_start is not None and np.size(x_start):
            raise ParameterError(f"{name}: x_start given, but a static gain (len(a) = 1) has no states")
        for arg, fixed, starts in (("init", True, init), ("guess", False, guess), ("state_select", None, state_select)):
            if starts is not None and not isinstance(starts, dict):
                raise ParameterError(f"{name}: {arg} must be a dict {{'variable': value}}, got {type(starts).__name__} "
                                     f"{starts!r}")
            for var, value in (starts or {}).items():
                if fixed is None:
                    self.set_state_select(var, value)
                else:
                    self.set_start(var, value, fixed=fixed)

    def check(self, values: dict) -> None:
        a = values.get("a")
        if a is not None and np.ravel(a)[0] == 0.0:
            raise ParameterError(f"{self.where}: leading denominator coefficient a[0] must be != 0, "
                                 f"got a = {np.ravel(a).tolist()}")

    def _scaling(self) -> tuple[ca.SX, ca.SX, ca.SX]:
        """``bb`` (b padded to the length of a), ``d = bb[0]/a[0]`` and ``a_end`` (MSL)."""
        a = self.a
        bb = ca.vertcat(ca.SX.zeros(a.numel() - self.b.numel()), self.b)
        a_end = no_event(a[-1] > 100 * np.finfo(float).eps * ca.norm_2(a), a[-1], 1.0)
        return bb, bb[0] / a[0], a_end

    def initial_equations(self) -> list:
        if not self.nx:
            return []
        _, _, a_end = self._scaling()
        xs = self.x_scaled
        if self.init_type == "steady_state":
            return [eq(der(xs), 0.0, label="steady state")]
        if self.init_type == "initial_state":
            return [eq(xs, self.x_start * a_end, label="x = x_start")]
        if self.init_type == "initial_output":
            out = [eq(self.y, self.y_start, label="y = y_start")]
            return out + ([eq(der(xs[1:]), 0.0, label="steady higher states")] if self.nx > 1 else [])
        return []

    def equations(self) -> list:
        bb, d, a_end = self._scaling()
        if not self.nx:
            return [eq(self.y, d * self.u)]
        a, xs = self.a, self.x_scaled
        eqs = [eq(a[0] * der(xs[0]), -ca.dot(a[1:], xs) + a_end * self.u)]
        if self.nx > 1:
            eqs.append(eq(der(xs[1:]), xs[:-1]))
        eqs += [eq(self.y, ca.dot(bb[1:] - d * a[1:], xs) / a_end + d * self.u), eq(self.x, xs / a_end)]
        return eqs
