"""Open-chain multibody systems against independent references (flexlib.models.reference.closed_form).

Planar set-up: world x horizontal, y up, gravity −y; joint axes along z; angles from the downward
vertical are θ = φ + π/2 where φ is the Revolute angle measured from +x.
"""

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World
from flexlib.models.reference import closed_form as ref
from tests.components.mechanics.multibody.crossings import upward_crossings

G = 9.81


class PhysicalPendulum(fl.Model):
    """Revolute at the world origin, a massless rod of length L along the link's x axis, a body at its end."""

    def __init__(self, theta0: float, L: float = 1.0, m: float = 1.0, I_cm: float = 0.0, w0: float = 0.0) -> None:
        super().__init__()
        self.world = World(g=G)
        self.rev = Revolute(n=[0, 0, 1], init={"phi": theta0 - np.pi / 2, "w": w0})
        self.rod = FixedTranslation(r=[L, 0, 0])
        self.body = Body(m=m, I=np.diag([I_cm, I_cm, I_cm]))
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.body.frame_a)


@pytest.mark.parametrize(("theta0", "I_cm"), [(0.05, 0.0), (1.2, 0.0), (1.2, 0.04)])
def test_pendulum_period(theta0, I_cm):
    """Period vs the exact large-amplitude period (elliptic integral), 1e-5 relative (small angle: 0.05 rad
    is also compared with 2π·sqrt(L/g)(1 + θ0²/16) to 1e-6)."""
    sim = fl.Simulation(PhysicalPendulum(theta0, I_cm=I_cm), use_cache=False)
    assert sorted(sim.states) == ["rev.phi", "rev.w"]
    res = sim.run(8.0, dt_out=2e-3, rtol=1e-10, atol=1e-12)
    theta = res["rev.phi"] + np.pi / 2
    periods = np.diff(upward_crossings(res.t, theta, res["rev.w"]))
    exact = ref.physical_pendulum_period(1.0, 1.0, I_cm, G, theta0)
    assert len(periods) >= 2
    np.testing.assert_allclose(periods, exact, rtol=1e-5)
    if theta0 < 0.1:
        np.testing.assert_allclose(periods, 2 * np.pi * np.sqrt(1 / G) * (1 + theta0**2 / 16), rtol=1e-6)


def test_pendulum_hinge_force_statics():
    """At rest hanging straight down the hinge carries the weight: world-side cut force = (0, m g, 0)."""
    res = fl.Simulation(PhysicalPendulum(0.0, m=2.5), use_cache=False).run(1.0, dt_out=0.5, rtol=1e-10, atol=1e-12)
    # force of the joint on the world frame (flow into World) is the weight pulling down
    np.testing.assert_allclose(res["world.frame_b.f"][-1], [0.0, -2.5 * G, 0.0], atol=1e-8)
    np.testing.assert_allclose(res["rev.phi"], -np.pi / 2, atol=1e-12)


class DoublePendulum(fl.Model):
    """Two revolutes and two point masses at the ends of massless rods."""

    def __init__(self, th1: float, th2: float, L1: float = 1.0, L2: float = 0.7, m1: float = 1.0,
                 m2: float = 0.5) -> None:
        super().__init__()
        self.world = World(g=G)
        self.rev1 = Revolute(init={"phi": th1 - np.pi / 2, "w": 0.0})
        self.rod1 = FixedTranslation(r=[L1, 0, 0])
        self.body1 = Body(m=m1, I=np.zeros((3, 3)))
        self.rev2 = Revolute(init={"phi": th2 - th1, "w": 0.0})
        self.rod2 = FixedTranslation(r=[L2, 0, 0])
        self.body2 = Body(m=m2, I=np.zeros((3, 3)))
        self.connect(self.world.frame_b, self.rev1.frame_a)
        self.connect(self.rev1.frame_b, self.rod1.frame_a)
        self.connect(self.rod1.frame_b, self.body1.frame_a, self.rev2.frame_a)
        self.connect(self.rev2.frame_b, self.rod2.frame_a)
        self.connect(self.rod2.frame_b, self.body2.frame_a)


def test_double_pendulum_energy_and_reference():
    """Energy conserved to 1e-6 relative over 10 s; first 2 s equal the minimal-coordinate ODE (1e-6 rad)."""
    from scipy.integrate import solve_ivp

    th1, th2 = 1.0, 2.0
    sim = fl.Simulation(DoublePendulum(th1, th2), use_cache=False)
    res = sim.run(10.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    v1, v2 = res["body1.v_0"], res["body2.v_0"]
    y1, y2 = res["body1.r_0"][:, 1], res["body2.r_0"][:, 1]
    energy = 0.5 * 1.0 * np.sum(v1**2, axis=1) + 0.5 * 0.5 * np.sum(v2**2, axis=1) + G * (1.0 * y1 + 0.5 * y2)
    scale = 1.0 * G * 1.0 + 0.5 * G * 1.7
    assert np.max(np.abs(energy - energy[0])) / scale <= 1e-6
    rhs, _ = ref.double_pendulum_point_masses(1.0, 0.5, 1.0, 0.7, G)
    early = res.t <= 2.0
    sol = solve_ivp(rhs, (0, 2.0), [th1, th2, 0, 0], t_eval=res.t[early], rtol=1e-12, atol=1e-12, method="DOP853")
    theta1 = res["rev1.phi"][early] + np.pi / 2
    theta2 = theta1 + res["rev2.phi"][early]
    np.testing.assert_allclose(theta1, sol.y[0], atol=1e-6)
    np.testing.assert_allclose(theta2, sol.y[1], atol=1e-6)
