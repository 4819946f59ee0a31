"""Tests of the acceleration and relative-speed sensors of the 1D libraries (MSL
``Translational.Sensors.AccSensor``/``RelSpeedSensor``, ``Rotational.Sensors.AccSensor``/``RelSpeedSensor``).

Reference: two free bodies coupled by a spring, released with the spring stretched by x0. The
stretch oscillates as x0 cos(ω t), ω² = c (1/m1 + 1/m2); body 1 accelerates with c x/m1, body 2
with −c x/m2, and the relative speed is −x0 ω sin(ω t) (Meirovitch, *Elements of Vibration
Analysis*, §3.2, semi-definite system). Runs at rtol = 1e-8, atol = 1e-10; tolerance 1e-6 of each
quantity's amplitude. The sensors must not load the flanges (their flange flows are zero).
"""

from __future__ import annotations

from types import ModuleType

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics import rotational as rot
from flexlib.components.mechanics import translational as tr

TOL = {"rtol": 1e-8, "atol": 1e-10}
X0 = 0.05


class SpringCoupled(fl.Model):
    """body1 -- spring -- body2 of one 1D library ``lib`` (translational masses or rotational inertias, given by
    name), with acceleration sensors on both and a relative-speed sensor."""

    def __init__(self, lib: ModuleType, bodies: dict[str, fl.Component], c: float) -> None:
        super().__init__()
        (name1, body1), (name2, body2) = bodies.items()
        setattr(self, name1, body1)
        setattr(self, name2, body2)
        self.spring = lib.Spring(c=c)
        self.acc1 = lib.AccSensor()
        self.acc2 = lib.AccSensor()
        self.rel = lib.RelativeSpeedSensor()
        self.connect(body1.flange_b, self.spring.flange_a, self.acc1.flange, self.rel.flange_a)
        self.connect(self.spring.flange_b, body2.flange_a, self.acc2.flange, self.rel.flange_b)


def two_masses(m1: float, m2: float, c: float) -> SpringCoupled:
    """mass1 -- spring -- mass2, mass2 released X0 from the unstretched length."""
    return SpringCoupled(tr, {"mass1": tr.Mass(m=m1, init={"s": 0.0, "v": 0.0}),
                              "mass2": tr.Mass(m=m2, init={"s": X0, "v": 0.0})}, c)


def two_inertias(J1: float, J2: float, c: float) -> SpringCoupled:
    """inertia1 -- spring -- inertia2, inertia2 released X0 from the unstretched angle."""
    return SpringCoupled(rot, {"inertia1": rot.Inertia(J=J1, init={"phi": 0.0, "w": 0.0}),
                               "inertia2": rot.Inertia(J=J2, init={"phi": X0, "w": 0.0})}, c)


def reference(t: np.ndarray, m1: float, m2: float, c: float) -> tuple[np.ndarray, ...]:
    omega = np.sqrt(c * (1.0 / m1 + 1.0 / m2))
    x = X0 * np.cos(omega * t)
    return c * x / m1, -c * x / m2, -X0 * omega * np.sin(omega * t), x, omega


#: Per library: model builder, (body 1 inertia, body 2 inertia, c), the sensor speed checked against its body's
#: speed, the relative speed and position of ``rel`` and the flange flow variable.
CASES = {
    "translational": (two_masses, (1.0, 3.0, 300.0), ("acc1.v", "mass1.v"), "rel.v_rel", "rel.s_rel", "f"),
    "rotational": (two_inertias, (0.5, 2.0, 80.0), ("acc2.w", "inertia2.w"), "rel.w_rel", "rel.phi_rel", "tau"),
}


@pytest.mark.parametrize("library", list(CASES))
def test_acc_and_relative_speed_sensors(library):
    """a1 = c x/m1, a2 = −c x/m2, v_rel = −x0 ω sin ωt, s_rel = x (with inertias: a1 = c φ/J1, a2 = −c φ/J2,
    w_rel = −φ0 ω sin ωt); tolerance 1e-6 of the amplitudes."""
    build, (m1, m2, c), (speed, body_speed), rel_speed, rel_position, flow = CASES[library]
    res = fl.Simulation(build(m1, m2, c), use_cache=False).run(1.0, dt_out=0.01, **TOL)
    a1, a2, v_rel, x, omega = reference(res.t, m1, m2, c)
    np.testing.assert_allclose(res["acc1.a"], a1, rtol=0, atol=1e-6 * c * X0 / m1)
    np.testing.assert_allclose(res["acc2.a"], a2, rtol=0, atol=1e-6 * c * X0 / m1)
    np.testing.assert_allclose(res[speed], res[body_speed], rtol=0, atol=1e-9)
    np.testing.assert_allclose(res[rel_speed], v_rel, rtol=0, atol=1e-6 * X0 * omega)
    np.testing.assert_allclose(res[rel_position], x, rtol=0, atol=1e-6 * X0)
    for connector in ("acc1.flange", "acc2.flange", "rel.flange_a", "rel.flange_b"):
        np.testing.assert_allclose(res[f"{connector}.{flow}"], 0.0, rtol=0, atol=1e-12)
