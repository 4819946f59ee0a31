"""Bench tests of :class:`flexlib.models.boom.SlewDrive`: supply 300 bar, tank, a turret inertia on the flange.

References:

* full command, pure inertia: the compensated meter-in edge passes the valve's rating ``Q_nom`` (the supply exceeds
  the load pressure by more than ``dp_nom``), the motor turns at ``Q_nom/D`` and the turret at ``Q_nom/(D·ratio)``
  (Merritt §6, ``q = D ω``). Tolerance 1e-2 (the brief's): the rating is a volume flow at the reference density,
  the motor counts it at its inlet pressure (``Δp/β`` ≈ 0.2 %); measured after 10 s (settled from 8 s on): +3.0e-3.
* holding with ``u = 0`` against a load torque ``τ`` on the turret (a slope, the wind): the closed centre traps
  the oil; the turret swings on the oil spring, ``k = ratio²·D²·β·(1/V_a + 1/V_b)`` about the turret axis, from
  rest: its angle stays within ``2τ/k`` (the undamped swing's peak; 5 % for the pressure dependence of the
  density; measured 1.015), the mean motor pressure difference is the holding pressure ``τ/(ratio·D)`` (5 %;
  measured 0.2 %). The swing takes the unloaded line to −83 bar absolute: the pure liquid does not cavitate and the
  drive has no make-up valves (nor a slewing brake) — as the slew drive of ``models/pump_truck/model.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.hydraulics import PressureSource, Tank
from flexlib.components.hydraulics.fluid import HLP46
from flexlib.components.mechanics import rotational
from flexlib.errors import ParameterError
from flexlib.models.boom import SlewDrive

D, RATIO, Q_NOM, V_HOSE, J_TURRET = 50e-6 / (2 * math.pi), 300.0, 25.0 / 60000, 1e-3, 5e4
TOL = {"rtol": 1e-8, "atol": 1e-10}


class Bench(fl.Model):
    """Slew drive on a 300 bar supply, a turret inertia on its flange, a constant command and load torque."""

    def __init__(self, u: float, tau: float) -> None:
        super().__init__()
        self.supply, self.tank = PressureSource(p=HLP46.p_ref + 300e5), Tank()
        self.drive = SlewDrive()
        self.turret = rotational.Inertia(J=J_TURRET, init={"phi": 0.0, "w": 0.0})
        self.load = rotational.Torque()
        self.command, self.torque = Constant(k=u), Constant(k=tau)
        for a, b in ((self.supply.port, self.drive.port_P), (self.tank.port, self.drive.port_T),
                     (self.drive.flange, self.turret.flange_a), (self.turret.flange_b, self.load.flange),
                     (self.command.y, self.drive.u), (self.torque.y, self.load.tau)):
            self.connect(a, b)


def test_full_command_speed():
    res = fl.Simulation(Bench(1.0, 0.0), use_cache=False).run(10.0, dt_out=0.05, **TOL)
    w_motor = Q_NOM / D
    assert abs(res["drive.motor.w"][-1] / w_motor - 1) < 1e-2
    assert abs(res["turret.w"][-1] / (w_motor / RATIO) - 1) < 1e-2
    assert abs(res["turret.a"][-1]) < 1e-3 * w_motor / RATIO  # steady


def test_holding_with_zero_command():
    """A torque step on the held turret: the line it pressurises is the oil spring ``k = ratio²·D²·β/V`` (the
    other line's make-up valve holds it at tank pressure instead of letting it go below vacuum), so the turret
    swings up to twice the static ``tau/k`` (undamped step response), and every line stays above 0 bar absolute."""
    tau = 2e4
    res = fl.Simulation(Bench(0.0, tau), use_cache=False).run(20.0, dt_out=0.01, **TOL)
    k = RATIO**2 * D**2 * HLP46.beta / V_HOSE
    phi = res["turret.phi"]
    assert np.max(np.abs(phi)) < 2 * tau / k * 1.05
    assert np.max(np.abs(phi)) > 2 * tau / k * 0.9  # it does swing on the oil spring
    assert min(res["drive.line_a.p"].min(), res["drive.line_b.p"].min()) > 0.0
    dp_hold = tau / (RATIO * D)
    dp = res["drive.motor.dp"]
    assert abs(np.mean(dp) - np.sign(np.mean(dp)) * dp_hold) < 0.05 * dp_hold


@pytest.mark.parametrize(("arg", "value"), [("D", 0.0), ("ratio", -300.0), ("Q_nom", float("nan")),
                                            ("J_rotor", "0.02"), ("V_hose", -1e-3), ("f_spool", 0.0)])
def test_bad_arguments(arg, value):
    with pytest.raises(ParameterError, match=rf"SlewDrive: {arg} must"):
        SlewDrive(**{arg: value})
