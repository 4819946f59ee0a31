"""Closed kinematic loops: a planar four-bar of four ordinary Revolutes built in 3D.

Reference: closed-form four-bar position analysis (Norton, *Design of Machinery*, §4.5) in
flexlib.models.reference.closed_form. Link lengths a (crank), b (coupler), c (rocker), ground d.
"""

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Fixed, FixedTranslation, Revolute, World
from flexlib.models.reference import closed_form as ref
from flexlib.models.reference.four_bar import A, B, C, D, FourBar
from flexlib.models.reference.slider_crank import SliderCrank


def test_planar_fourbar_with_four_revolutes():
    """Runs with four ordinary Revolutes: 3 redundant loop equations are found and reported; the
    loop is assembled from start angles off by 0.1 rad; the rocker and coupler angles follow the
    closed-form position analysis to 1e-7 rad over a full crank turn (states re-selected as it goes)."""
    th2 = 0.3
    th3, th4 = ref.fourbar_angles(A, B, C, D, th2, "open")
    from flexlib.compile.flatten import flatten
    from flexlib.compile.passes.multibody.redundancy import remove_redundant
    from flexlib.compile.simplify import simplify

    model = FourBar(th2, th3 + 0.1, th4 - 0.1, w2=6.0)
    flat = flatten(model, check=False)
    simple = remove_redundant(simplify(flat), {q.sym.element_hash(): q.value for q in flat.parameters})
    dropped = sorted(text.split("; ")[1] for text in simple.redundant)
    assert dropped == ["force along world z at rev3.frame_b is statically indeterminate and set to 0",
                       "torque about rev3.frame_b axis x is statically indeterminate and set to 0",
                       "torque about rev3.frame_b axis y is statically indeterminate and set to 0"]
    sim = fl.Simulation(model, use_cache=False)
    assert len(sim.report.redundant) == 3
    assert all("indeterminate" in text for text in sim.report.redundant)
    res = sim.run(1.2, dt_out=0.01, rtol=1e-7, atol=1e-9)
    theta2 = res["rev1.phi"]
    assert theta2[-1] - theta2[0] > 2 * np.pi  # a full crank turn
    theta3 = theta2 + res["rev2.phi"]
    theta4 = res["rev4.phi"]
    ref3, ref4 = ref.fourbar_angles(A, B, C, D, theta2, "open")
    wrap = lambda x: (x + np.pi) % (2 * np.pi) - np.pi  # noqa: E731
    np.testing.assert_allclose(wrap(theta3 - ref3), 0.0, atol=1e-7)
    np.testing.assert_allclose(wrap(theta4 - ref4), 0.0, atol=1e-7)
    # the coupler's end coincides with the rocker's end (loop closed to solver tolerance)
    np.testing.assert_allclose(res["coupler.frame_b.r_0"], res["rocker.frame_b.r_0"], atol=1e-9)


class BeamOnPinWithLink(fl.Model):
    """A horizontal uniform beam (mass m, length L) pinned to the world at x = 0 and hung at x = L from
    a vertical massless link of length h whose upper end is pinned to a fixed frame at (L, h, 0)."""

    def __init__(self, m: float = 3.0, L: float = 2.0, h: float = 0.8) -> None:
        super().__init__()
        self.world = World(g=9.81)
        self.top = Fixed(r=[L, h, 0])
        self.pin = Revolute(guess={"phi": 0.0})
        self.beam = Body(m=m, r_CM=[L / 2, 0, 0], I=np.diag([1e-4, m * L**2 / 12, m * L**2 / 12]))
        self.beam_rod = FixedTranslation(r=[L, 0, 0])
        self.end = Revolute(guess={"phi": 0.0})
        self.link = FixedTranslation(r=[0, h, 0])
        self.top_pin = Revolute(guess={"phi": 0.0})
        self.connect(self.world.frame_b, self.pin.frame_a)
        self.connect(self.pin.frame_b, self.beam.frame_a, self.beam_rod.frame_a)
        self.connect(self.beam_rod.frame_b, self.end.frame_a)
        self.connect(self.end.frame_b, self.link.frame_a)
        self.connect(self.link.frame_b, self.top_pin.frame_a)
        self.connect(self.top_pin.frame_b, self.top.frame_b)


def test_loop_closed_in_its_mirrored_branch_is_refused():
    """The orientation residue of a loop closure (the sine part of the cut frames' relative rotation, as Modelica's
    equalityConstraint) also vanishes at a half-turn. A start guess of the cut joint half a turn off makes the
    consistent start close the loop there, where the forces across the cut act in reversed axes (a rigid four-bar
    then lost half its kinetic energy in 0.5 s without any damping): the run is refused, naming the loop closure,
    instead of returning that motion. The same model from the guess near the assembly runs and keeps its kinetic
    energy to 1e-6."""

    from flexlib.errors import InitializationError

    th2 = 0.3
    th3, th4 = ref.fourbar_angles(A, B, C, D, th2, "open")
    flipped = FourBar(th2, th3, th4, w2=6.0)
    flipped.rev3.set_start("phi", th4 - th3 + np.pi, fixed=False)
    message = (r"mirrored branch at the start(.|\n)*loop closure rev3\.frame_b ~ rocker\.frame_b: "
               r"relative rotation of the cut frames 180\.0 deg")
    with pytest.raises(InitializationError, match=message):
        fl.Simulation(flipped, use_cache=False).run(0.1, dt_out=0.05, progress=False)
    res = fl.Simulation(FourBar(th2, th3, th4, w2=6.0), use_cache=False).run(0.5, dt_out=0.05, rtol=1e-9, atol=1e-11,
                                                                          progress=False)
    # kinetic energy of the three links (no gravity, no damping: conserved)
    ke = 0.0
    for body, m, L in (("crank_mass", 1.0, A), ("coupler_mass", 2.0, B), ("rocker_mass", 1.5, C)):
        v = np.asarray(res[f"{body}.v_0"])[:, :2]
        w = np.asarray(res[f"{body}.w_a"])[:, 2]
        T = np.asarray(res[f"{body}.frame_a.T"]).reshape(-1, 3, 3, order="F")
        r_cm = np.einsum("kji,j->ki", T, np.array([-L / 2, 0.0, 0.0]))[:, :2]
        v_cm = v + np.column_stack([-w * r_cm[:, 1], w * r_cm[:, 0]])
        ke = ke + 0.5 * m * (v_cm**2).sum(axis=1) + 0.5 * (m * L**2 / 12) * w**2
    np.testing.assert_allclose(ke, ke[0], rtol=1e-6)


def test_static_reactions_beam_pin_link():
    """A statically determinate structure in the plane (0 DOF, 3 redundant out-of-plane loop rows): the
    in-plane hinge forces equal statics (pin: R_x = 0, R_y = m g/2; link tension m g/2) to 1e-8 relative;
    the dropped out-of-plane directions carry zero reaction, are reported, and leave the out-of-plane force
    indeterminate (its read warns)."""
    m, L, g = 3.0, 2.0, 9.81
    sim = fl.Simulation(BeamOnPinWithLink(m, L), use_cache=False)
    assert sim.states == []
    assert len(sim.report.redundant) == 3
    res = sim.run(1.0, dt_out=0.5, rtol=1e-10, atol=1e-12)
    Rx, Ry, T = ref.beam_pin_link_reactions(m, L, g)
    # force of the mechanism on the ground frames (resolved in world: both frames have T = I)
    for frame, in_plane in (("world", [-Rx, -Ry]), ("top", [0.0, -T])):
        f = np.array([res[f"{frame}.frame_b.f[{i}]"][-1] for i in (0, 1)])
        np.testing.assert_allclose(f, in_plane, rtol=0, atol=1e-8 * m * g)
        assert f"{frame}.frame_b.f[2]" in res.indeterminate
        with pytest.warns(fl.IndeterminateReactionWarning, match=rf"{frame}\.frame_b\.f\[2\] is statically"):
            np.testing.assert_allclose(res[f"{frame}.frame_b.f[2]"][-1], 0.0, atol=1e-8 * m * g)
    np.testing.assert_allclose(res["pin.phi"], 0.0, atol=1e-12)




def test_slider_crank_kinematics():
    """Slider position and velocity vs the analytic slider-crank relations (Heywood §2.2) along a
    dynamic run through full turns, 1e-8 m and 1e-7 m/s; the loop needs no special joints."""
    r, rod_length = 0.1, 0.35
    sim = fl.Simulation(SliderCrank(0.4, r, rod_length, w0=8.0), use_cache=False)
    assert len(sim.report.redundant) == 3
    res = sim.run(1.0, dt_out=0.01, rtol=1e-8, atol=1e-10)
    theta, omega = res["crank_joint.phi"], res["crank_joint.w"]
    assert theta[-1] - theta[0] > 2 * np.pi
    np.testing.assert_allclose(res["slide.s"], ref.slider_position(theta, r, rod_length), rtol=0, atol=1e-8)
    np.testing.assert_allclose(res["slide.v"], ref.slider_velocity(theta, omega, r, rod_length), rtol=0,
                               atol=1e-7)


def test_slider_crank_static_torque_virtual_work():
    """Crank held still against a piston force F: the holding torque equals F·dx/dθ (virtual work), 1e-8.

    Built without the planar-geometry assumption: at atol 1e-12 N the world reaction (≈ 0, the difference of
    660 N reactions, round-off ≈ 1e-13 N) sits at its error weight, and IDA's Newton test fails on round-off at
    some crank angles in either build (a sweep of 16 angles: θ = 4.86 without, θ = 2.0 with the assumption)."""
    r, rod_length, F = 0.1, 0.35, 1000.0
    for theta in (0.6, 2.0, 4.0):
        sim = fl.Simulation(SliderCrank(theta, r, rod_length, lock_crank=True, F=F), use_cache=False,
                            assume_zero_geometry=False)
        res = sim.run(0.1, dt_out=0.05, rtol=1e-10, atol=1e-12)
        holding = res["crank_joint.tau"][-1]  # tau: torque the drive (axis flange) applies to the crank about n
        np.testing.assert_allclose(holding, ref.crank_torque_virtual_work(theta, r, rod_length, F), rtol=1e-8)
