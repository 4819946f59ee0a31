"""Joint friction in the Revolute: journal-bearing Coulomb level μ·r·|F| with preload, Stribeck, viscous."""

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Revolute, World

G = 9.81


class Rotor(fl.Model):
    """A balanced disk (CM on the axis) on a frictional revolute; ``axis`` is the joint axis in world."""

    def __init__(self, axis, w0=20.0, J=0.05, m=4.0, **friction) -> None:
        super().__init__()
        self.world = World(g=G)
        self.bearing = Revolute(n=axis, use_friction=True, init={"phi": 0.0, "w": w0}, **friction)
        self.disk = Body(m=m, I=np.diag([J, J, J]))
        self.connect(self.world.frame_b, self.bearing.frame_a)
        self.connect(self.bearing.frame_b, self.disk.frame_a)


@pytest.mark.parametrize(("axis", "F_preload", "F_radial"), [([0, 0, 1], 0.0, 4.0 * G), ([0, 1, 0], 150.0, 0.0)])
def test_coulomb_bearing_friction_decelerates_linearly(axis, F_preload, F_radial):
    """Horizontal axis: the weight m·g is the radial bearing load; vertical axis: only the preload acts
    radially (the weight is axial). Deceleration = μ·r·(F_radial + F_preload)/J exactly (1e-6) while
    w ≫ w_reg; the rotor then stops."""
    mu, r, J, w0 = 0.1, 0.02, 0.05, 20.0
    decel = mu * r * (F_radial + F_preload) / J
    t_stop = w0 / decel
    res = fl.Simulation(Rotor(axis, w0=w0, J=J, mu=mu, r_bearing=r, F_preload=F_preload),
                        use_cache=False).run(1.2 * t_stop, dt_out=0.01, rtol=1e-10, atol=1e-12)
    moving = res.t < 0.95 * t_stop
    np.testing.assert_allclose(res["bearing.w"][moving], w0 - decel * res.t[moving], rtol=1e-6, atol=1e-9)
    assert abs(res["bearing.w"][-1]) < 1e-2


def test_stribeck_and_viscous_curve():
    """Friction torque vs speed follows (τ_C + (s−1)τ_C e^{−(w/w_s)²})·tanh(w/w_reg) + d·w (1e-8 at rtol 1e-10:
    the torque depends on the bearing's reaction force, a derivative-level unknown outside IDA's error test
    whose value between steps is interpolated)."""
    tau_c0, s, w_s, d = 0.3, 1.8, 0.5, 0.02
    res = fl.Simulation(Rotor([0, 0, 1], w0=3.0, tau_c0=tau_c0, stribeck=s, w_s=w_s, d=d, w_reg=1e-3),
                        use_cache=False).run(2.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    w = res["bearing.w"]
    expected = (tau_c0 * (1 + (s - 1) * np.exp(-(w / w_s) ** 2)) * np.tanh(w / 1e-3) + d * w)
    np.testing.assert_allclose(res["bearing.tau_f"], expected, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(res["bearing.tau"], -res["bearing.tau_f"], atol=1e-12)
