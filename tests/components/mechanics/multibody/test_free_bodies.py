"""Free rotation (quaternion states behind a spherical joint): the heavy symmetric top."""

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Spherical, World
from flexlib.components.mechanics.multibody.quaternions import quaternion_from_T
from flexlib.models.reference import closed_form as ref

G = 9.81


class HeavyTop(fl.Model):
    """Symmetric top on a fixed tip (spherical joint at the world origin); symmetry axis = body z."""

    def __init__(self, T0: np.ndarray, w0: np.ndarray, m: float, d: float, I1_cm: float, I3: float) -> None:
        super().__init__()
        self.world = World(g=G)
        self.tip = Spherical()
        self.top = Body(m=m, r_CM=[0, 0, d], I=np.diag([I1_cm, I1_cm, I3]), Q_start=quaternion_from_T(T0),
                        w_start=w0, orientation_fixed=True, w_fixed=True)
        self.connect(self.world.frame_b, self.tip.frame_a)
        self.connect(self.tip.frame_b, self.top.frame_a)


def test_heavy_top_steady_precession():
    """Goldstein §5.7: with ω3 and the slow root Ω of I1·Ω²·cosθ − I3·ω3·Ω + m g l = 0 the symmetry axis
    keeps its tilt (|Δθ| ≤ 1e-6 rad over 1 s) and precesses about the vertical at Ω (relative error 5e-6, fitted);
    energy is conserved to 1e-6 relative and the quaternion keeps unit norm (1e-9)."""
    m, d, I1_cm, I3 = 1.0, 0.2, 0.02, 0.04
    theta, omega3 = 0.6, 20.0
    I1_tip = I1_cm + m * d**2
    slow, _ = ref.heavy_top_steady_precession(m, G, d, I1_tip, I3, theta, omega3)
    ic = ref.heavy_top_initial_conditions(theta, omega3, slow, l=d, world_up="y")
    T0 = ic.R.T  # flexlib/MSL T maps world → body; the reference R maps body → world
    sim = fl.Simulation(HeavyTop(T0, ic.omega_body, m, d, I1_cm, I3), use_cache=False)
    assert sim.report.index >= 1
    res = sim.run(1.0, dt_out=0.005, rtol=1e-10, atol=1e-12)
    Q = res["top.Q"]
    np.testing.assert_allclose(np.sum(Q**2, axis=1), 1.0, atol=1e-9)
    # symmetry axis in world = third row of T = third column of R
    axis = res["top.frame_a.T"].reshape(-1, 3, 3, order="F")[:, 2, :]
    tilt = np.arccos(np.clip(axis[:, 1], -1, 1))  # from world +y (up)
    np.testing.assert_allclose(tilt, theta, atol=1e-6)
    azimuth = np.unwrap(np.arctan2(axis[:, 0], axis[:, 2]))  # about +y
    rate = np.polyfit(res.t, azimuth, 1)[0]
    np.testing.assert_allclose(abs(rate), slow, rtol=5e-6)  # rate fitted over 1 s (residual nutation)
    w = res["top.w_a"]
    cm_height = d * axis[:, 1]
    # kinetic energy about the fixed tip from the body-frame angular velocity
    energy = 0.5 * (I1_tip * (w[:, 0] ** 2 + w[:, 1] ** 2) + I3 * w[:, 2] ** 2) + m * G * cm_height
    np.testing.assert_allclose(energy, energy[0], rtol=1e-6)
