"""Beam FE mesher: static deflections and natural frequencies against closed forms, Timoshenko and tapered
beams against independent computations, sections, and the FE matrix files.

References (each test names its own): Euler–Bernoulli closed forms (e.g. R. D. Blevins, *Formulas for Natural
Frequency and Mode Shape*, Van Nostrand 1979, tab. 8-1: beta_n L = 4.7300, 7.8532, 10.9956 free-free;
1.8751, 4.6941, 7.8548 clamped-free); Timoshenko hinged-hinged frequency equation (S. M. Han, H. Benaroya,
T. Wei, "Dynamics of transversely vibrating beams using four engineering theories", *J. Sound Vib.* 225 (1999)
935-988, eq. for the hinged-hinged Timoshenko beam).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate as si
import scipy.io
import scipy.linalg as la
import scipy.sparse.linalg as sla

from flexlib.fe import beam_mesh, box, circle, i_section, read_fe, read_matrix_market, rectangle, tube

E, RHO, L = 2.1e11, 7850.0, 2.0
SEC = rectangle(0.02, 0.03)  # b along z, h along y: Iz (x-y bending) > Iy


def y_bending(fe, vectors):
    """Mask of mode vectors whose translation is mostly along y (bending in the x-y plane); torsion modes,
    whose translations are round-off, are excluded."""
    parts = np.array([[np.sum(vectors[fe.dof_map[:, a][fe.dof_map[:, a] >= 0], j] ** 2) for a in range(3)]
                      for j in range(vectors.shape[1])])
    return (parts[:, 1] > 0.9 * parts.sum(axis=1)) & (parts[:, 1] > 1e-9 * parts[:, 1].max())


def eig_full(fe):
    w, V = la.eigh(fe.K.toarray(), fe.M.toarray())
    return np.sqrt(np.maximum(w, 0.0)), V


@pytest.mark.parametrize("n_el", [1, 4, 7])
def test_cantilever_tip_load_exact_euler_bernoulli(n_el):
    """Tip load P: tip deflection P L^3 / (3 E Iz) and slope P L^2 / (2 E Iz), exact for EB elements (1e-10)."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), n_el, SEC, E=E, rho=RHO).constrained([0])
    F = np.zeros(fe.n_dofs)
    P = 250.0
    F[fe.dofs([n_el], ["uy"])] = P
    u = sla.spsolve(fe.K.tocsc(), F)
    assert u[fe.dofs([n_el], ["uy"])][0] == pytest.approx(P * L**3 / (3 * E * SEC.Iz), rel=1e-10)
    assert u[fe.dofs([n_el], ["rz"])][0] == pytest.approx(P * L**2 / (2 * E * SEC.Iz), rel=1e-10)


def test_cantilever_self_weight_exact_euler_bernoulli():
    """Self weight: tip deflection rho A g L^4 / (8 E I) exact at the nodes for EB elements with the consistent
    load (Tong 1969 nodal exactness), in both bending planes (1e-10)."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 5, SEC, E=E, rho=RHO).constrained([0])
    g = 9.81
    for comp, inertia, gvec in (("uy", SEC.Iz, (0, -g, 0)), ("uz", SEC.Iy, (0, 0, -g))):
        u = sla.spsolve(fe.K.tocsc(), fe.gravity_load(gvec))
        exact = -RHO * SEC.A * g * L**4 / (8 * E * inertia)
        assert u[fe.dofs([5], [comp])][0] == pytest.approx(exact, rel=1e-10)


def test_cantilever_tip_load_timoshenko_adds_shear_deflection():
    """Timoshenko: tip deflection P L^3/(3 E I) + P L/(G As), exact (1e-10) for any mesh."""
    sec = rectangle(0.05, 0.2)
    G = E / 2.6
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 3, sec, E=E, rho=RHO, G=G, theory="timoshenko").constrained([0])
    F = np.zeros(fe.n_dofs)
    F[fe.dofs([3], ["uy"])] = 1e4
    u = sla.spsolve(fe.K.tocsc(), F)
    exact = 1e4 / (3 * E * sec.Iz) + 1e4 / (G * sec.Asy)
    assert u[fe.dofs([3], ["uy"])][0] == pytest.approx(exact, rel=1e-10)


def test_tapered_cantilever_tip_load_matches_quadrature():
    """Tapered cantilever (height h0 -> h0/2): tip deflection P int_0^L (L-x)^2 / (E I(x)) dx (unit-load method,
    scipy.integrate.quad) to 1e-9: the flexibility-based element is exact up to its 8-point quadrature."""
    b, h0 = 0.02, 0.04

    def section(s):
        return rectangle(b, h0 * (1 - s / 2))

    fe = beam_mesh((0, 0, 0), (L, 0, 0), 6, section, E=E, rho=RHO).constrained([0])
    F = np.zeros(fe.n_dofs)
    F[fe.dofs([6], ["uy"])] = 100.0
    u = sla.spsolve(fe.K.tocsc(), F)
    exact = si.quad(lambda x: 100.0 * (L - x) ** 2 / (E * b * (h0 * (1 - x / (2 * L))) ** 3 / 12), 0, L,
                    epsabs=0, epsrel=1e-13)[0]
    assert u[fe.dofs([6], ["uy"])][0] == pytest.approx(exact, rel=1e-9)


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_clamped_frequencies_vs_euler_bernoulli(mass):
    """Clamped-free: first three x-y bending frequencies within 0.5 % of (beta_n L)^2 sqrt(E I/(rho A L^4)),
    beta_n L = 1.8751, 4.6941, 7.8548, at 32 elements (consistent and HRZ-lumped mass), from the full FE model
    and from its improved Craig–Bampton reduction (interface at the tip, 12 fixed-interface modes)."""
    from flexlib.fe import craig_bampton

    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, SEC, E=E, rho=RHO, mass=mass).constrained([0])
    ref = np.array([1.8751, 4.6941, 7.8548]) ** 2 * math.sqrt(E * SEC.Iz / (RHO * SEC.A * L**4))
    omega, V = eig_full(fe)
    assert np.abs(omega[y_bending(fe, V)][:3] / ref - 1).max() < 5e-3
    cb = craig_bampton(fe.M, fe.K, fe.dofs([32]), 12)
    assert np.abs(cb.omega[y_bending(fe, cb.modes)][:3] / ref - 1).max() < 5e-3


def test_timoshenko_slender_agrees_with_euler_bernoulli_and_stubby_does_not():
    """Hinged-hinged beams, x-y bending. Slender (L/h = 100): Timoshenko and EB elements agree within 0.5 %.
    Stubby (L/h = 5): Timoshenko elements match the exact Timoshenko frequency equation (Han, Benaroya & Wei
    1999) within 0.5 % for modes 1-3 at 32 elements, while EB overestimates them by more than 3 %."""
    G = E / 2.6

    def hinged(theory, h):
        sec = rectangle(0.1, h, nu=0.3)
        fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, sec, E=E, rho=RHO, G=G, theory=theory)
        fe = fe.constrained([0], ["ux", "uy", "uz", "rx"]).constrained([32], ["uy", "uz"])
        omega, V = eig_full(fe)
        return omega[y_bending(fe, V)][:3], sec

    def timoshenko_exact(sec):
        out = []
        kG = G * sec.Asy / sec.A
        for n in (1, 2, 3):
            k = n * math.pi / L
            a = RHO**2 * sec.Iz / kG
            bq = RHO * sec.A + RHO * sec.Iz * k**2 * (1 + E / kG)
            c = E * sec.Iz * k**4
            out.append(math.sqrt((bq - math.sqrt(bq**2 - 4 * a * c)) / (2 * a)))
        return np.array(out)

    eb, _ = hinged("euler-bernoulli", L / 100)
    ti, sec = hinged("timoshenko", L / 100)
    assert np.abs(ti / eb - 1).max() < 5e-3
    assert np.abs(ti / timoshenko_exact(sec) - 1).max() < 5e-3
    eb, sec = hinged("euler-bernoulli", L / 5)
    ti, _ = hinged("timoshenko", L / 5)
    ref = timoshenko_exact(sec)
    assert np.abs(ti / ref - 1).max() < 5e-3
    assert np.all(eb / ref - 1 > 0.03)


def test_tapered_cantilever_frequencies_vs_rayleigh_ritz():
    """Tapered cantilever (height h0 -> h0/2, constant width), x-y bending: first three frequencies at 32
    elements within 0.1 % of an independent Rayleigh–Ritz solution (12 polynomial trial functions
    xi^2 P_k(2 xi - 1) satisfying the clamped conditions, 40-point Gauss quadrature; converged to < 1e-7)."""
    b, h0 = 0.02, 0.04

    def height(xi):
        return h0 * (1 - xi / 2)

    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, lambda s: rectangle(b, height(s)), E=E, rho=RHO).constrained([0])
    omega, V = eig_full(fe)
    got = omega[y_bending(fe, V)][:3]

    P = np.polynomial.Polynomial
    basis = [P([0, 0, 1]) * np.polynomial.Legendre.basis(k, domain=[0, 1]).convert(kind=P) for k in range(12)]
    xg, wg = np.polynomial.legendre.leggauss(40)
    xi, w = (xg + 1) / 2, wg / 2
    EI = E * b * height(xi) ** 3 / 12
    rA = RHO * b * height(xi)
    phi = np.array([p(xi) for p in basis])
    d2 = np.array([p.deriv(2)(xi) for p in basis]) / L**2
    Kr = (d2 * EI * w * L) @ d2.T
    Mr = (phi * rA * w * L) @ phi.T
    ref = np.sqrt(la.eigh(Kr, Mr, eigvals_only=True)[:3])
    assert np.abs(got / ref - 1).max() < 1e-3


def test_rigid_body_fields_and_mass():
    """The six rigid-body fields are in the null space of K (1e-9 relative) and R^T M R holds the analytic
    mass rho A L, first moment rho A L^2/2 and inertia rho A L^3/3 (EB, no rotary inertia) about the start."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 8, SEC, E=E, rho=RHO)
    R = fe.rigid_body_modes()
    assert np.abs(fe.K @ R).max() < 1e-9 * abs(fe.K).max()
    MR = R.T @ (fe.M @ R)
    m = RHO * SEC.A * L
    assert MR[1, 1] == pytest.approx(m, rel=1e-12)
    assert MR[1, 5] == pytest.approx(m * L / 2, rel=1e-12)
    assert MR[5, 5] == pytest.approx(m * L**2 / 3, rel=1e-12)
    assert MR[3, 3] == pytest.approx(RHO * SEC.Ip * L, rel=1e-12)


def test_sections_against_textbook_values():
    """Section formulas (Pilkey 2005; Roark tab. 10.7): circle, tube (thin-walled limit J = 2 pi r^3 t),
    square J = 0.1406 a^4 (Roark: 2.25 (a/2)^4 = 0.1406 a^4, formula within 0.5 %), box (Bredt), I section."""
    c = circle(0.1)
    assert c.Iz == pytest.approx(math.pi * 0.1**4 / 64) and c.J == pytest.approx(math.pi * 0.1**4 / 32)
    t = tube(1.0, 0.001)
    r = (1.0 - 0.001) / 2
    assert t.J == pytest.approx(2 * math.pi * r**3 * 0.001, rel=1e-5)
    assert t.Asy / t.A == pytest.approx(2 * 1.3 / (4 + 3 * 0.3), rel=1e-3)  # thin tube: Cowper 1966 tab. 1
    assert rectangle(0.1, 0.1).J == pytest.approx(0.1406 * 0.1**4, rel=5e-3)
    bx = box(0.2, 0.3, 0.01)
    assert bx.Iz == pytest.approx((0.2 * 0.3**3 - 0.18 * 0.28**3) / 12)
    assert bx.J == pytest.approx(4 * (0.19 * 0.29) ** 2 * 0.01 / (2 * (0.19 + 0.29)))
    ib = i_section(0.1, 0.2, 0.006, 0.01)
    assert ib.A == pytest.approx(2 * 0.1 * 0.01 + 0.18 * 0.006)
    assert ib.Iz == pytest.approx((0.1 * 0.2**3 - 0.094 * 0.18**3) / 12)
    with pytest.raises(ValueError, match="tube section: wall thickness"):
        tube(0.1, 0.06)
    with pytest.raises(ValueError, match="rectangle section: h"):
        rectangle(0.1, -1.0)


def test_fe_files_round_trip(tmp_path):
    """An FE model written to .npz and to Matrix Market + text tables reads back with identical matrices."""
    fe = beam_mesh((0, 0, 0), (1.0, 0.5, 0), 5, tube(0.05, 0.004), E=E, rho=RHO, theory="timoshenko")
    fe.write_npz(tmp_path / "beam.npz")
    back = read_fe(tmp_path / "beam.npz")
    assert (back.M != fe.M).nnz == 0 and (back.K != fe.K).nnz == 0
    assert np.array_equal(back.nodes, fe.nodes) and np.array_equal(back.dof_map, fe.dof_map)
    scipy.io.mmwrite(tmp_path / "M.mtx", fe.M, symmetry="symmetric")
    scipy.io.mmwrite(tmp_path / "K.mtx", fe.K, symmetry="symmetric")
    np.savetxt(tmp_path / "nodes.csv", fe.nodes, delimiter=",")
    mm = read_matrix_market(tmp_path / "M.mtx", tmp_path / "K.mtx", tmp_path / "nodes.csv")
    assert abs(mm.M - fe.M).max() <= 1e-15 * abs(fe.M).max()
    assert abs(mm.K - fe.K).max() <= 1e-15 * abs(fe.K).max()
    assert np.array_equal(mm.dof_map, fe.dof_map)


def test_section_forces_and_fibre_stress_of_cantilever():
    """Cantilever (Timoshenko, 4 elements) under tip forces (Fx, Fy, Fz) = (1000, 100, 30) N: section forces at
    every element end N = Fx, Vy = Fy, Mz = Fy (L - x), My = -Fz (L - x) (statics), and the corner-fibre
    stress N/A + My z/Iy - Mz y/Iz at every node, exact to 1e-9 relative."""
    from flexlib.fe import beam_stress_modes, section_force_modes

    b, h = 0.02, 0.03
    sec = rectangle(b, h)
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 4, sec, E=E, rho=RHO, theory="timoshenko").constrained([0])
    F = np.zeros(fe.n_dofs)
    F[fe.dofs([4], ["ux", "uy", "uz"])] = (1000.0, 100.0, 30.0)
    u = sla.spsolve(fe.K.tocsc(), F)[:, None]
    sf = section_force_modes(fe, u)[0]  # (E, 2, 6)
    x = np.array([[e * L / 4, (e + 1) * L / 4] for e in range(4)])
    scale = 100.0 * L
    assert np.abs(sf[..., 0] - 1000.0).max() < 1e-9 * 1000.0
    assert np.abs(sf[..., 1] - 100.0).max() < 1e-9 * 100.0
    assert np.abs(sf[..., 5] - 100.0 * (L - x)).max() < 1e-9 * scale
    assert np.abs(sf[..., 4] + 30.0 * (L - x)).max() < 1e-9 * scale
    stress = beam_stress_modes(fe, u, (h / 2, b / 2))[0]
    xn = np.linspace(0, L, 5)
    exact = 1000.0 / sec.A - 30.0 * (L - xn) * (b / 2) / sec.Iy - 100.0 * (L - xn) * (h / 2) / sec.Iz
    assert np.abs(stress[:, 0] - exact).max() < 1e-9 * np.abs(exact).max()
    assert np.abs(stress[:, 1:]).max() == 0.0  # uniaxial along the body x axis


def test_nodes_at_given_stations_keep_the_beam_exact():
    """``nodes_at`` puts nodes at joint and bracket stations (unequal elements): they lie there to 1e-12 m, the
    mass is ρAL (1e-12), a tip load still deflects the cantilever by PL³/3EI (Euler–Bernoulli elements are exact
    for nodal loads, 1e-9) and the first three clamped frequencies stay within 0.05 % of Euler–Bernoulli
    (40 elements)."""
    from flexlib.fe import rectangle

    b, h, L, E, rho = 0.02, 0.04, 2.0, 2.1e11, 7850.0
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 40, rectangle(b, h), E=E, rho=rho, nodes_at=[0.333, 1.5, 1.93])
    assert fe.nodes.shape[0] == 41
    for x in (0.333, 1.5, 1.93):
        assert np.abs(fe.nodes[:, 0] - x).min() < 1e-12
    assert fe.mass_points.masses.sum() == pytest.approx(rho * b * h * L, rel=1e-12)
    held = fe.constrained([0])
    f = np.zeros(held.n_dofs)
    f[held.dofs([40], ["uy"])] = 1.0
    u = np.linalg.solve(held.K.toarray(), f)
    Iz, Iy = b * h**3 / 12, h * b**3 / 12
    assert u[held.dofs([40], ["uy"])][0] == pytest.approx(L**3 / (3 * E * Iz), rel=1e-9)
    w = np.sqrt(np.sort(la.eigh(held.K.toarray(), held.M.toarray(), eigvals_only=True)))
    beta = np.array([1.875104, 4.694091, 7.854757])
    weak = beta**2 * np.sqrt(E * Iy / (rho * b * h * L**4))
    bending_weak = [x for x in w if np.min(np.abs(x / weak - 1)) < 5e-3][:3]
    np.testing.assert_allclose(bending_weak, weak, rtol=5e-4)


def test_bad_nodes_at_are_named():
    from flexlib.fe import rectangle

    with pytest.raises(ValueError, match=r"nodes_at must lie on the axis, 0 \.\. 2 m"):
        beam_mesh((0, 0, 0), (2, 0, 0), 8, rectangle(0.02, 0.04), E=2e11, rho=7850.0, nodes_at=[2.5])
    with pytest.raises(ValueError, match=r"4 parts .* need at least as many elements, got n_elements=3"):
        beam_mesh((0, 0, 0), (2, 0, 0), 3, rectangle(0.02, 0.04), E=2e11, rho=7850.0, nodes_at=[0.5, 1.0, 1.5])
