"""Bench tests of :class:`flexlib.models.boom.PowerUnit` against the steady states of its component laws.

References (steady state, the supply volume at rest; solved by hand as one scalar equation, ``brentq``):

* dead-headed (``port_P`` closed): the pump's delivery ``rho_T·eps(Δp)·D·w`` equals the relief valve's leakage
  ``rho_m·G_leak·Δp`` (its only outlet) with the compensator law ``eps = clamp(1 − (Δp − p_comp)/dp_reg)`` whose
  lower corner is the quadratic fillet ``(x + h)²/(4h)``, ``h = 0.025`` (Simscape *Pressure-Compensated Pump*);
  the pressure sits at the top of the regulation band, ``p_comp + dp_reg``;
* into a small orifice (half the pump's flow): ``eps`` on the linear part of the compensator law and the orifice's
  turbulent law ``m = Cd·A·sqrt(2·rho_m·Δp)`` (its laminar correction ``(1 + (p_cr/Δp)²)^(-1/4)``, ``p_cr`` of a few
  Pa, is below 1e-12 here);
* into a large orifice at low pressure: the pump's full flow ``eta_v·D·w`` (volumetric efficiency law), the pressure
  from the orifice law;
* relief valve set below the compensator: the full flow through the relief, ``Δp = p_relief + p_grad·q_relief``.

Tolerance: 1e-6 relative on the pressure rise (the brief asks 1e-3; the runs meet 1e-8), 1e-9 on the flow.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import flexlib as fl
from flexlib.components.hydraulics import Orifice
from flexlib.components.hydraulics.fluid import HLP46
from flexlib.errors import ParameterError
from flexlib.models.boom import PowerUnit

TOL = {"rtol": 1e-9, "atol": 1e-10}
P_T = HLP46.p_ref
D, W = 140e-6 / (2 * math.pi), 1500 * 2 * math.pi / 60
P_COMP, DP_REG, G_LEAK, CD = 32e6, 1e6, 1e-14, 0.64


class Bench(fl.Model):
    """A power unit, its supply port closed or discharging through an orifice of area ``A`` to its tank port."""

    def __init__(self, A: float | None, **unit) -> None:
        super().__init__()
        self.unit = PowerUnit(**unit)
        if A is not None:
            self.load = Orifice(A=A)
            self.connect(self.unit.port_P, self.load.port_a)
            self.connect(self.load.port_b, self.unit.port_T)


def run(model: fl.Model, t_end: float) -> fl.Result:
    return fl.Simulation(model, use_cache=False).run(t_end, dt_out=t_end / 20, **TOL)


def rho(p: float) -> float:
    return float(HLP46.density(p))


def eps(dp: float) -> float:
    """The compensator law with its rounded corners (smoothing 0.05 of dp_reg: fillet half-width h = 0.025)."""
    h = 0.025

    def ramp(x: float) -> float:
        return 0.0 if x <= -h else x if x >= h else (x + h) ** 2 / (4 * h)

    x = 1.0 - (dp - P_COMP) / DP_REG
    return ramp(x) - ramp(x - 1.0)


def relief_flow(dp: float, p_crack: float = 35e6, p_grad: float = 1e10) -> float:
    """Mass flow of the relief valve (straight part of its law, or closed: leakage only)."""
    return rho(P_T + dp / 2) * (G_LEAK * dp + max(dp - p_crack, 0.0) / p_grad)


def orifice_flow(dp: float, A: float) -> float:
    return CD * A * math.sqrt(2 * rho(P_T + dp / 2) * dp)


def test_dead_headed_pressure_at_top_of_band():
    res = run(Bench(None), 0.2)
    exact = brentq(lambda dp: rho(P_T) * eps(dp) * D * W - relief_flow(dp), P_COMP, P_COMP + 2 * DP_REG, xtol=1e-6)
    assert abs(exact - (P_COMP + DP_REG)) < 0.03 * DP_REG  # the top of the band, within the fillet
    dp = res["unit.pump.dp"][-1]
    assert abs(dp / exact - 1) < 1e-6, (dp, exact)
    assert res["unit.supply.p"][-1] < P_T + 35e6  # below the relief setting


def test_small_orifice_in_regulation_band():
    A = 0.5 * D * W / (CD * math.sqrt(2 * P_COMP / 860.0))  # about half the pump's flow at p_comp
    res = run(Bench(A), 0.2)
    exact = brentq(lambda dp: rho(P_T) * eps(dp) * D * W - relief_flow(dp) - orifice_flow(dp, A),
                   P_COMP, P_COMP + DP_REG, xtol=1e-6)
    assert 0.3 < eps(exact) < 0.7  # on the linear part of the law
    assert abs(res["unit.pump.dp"][-1] / exact - 1) < 1e-6


def test_low_pressure_full_flow():
    eta_v, A = 0.95, 2e-4
    res = run(Bench(A, eta_v=eta_v), 0.2)
    q = eta_v * D * W  # full displacement below p_comp
    exact = brentq(lambda dp: rho(P_T) * q - relief_flow(dp) - orifice_flow(dp, A), 1e3, P_COMP, xtol=1e-6)
    assert exact < 0.5 * P_COMP
    assert abs(res["unit.pump.q"][-1] / q - 1) < 1e-9
    assert abs(res["unit.pump.dp"][-1] / exact - 1) < 1e-6
    assert abs(res["unit.supply.p"][-1] - P_T - exact) < 1e-6 * exact


def test_relief_below_compensator_caps_pressure():
    p_relief, p_grad = 15e6, 1e9
    res = run(Bench(None, p_relief=p_relief, p_grad=p_grad), 0.5)
    exact = brentq(lambda dp: rho(P_T) * D * W - relief_flow(dp, p_relief, p_grad), p_relief, P_COMP, xtol=1e-6)
    assert exact == pytest.approx(p_relief + p_grad * D * W, rel=1e-2)  # 150 bar + 35 bar over the setting
    assert abs(res["unit.pump.dp"][-1] / exact - 1) < 1e-6, (res["unit.pump.dp"][-1], exact)
    assert np.all(res["unit.pump.eps"][1:] > 0.999)  # full stroke once the start pressure (p_comp + dp_reg) is relieved


@pytest.mark.parametrize(("arg", "value"), [("D", -1.0), ("speed", 0.0), ("p_comp", float("nan")),
                                            ("eta_v", 1.5), ("V_supply", "5 L"), ("p_grad", -1e10)])
def test_bad_arguments_name_part_and_argument(arg, value):
    with pytest.raises(ParameterError, match=rf"PowerUnit: {arg} must"):
        PowerUnit(**{arg: value})
