"""Linear analysis (``flexlib.analysis``) against references we did not derive from flexlib.

- Two masses on springs (wall–k1–m1–k2–m2, damper d between the masses): eigenvalues and the receptance
  ``H = (K + jωD − ω²M)⁻¹`` in closed form (any vibration textbook; Géradin & Rixen, *Mechanical Vibrations*,
  3rd ed., §2.3).
- Compound pendulum linearised at the bottom: ``ω² = m g L / (I + m L²)`` (the textbook small-angle result).
- Hydraulic cylinder holding a mass with both ports closed: the oil-spring frequency
  ``ω² = β (A_p²/V_A + A_r²/V_B) / m`` (Merritt, *Hydraulic Control Systems*, 1967, §5.2, for a differential
  cylinder), pure liquid (``β`` constant).
- A flexible cantilever (beam FE, HRZ-lumped mass) on a revolute joint, joint locked: the FE model's own
  clamped eigenfrequencies from ``scipy.linalg.eigh`` on its stiffness and mass matrices.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

import flexlib as fl
from flexlib.components.control import Constant
from flexlib.components.hydraulics import DoubleActingCylinder
from flexlib.components.hydraulics.fluid import Fluid
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World
from flexlib.components.mechanics.translational import Damper, Fixed, Force, Mass, Spring
from flexlib.fe import beam_mesh, modal_data_from_fe, rectangle
from flexlib.units import g_n

M1, M2, K1, K2, D12 = 2.0, 0.5, 3.0e4, 1.2e4, 15.0


class TwoMass(fl.Model):
    def __init__(self, d: float = 0.0):
        super().__init__()
        self.wall = Fixed()
        self.k1 = Spring(c=K1)
        self.m1 = Mass(m=M1, init={"s": 0.0, "v": 0.0})
        self.k2 = Spring(c=K2)
        self.m2 = Mass(m=M2, init={"s": 0.0, "v": 0.0})
        self.src = Constant(k=0.0)
        self.push = Force()
        self.connect(self.wall.flange, self.k1.flange_a)
        self.connect(self.k1.flange_b, self.m1.flange_a)
        self.connect(self.m1.flange_b, self.k2.flange_a)
        self.connect(self.k2.flange_b, self.m2.flange_a)
        self.connect(self.src.y, self.push.f)
        self.connect(self.push.flange, self.m2.flange_b)
        if d:
            self.d12 = Damper(d=d)
            self.connect(self.m1.flange_b, self.d12.flange_a)
            self.connect(self.d12.flange_b, self.m2.flange_a)


def _chain_matrices(d: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    M = np.diag([M1, M2])
    K = np.array([[K1 + K2, -K2], [-K2, K2]])
    D = np.array([[d, -d], [-d, d]])
    return M, K, D


def test_two_mass_chain_frequencies_are_exact():
    """Undamped: the two natural frequencies from det(K − ω² M) = 0 (quadratic formula), to 1e-10."""
    modes = fl.modal_analysis(TwoMass())
    a, b, c = M1 * M2, -(M1 * K2 + M2 * (K1 + K2)), K1 * K2
    w2 = np.sort([(-b - np.sqrt(b * b - 4 * a * c)) / (2 * a), (-b + np.sqrt(b * b - 4 * a * c)) / (2 * a)])
    np.testing.assert_allclose(modes.frequencies, np.sqrt(w2) / (2 * np.pi), rtol=1e-10)
    np.testing.assert_allclose(modes.damping, 0.0, atol=1e-10)
    # mode shapes: the ratio of the two mass amplitudes is the eigenvector of (K − ω² M)
    for k, w in enumerate(np.sqrt(w2)):
        ratio = (K1 + K2 - w**2 * M1) / K2  # x2 / x1 from the first row
        np.testing.assert_allclose(modes.shape("m2.s")[k] / modes.shape("m1.s")[k], ratio, rtol=1e-9)


def test_two_mass_chain_receptance_with_damper():
    """H(f) from the force on m2 to both positions equals (K + jωD − ω²M)⁻¹ (second column), to 1e-10."""
    lin = fl.linearize(TwoMass(D12), inputs=["src.k"], outputs=["m1.s", "m2.s", "m2.v"])
    M, K, D = _chain_matrices(D12)
    f = np.array([0.5, 10.0, 25.0, 40.0, 200.0])
    H = lin.frequency_response(f)
    for k, fk in enumerate(f):
        w = 2 * np.pi * fk
        ref = np.linalg.solve(K + 1j * w * D - w**2 * M, [0.0, 1.0])
        np.testing.assert_allclose(H[k, :2, 0], ref, rtol=1e-10, atol=0)
        np.testing.assert_allclose(H[k, 2, 0], 1j * w * ref[1], rtol=1e-10)
    np.testing.assert_allclose(lin.frequency_response(f, "src.k", "m2.s"), H[:, 1, 0], rtol=0, atol=0)
    eig = np.sort_complex(np.linalg.eigvals(lin.A))
    Z = np.zeros((2, 2))
    ref = np.linalg.eigvals(np.block([[Z, np.eye(2)], [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]]))
    np.testing.assert_allclose(eig, np.sort_complex(ref), rtol=1e-10)


class BobPendulum(fl.Model):
    def __init__(self, m: float, L: float, I_zz: float):
        super().__init__()
        self.world = World()
        self.rev = Revolute(n=[0, 0, 1], init={"phi": -np.pi / 2, "w": 0.0})
        self.rod = FixedTranslation(r=[L, 0, 0])
        self.bob = Body(m=m, r_CM=[0, 0, 0], I=np.diag([I_zz, I_zz, I_zz]))
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.bob.frame_a)


def test_pendulum_at_the_bottom():
    """ω = √(m g L / (I + m L²)), undamped, to 1e-10; locking the joint leaves no mode."""
    m, L, Izz = 3.0, 0.8, 0.05
    sim = fl.Simulation(BobPendulum(m, L, Izz))
    modes = fl.modal_analysis(sim)
    osc = modes.oscillatory
    assert osc.sum() == 1
    np.testing.assert_allclose(modes.frequencies[osc], np.sqrt(m * g_n * L / (Izz + m * L**2)) / (2 * np.pi),
                               rtol=1e-10)
    assert abs(modes.damping[osc][0]) < 1e-10
    locked = fl.modal_analysis(sim, lock=["rev"])
    assert len(locked.eigenvalues) == 0 and locked.locked == ["rev"]


def test_oil_spring_of_a_closed_cylinder():
    """Both ports closed, pure liquid: f = √(β (A_p²/V_A + A_r²/V_B) / m) / 2π to 1e-9; the pressures in the
    mode are in the ratio of the chamber stiffnesses (−β A_p/V_A : β A_r/V_B per metre of rod travel)."""
    beta, d_bore, d_rod, stroke, x0, m_rod, m_load = 1.5e9, 0.1, 0.056, 0.8, 0.3, 12.0, 800.0
    A_p = np.pi / 4 * d_bore**2
    A_r = A_p - np.pi / 4 * d_rod**2
    p_A = 100e5
    p_B = p_A * A_p / A_r  # static balance with p_amb = 0

    class Cyl(fl.Model):
        def __init__(self):
            super().__init__()
            fluid = Fluid(name="test oil", beta=beta)
            self.ground = Fixed()
            self.cyl = DoubleActingCylinder(d_bore=d_bore, d_rod=d_rod, stroke=stroke, m=m_rod, x_start=x0,
                                            p_A_start=p_A, p_B_start=p_B, p_amb=0.0, fluid=fluid)
            self.load = Mass(m=m_load)
            self.connect(self.ground.flange, self.cyl.flange_a)
            self.connect(self.cyl.flange_b, self.load.flange_a)

    modes = fl.modal_analysis(Cyl())
    V_A = 1e-5 + A_p * x0
    V_B = 1e-5 + A_r * (stroke - x0)
    f_ref = np.sqrt(beta * (A_p**2 / V_A + A_r**2 / V_B) / (m_rod + m_load)) / (2 * np.pi)
    osc = np.flatnonzero(modes.oscillatory)
    assert len(osc) == 1
    np.testing.assert_allclose(modes.frequencies[osc[0]], f_ref, rtol=1e-9)
    k = osc[0]
    dp_A, dp_B, dx = modes.shape("cyl.p_A")[k], modes.shape("cyl.p_B")[k], modes.shape("cyl.x")[k]
    np.testing.assert_allclose(dp_A / dx, -beta * A_p / V_A, rtol=1e-8)
    np.testing.assert_allclose(dp_B / dx, beta * A_r / V_B, rtol=1e-8)


# the joint is locked in the analysis: there the clamped basis is the right one
@pytest.mark.filterwarnings("ignore:.*clamped basis.*free revolute:flexlib.errors.ModalDataWarning")
def test_clamped_flexible_body_on_a_locked_joint_matches_its_fe_model():
    """A cantilever (32 beam elements, HRZ-lumped mass) attached by its reference node to a revolute joint: with
    the joint locked its six lowest modes are the FE model's clamped eigenfrequencies (eigh of K and M without
    node 0), to 1e-8; free, the lowest mode is the pendulum mode below them."""
    fe = beam_mesh((0, 0, 0), (1.2, 0, 0), 32, rectangle(0.04, 0.02), E=2.1e11, rho=7850, mass="lumped")
    data = modal_data_from_fe(fe, [0], 6, reference_node=0)

    class Arm(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World()
            self.rev = Revolute(n=[0, 0, 1], init={"phi": -np.pi / 2, "w": 0.0})
            self.arm = FlexibleBody(data)
            self.connect(self.world.frame_b, self.rev.frame_a)
            self.connect(self.rev.frame_b, self.arm.frame_a)

    sim = fl.Simulation(Arm())
    locked = fl.modal_analysis(sim, lock=["rev"], steady_state=True)
    node0 = fe.dof_map[int(fe.node_index([0])[0])]
    free_dofs = np.setdiff1d(np.arange(fe.K.shape[0]), node0[node0 >= 0])
    K = fe.K.toarray()[np.ix_(free_dofs, free_dofs)]
    M = fe.M.toarray()[np.ix_(free_dofs, free_dofs)]
    w2 = sla.eigh(K, M, eigvals_only=True, subset_by_index=[0, 5])
    np.testing.assert_allclose(np.sort(locked.frequencies), np.sqrt(w2) / (2 * np.pi), rtol=1e-8)
    free = fl.modal_analysis(sim, steady_state=True)
    assert free.frequencies[free.oscillatory][0] < 0.5 * locked.frequencies.min()


def test_bad_requests_are_named_errors():
    sim = fl.Simulation(TwoMass())
    with pytest.raises(fl.LinearizationError, match=r"src\.kk"):
        fl.linearize(sim, inputs=["src.kk"])
    with pytest.raises(fl.LinearizationError, match=r"m3\.s"):
        fl.linearize(sim, outputs=["m3.s"])
    with pytest.raises(fl.LinearizationError, match="cannot lock 'm1'"):
        fl.modal_analysis(sim, lock=["m1"])
    with pytest.raises(fl.LinearizationError, match="needs the time"):
        fl.linearize(sim, at=sim.run(0.1, progress=False))


def test_linearization_along_a_result_and_sweeps():
    """At a time of a swinging pendulum's result the state matrix is [[0, 1], [−ω0² cos θ, 0]] at the state of
    the point (θ from the bottom), to 1e-9; a sweep over result times gives f = ω0 √cos θ / 2π; a pose sweep of
    the closed cylinder over its piston position follows the oil-spring formula."""
    m, L, Izz = 3.0, 0.8, 0.05
    w0 = np.sqrt(m * g_n * L / (Izz + m * L**2))
    model = BobPendulum(m, L, Izz)
    model.rev.set_start("phi", -np.pi / 2 + 1.0)
    sim = fl.Simulation(model)
    res = sim.run(1.5, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False)
    lin = fl.linearize(sim, at=res, t=0.37, outputs=["rev.phi"])
    assert lin.states == ["rev.phi", "rev.w"]
    theta = lin.point.y[sim.compiled.y_names.index("rev.phi")] + np.pi / 2
    np.testing.assert_allclose(theta, res.value("rev.phi", 0.37) + np.pi / 2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(lin.A, [[0.0, 1.0], [-w0**2 * np.cos(theta), 0.0]], rtol=1e-9, atol=1e-12)
    times = [0.0, 0.2, 0.5, 0.9]
    sweep = fl.modal_sweep(sim, at=res, times=times, n_modes=1)
    th = np.array([res.value("rev.phi", tk) for tk in times]) + np.pi / 2
    np.testing.assert_allclose(sweep.frequencies[:, 0], w0 * np.sqrt(np.cos(th)) / (2 * np.pi), rtol=1e-8)

    beta, d_bore, d_rod, stroke, m_load = 1.5e9, 0.1, 0.056, 0.8, 800.0
    A_p = np.pi / 4 * d_bore**2
    A_r = A_p - np.pi / 4 * d_rod**2

    class Cyl(fl.Model):
        def __init__(self):
            super().__init__()
            self.ground = Fixed()
            self.cyl = DoubleActingCylinder(d_bore=d_bore, d_rod=d_rod, stroke=stroke, m=0.0, x_start=0.4,
                                            p_A_start=50e5, p_B_start=50e5 * A_p / A_r, p_amb=0.0,
                                            fluid=Fluid(name="test oil", beta=beta))
            self.load = Mass(m=m_load)
            self.connect(self.ground.flange, self.cyl.flange_a)
            self.connect(self.cyl.flange_b, self.load.flange_a)

    xs = [0.1, 0.4, 0.7]
    sweep = fl.modal_sweep(Cyl(), poses=[{"cyl.x_start": x} for x in xs], n_modes=1, steady_state=False)
    ref = [np.sqrt(beta * (A_p**2 / (1e-5 + A_p * x) + A_r**2 / (1e-5 + A_r * (stroke - x))) / m_load) / (2 * np.pi)
           for x in xs]
    np.testing.assert_allclose(sweep.frequencies[:, 0], ref, rtol=1e-9)
    assert len(sweep.points) == 3 and len(sweep.modes) == 3


# the rigid-DOF count does not depend on the basis: the rod keeps the clamped one
@pytest.mark.filterwarnings("ignore:.*clamped basis.*free revolute:flexlib.errors.ModalDataWarning")
def test_rigid_dof_count_on_a_loop_closed_through_a_flexible_body_warns():
    """A flexible rod pinned to the ground at both ends closes a loop through its elastic coordinates: the rigid
    degrees of freedom (none here) are counted with those coordinates held, a count that can miss some in an
    over-constrained mechanism with flexible links, so mobility (and lock="rigid") say so with an AnalysisWarning
    that names the count."""
    from flexlib.errors import AnalysisWarning
    from flexlib.fe import circle

    data = modal_data_from_fe(beam_mesh((0, 0, 0), (0.3, 0, 0), 4, circle(0.006), E=2.1e11, rho=7850.0), [0, 4], 1,
                              reference_node=0, title="rod")

    class PinnedRod(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.world = World()
            self.ja = Revolute(n=[0, 0, 1], guess={"phi": 0.0})
            self.rod = FlexibleBody(data)
            self.jb = Revolute(n=[0, 0, 1], guess={"phi": 0.0})
            self.pb = FixedTranslation(r=[0.3, 0, 0])
            self.connect(self.world.frame_b, self.ja.frame_a, self.pb.frame_a)
            self.connect(self.ja.frame_b, self.rod.frame_a)
            self.connect(self.rod.frame_b, self.jb.frame_a)
            self.connect(self.pb.frame_b, self.jb.frame_b)

    with pytest.warns(AnalysisWarning, match=r"this count \(0\) can miss"):
        assert fl.analysis.mobility(fl.Simulation(PinnedRod()), steady_state=True)[0] == 0
