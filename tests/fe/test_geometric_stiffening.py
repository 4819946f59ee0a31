"""Modal geometric stiffness per unit load case (Wallrapp & Schwertassek 1991): centrifugal stiffening of a
rotating cantilever (Southwell coefficient) and the Euler buckling load of a cantilever under a tip force.

References: the Southwell coefficient of the first flapwise mode of a uniform cantilever rotating about its
root, K1 = 1.1933 (A. D. Wright, C. E. Smith, R. W. Thresher, J. L. C. Wang, "Vibration modes of centrifugally
stiffened beams", *J. Appl. Mech.* 49 (1982) 197-202), recomputed here independently as the Rayleigh quotient
of the analytic first mode; Euler's buckling load of a cantilever, pi^2 E I / (4 L^2) (S. P. Timoshenko,
J. M. Gere, *Theory of Elastic Stability*, 2nd ed., 1961, §2.1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate as si
import scipy.linalg as la

from flexlib.fe import ModalData, beam_mesh, modal_data_from_fe, rectangle

E, RHO, L = 2.1e11, 7850.0, 2.0
B, H = 0.02, 0.03  # Iy = H B^3/12 < Iz: the lowest bending mode is along z (flapwise for rotation about z)


@pytest.fixture(scope="module")
def cantilever():
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, rectangle(B, H), E=E, rho=RHO).constrained([0])
    return modal_data_from_fe(fe, [32], 10, free=False, geometric_stiffening=True, support_nodes=[0])


def test_southwell_coefficient_of_rotating_cantilever(cantilever):
    """Rotation about z at Omega: omega_1^2 = omega_0^2 + K1 Omega^2 from K_gen + Omega^2 G[omega_zz]; K1 within
    0.1 % of the Rayleigh quotient int (L^2 - x^2)/2 phi'^2 dx / int phi^2 dx of the analytic first mode, which
    itself equals the published 1.1933 (1e-3)."""
    md = cantilever
    K, M, G = md.generalized_stiffness, md.generalized_mass, md.geometric_stiffness["omega_zz"]
    w0 = la.eigh(K, M, eigvals_only=True)[0]
    omega2 = 1e-4 * w0
    K1 = (la.eigh(K + omega2 * G, M, eigvals_only=True)[0] - w0) / omega2

    z = 1.8751040687
    sig = (math.cosh(z) + math.cos(z)) / (math.sinh(z) + math.sin(z))
    beta = z / L

    def phi(x):
        return math.cosh(beta * x) - math.cos(beta * x) - sig * (math.sinh(beta * x) - math.sin(beta * x))

    def dphi(x):
        return beta * (math.sinh(beta * x) + math.sin(beta * x) - sig * (math.cosh(beta * x) - math.cos(beta * x)))

    num = si.quad(lambda x: (L**2 - x**2) / 2 * dphi(x) ** 2, 0, L, epsabs=0, epsrel=1e-12)[0]
    den = si.quad(lambda x: phi(x) ** 2, 0, L, epsabs=0, epsrel=1e-12)[0]
    reference = num / den
    assert reference == pytest.approx(1.1933, rel=1e-3)
    assert K1 == pytest.approx(reference, rel=1e-3)


def test_euler_buckling_load_from_tip_force_case(cantilever):
    """Compressive tip force P along -x: K_gen - P G[F32_ux] becomes singular at P = pi^2 E Iy / (4 L^2)
    (lowest bending plane), within 0.5 %."""
    md = cantilever
    G = md.geometric_stiffness["F32_ux"]
    lam = la.eigh(md.generalized_stiffness, G + 1e-12 * np.abs(G).max() * np.eye(md.n_modes), eigvals_only=True)
    Iy = H * B**3 / 12
    assert lam[lam > 0].min() == pytest.approx(math.pi**2 * E * Iy / (4 * L**2), rel=5e-3)


def test_free_body_geometric_stiffness_round_trip(tmp_path):
    """A free body with geometric stiffening: 12 inertial cases plus 6 per non-support interface node, each
    symmetric; written and read back bit-exactly, in the content hash, sliced by select()."""
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 16, rectangle(B, H), E=E, rho=RHO)
    md = modal_data_from_fe(fe, [0, 16], 6, geometric_stiffening=True)
    assert len(md.geometric_stiffness) == 12 + 6
    for G in md.geometric_stiffness.values():
        assert np.array_equal(G, G.T)
    back = ModalData.read(md.write(tmp_path / "geo.h5"))
    assert back.content_hash() == md.content_hash()
    for k, G in md.geometric_stiffness.items():
        assert back.geometric_stiffness[k].tobytes() == G.tobytes()
    sub = md.select([1, 0])
    assert np.array_equal(sub.geometric_stiffness["omega_zz"], md.geometric_stiffness["omega_zz"][np.ix_([1, 0],
                                                                                                          [1, 0])])
    plain = modal_data_from_fe(fe, [0, 16], 6)
    assert plain.geometric_stiffness is None and plain.content_hash() != md.content_hash()
