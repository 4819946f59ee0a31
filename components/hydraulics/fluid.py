"""Hydraulic fluid property record (the ``Medium`` of the hydraulics library).

A :class:`Fluid` is a structural choice, like a Modelica ``Medium`` package: its numbers
enter the equations as constants, so changing the fluid changes the model (and its cache
key); component parameters stay run-time tunable.

Density follows from a bulk modulus that is constant for the pure liquid,
``beta = rho * dp/drho``, so ``rho_liq(p) = rho_ref * exp((p - p_ref) / beta)``.
Entrained (undissolved) air adds a gas volume fraction ``x_air`` at ``p_ref`` that is
compressed polytropically, ``V_air(p) = V_air_ref * (p_ref / p)^(1/n)``. The mixture
density and its effective bulk modulus ``beta_eff = rho / (d rho/dp)`` are then

    rho(p)      = m / (V_liq(p) + V_air(p))     per unit mass, with
    V_liq/m     = (1 - x_air) / rho_ref * exp(-(p - p_ref) / beta)
    V_air/m     = x_air / rho_ref * (p_ref / p)^(1/n)

(air mass neglected), which is the model of Simscape Fluids' isothermal liquid with
entrained air and of Merritt (1967), *Hydraulic Control Systems*, §2.3. With ``x_air = 0``
the pure-liquid law is recovered and ``beta_eff = beta``.

References
----------
H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §2.3 (effective bulk modulus).
MathWorks Simscape Fluids, *Isothermal Liquid Properties (IL)* block documentation.
"""

from __future__ import annotations

import difflib
import functools
import math
from dataclasses import dataclass
from typing import Any

import casadi as ca

from flexlib.core.values import not_a_scalar
from flexlib.errors import ParameterError

__all__ = ["HLP46", "Fluid"]

#: The numeric fields of :class:`Fluid` and their units (each checked when a record is made)
_UNITS = {"rho_ref": "kg/m3", "p_ref": "Pa", "beta": "Pa", "nu": "m2/s", "x_air": "1", "n_air": "1", "p_min": "Pa"}


@dataclass(frozen=True)
class Fluid:
    """Properties of a hydraulic liquid, optionally with entrained air.

    Parameters
    ----------
    name : str
        Name used in reports.
    rho_ref : float
        Density of the liquid at ``p_ref`` [kg/m3], > 0. Every numeric field must be a finite real number (not a
        string, a bool or an array); a bad one raises :class:`~flexlib.ParameterError` naming the field.
    p_ref : float
        Reference (atmospheric) absolute pressure [Pa], > 0.
    beta : float
        Isothermal bulk modulus of the pure liquid [Pa], > 0.
    nu : float
        Kinematic viscosity [m2/s], > 0.
    x_air : float
        Volume fraction of entrained air at ``p_ref`` [1], 0 <= x_air < 1.
    n_air : float
        Polytropic exponent of the air [1] (1 = isothermal, 1.4 = adiabatic).
    p_min : float
        Lowest absolute pressure the property laws are evaluated at [Pa]; below it the
        air law is clamped so that a cavitating volume does not divide by zero.
    """

    name: str = "HLP46"
    rho_ref: float = 870.0
    p_ref: float = 1.01325e5
    beta: float = 1.6e9
    nu: float = 46e-6
    x_air: float = 0.0
    n_air: float = 1.0
    p_min: float = 1e3

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise ParameterError(f"Fluid: name must be a string, got {self.name!r}")
        for field, unit in _UNITS.items():
            value = getattr(self, field)
            label = f"Fluid {self.name!r}: {field}"
            why = not_a_scalar(value)
            if why is not None:
                raise ParameterError(f"{label} must be a real number [{unit}], got {value!r} ({why})")
            v = float(value)
            if not math.isfinite(v):
                raise ParameterError(f"{label} must be finite, got {value!r} [{unit}]")
            if field == "x_air":
                if not 0.0 <= v < 1.0:
                    raise ParameterError(f"{label} must be in [0, 1), got {value!r} [{unit}]")
            elif not v > 0:
                raise ParameterError(f"{label} must be > 0, got {value!r} [{unit}]")
            object.__setattr__(self, field, v)  # a plain float: numpy scalars would leak into the equations

    @property
    def mu(self) -> float:
        """Dynamic viscosity at ``p_ref`` [Pa.s]."""
        return self.nu * self.rho_ref

    def specific_volume(self, p: Any) -> Any:
        """Specific volume ``1/rho`` of the mixture at absolute pressure ``p`` [m3/kg]."""
        v_liq = (1.0 - self.x_air) / self.rho_ref * ca.exp(-(p - self.p_ref) / self.beta)
        if self.x_air == 0.0:
            return v_liq
        p_c = ca.fmax(p, self.p_min)
        return v_liq + self.x_air / self.rho_ref * (self.p_ref / p_c) ** (1.0 / self.n_air)

    def density(self, p: Any) -> Any:
        """Density of the mixture at absolute pressure ``p`` [kg/m3] (CasADi or float)."""
        return 1.0 / self.specific_volume(p)

    @property
    def p_zero(self) -> float:
        """Reference pressure of the chambers' mass deviation [Pa]: 0 (absolute) for the pure liquid, ``p_min``
        with entrained air (whose density vanishes at 0 Pa); see :func:`~.interfaces.chamber_equations`."""
        return 0.0 if self.x_air == 0.0 else self.p_min

    def density_deviation(self, p: Any, p0: Any = None) -> Any:
        """``rho(p) - rho(p0)`` [kg/m3] computed without cancellation (``expm1``); ``p0`` defaults to ``p_ref``.

        The difference is small (``rho·(p − p0)/beta``: 5 kg/m3 for 100 bar) and forming it as
        ``rho(p) − rho(p0)`` would lose four to five digits; the chamber mass balance
        (:func:`~.interfaces.chamber_equations`) is written in deviations to keep them. With the specific
        volume ``v = 1/rho`` of the mixture (module docstring)::

            rho(p) − rho(p0) = (v(p0) − v(p)) / (v(p)·v(p0)),
            v(p0) − v(p) = −(1 − x_air)/rho_ref·e^(−u0)·expm1(−(p − p0)/beta)
                           − x_air/rho_ref·(p_ref/p0)^(1/n)·expm1(ln(p0/p)/n),   u0 = (p0 − p_ref)/beta
        """
        p0 = self.p_ref if p0 is None else p0
        dp = p - p0
        if self.x_air == 0.0:
            return self.rho_ref * ca.exp((p0 - self.p_ref) / self.beta) * ca.expm1(dp / self.beta)
        p_c, p0_c = ca.fmax(p, self.p_min), ca.fmax(p0, self.p_min)
        dv = (-(1.0 - self.x_air) * ca.exp(-(p0 - self.p_ref) / self.beta) * ca.expm1(-dp / self.beta)
              - self.x_air * (self.p_ref / p0_c) ** (1.0 / self.n_air) * ca.expm1(ca.log(p0_c / p_c) / self.n_air)) \
            / self.rho_ref
        return dv / (self.specific_volume(p) * self.specific_volume(p0))

    def bulk_modulus(self, p: Any) -> Any:
        """Effective bulk modulus ``rho / (d rho / dp)`` at absolute pressure ``p`` [Pa]."""
        v_liq = (1.0 - self.x_air) / self.rho_ref * ca.exp(-(p - self.p_ref) / self.beta)
        dv_dp = -v_liq / self.beta
        v = v_liq
        if self.x_air != 0.0:
            p_c = ca.fmax(p, self.p_min)
            v_air = self.x_air / self.rho_ref * (self.p_ref / p_c) ** (1.0 / self.n_air)
            v = v + v_air
            dv_dp = dv_dp - v_air / (self.n_air * p_c)
        return -v / dv_dp


#: HLP46-like mineral oil at 40 °C, no entrained air (ISO VG 46: nu = 46 mm2/s at 40 °C).
_dataclass_init = Fluid.__init__


@functools.wraps(_dataclass_init)
def _checked_init(self: Fluid, *args: Any, **kwargs: Any) -> None:
    """The dataclass constructor, with a misspelt field named (``Fluid(bulk=1e9)``, also through
    ``dataclasses.replace``) instead of Python's TypeError."""
    fields = ["name", *_UNITS]
    for key in kwargs:
        if key not in fields:
            close = difflib.get_close_matches(key, fields, n=2)
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            raise ParameterError(f"Fluid: unknown field {key!r}{hint} (fields: {', '.join(fields)})")
    if len(args) > len(fields):
        raise ParameterError(f"Fluid: {len(args)} positional values for {len(fields)} fields ({', '.join(fields)})")
    _dataclass_init(self, *args, **kwargs)


Fluid.__init__ = _checked_init  # type: ignore[method-assign]

HLP46 = Fluid()
