"""Joining beam meshes into one frame (:func:`flexlib.fe.join_models`).

References: a beam meshed in two parts and joined is the beam meshed whole (assembly of element matrices, Cook et
al. 2002 §2.8); the static deflection of a clamped L-frame under a tip load from Castigliano's theorem
(Euler–Bernoulli members, bending and axial strain energy: W. C. Young, R. G. Budynas, *Roark's Formulas for Stress
and Strain*, 7th ed., §8.1), which the frame elements reproduce exactly for nodal loads.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from flexlib.errors import RunArgumentError
from flexlib.fe import beam_mesh, box, join_models, modal_data_from_fe, rectangle

SECTION = box(0.08, 0.12, 0.004)


def test_a_beam_joined_from_two_parts_is_the_beam_meshed_whole():
    """M, K to round-off (1e-12 of their largest entry); mass properties, Craig–Bampton frequencies and section
    forces of the modal data equal (1e-9); the joined node order: the first part's nodes first."""
    whole = beam_mesh((0, 0, 0), (0.5, 0, 0), 10, SECTION, E=6e10, rho=1600.0, theory="timoshenko")
    a = beam_mesh((0, 0, 0), (0.2, 0, 0), 4, SECTION, E=6e10, rho=1600.0, theory="timoshenko")
    b = beam_mesh((0.2, 0, 0), (0.5, 0, 0), 6, SECTION, E=6e10, rho=1600.0, theory="timoshenko")
    joined = join_models([a, b])
    assert joined.nodes.shape == (11, 3)
    np.testing.assert_allclose(joined.nodes, whole.nodes, atol=1e-15)
    for name in ("M", "K"):
        A, B = getattr(joined, name), getattr(whole, name)
        assert abs(A - B).max() <= 1e-12 * abs(B).max(), name
    d_whole = modal_data_from_fe(whole, [0, 10], 4)
    d_joined = modal_data_from_fe(join_models([b, a]), [7, 6], 4)  # b first: nodes 0..6 are b's, a's 0 is 7
    assert d_joined.mass == pytest.approx(d_whole.mass, rel=1e-12)
    np.testing.assert_allclose(d_joined.inertia, d_whole.inertia, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(d_joined.frequencies, d_whole.frequencies, rtol=1e-9)
    assert d_joined.section_forces.shape == d_whole.section_forces.shape


def test_a_clamped_l_frame_deflects_as_castigliano_says():
    """Member 1 along x (length a), member 2 along y (length b) welded at the corner, clamped at the origin, a
    force P along −y at the free end: ``δ_y = P a³/(3 E I) + P b/(E A)`` (member 1 bent as a cantilever, member 2
    compressed) and the corner's rotation turns member 2, ``δ_x = P a² b/(2 E I)``; to 1e-9."""
    a, b, P, E = 0.4, 0.3, 100.0, 2.1e11
    sec = rectangle(0.02, 0.03)
    m1 = beam_mesh((0, 0, 0), (a, 0, 0), 3, sec, E=E, rho=7850.0)
    m2 = beam_mesh((a, 0, 0), (a, b, 0), 2, sec, E=E, rho=7850.0, y_axis=(-1.0, 0.0, 0.0))
    frame = join_models([m1, m2])
    tip = int(np.argmin(np.linalg.norm(frame.nodes - [a, b, 0], axis=1)))
    held = frame.constrained([0])
    f = np.zeros(held.n_dofs)
    f[held.dof_map[tip, 1]] = -P
    u = spla.spsolve(held.K.tocsc(), f)
    ux, uy = u[held.dof_map[tip, 0]], u[held.dof_map[tip, 1]]
    assert uy == pytest.approx(-(P * a**3 / (3 * E * sec.Iz) + P * b / (E * sec.A)), rel=1e-9)
    assert ux == pytest.approx(P * a**2 * b / (2 * E * sec.Iz), rel=1e-9)


@pytest.mark.parametrize("bad, match", [([], "non-empty sequence"), (["fe"], "non-empty sequence")])
def test_join_models_refuses_what_is_not_a_list_of_models(bad, match):
    with pytest.raises(RunArgumentError, match=match):
        join_models(bad)


def test_join_models_refuses_a_bad_tolerance_and_a_part_with_coinciding_nodes():
    part = beam_mesh((0, 0, 0), (1.0, 0, 0), 2, SECTION, E=6e10, rho=1600.0)
    for tol in (0.0, -1.0, float("nan"), True, "1e-9"):
        with pytest.raises(RunArgumentError, match="tol"):
            join_models([part], tol=tol)
    with pytest.raises(RunArgumentError, match="coincide"):
        join_models([part], tol=0.6)  # nodes 0.5 m apart are one within 0.6 m
