"""FlexibleBody (floating frame of reference, modal superposition) against references it was not built from.

References
----------
- Cantilever statics: tip deflection ``ρ A g L⁴ / (8 E I)`` under its own weight and ``P L³ / (3 E I)`` under a tip
  load (Euler–Bernoulli; S. P. Timoshenko, J. M. Gere, *Mechanics of Materials*, §9.3).
- Conservation of energy and angular momentum of a free flexible body, computed independently from the FE mass
  points (positions, masses, rotary inertias of the Gauss points) and the mode shapes, not from the invariants.
- A rigid ``Body`` with the same mass properties (zero modes must reproduce it exactly).
- The spinning cantilever: out-of-plane frequency ``ω² = ω0² + K1 Ω²`` and in-plane ``ω² = ω0² + (K1 − 1) Ω²``
  with the Southwell coefficient K1 = 1.1933 of the first mode (A. D. Wright, C. E. Smith, R. W. Thresher,
  J. L. C. Wang, *J. Appl. Mech.* 49 (1982) 197–202; the in-plane −Ω² is the centrifugal softening of
  chordwise motion, e.g. L. Meirovitch, *Principles and Techniques of Vibrations*, 1997, §7.15).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import ModalDataWarning, ModalValidityWarning
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.components.mechanics.flexible.body import _cayley
from flexlib.components.mechanics.multibody import Body, Revolute, World, WorldForce
from flexlib.fe import Section, beam_mesh, modal_data_from_fe, rectangle
from flexlib.models.reference.signal_chain import VectorConstant
from tests.components.mechanics.flexible.benches import TipLoaded

# the seed-001 beam: steel-like, very slender
E, RHO, L, A, I_AREA = 2e11, 8000.0, 1.5, 1e-4, 1e-10
SEED_SECTION = Section(A=A, Iy=I_AREA, Iz=I_AREA, J=2 * I_AREA)
G = 9.81
QUIET = {"progress": False}


@pytest.fixture(scope="module")
def cantilever_data():
    """Seed beam, reference frame attached at node 0 (tangent frame), tip node 32 an interface node."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, SEED_SECTION, E=E, rho=RHO)
    return modal_data_from_fe(fe, [32], 4, reference_node=0)


class Cantilever(fl.Model):
    def __init__(self, data, g=G, tip_force=None, modes=None):
        super().__init__()
        self.world = World(g=g)
        self.beam = FlexibleBody(data, modes=modes, zeta=np.ones(data.n_modes if modes is None else modes))
        self.connect(self.world.frame_b, self.beam.frame_a)
        if tip_force is not None:
            self.src = VectorConstant(k=tip_force)
            self.force = WorldForce()
            self.connect(self.src.y, self.force.force)
            self.connect(self.force.frame_b, self.beam.frame_b)


def test_cantilever_under_gravity_and_tip_load(cantilever_data):
    """Statics (steady-state initialisation): own weight ρAgL⁴/8EI within 0.5 % (all ten modes: 1e-6) and with the
    four lowest modes only (0.5 %); a tip load P: PL³/3EI within 1e-6 (the tip's static mode is in the basis)."""
    sag = RHO * A * G * L**4 / (8 * E * I_AREA)
    for modes, tol in ((None, 1e-6), (4, 5e-3)):
        # the sag is 17 % of the length (0.22 rad at the tip): linear statics against linear beam theory, and the
        # validity monitor says it lies past the small-deformation range
        with pytest.warns(ModalValidityWarning, match=r"^beam: elastic (displacement .* is 16.6 % of|rotation 0.22)"):
            res = fl.Simulation(Cantilever(cantilever_data, modes=modes), use_cache=False).run(
                1e-3, steady_state=True, **QUIET)
        assert res["beam.frame_b.r_0"][0, 1] == pytest.approx(-sag, rel=tol)
    P = 0.05
    res = fl.Simulation(Cantilever(cantilever_data, g=0.0, tip_force=[0.0, 0.0, -P]), use_cache=False).run(
        1e-3, steady_state=True, **QUIET)
    tip = res["beam.frame_b.r_0"][0]
    assert tip[2] == pytest.approx(-P * L**3 / (3 * E * I_AREA), rel=1e-6)
    assert tip[1] == pytest.approx(0.0, abs=1e-12)


def test_free_body_conserves_energy_and_angular_momentum():
    """A free, undamped, spinning and vibrating Timoshenko beam (rotary inertia on) without gravity: kinetic plus
    strain energy and the angular momentum about the world origin, both computed from the FE mass points (not the
    invariants), are constant to 1e-7 and 1e-9 relative over 0.1 s."""
    fe = beam_mesh((0, 0, 0), (1.0, 0.1, 0.05), 8, rectangle(0.02, 0.03), E=7e10, rho=2700, theory="timoshenko")
    data = modal_data_from_fe(fe, [0, 8], 3, free=True).select([0, 1, 2, 3])
    m = data.n_modes
    rng = np.random.default_rng(0)
    q0, qd0 = rng.normal(size=m) * 3e-3, rng.normal(size=m) * 1e-1

    class FreeBeam(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World(g=0.0)
            self.beam = FlexibleBody(data, zeta=np.zeros(m), orientation_fixed=True, w_fixed=True,
                                     w_start=[3.0, -5.0, 20.0],
                                     init={"q": q0, "qd": qd0, "r_0": [0, 0, 0], "v_0": [0.1, 0, 0]})

    model = FreeBeam()
    res = fl.Simulation(model, use_cache=False).run(0.1, dt_out=0.002, rtol=1e-10, atol=1e-12, **QUIET)
    _t, _q, _r, T_ref = model.beam.motion(res)  # reference orientation recovered from frame_a (checked below)
    pts = fe.mass_points
    modes = fe.dof_fields(data.translational_modes, data.rotational_modes)
    Pt = (pts.Nt @ modes).reshape(-1, 3, m)
    Pr = (pts.Nr @ modes).reshape(-1, 3, m)
    Psi0 = data.rotational_modes[:, data.node_index(0), :].T
    energy, momentum = [], []
    for k in range(len(res.t)):
        q, qd, w = res["beam.q"][k], res["beam.qd"][k], res["beam.w"][k]
        T_rel = np.array(ca.DM(_cayley(ca.DM(Psi0 @ q), ca.DM(Psi0 @ qd))[0]))
        T = T_rel.T @ res["beam.frame_a.T"][k].reshape(3, 3, order="F")  # world -> body
        np.testing.assert_allclose(T_ref[k], T, atol=1e-14)
        x = pts.positions + Pt @ q
        v = T @ res["beam.v_0"][k] + np.cross(w, x) + Pt @ qd       # body axes
        om = w + Pr @ qd
        kinetic = 0.5 * pts.masses @ np.sum(v * v, axis=1) + 0.5 * np.einsum("pa,pab,pb->", om, pts.inertias, om)
        energy.append(kinetic + 0.5 * q @ data.generalized_stiffness @ q)
        r_w, v_w = res["beam.r_0"][k] + x @ T, v @ T
        momentum.append(pts.masses @ np.cross(r_w, v_w) + T.T @ np.einsum("pab,pb->a", pts.inertias, om))
    energy, momentum = np.array(energy), np.array(momentum)
    assert np.ptp(energy) / energy[0] < 1e-7
    assert np.abs(momentum - momentum[0]).max() / np.linalg.norm(momentum[0]) < 1e-9
    # the deformation really moved: not a rigid-body check in disguise
    assert np.ptp(res["beam.q"][:, 0]) > 5e-4


def test_zero_modes_moves_exactly_as_the_rigid_body():
    """A pendulum swung 1.2 rad: a FlexibleBody with modes=0 and a Body with the file's mass, centre of mass and
    inertia about the centre of mass give the same angle history and hinge force to the integration error at
    rtol 1e-11 (1e-7 rad, 1e-6 of the largest force over 2 s; the two DAEs differ in form, not in solution)."""
    fe = beam_mesh((0, 0, 0), (0.8, 0.05, 0.02), 6, rectangle(0.03, 0.02), E=2e11, rho=7800)
    data = modal_data_from_fe(fe, [0, 6], 4, free=True)

    class HingedBeam(fl.Model):
        def __init__(self, flexible: bool):
            super().__init__()
            self.world = World(g=G)
            self.rev = Revolute(n=[0, 0.3, 1], init={"phi": 1.2, "w": 0.0})
            if flexible:
                self.body = FlexibleBody(data, modes=0)
            else:
                self.body = Body(m=data.mass, r_CM=data.center_of_mass, I=data.inertia_cm)
            self.connect(self.world.frame_b, self.rev.frame_a)
            self.connect(self.rev.frame_b, self.body.frame_a)

    tol = {"rtol": 1e-11, "atol": 1e-12, "dt_out": 0.01}
    flex = fl.Simulation(HingedBeam(True), use_cache=False).run(2.0, **tol, **QUIET)
    rigid = fl.Simulation(HingedBeam(False), use_cache=False).run(2.0, **tol, **QUIET)
    np.testing.assert_allclose(flex["rev.phi"], rigid["rev.phi"], atol=1e-7, rtol=0)
    np.testing.assert_allclose(flex["rev.frame_a.f"], rigid["rev.frame_a.f"], rtol=0,
                               atol=1e-6 * np.abs(rigid["rev.frame_a.f"]).max())


def test_frames_stay_orthogonal_and_follow_the_frame_rule(cantilever_data):
    """A flexible pendulum released horizontally (large elastic rotations at the tip): the tip frame's T is
    orthogonal to 1e-12 and its finite-difference derivative matches −[w×]T (the engine's frame rule) to 1e-4
    of |w|."""

    class HingedBeam(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World(g=G)
            self.rev = Revolute(n=[0, 0, 1], init={"phi": 0.0, "w": 0.0})
            self.beam = FlexibleBody(cantilever_data, modes=4)
            self.connect(self.world.frame_b, self.rev.frame_a)
            self.connect(self.rev.frame_b, self.beam.frame_a)

    h = 1e-4
    with pytest.warns(ModalDataWarning, match="clamped basis at its reference node 0, which sits on the free revolute"):
        sim = fl.Simulation(HingedBeam(), use_cache=False)  # the cantilever basis on purpose: large tip rotations
    res = sim.run(0.6, dt_out=h, rtol=1e-10, atol=1e-12, **QUIET)
    T = res["beam.frame_b.T"].reshape(-1, 3, 3, order="F")
    w = res["beam.frame_b.w"]
    assert np.abs(np.einsum("kij,klj->kil", T, T) - np.eye(3)).max() < 1e-12
    dT = (T[2:] - T[:-2]) / (2 * h)
    skew = np.zeros((len(w), 3, 3))
    skew[:, 0, 1], skew[:, 0, 2], skew[:, 1, 2] = -w[:, 2], w[:, 1], -w[:, 0]
    skew -= skew.transpose(0, 2, 1)
    rule = -np.einsum("kij,kjl->kil", skew, T)[1:-1]
    assert np.abs(dT - rule).max() < 1e-4 * np.abs(w).max()
    # the tip frame really turned relative to the reference (elastic rotation of several mrad)
    rel = np.einsum("kij,klj->kil", T, res["beam.frame_a.T"].reshape(-1, 3, 3, order="F"))
    assert np.abs(rel[:, 0, 1]).max() > 5e-3


def _period(t, x):
    """Mean period from upward zero crossings (linear interpolation)."""
    k = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    tc = t[k] - x[k] * (t[k + 1] - t[k]) / (x[k + 1] - x[k])
    return (tc[-1] - tc[0]) / (len(tc) - 1)


@pytest.fixture(scope="module")
def spinning_data():
    fe = beam_mesh((0, 0, 0), (2.0, 0, 0), 24, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    return modal_data_from_fe(fe, [24], 6, reference_node=0, geometric_stiffening=True)


def test_spinning_beam_needs_geometric_stiffening(spinning_data):
    """A cantilever on a hub spinning at Ω = 30 rad/s about z (hub inertia 1e6 kg m²), its first flap (z) and lag (y)
    modes excited: with geometric stiffening the
    out-of-plane (z) and in-plane (y) tip vibration frequencies follow the Southwell laws within 0.5 %; without it
    the out-of-plane frequency stays at its non-rotating value (> 25 % low), the linear modal body's known
    failure."""
    omega = 30.0
    data = spinning_data
    low = [k for k in np.argsort(data.frequencies) if data.frequencies[k] < 50.0]
    assert len(low) == 4  # first and second bending in each plane

    class Spinning(fl.Model):
        def __init__(self, stiffening: bool):
            super().__init__()
            self.world = World(g=0.0)
            self.rev = Revolute(n=[0, 0, 1], init={"phi": 0.0, "w": omega})
            self.hub = Body(m=1.0, I=np.diag([1e6, 1e6, 1e6]))
            self.beam = FlexibleBody(data, modes=low, zeta=np.zeros(4), geometric_stiffening=stiffening,
                                     init={"q": np.zeros(4), "qd": [1e-3, 1e-3, 0.0, 0.0]})
            self.connect(self.world.frame_b, self.rev.frame_a)
            self.connect(self.rev.frame_b, self.hub.frame_a)
            self.connect(self.rev.frame_b, self.beam.frame_a)

    tip = data.node_index(24)
    Phi = np.stack([data.translational_modes[k, tip] for k in low], axis=1)  # (3, 4)
    K1 = 1.1933
    Iy, Iz, A_, rho = 0.03 * 0.02**3 / 12, 0.02 * 0.03**3 / 12, 6e-4, 7850.0
    w0 = [1.8751040687**2 * np.sqrt(2.1e11 * Ii / (rho * A_ * 2.0**4)) for Ii in (Iy, Iz)]
    periods = {}
    for stiffening in (True, False):
        # the centrifugal stretch is a static response the four bending modes leave out (the monitor says so; it is
        # µm, and the bending frequencies do not depend on it)
        with pytest.warns(ModalValidityWarning, match=r"^beam: the left-out modes' static response carries"):
            res = fl.Simulation(Spinning(stiffening), use_cache=False).run(1.0, dt_out=2e-4, rtol=1e-9,
                                                                             atol=1e-12, **QUIET)
        u = res["beam.q"] @ Phi.T
        periods[stiffening] = (_period(res.t, u[:, 2]), _period(res.t, u[:, 1]))
    flap, lag = (2 * np.pi / p for p in periods[True])
    assert flap == pytest.approx(np.sqrt(w0[0] ** 2 + K1 * omega**2), rel=5e-3)
    assert lag == pytest.approx(np.sqrt(w0[1] ** 2 + (K1 - 1) * omega**2), rel=5e-3)
    flap_linear = 2 * np.pi / periods[False][0]
    assert flap_linear == pytest.approx(w0[0], rel=5e-3)
    assert flap_linear < 0.75 * flap


def test_cache_keys_on_modal_content_not_path(tmp_path, cantilever_data, monkeypatch):
    """The same data under two file names reuses the compiled model; changed data in the same file rebuilds it."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path / "cache"))
    a, b = tmp_path / "a.h5", tmp_path / "b.h5"
    cantilever_data.write(a)
    cantilever_data.write(b)

    class BeamModel(fl.Model):
        def __init__(self, path):
            super().__init__()
            self.world = World(g=G)
            self.beam = FlexibleBody(path, modes=2)
            self.connect(self.world.frame_b, self.beam.frame_a)

    assert not fl.Simulation(BeamModel(a)).build_info["cached"]
    assert fl.Simulation(BeamModel(b)).build_info["cached"]
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, SEED_SECTION, E=1.01 * E, rho=RHO)
    modal_data_from_fe(fe, [32], 4, reference_node=0).write(a)
    assert not fl.Simulation(BeamModel(a)).build_info["cached"]


# energy conservation holds in any basis: the arm keeps the clamped one the build advises against
@pytest.mark.filterwarnings("ignore:.*clamped basis.*free revolute:flexlib.errors.ModalDataWarning")
def test_geometric_stiffening_keeps_energy(spinning_data):
    """A cantilever on a free pin (no torque, no damping), spinning at 3 rad/s with its lag modes excited: the
    stiffened body's energy — kinetic energy of the FE mass points, minus the foreshortening term
    ½ ω² qᵀ G_ωzz q the stiffening stands for, plus the strain energy — stays constant to 1e-8 (the drift falls
    with the tolerance: 1.6e-7 at rtol 1e-9, 3e-9 at 1e-11) while the spin rate swings by 19 rad/s with the
    vibration."""
    data = spinning_data
    lag = [k for k in np.argsort(data.frequencies)
           if np.abs(data.translational_modes[k, :, 1]).max() > np.abs(data.translational_modes[k, :, 2]).max()][:3]

    class PinnedBeam(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World(g=0.0)
            self.pin = Revolute(n=[0, 0, 1], init={"phi": 0.0, "w": 3.0})
            self.beam = FlexibleBody(data, modes=lag, zeta=np.zeros(3), geometric_stiffening=True,
                                     init={"q": [0.05, 0.0, 0.0], "qd": [0.0, 0.5, 0.0]})
            self.connect(self.world.frame_b, self.pin.frame_a)
            self.connect(self.pin.frame_b, self.beam.frame_a)

    res = fl.Simulation(PinnedBeam(), use_cache=False).run(1.0, dt_out=0.01, rtol=1e-11, atol=1e-13, **QUIET)
    sel = data.select(lag)
    fe = beam_mesh((0, 0, 0), (2.0, 0, 0), 24, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0).constrained([0])
    pts = fe.mass_points
    shapes = fe.dof_fields(sel.translational_modes, sel.rotational_modes)
    Pt, Pr = (pts.Nt @ shapes).reshape(-1, 3, 3), (pts.Nr @ shapes).reshape(-1, 3, 3)
    G_zz = sel.geometric_stiffness["omega_zz"]
    energy = []
    for q, qd, w in zip(res["beam.q"], res["beam.qd"], res["beam.w"], strict=True):
        x = pts.positions + Pt @ q
        v, om = np.cross(w, x) + Pt @ qd, w + Pr @ qd
        kinetic = 0.5 * pts.masses @ np.sum(v * v, axis=1) + 0.5 * np.einsum("pa,pab,pb->", om, pts.inertias, om)
        energy.append(kinetic - 0.5 * w[2] ** 2 * (q @ G_zz @ q) + 0.5 * q @ sel.generalized_stiffness @ q)
    assert np.ptp(energy) / energy[0] < 1e-8
    assert np.ptp(res["beam.w"][:, 2]) > 5.0  # the spin really swings


def test_docs_example_runs(tmp_path, monkeypatch, capsys):
    """The example of docs/flexible_body.md runs as written; the arm hangs below its hinge line after 2 s and has
    deflected (nonzero modal coordinates)."""
    from pathlib import Path

    doc = (Path(__file__).parents[4] / "docs" / "flexible_body.md").read_text()
    code = doc.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path / "cache"))
    scope: dict = {}
    exec(compile(code.replace("dt_out=0.01)", "dt_out=0.01, progress=False)"), "docs/flexible_body.md", "exec"),
         scope)
    res = scope["res"]
    assert res["arm.frame_b.r_0"][-1, 1] < -0.5
    assert np.abs(res["arm.q"][-1]).max() > 1e-6
    assert capsys.readouterr().out.strip()


def _fourbar(coupler_E: float | None):
    """The crank-rocker four-bar of test_loops (crank 0.2 m, coupler 0.7 m, rocker 0.9 m, ground 0.6 m; 1, 2,
    1.5 kg uniform rods; no gravity; crank at 0.3 rad, 6 rad/s), the coupler rigid (``None``) or a FlexibleBody
    beam of Young's modulus ``coupler_E`` [Pa] with two frames (its pins) and its first in-plane and first
    out-of-plane bending modes (the pins lock the latter: the loop's tilting rows stop being redundant)."""
    from flexlib.components.mechanics.multibody import Body, FixedTranslation

    class FourBar(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World(g=0.0)
            self.r1 = Revolute(n=[0, 0, 1], init={"phi": 0.3, "w": 6.0})
            self.crank_rod = FixedTranslation(r=[0.2, 0, 0])
            self.crank = Body(m=1.0, r_CM=[0.1, 0, 0], I=np.diag([1e-6, 1.0 * 0.2**2 / 12, 1.0 * 0.2**2 / 12]))
            self.r2 = Revolute(n=[0, 0, 1])
            if coupler_E is None:
                self.coupler = Body(m=2.0, r_CM=[0.35, 0, 0], I=np.diag([1e-6, 2.0 * 0.7**2 / 12, 2.0 * 0.7**2 / 12]))
                self.coupler_rod = FixedTranslation(r=[0.7, 0, 0])
                self.connect(self.coupler.frame_a, self.coupler_rod.frame_a)
                coupler_a, coupler_b = self.coupler.frame_a, self.coupler_rod.frame_b
            else:
                rho = 2.0 / (0.7 * 0.02 * 0.01)
                fe = beam_mesh((0, 0, 0), (0.7, 0, 0), 10, rectangle(0.02, 0.01), E=coupler_E, rho=rho)
                data = modal_data_from_fe(fe, [0, 10], 2, free=True)
                self.coupler = FlexibleBody(data, modes=2)
                coupler_a, coupler_b = self.coupler.frame_a, self.coupler.frame_b
            self.r3 = Revolute(n=[0, 0, 1])
            self.rocker = Body(m=1.5, r_CM=[0.45, 0, 0], I=np.diag([1e-6, 1.5 * 0.9**2 / 12, 1.5 * 0.9**2 / 12]))
            self.rocker_rod = FixedTranslation(r=[0.9, 0, 0])
            self.ground = FixedTranslation(r=[0.6, 0, 0])
            self.r4 = Revolute(n=[0, 0, 1])
            self.connect(self.world.frame_b, self.r1.frame_a, self.ground.frame_a)
            self.connect(self.r1.frame_b, self.crank_rod.frame_a, self.crank.frame_a)
            self.connect(self.crank_rod.frame_b, self.r2.frame_a)
            self.connect(self.r2.frame_b, coupler_a)
            self.connect(coupler_b, self.r3.frame_a)
            self.connect(self.ground.frame_b, self.r4.frame_a)
            self.connect(self.r4.frame_b, self.rocker.frame_a, self.rocker_rod.frame_a)
            self.connect(self.rocker_rod.frame_b, self.r3.frame_b)

    return FourBar()


def test_flexible_coupler_closes_a_loop():
    """A four-bar whose coupler is a FlexibleBody (its two frames in the loop) with one in-plane and one out-of-plane
    mode: the pins lock the out-of-plane mode, so the loop drops two redundant rows (not three) and the flexible
    body's default start values are taken only for the free mode (no over-specified start). With a stiff coupler
    (E = 2e13 Pa, 100× steel) the crank angle follows the rigid four-bar within 2e-4 rad over 0.5 s; with a steel
    coupler the in-plane mode deflects and the locked one stays at round-off."""
    tol = {"dt_out": 0.005, "rtol": 1e-8, "atol": 1e-10, **QUIET}
    rigid = fl.Simulation(_fourbar(None), use_cache=False).run(0.5, **tol)
    sim = fl.Simulation(_fourbar(2e13), use_cache=False)
    assert sum("dropped redundant constraint" in line for line in sim.report.redundant) == 2
    stiff = sim.run(0.5, **tol)
    np.testing.assert_allclose(np.interp(rigid.t, stiff.t, stiff["r1.phi"]), rigid["r1.phi"], atol=2e-4, rtol=0)
    steel = fl.Simulation(_fourbar(2e11), use_cache=False).run(0.5, **tol)
    q = steel["coupler.q"]
    assert np.abs(q[:, 0]).max() > 1e-6
    assert np.abs(q[:, 1]).max() < 1e-12


def test_stress_and_drawing_from_a_simulation(tmp_path):
    """A rectangular cantilever (20 × 40 mm, 1 m) under a 500 N tip load in −y, statics by steady-state
    initialisation: the von Mises stress at the clamped root's outer fibre from the body's stress modes equals
    beam theory's P·L·(h/2)/Iz within 1e-6, the tip deflects by PL³/3EIz, and the motion writes a VTK series whose
    collection lists every output instant."""
    from flexlib.fe import nodal_stress, von_mises, write_vtk_series

    b, h, L, P, Ey = 0.02, 0.04, 1.0, 500.0, 2.1e11
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 16, rectangle(b, h), E=Ey, rho=7850.0)
    data = modal_data_from_fe(fe, [16], 4, reference_node=0, stress_fibre=(h / 2, 0.0))

    model = TipLoaded(data, P)
    res = fl.Simulation(model, use_cache=False).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    Iz = b * h**3 / 12
    assert res["beam.frame_b.r_0"][0, 1] == pytest.approx(-P * L**3 / (3 * Ey * Iz), rel=1e-6)
    t, q, r_0, T = model.beam.motion(res)
    root = von_mises(nodal_stress(model.beam.modal_data, q[:1], nodes=[0]))[0, 0]
    assert root == pytest.approx(P * L * (h / 2) / Iz, rel=1e-6)
    path = write_vtk_series(tmp_path / "beam.pvd", model.beam.modal_data, t, q, r_0, T)
    assert path.read_text().count("<DataSet") == len(t)


def test_kane_spin_up_beam():
    """The spin-up beam of Kane, Ryan & Banerjee (J. Guid. Control Dyn. 10 (1987) 139-151), the benchmark of geometric
    stiffening: L = 10 m, ρA = 1.2 kg/m, EI = 14 000 N m², hub angle θ = ω_s/T_s (t²/2 + (T_s/2π)² (cos(2πt/T_s) − 1))
    up to T_s = 15 s, then ω_s t − ω_s T_s/2, ω_s = 6 rad/s (above the first bending frequency, 3.8 rad/s). With
    stiffening, the in-plane tip deflection at t = 5, 7.5, 10 s equals the quasi-static deflection of the full FE
    model under the Euler load at the current α, stiffened by the centrifugal field's geometric stiffness and softened
    by −ω² M (in-plane), within 3 % (the spin-up is slow against the 0.6 Hz mode); after the spin-up it returns to
    below 1 cm. Without stiffening the linear modal body diverges (the textbook failure)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla

    from flexlib.components.mechanics.rotational import Position
    from flexlib.fe import geometric_stiffness_matrix, inertial_load_cases

    L, rhoA, EI, Ey = 10.0, 1.2, 14000.0, 7e10
    A, Iz = 4e-4, EI / Ey
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 20, Section(A=A, Iy=10 * Iz, Iz=Iz, J=20 * Iz), E=Ey, rho=rhoA / A)
    data = modal_data_from_fe(fe, [20], 8, reference_node=0, geometric_stiffening=True)
    t = data.translational_modes
    in_plane = [k for k in np.argsort(data.frequencies)
                if np.abs(t[k, :, 1]).max() > max(np.abs(t[k, :, 0]).max(), 10 * np.abs(t[k, :, 2]).max())][:4]
    Ts, ws = 15.0, 6.0

    class Profile(fl.Component):
        y = fl.Output(unit="rad", doc="Hub angle")

        def equations(self):
            tt = fl.time
            spin_up = ws / Ts * (tt**2 / 2 + (Ts / (2 * np.pi)) ** 2 * (ca.cos(2 * np.pi * tt / Ts) - 1))
            return [fl.eq(self.y, fl.if_else(tt < Ts, spin_up, ws * (tt - Ts / 2)))]

    class SpinUp(fl.Model):
        def __init__(self, stiffening: bool):
            super().__init__()
            self.world = World(g=0.0)
            self.hub = Revolute(n=[0, 0, 1], use_axis_flange=True)
            self.drive = Position()
            self.profile = Profile()
            self.beam = FlexibleBody(data, modes=in_plane, zeta=np.zeros(4), geometric_stiffening=stiffening)
            self.connect(self.world.frame_b, self.hub.frame_a)
            self.connect(self.hub.frame_b, self.beam.frame_a)
            self.connect(self.profile.y, self.drive.phi_ref)
            self.connect(self.drive.flange, self.hub.axis)

    def tip_deflection(res):
        T_hub = res["beam.frame_a.T"].reshape(-1, 3, 3, order="F")
        return np.einsum("kij,kj->ki", T_hub, res["beam.frame_b.r_0"] - res["beam.frame_a.r_0"])[:, 1]

    res = fl.Simulation(SpinUp(True), use_cache=False).run(20.0, dt_out=0.05, rtol=1e-7, atol=1e-9, **QUIET)
    v = tip_deflection(res)
    held = fe.constrained([0])
    cases = inertial_load_cases(held)
    KG = geometric_stiffness_matrix(held, sla.spsolve(held.K.tocsc(), cases["omega_zz"]))
    y = held.dofs(list(range(1, 21)), ["uy"])
    My = sp.csr_matrix((held.M.tocsr()[np.ix_(y, y)].toarray().ravel(),
                        (np.repeat(y, y.size), np.tile(y, y.size))), shape=held.M.shape)
    for tq in (5.0, 7.5, 10.0):
        omega = ws / Ts * (tq - Ts / (2 * np.pi) * np.sin(2 * np.pi * tq / Ts))
        alpha = ws / Ts * (1 - np.cos(2 * np.pi * tq / Ts))
        u = sla.spsolve((held.K + omega**2 * (KG - My)).tocsc(), alpha * cases["alpha_z"])
        quasi_static = u[held.dofs([20], ["uy"])][0]
        assert np.interp(tq, res.t, v) == pytest.approx(quasi_static, rel=0.03)
    assert abs(v[-1]) < 0.01
    with pytest.raises(fl.SolverError):  # diverges: IDA gives up, or
        # ... the run ends and the validity monitor says the deformation left the small-deformation range
        with pytest.warns(ModalValidityWarning, match=r"^beam: elastic (displacement|rotation)"):
            linear = fl.Simulation(SpinUp(False), use_cache=False).run(20.0, dt_out=0.05, rtol=1e-7, atol=1e-9,
                                                                       **QUIET)
        if np.abs(tip_deflection(linear)).max() > L:  # ... the deflection exceeds the beam's length
            raise fl.SolverError("diverged")
