"""Craig–Bampton reduction (improved, orthonormalised), inertia invariants, and the seed-001 pinned-free beam.

References: Craig & Bampton 1968 (constraint modes reproduce the static response to interface loads exactly);
Blevins 1979 tab. 8-1 (free-free beta_n L = 4.7300, 7.8532, 10.9956; pinned-free and clamped-pinned
beta_n L = 3.9266, 7.0686, 10.2102); rigid-body properties of a uniform rod (rho A L, L/2, rho A L^3/12 about
the centre of mass).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate as si
import scipy.linalg as la
import scipy.optimize as so
import scipy.sparse.linalg as sla

from flexlib.fe import (
    ModalData,
    Section,
    beam_mesh,
    craig_bampton,
    inertia_invariants,
    modal_data_from_fe,
    modal_participation,
    rectangle,
)

E, RHO, L = 2.1e11, 7850.0, 2.0
SEC = rectangle(0.02, 0.03)
#: The pinned-free beam of seed 001 (Cuadrado et al.): 8000 kg/m3, 2e11 Pa, 1.5 m, 1e-4 m2, 1e-10 m4.
SEED = {"E": 2e11, "rho": 8000.0, "L": 1.5, "section": Section(A=1e-4, Iy=1e-10, Iz=1e-10, J=2e-10, name="seed 001")}


def y_bending(md):
    """Mask of modal-data modes whose translation is mostly along y."""
    t = md.translational_modes
    parts = np.einsum("mna,mna->ma", t, t)
    return (parts[:, 1] > 0.9 * parts.sum(axis=1)) & (parts[:, 1] > 1e-9 * parts[:, 1].max())


@pytest.mark.parametrize("orthogonalize", [True, False])
def test_static_response_to_interface_loads_is_exact(orthogonalize):
    """Cantilever (32 elements) with interface nodes 16 and 32 and 4 fixed-interface modes: the reduced model's
    static response to any interface load equals the full model's at every DOF (1e-10 relative, by
    construction of the constraint modes)."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, SEC, E=E, rho=RHO).constrained([0])
    b = fe.dofs([16, 32])
    cb = craig_bampton(fe.M, fe.K, b, 4, orthogonalize=orthogonalize)
    rng = np.random.default_rng(1)
    F = np.zeros((fe.n_dofs, 3))
    F[b] = rng.normal(size=(b.size, 3)) * np.array([1e3, 1e3, 1e3, 1e2, 1e2, 1e2] * 2)[:, None]
    full = sla.spsolve(fe.K.tocsc(), F)
    reduced = cb.modes @ np.linalg.solve(cb.generalized_stiffness, cb.modes.T @ F)
    assert np.abs(reduced - full).max() <= 1e-10 * np.abs(full).max()


def test_lowest_frequencies_match_full_model():
    """Cantilever, interface nodes 16 and 32, 80 fixed-interface modes: the lowest 6 frequencies (x-y and x-z
    bending) of the orthonormalised Craig–Bampton model equal the full FE model's to 1e-6 relative (measured
    2e-7; with 40 modes 5e-6), and the modes are mass-orthonormal (1e-9)."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, SEC, E=E, rho=RHO).constrained([0])
    cb = craig_bampton(fe.M, fe.K, fe.dofs([16, 32]), 80)
    full = np.sqrt(la.eigh(fe.K.toarray(), fe.M.toarray(), eigvals_only=True)[:6])
    assert np.abs(cb.omega[:6] / full - 1).max() < 1e-6
    assert np.abs(cb.modes.T @ (fe.M @ cb.modes) - np.eye(cb.modes.shape[1])).max() < 1e-9
    assert np.allclose(cb.generalized_stiffness, np.diag(cb.omega**2), rtol=0, atol=1e-9 * cb.omega.max() ** 2)


@pytest.mark.parametrize(("mass", "n_el", "tol"), [("consistent", 32, 5e-3), ("lumped", 32, 1e-2),
                                                  ("lumped", 64, 2.5e-3)])
def test_free_free_frequencies_and_invariants(mass, n_el, tol):
    """Free beam, interface at both ends, 12 fixed-interface modes, six rigid modes removed: first three x-y
    bending frequencies vs (beta_n L)^2 sqrt(E Iz/(rho A L^4)), beta_n L = 4.7300, 7.8532, 10.9956: within
    0.5 % at 32 elements with consistent mass (measured 0.010, 0.092, 0.13 % with 12 fixed-interface modes; the
    full FE model alone 2e-5); the HRZ-lumped mass converges as h^2 (measured -0.35, -0.56, -0.82 % at 32
    elements, -0.08, -0.07, -0.11 % at 64), tested at 1 % and 0.25 %. Body mass
    rho A L (1e-12), centre of mass L/2, inertia about the centre of mass rho A L^3/12 in bending (EB: no
    rotary inertia) and rho Ip L in torsion (consistent mass, 1e-10); the modes are
    mass-orthogonal to the rigid motions, so I3 = I4 = 0 (mean-axis conditions, 1e-9 relative)."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), n_el, SEC, E=E, rho=RHO, mass=mass)
    md = modal_data_from_fe(fe, [0, n_el], 12, title="free-free")
    assert md.provenance["n_rigid_modes_removed"] == 6
    assert np.all(md.frequencies > 0)
    got = 2 * math.pi * md.frequencies[y_bending(md)][:3]
    ref = np.array([4.7300, 7.8532, 10.9956]) ** 2 * math.sqrt(E * SEC.Iz / (RHO * SEC.A * L**4))
    assert np.abs(got / ref - 1).max() < tol
    m = RHO * SEC.A * L
    assert md.mass == pytest.approx(m, rel=1e-12)
    assert md.center_of_mass == pytest.approx([L / 2, 0, 0], abs=1e-12 * L)
    if mass == "consistent":
        Icm = np.diag([RHO * SEC.Ip * L, m * L**2 / 12, m * L**2 / 12])
        assert np.abs(md.inertia_cm - Icm).max() < 1e-10 * m * L**2
    scale = math.sqrt(m) * L
    assert np.abs(md.invariants["I3"]).max() < 1e-9 * math.sqrt(m)
    assert np.abs(md.invariants["I4"]).max() < 1e-9 * scale


def test_consistent_invariants_against_direct_integration():
    """I1..I9 of the consistent description equal a direct numerical integration of the continuum with
    independently coded Hermite/linear interpolation (200 midpoint samples per element, cross products by
    numpy.cross), for a beam off the origin (tolerance 1e-5 relative, the midpoint rule's error); I6 equals
    Phi^T M Phi and I7 the rigid-body block of the FE mass (1e-10)."""
    n_el, start, length = 4, np.array([0.1, 0.2, -0.3]), 1.2
    fe = beam_mesh(start, start + np.array([length, 0, 0]), n_el, SEC, E=E, rho=RHO)
    modes = np.random.default_rng(3).normal(size=(fe.n_dofs, 3))
    inv = inertia_invariants(fe.mass_points, modes)
    R = fe.rigid_body_modes()
    assert np.abs(inv["I6"] - modes.T @ fe.M @ modes).max() < 1e-10 * np.abs(inv["I6"]).max()
    assert np.abs(inv["I7"] - (R.T @ fe.M @ R)[3:, 3:]).max() < 1e-10 * np.abs(inv["I7"]).max()

    he = length / n_el
    s = (np.arange(200) + 0.5) / 200
    H = np.array([2 * s**3 - 3 * s**2 + 1, he * (s**3 - 2 * s**2 + s), -2 * s**3 + 3 * s**2, he * (s**3 - s**2)])
    dm = RHO * SEC.A * he / 200
    pos, disp = [], []
    for e in range(n_el):
        d = modes[6 * e:6 * e + 12]  # (12, 3): node e then node e+1
        u = np.stack([np.outer(1 - s, d[0]) + np.outer(s, d[6]),
                      H.T @ d[[1, 5, 7, 11]],
                      H.T @ (d[[2, 4, 8, 10]] * np.array([1, -1, 1, -1])[:, None])], axis=1)  # (200, 3, 3)
        pos.append(start + np.outer(e * he + s * he, [1, 0, 0]))
        disp.append(u)
    pos, disp = np.concatenate(pos), np.concatenate(disp)  # (P, 3), (P, 3 comps, 3 modes)

    def sk(v):
        return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    I5 = np.zeros((3, 3, 3))
    I8 = np.zeros((3, 3, 3))
    I9 = np.zeros((3, 3, 3, 3))
    for p in range(pos.shape[0]):
        Phi = disp[p]
        for j in range(3):
            I5[j] += dm * sk(Phi[:, j]) @ Phi
            I8[j] += dm * sk(pos[p]).T @ sk(Phi[:, j])
            for k in range(3):
                I9[j, k] += dm * sk(Phi[:, j]).T @ sk(Phi[:, k])
    I3 = dm * disp.sum(axis=0)
    I2 = dm * pos.sum(axis=0)
    for name, ref in (("I2", I2), ("I3", I3), ("I5", I5), ("I8", I8), ("I9", I9)):
        assert np.abs(inv[name] - ref).max() < 1e-5 * np.abs(ref).max(), name
    assert float(inv["I1"]) == pytest.approx(RHO * SEC.A * length, rel=1e-12)


def test_seed_pinned_free_beam_frequencies(tmp_path):
    """Seed 001 beam (8000 kg/m3, 2e11 Pa, 1.5 m, 1e-4 m2, 1e-10 m4), 32 elements, interface nodes at the pin
    and the tip, 10 fixed-interface modes: the free-body modal data, pinned at node 0 through the linearised
    floating-frame equations (mass matrix from I1, I2, I3, I4, I6, I7; constraint: frame translation plus the
    node's modal translation = 0), gives the pinned-free frequencies (beta_n L)^2 sqrt(E I/(rho A L^4)),
    beta_n L = 3.9266, 7.0686, 10.2102, within 0.5 % (computed from the data read back from its file)."""
    s = SEED
    fe = beam_mesh((0, 0, 0), (s["L"], 0, 0), 32, s["section"], E=s["E"], rho=s["rho"])
    md = modal_data_from_fe(fe, [0, 32], 10, title="seed 001 pinned-free beam")
    md = ModalData.read(md.write(tmp_path / "seed001.h5"))  # the file, as a FlexibleBody would load it
    inv, m = md.invariants, md.n_modes
    n = 6 + m
    Mf = np.zeros((n, n))
    Mf[:3, :3] = float(inv["I1"]) * np.eye(3)
    I2x = np.array([[0, -inv["I2"][2], inv["I2"][1]], [inv["I2"][2], 0, -inv["I2"][0]],
                    [-inv["I2"][1], inv["I2"][0], 0]])
    Mf[:3, 3:6], Mf[3:6, :3] = -I2x, I2x
    Mf[:3, 6:], Mf[6:, :3] = inv["I3"], inv["I3"].T
    Mf[3:6, 3:6] = inv["I7"]
    Mf[3:6, 6:], Mf[6:, 3:6] = inv["I4"], inv["I4"].T
    Mf[6:, 6:] = inv["I6"]
    Kf = np.zeros((n, n))
    Kf[6:, 6:] = md.generalized_stiffness
    C = np.hstack([np.eye(3), np.zeros((3, 3)), md.translational_modes[:, md.node_index(0), :].T])
    N = la.null_space(C)
    w = la.eigh(N.T @ Kf @ N, N.T @ Mf @ N, eigvals_only=True)
    omega = np.sqrt(np.clip(w, 0, None))
    elastic = np.unique(np.round(omega[omega > 1.0], 3))[:3]  # each bending frequency twice (square section)
    ref = np.array([3.9266, 7.0686, 10.2102]) ** 2 * math.sqrt(s["E"] * 1e-10 / (s["rho"] * 1e-4 * s["L"] ** 4))
    assert np.abs(elastic / ref - 1).max() < 5e-3


def test_mpf_of_seed_beam_against_analytic_modes():
    """MPF method on the seed-001 beam: fixed-interface (clamped-pinned) modes of 64 elements under the
    distributed inertia load of a rigid rotation with angular acceleration alpha (q(x) = rho A alpha x). The
    shares of the first four bending modes equal those from the analytic clamped-pinned modes
    (q_i = int psi_i x dx / omega_i^2, beta_n L roots of tan = tanh) within 0.5 % (relative); the first mode
    dominates (100 %) and only the second is above 1 % (the paper's Table 2 conclusion: 100, 3.46, 0.77, 0.17)."""
    s = SEED
    Lb, n_el = s["L"], 64
    # out-of-plane Iy raised so the x-y and x-z bending modes do not coincide (their eigenvectors would mix)
    section = Section(A=1e-4, Iy=4e-10, Iz=1e-10, J=2e-10, name="seed 001, stiff out of plane")
    fe = beam_mesh((0, 0, 0), (Lb, 0, 0), n_el, section, E=s["E"], rho=s["rho"])
    b = np.concatenate([fe.dofs([0]), fe.dofs([n_el], ["ux", "uy", "uz"])])
    cb = craig_bampton(fe.M, fe.K, b, 24, orthogonalize=False)
    nb = b.size
    modes, omega = cb.basis[:, nb:], cb.fixed_interface_omega
    field = np.zeros(fe.n_dofs)  # v(x) = x, rz = 1: the rigid-rotation field, so M @ field is the consistent load
    field[fe.dof_map[:, 1]] = fe.nodes[:, 0]
    field[fe.dof_map[:, 5]] = 1.0
    table = modal_participation(modes, omega**2, fe.M @ field, frequencies=omega / (2 * math.pi))
    shares = np.array([r.share for r in table.rows if r.share > 1e-6])[:4]

    roots = [so.brentq(lambda z: math.tan(z) - math.tanh(z), (n + 0.25) * math.pi - 0.3, (n + 0.25) * math.pi + 0.3)
             for n in (1, 2, 3, 4)]
    amps = []
    for z in roots:
        beta = z / Lb
        sig = (math.cosh(z) - math.cos(z)) / (math.sinh(z) - math.sin(z))

        def psi(x, beta=beta, sig=sig):
            return math.cosh(beta * x) - math.cos(beta * x) - sig * (math.sinh(beta * x) - math.sin(beta * x))

        norm = si.quad(lambda x: psi(x) ** 2, 0, Lb, epsabs=0, epsrel=1e-12, limit=200)[0]
        amps.append(si.quad(lambda x: psi(x) * x, 0, Lb, epsabs=0, epsrel=1e-12, limit=200)[0]
                    / math.sqrt(norm) / beta**4)
    ref = np.abs(amps) / np.abs(amps).max() * 100
    assert np.abs(shares / ref - 1).max() < 5e-3
    assert shares[0] == pytest.approx(100.0)
    kept = [r for r in table.rows if r.kept]
    assert len(kept) == 2
    assert "MPF [%]" in str(table)


def test_sparse_shift_invert_matches_dense(monkeypatch):
    """Fixed-interface modes of a 121-node Timoshenko box beam: scipy eigsh shift-invert on the sparse LU of
    K_ii (used above 400 interior DOFs) equals the dense solution to 1e-9 relative."""
    import flexlib.fe.reduction as reduction
    from flexlib.fe import box

    fe = beam_mesh((0, 0, 0), (5.0, 0, 0), 120, box(0.2, 0.3, 0.01), E=E, rho=RHO, theory="timoshenko")
    fe = fe.constrained([0])
    sparse = craig_bampton(fe.M, fe.K, fe.dofs([120]), 15)
    monkeypatch.setattr(reduction, "_DENSE_LIMIT", 10**9)
    dense = craig_bampton(fe.M, fe.K, fe.dofs([120]), 15)
    assert np.abs(sparse.fixed_interface_omega / dense.fixed_interface_omega - 1).max() < 1e-9
    assert np.abs(sparse.omega / dense.omega - 1).max() < 1e-9


def test_modal_section_forces_reproduce_static_moment():
    """Clamped beam (node 0 held, free=False), interface node 32, 6 fixed-interface modes, stress fibre at the
    top corner: a static tip force P through the modal data (q = K_gen^-1 Phi_tip^T P) gives the bending moment
    P (L - x) at every element end and the root fibre stress -P L (h/2)/Iz, exact (1e-9 relative): the
    constraint mode spans the static response to interface loads."""
    b, h = 0.02, 0.03
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, rectangle(b, h), E=E, rho=RHO).constrained([0])
    md = modal_data_from_fe(fe, [32], 6, free=False, stress_fibre=(h / 2, b / 2))
    P = 40.0
    q = np.linalg.solve(md.generalized_stiffness, md.translational_modes[:, md.node_index(32), 1] * P)
    Mz = np.einsum("m,meb->eb", q, md.section_forces[..., 5])
    x = np.array([[e, e + 1] for e in range(32)]) * L / 32
    assert np.abs(Mz - P * (L - x)).max() < 1e-9 * P * L
    sigma_root = q @ md.stress_modes[:, md.node_index(0), 0]
    assert sigma_root == pytest.approx(-P * L * (h / 2) / SEC.Iz, rel=1e-9)


def test_external_fe_model_gets_lumped_invariants(tmp_path):
    """An FE model read from a file (no element data) gets the lumped description from M: nodal masses are the
    translational row sums (total mass rho A L exact, 1e-12; centre of mass L/2 exact for a uniform beam, whose
    row sums are symmetric), and the invariants are marked "lumped"; frequencies equal those of the beam model."""
    from flexlib.fe import read_fe

    fe = beam_mesh((0, 0, 0), (L, 0, 0), 16, SEC, E=E, rho=RHO)
    fe.write_npz(tmp_path / "beam.npz")
    ext = read_fe(tmp_path / "beam.npz")
    md = modal_data_from_fe(ext, [0, 16], 6)
    ref = modal_data_from_fe(fe, [0, 16], 6)
    assert md.mass_description == "lumped" and ref.mass_description == "consistent"
    assert md.mass == pytest.approx(RHO * SEC.A * L, rel=1e-12)
    assert md.center_of_mass == pytest.approx([L / 2, 0, 0], abs=1e-12 * L)
    assert md.frequencies == pytest.approx(ref.frequencies, rel=1e-10)
    assert md.section_forces is None and ref.section_forces is not None


def test_pinned_attachment_gives_hinged_beam_modes():
    """``reference_node=0, attachment="pinned"``: the modes are the pinned-free beam's (β_n L = 3.9266, 7.0686,
    10.2102, Blevins, *Formulas for Natural Frequency and Mode Shape*, table 8-1), within 0.1 % at 32 elements;
    the pin node does not translate and turns elastically; every mode is mass-orthogonal to the rotations about the
    pin (the reference frame turns with the mean rotation: the angular momentum about the pin of each mode, the
    rows of I4, vanishes)."""
    import math

    E, rho, L = 2e11, 8000.0, 1.5
    sec = rectangle(0.02, 0.01)
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, sec, E=E, rho=rho)
    md = modal_data_from_fe(fe, [32], 12, reference_node=0, attachment="pinned")
    assert md.interface_nodes.tolist() == [0, 32]
    t = md.translational_modes
    in_plane = [k for k in np.argsort(md.frequencies) if np.abs(t[k, :, 1]).max() > 10 * np.abs(t[k, :, 2]).max()
                and np.abs(t[k, :, 1]).max() > np.abs(t[k, :, 0]).max()]
    scale = math.sqrt(E * sec.Iz / (rho * sec.A * L**4))
    exact = np.array([3.9266, 7.0686, 10.2102]) ** 2 * scale / (2 * math.pi)
    np.testing.assert_allclose(md.frequencies[in_plane[:3]], exact, rtol=1e-3)
    assert np.abs(t[:, 0, :]).max() == 0.0
    assert np.abs(md.rotational_modes[in_plane[0], 0, 2]) > 0.1 * np.abs(md.rotational_modes[in_plane[0]]).max()
    I4 = md.invariants["I4"]
    assert np.abs(I4).max() <= 1e-9 * np.sqrt(md.mass) * L
