"""Bench test of :class:`flexlib.models.boom.LeverLink`: joint 3 of the pump truck's record (lever-and-link,
branch ``sigma = +1``) between a ground section k−1 (the world frame, horizontal) and a section k (a ``Body``) on a
revolute joint held at the angle ``q`` by its drive flange (a rotational ``Fixed``); a cylinder from the housing
``H`` to the lever tip ``T`` is a ``LineForce`` carrying a constant push ``F``.

References and tolerances:

* Statics by virtual work (J. L. Meriam, L. G. Kraige, *Engineering Mechanics: Statics*, ch. 7): the torque the
  joint's drive applies to section k is ``tau = dV/dq − F dl/dq``, with ``dl/dq`` the closed-form lever arm of
  :func:`models.pump_truck.kinematics.fourbar_state` and ``V = g Σ m y`` over section k, lever and link (centres at
  mid-length), ``dV/dq`` by central differences of the closed-form positions (step 1e-6 rad, error ~1e-10); 1e-6
  relative to ``F |dl/dq|`` (measured 1e-12 … 1e-10), in three poses: extended (q = 0), −90° and −175° (3° from
  the fold). Massive (the truck's lever and link masses, :func:`models.pump_truck.geometry.linkage_masses`) and
  massless linkage (they differ by ~400 N.m, the linkage's weight).
* Kinematics: with the revolutes' start guesses 0.1 rad off, the lever angle ``pivot.phi`` the initialisation
  finds equals the closed-form circle intersection (Norton ch. 4, :meth:`LeverLink.start_angles`) to 1e-9 rad at
  seven joint angles across the range.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.mechanics import rotational, translational
from flexlib.components.mechanics.multibody import Body, FixedTranslation, LineForce, Revolute, World
from flexlib.errors import ParameterError
from flexlib.models.boom import LeverLink
from flexlib.models.pump_truck.geometry import linkage_masses
from flexlib.models.pump_truck.kinematics import fourbar_state, rot
from flexlib.models.pump_truck.parameters import PumpTruckParameters

RECORD = PumpTruckParameters()
DRIVE = RECORD.drive(3)
F = 2.0e5  # cylinder push [N]
M_SEC, R_SEC = 1500.0, np.array([3.0, 0.2])  # section k: mass [kg], centre of mass in its frame [m]
G = 9.81
M_LEVER, M_LINK = linkage_masses(RECORD, 3)


class Bench(fl.Model):
    """Ground section k−1, joint held at ``q``, section k, LeverLink, constant-force cylinder H → T."""

    def __init__(self, q: float, m_lever: float, m_link: float, offset: float = 0.0) -> None:
        super().__init__()
        d = DRIVE
        self.world = World(g=G)
        self.joint = Revolute(use_axis_flange=True)
        self.hold = rotational.Fixed(phi0=q)
        self.section = Body(m=M_SEC, r_CM=[*R_SEC, 0.0], I=np.diag([10.0, 500.0, 500.0]))
        self.pin_C = FixedTranslation(r=[*d.c, 0.0])
        self.pin_P = FixedTranslation(r=[*d.P, 0.0])
        self.pin_H = FixedTranslation(r=[*d.H, 0.0])
        guess = np.asarray(LeverLink.start_angles(q, d.P, d.c, d.r, d.s, d.sigma)) + offset
        self.linkage = LeverLink(d.r, d.s, m_lever, m_link, guess=guess)
        self.line = LineForce()
        self.push = translational.Force(use_support=True)
        self.force = Constant(k=F)
        self.connect(self.world.frame_b, self.joint.frame_a, self.pin_P.frame_a, self.pin_H.frame_a)
        pairs = [(self.hold.flange, self.joint.axis), (self.pin_P.frame_b, self.linkage.frame_pivot),
                 (self.linkage.frame_bracket, self.pin_C.frame_b), (self.pin_H.frame_b, self.line.frame_a),
                 (self.linkage.frame_tip, self.line.frame_b), (self.line.flange_a, self.push.support),
                 (self.line.flange_b, self.push.flange)]
        for a, b in pairs:
            self.connect(a, b)
        self.connect(self.joint.frame_b, self.section.frame_a, self.pin_C.frame_a)
        self.connect(self.force.y, self.push.f)


def potential(q: float, m_lever: float, m_link: float) -> float:
    """``V = g Σ m y`` of section k, lever and link at joint angle ``q`` (closed-form kinematics) [J]."""
    d = DRIVE
    st = fourbar_state(q, d.P, d.H, d.c, d.r, d.s, d.sigma)
    P = np.asarray(d.P)
    return G * (M_SEC * (rot(q) @ R_SEC)[1] + m_lever * (P[1] + st.T[1]) / 2 + m_link * (st.T[1] + st.C[1]) / 2)


POSES = {"extended": 0.0, "raised": -math.pi / 2, "near fold": math.radians(-175.0)}


@pytest.fixture(scope="module")
def sims():
    return {}


def solve(sims: dict, q: float, m_lever: float, m_link: float, offset: float = 0.0):
    model = Bench(q, m_lever, m_link, offset)
    key = m_lever > 0
    sims[key] = fl.Simulation(model, codegen=False) if key not in sims else sims[key].with_model(model)
    return sims[key].initialize()


@pytest.mark.parametrize("massive", [True, False], ids=["massive", "massless"])
@pytest.mark.parametrize("pose", list(POSES))
def test_joint_torque_by_virtual_work(sims, pose, massive):
    q = POSES[pose]
    m_lever, m_link = (M_LEVER, M_LINK) if massive else (0.0, 0.0)
    res = solve(sims, q, m_lever, m_link)
    arm = fourbar_state(q, DRIVE.P, DRIVE.H, DRIVE.c, DRIVE.r, DRIVE.s, DRIVE.sigma).lever_arm
    h = 1e-6
    dV = (potential(q + h, m_lever, m_link) - potential(q - h, m_lever, m_link)) / (2 * h)
    tau = float(np.asarray(res["joint.tau"])[0])
    assert tau == pytest.approx(dV - F * arm, abs=1e-6 * F * abs(arm))


def test_lever_angle_closed_form(sims):
    d = DRIVE
    for q in np.radians([-176.0, -150.0, -120.0, -90.0, -60.0, -30.0, 0.0]):
        res = solve(sims, float(q), M_LEVER, M_LINK, offset=0.1)
        phi = float(np.asarray(res["linkage.pivot.phi"])[0])
        ref = LeverLink.start_angles(float(q), d.P, d.c, d.r, d.s, d.sigma)[0]
        assert math.remainder(phi - ref, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize(("kwargs", "argument"), [
    ({"r": 0.0, "s": 1.0}, "r"), ({"r": 1.0, "s": "x"}, "s"), ({"r": 1.0, "s": 1.0, "m_lever": -1.0}, "m_lever"),
    ({"r": 1.0, "s": 1.0, "m_link": float("nan")}, "m_link"), ({"r": 1.0, "s": 1.0, "guess": (0.0, 1.0)}, "guess"),
])
def test_bad_input(kwargs, argument):
    with pytest.raises(ParameterError, match=f"LeverLink: {argument} "):
        LeverLink(**kwargs)


def test_pose_that_cannot_close():
    with pytest.raises(ParameterError, match=r"LeverLink: q = .*cannot close"):
        LeverLink.at_pose(0.0, (-0.5, 0.7), (-0.8, 0.0), 0.1, 0.1, 1)
