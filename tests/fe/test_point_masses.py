"""Rigid point masses attached to FE nodes (non-structural mass with offsets, Nastran's CONM2).

References: the clamped–free Euler–Bernoulli beam with a tip mass ``M_t`` has the frequency equation
``1 + cos(bL) cosh(bL) + (M_t / (m L)) bL (cos(bL) sinh(bL) - sin(bL) cosh(bL)) = 0`` with
``omega = (bL)^2 sqrt(EI / (m L^4))`` (Blevins, *Formulas for Natural Frequency and Mode Shape*, 1979, Table 8-8,
solved here by bracketing); rigid-body mass properties of a box beam plus an offset pipe line by hand (parallel-axis
theorem).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as la
from scipy.optimize import brentq

from flexlib.fe import beam_mesh, box, modal_data_from_fe, rectangle

E, RHO, L = 2.1e11, 7850.0, 2.0


def _tip_mass_frequency(EI: float, m: float, M_tip: float) -> float:
    """First bending frequency [rad/s] of a cantilever with a tip mass (exact frequency equation)."""
    ratio = M_tip / (m * L)

    def f(x: float) -> float:
        return 1 + math.cos(x) * math.cosh(x) + ratio * x * (math.cos(x) * math.sinh(x) - math.sin(x) * math.cosh(x))

    root = brentq(f, 0.3, 1.9)
    return root**2 * math.sqrt(EI / (m * L**4))


def test_cantilever_with_tip_mass_matches_the_exact_frequency():
    """A 40 kg mass on the tip of a 2 m, 20 x 40 mm steel cantilever (12.6 kg): the first frequency (bending about
    the weak axis, I = h b³/12) within 1e-5 of the exact one; the same mass 0.3 m beyond the tip on an offset
    lowers it further (its lever and rotary inertia about the tip)."""
    b, h = 0.02, 0.04
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, rectangle(b, h), E=E, rho=RHO)
    held = fe.with_point_masses([32], [40.0]).constrained([0])
    w2 = la.eigh(held.K.toarray(), held.M.toarray(), eigvals_only=True)
    I_weak = h * b**3 / 12
    exact = _tip_mass_frequency(E * I_weak, RHO * b * h, 40.0)
    assert math.sqrt(w2[0]) == pytest.approx(exact, rel=1e-5)
    offset = fe.with_point_masses([32], [40.0], offsets=[[0.3, 0.0, 0.0]]).constrained([0])
    w2_off = la.eigh(offset.K.toarray(), offset.M.toarray(), eigvals_only=True)
    assert math.sqrt(w2_off[0]) < 0.95 * exact


def test_offset_pipe_mass_gives_the_hand_mass_properties():
    """A 9 m box section (250 x 400 x 8 mm) carrying a 40 kg/m pipe 0.35 m above its axis, lumped at the 33 nodes
    (end nodes half): the modal data's mass, centre of mass and inertia about the origin equal the hand sum of the
    box (its own consistent mass points) and the pipe points to 1e-9."""
    Lb, mu, off = 9.0, 40.0, 0.35
    section = box(0.25, 0.4, 0.008)
    fe = beam_mesh((0, 0, 0), (Lb, 0, 0), 32, section, E=E, rho=RHO, rotary_inertia=True)
    share = np.full(33, mu * Lb / 32)
    share[[0, -1]] /= 2
    loaded = fe.with_point_masses(np.arange(33), share, offsets=np.tile([0.0, off, 0.0], (33, 1)))
    data = modal_data_from_fe(loaded, [0, 32], 2)
    pts = fe.mass_points
    m_box = pts.masses.sum()
    pipe_x = fe.nodes[:, 0]
    m = m_box + share.sum()
    assert data.mass == pytest.approx(m, rel=1e-12)
    com = (pts.masses @ pts.positions + share @ np.column_stack([pipe_x, np.full(33, off), np.zeros(33)])) / m
    np.testing.assert_allclose(data.center_of_mass, com, rtol=1e-9, atol=1e-12)

    def inertia(ms: np.ndarray, xs: np.ndarray) -> np.ndarray:
        return np.einsum("p,pij->ij", ms, (xs * xs).sum(1)[:, None, None] * np.eye(3) - xs[:, :, None] * xs[:, None, :])

    pipe_pos = np.column_stack([pipe_x, np.full(33, off), np.zeros(33)])
    I_hand = inertia(pts.masses, pts.positions) + pts.inertias.sum(0) + inertia(share, pipe_pos)
    np.testing.assert_allclose(data.inertia, I_hand, rtol=1e-9, atol=1e-9 * np.abs(I_hand).max())


def test_bad_point_masses_are_named():
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 4, rectangle(0.02, 0.04), E=E, rho=RHO)
    with pytest.raises(KeyError, match="no node with id 9"):
        fe.with_point_masses([9], [1.0])
    with pytest.raises(ValueError, match=r"negative mass -1\.0 kg at node 2"):
        fe.with_point_masses([2], [-1.0])
    with pytest.raises(ValueError, match="2 nodes but 1 masses"):
        fe.with_point_masses([1, 2], [1.0])
    with pytest.raises(ValueError, match="'offsets' has non-finite"):
        fe.with_point_masses([1], [1.0], offsets=[[np.nan, 0, 0]])
    with pytest.raises(ValueError, match="node 0 lacks the DOFs"):
        fe.constrained([0], ("rx", "ry", "rz")).with_point_masses([0], [1.0], offsets=[[0, 0.1, 0]])
