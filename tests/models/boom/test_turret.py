"""Bench test of :class:`flexlib.models.boom.Turret`: the turret with a point mass ``m`` on an arm ``r`` at its top
(on ``frame_joint1``), slewed from rest by a constant torque ``tau`` on its axis flange, under gravity.

References and tolerances:

* Rigid-body rotation about a fixed axis (Meriam–Kraige, *Dynamics*, ch. 6): ``alpha = tau / (J_slew + m r²)``
  at the start (at rest the regularised friction ``tau_c tanh(w / w_reg)`` is zero); 1e-6 relative. The point mass's
  weight is a tilting moment the bearing carries; it does not slew the turret.
* Friction breakaway: below the friction torque (``tau = tau_c / 2``) the turret only creeps, at the speed where
  the regularised friction balances the drive, ``w = w_reg atanh(tau / tau_c)`` (the time constant
  ``J w_reg / tau_c`` ≈ 0.02 s, reached to 1e-6 after 1 s); above it (``tau = 2 tau_c``) it accelerates with
  ``(tau − tau_c) / J`` once ``w ≫ w_reg`` (``1 − tanh(w / w_reg)`` < 1e-20 at 1 s); 1e-6 relative.
* The joint-1 frames sit where the turret puts them after slewing (rotation about ``y``), 1e-9 m.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.mechanics import rotational
from flexlib.components.mechanics.multibody import Body, World
from flexlib.errors import ParameterError
from flexlib.models.boom import Turret

M, R = 1000.0, 5.0  # point mass [kg] on an arm [m]
J, HEIGHT, H1 = 3500.0, 1.2, (0.45, -2.0)
TAU_C = 2.0e4
J_TOTAL = J + M * R**2


class Bench(fl.Model):
    """World, turret, point mass on an arm at the top, constant torque on the slewing axis."""

    def __init__(self, tau: float, tau_c: float, friction: str = "regularised") -> None:
        super().__init__()
        self.world = World()
        self.turret = Turret(mass=2500.0, J_slew=J, height=HEIGHT, H1=H1, tau_c=tau_c, w_reg=1e-2, friction=friction)
        self.arm = Body(m=M, r_CM=[R, 0.0, 0.0], I=np.zeros((3, 3)))
        self.drive = rotational.Torque()
        self.torque = Constant(k=tau)
        self.connect(self.world.frame_b, self.turret.frame_a)
        self.connect(self.turret.frame_joint1, self.arm.frame_a)
        self.connect(self.torque.y, self.drive.tau)
        self.connect(self.drive.flange, self.turret.axis)


@pytest.fixture(scope="module")
def sim():
    return fl.Simulation(Bench(1e4, TAU_C), codegen=False)


def test_angular_acceleration(sim):
    res = sim.initialize()
    assert float(np.asarray(res["turret.slew.a"])[0]) == pytest.approx(1e4 / J_TOTAL, rel=1e-6)


def test_friction_breakaway(sim):
    creep = sim.with_model(Bench(0.5 * TAU_C, TAU_C)).run(1.0, dt_out=0.1, rtol=1e-10, atol=1e-12, progress=False)
    assert float(creep["turret.slew.w"][-1]) == pytest.approx(1e-2 * math.atanh(0.5), rel=1e-6)
    slide = sim.with_model(Bench(2 * TAU_C, TAU_C)).run(1.0, dt_out=0.1, rtol=1e-10, atol=1e-12, progress=False)
    assert float(slide["turret.slew.a"][-1]) == pytest.approx(TAU_C / J_TOTAL, rel=1e-6)
    phi = float(slide["turret.slew.phi"][-1])
    top = np.array([0.0, HEIGHT, 0.0])
    # slewing by phi about y: x → (cos phi, 0, −sin phi)
    c, s = math.cos(phi), math.sin(phi)
    np.testing.assert_allclose(slide["turret.top.frame_b.r_0"][-1], top, atol=1e-9)
    np.testing.assert_allclose(slide["turret.housing.frame_b.r_0"][-1],
                               top + np.array([c * H1[0], H1[1], -s * H1[0]]), atol=1e-9)


def test_stick_slip_ring_holds_below_and_slides_above_the_friction_torque():
    """``friction="stick-slip"`` (MSL BearingFriction on the slew axis): half the friction torque holds the turret
    exactly (the angle does not move at all in 1 s, where the regularised ring creeps); twice the friction torque
    slews it at once with ``(tau − tau_c) / J`` (1e-9 relative: no regularisation to outgrow)."""
    held = fl.Simulation(Bench(0.5 * TAU_C, TAU_C, "stick-slip"), codegen=False).run(
        1.0, dt_out=0.1, rtol=1e-8, atol=1e-10, progress=False)
    assert np.max(np.abs(held["turret.slew.phi"])) == 0.0 and np.all(held["turret.ring.mode"] == 0)
    slide = fl.Simulation(Bench(2 * TAU_C, TAU_C, "stick-slip"), codegen=False).run(
        1.0, dt_out=0.1, rtol=1e-8, atol=1e-10, progress=False)
    np.testing.assert_allclose(slide["turret.slew.a"][1:], TAU_C / J_TOTAL, rtol=1e-9)
    with pytest.raises(ParameterError, match="friction must be one of regularised, stick-slip"):
        Turret(friction="coulomb")


def test_defaults_are_the_trucks():
    """The part's defaults are the 42 m record's turret."""
    from flexlib.models.pump_truck.parameters import PumpTruckParameters

    record = PumpTruckParameters()
    part = Turret()
    assert float(part.body.parameter_value("m")) == record.turret.mass
    assert part.top.parameter_value("r").tolist() == [0.0, record.turret.height, 0.0]
    assert part.housing.parameter_value("r").tolist() == [*record.joint1.H, 0.0]


@pytest.mark.parametrize(("kwargs", "argument"), [
    ({"mass": 0.0}, "mass"), ({"J_slew": -1.0}, "J_slew"), ({"height": float("inf")}, "height"),
    ({"tau_c": -1.0}, "tau_c"), ({"w_reg": 0.0}, "w_reg"), ({"H1": (1.0,)}, "H1"), ({"phi_start": "x"}, "phi_start"),
])
def test_bad_input(kwargs, argument):
    with pytest.raises(ParameterError, match=f"Turret: {argument} "):
        Turret(**kwargs)
