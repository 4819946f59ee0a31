"""``UniversalSpherical`` (MSL ``MultiBody.Joints.UniversalSpherical``) against closed forms; MSL's Fourbar2 with it is
compared with the Modelica Association's reference result in ``tests/msl``.

A 1 kg sphere (radius 0.1 m) hangs on the joint's massless 1 m rod, released from rest 30° off the vertical in the
plane normal to the universal's first axis ``z``: a planar pendulum (the sphere's own rotation is free: the spherical
joint carries no torque). By energy, at the bottom ``v² = 2 g L (1 − cos 30°)`` and the rod pulls with
``m g (3 − 2 cos 30°)`` (``f_rod`` is positive in compression); rtol 1e-6 at rtol 1e-10 of the run.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, UniversalSpherical, World
from flexlib.errors import ParameterError

G, L, M = 9.80665, 1.0, 1.0
ANGLE = np.radians(30.0)


class Hanging(fl.Model):
    def __init__(self, compute_rod_length: bool) -> None:
        super().__init__()
        self.world = World()
        rod = [L * np.sin(ANGLE), -L * np.cos(ANGLE), 0.0]
        self.joint = UniversalSpherical(n1_a=[0, 0, 1], rRod_ia=rod if not compute_rod_length else [0.3, -0.5, 0.0],
                                        compute_rod_length=compute_rod_length)
        self.ball = Body(m=M, I=np.eye(3) * 0.4 * M * 0.1**2, orientation_fixed=True, w_fixed=True,
                         init={"r_0": rod} if compute_rod_length else {})
        universal = self.joint.universal
        for name in ("w_a", "w_b") + (() if compute_rod_length else ("phi_a", "phi_b")):
            universal.set_start(name, 0.0, fixed=True)
        self.connect(self.world.frame_b, self.joint.frame_a)
        self.connect(self.joint.frame_b, self.ball.frame_a)


@pytest.mark.parametrize("compute_rod_length", [False, True])
def test_pendulum_on_the_rod_matches_energy_and_rod_force(compute_rod_length):
    """The lowest point's speed and rod pull as the closed forms (both rod-length options: given, or found at the
    start from the ball's position — 1 m); the rod length stays constant (1e-9)."""
    res = fl.Simulation(Hanging(compute_rod_length)).run(1.5, dt_out=0.001, rtol=1e-10, atol=1e-12,
                                                        progress=False)
    r = res["ball.frame_a.r_0"]
    k = int(np.argmin(r[:, 1]))
    speed = np.linalg.norm(res["ball.v_0"][k])
    np.testing.assert_allclose(speed, np.sqrt(2 * G * L * (1 - np.cos(ANGLE))), rtol=1e-5)
    np.testing.assert_allclose(res["joint.f_rod"][k], -M * G * (3 - 2 * np.cos(ANGLE)), rtol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(r, axis=-1), L, rtol=1e-9)
    np.testing.assert_allclose(res["joint.rodLength"], L, rtol=1e-9)


def test_rod_along_the_first_axis_is_refused():
    """``rRod_ia`` parallel to ``n1_a`` is the universal joint's singular configuration: refused, naming both."""
    with pytest.raises(ParameterError, match=r"n1_a .* is parallel to rRod_ia"):
        UniversalSpherical(n1_a=[0, 1, 0], rRod_ia=[0, 2, 0])
