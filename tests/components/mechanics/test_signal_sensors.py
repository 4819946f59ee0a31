"""Tests of the acceleration and relative-speed sensors of the 1D libraries (MSL
``Translational.Sensors.AccSensor``/``RelSpeedSensor``, ``Rotational.Sensors.AccSensor``/``RelSpeedSensor``).

Reference: two free bodies coupled by a spring, released with the spring stretched by x0. The
stretch oscillates as x0 cos(ω t), ω² = c (1/m1 + 1/m2); body 1 accelerates with c x/m1, body 2
with −c x/m2, and the relative speed is −x0 ω sin(ω t) (Meirovitch, *Elements of Vibration
Analysis*, §3.2, semi-definite system). Runs at rtol = 1e-8, atol = 1e-10; tolerance 1e-6 of each
quantity's amplitude. The sensors must not load the flanges (their flange flows are zero).
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.mechanics import rotational as rot
from flexlib.components.mechanics import translational as tr

TOL = {"rtol": 1e-8, "atol": 1e-10}
X0 = 0.05


class TwoMasses(fl.Model):
    """mass1 -- spring -- mass2, with acceleration sensors on both and a relative-speed sensor."""

    def __init__(self, m1: float, m2: float, c: float) -> None:
        super().__init__()
        self.mass1 = tr.Mass(m=m1, init={"s": 0.0, "v": 0.0})
        self.mass2 = tr.Mass(m=m2, init={"s": X0, "v": 0.0})
        self.spring = tr.Spring(c=c)
        self.acc1 = tr.AccSensor()
        self.acc2 = tr.AccSensor()
        self.rel = tr.RelativeSpeedSensor()
        self.connect(self.mass1.flange_b, self.spring.flange_a, self.acc1.flange, self.rel.flange_a)
        self.connect(self.spring.flange_b, self.mass2.flange_a, self.acc2.flange, self.rel.flange_b)


class TwoInertias(fl.Model):
    """inertia1 -- spring -- inertia2, with the rotational sensors."""

    def __init__(self, J1: float, J2: float, c: float) -> None:
        super().__init__()
        self.inertia1 = rot.Inertia(J=J1, init={"phi": 0.0, "w": 0.0})
        self.inertia2 = rot.Inertia(J=J2, init={"phi": X0, "w": 0.0})
        self.spring = rot.Spring(c=c)
        self.acc1 = rot.AccSensor()
        self.acc2 = rot.AccSensor()
        self.rel = rot.RelativeSpeedSensor()
        self.connect(self.inertia1.flange_b, self.spring.flange_a, self.acc1.flange, self.rel.flange_a)
        self.connect(self.spring.flange_b, self.inertia2.flange_a, self.acc2.flange, self.rel.flange_b)


def reference(t: np.ndarray, m1: float, m2: float, c: float) -> tuple[np.ndarray, ...]:
    omega = np.sqrt(c * (1.0 / m1 + 1.0 / m2))
    x = X0 * np.cos(omega * t)
    return c * x / m1, -c * x / m2, -X0 * omega * np.sin(omega * t), x, omega


def test_translational_acc_and_relative_speed_sensors():
    """a1 = c x/m1, a2 = −c x/m2, v_rel = −x0 ω sin ωt, s_rel = x; tolerance 1e-6 of the amplitudes."""
    m1, m2, c = 1.0, 3.0, 300.0
    res = fl.Simulation(TwoMasses(m1, m2, c), use_cache=False).run(1.0, dt_out=0.01, **TOL)
    a1, a2, v_rel, x, omega = reference(res.t, m1, m2, c)
    np.testing.assert_allclose(res["acc1.a"], a1, rtol=0, atol=1e-6 * c * X0 / m1)
    np.testing.assert_allclose(res["acc2.a"], a2, rtol=0, atol=1e-6 * c * X0 / m1)
    np.testing.assert_allclose(res["acc1.v"], res["mass1.v"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["rel.v_rel"], v_rel, rtol=0, atol=1e-6 * X0 * omega)
    np.testing.assert_allclose(res["rel.s_rel"], x, rtol=0, atol=1e-6 * X0)
    for flow in ("acc1.flange.f", "acc2.flange.f", "rel.flange_a.f", "rel.flange_b.f"):
        np.testing.assert_allclose(res[flow], 0.0, rtol=0, atol=1e-12)


def test_rotational_acc_and_relative_speed_sensors():
    """Same system with inertias: a1 = c φ/J1, a2 = −c φ/J2, w_rel = −φ0 ω sin ωt; 1e-6 of the amplitudes."""
    J1, J2, c = 0.5, 2.0, 80.0
    res = fl.Simulation(TwoInertias(J1, J2, c), use_cache=False).run(1.0, dt_out=0.01, **TOL)
    a1, a2, w_rel, phi, omega = reference(res.t, J1, J2, c)
    np.testing.assert_allclose(res["acc1.a"], a1, rtol=0, atol=1e-6 * c * X0 / J1)
    np.testing.assert_allclose(res["acc2.a"], a2, rtol=0, atol=1e-6 * c * X0 / J1)
    np.testing.assert_allclose(res["acc2.w"], res["inertia2.w"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["rel.w_rel"], w_rel, rtol=0, atol=1e-6 * X0 * omega)
    np.testing.assert_allclose(res["rel.phi_rel"], phi, rtol=0, atol=1e-6 * X0)
    for flow in ("acc1.flange.tau", "acc2.flange.tau", "rel.flange_a.tau", "rel.flange_b.tau"):
        np.testing.assert_allclose(res[flow], 0.0, rtol=0, atol=1e-12)
