"""Flexible shield 5 of the POLYCRANK fragment (issue 30, seed 002 §4.1): its FE model's mass properties and
frames, and its shell against beam theory. (The locked frequencies with it — each of the lowest three at most the
rigid shield's, the lowest 104.0 Hz against Dunkerley's 104.1 Hz — come from builds of the whole fragment, 30 s of
CPU each: ``python -m flexlib.models.robots.polycrank_study --shield``, docs/robots.md.)

References: the Euler–Bernoulli cantilever with a tip mass ``M``, frequency equation
``1 + cos λ cosh λ + λ (M / m) (cos λ sinh λ − sin λ cosh λ) = 0``, ``ω = λ² √(E I / (m L³))`` with the beam's
mass ``m`` (R. D. Blevins, *Formulas for Natural Frequency and Mode Shape*, Van Nostrand 1979, tab. 8-8); the
Timoshenko cantilever's tip compliance ``L³/(3 E I) + L/(G A_s)`` (S. Timoshenko, J. M. Gere, *Mechanics of
Materials*, 1972, §9.9).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as la
from scipy.optimize import brentq

from flexlib.fe import planar_modes
from flexlib.models.robots.polycrank import PolycrankParameters
from flexlib.models.robots.polycrank_shield import shield_fe, shield_modal_data, shield_shell_section

PAR = PolycrankParameters()


def test_the_flexible_shield_has_the_rigid_shields_mass_properties_and_frames():
    """The shield's modal data: mass ``m_shield5`` to 1e-9, centre of mass ``(L5/2, 0, 0)`` to 1e-12 m, inertia
    tensor about it ``I_shield5 · 1`` to 1e-9 of ``I_shield5``; its interface nodes (the frames) at ``A1``, ``A2`` and
    the outer channel's pins ``r_o (cos 2πk/6, sin 2πk/6, 0)`` (the rigid fragment's frames), to 1e-12 m; the kept
    in-plane modes are the shell's (below the spider's, which lie above 100 kHz)."""
    data = shield_modal_data(PAR)
    assert data.mass == pytest.approx(PAR.m_shield5, rel=1e-9)
    np.testing.assert_allclose(data.center_of_mass, [PAR.L5 / 2, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(data.inertia_cm, PAR.I_shield5 * np.eye(3), atol=1e-9 * PAR.I_shield5)
    frames = [data.coordinates[data.node_index(n)] for n in data.interface_nodes]
    pins = [[PAR.r_o * math.cos(a), PAR.r_o * math.sin(a), 0.0] for a in 2 * np.pi * np.arange(6) / 6]
    np.testing.assert_allclose(frames, [[0.0, 0.0, 0.0], [PAR.L5, 0.0, 0.0], *pins], atol=1e-12)
    kept = planar_modes(data, "xy")[:PAR.shield_modes]
    assert len(kept) == PAR.shield_modes and data.frequencies[kept].max() < 1e5 < data.frequencies[
        planar_modes(data, "xy")[PAR.shield_modes]]


def test_the_shell_bends_as_euler_bernoulli_and_deflects_as_timoshenko():
    """Flange held (``A1`` and the six pins clamped): (1) with Euler–Bernoulli members the lowest in-plane mode is
    the cantilever with the ``A2`` housing's mass at its tip, to 1 % of Blevins' closed form (measured 6e-7: 8
    cubic elements); (2) with the fragment's Timoshenko members a unit in-plane force at ``A2`` deflects it by
    ``L³/(3 E I_z) + L/(G A_sy)``, to 1e-9 (the frame element is exact for nodal loads)."""
    L, E = PAR.L5, PAR.E_shield
    sec = shield_shell_section(PAR)
    fe, ids = shield_fe(PAR, theory="euler-bernoulli")
    held = fe.constrained([ids[0], *ids[2:]])
    w2, V = la.eigh(held.K.toarray(), held.M.toarray())
    trans, rot = held.nodal_fields(V)
    in_plane = (np.sum(trans[:, :, :2] ** 2, axis=(1, 2)) + L**2 * np.sum(rot[:, :, 2] ** 2, axis=1)) / (
        np.sum(trans**2, axis=(1, 2)) + L**2 * np.sum(rot**2, axis=(1, 2)))
    f_fe = math.sqrt(w2[np.flatnonzero(in_plane > 0.999)[0]]) / (2 * math.pi)
    fit = fe.info["shield_fit"]
    m_beam = fit["rho_shell_kg_m3"] * sec.A * L
    mu = fit["m_A2_kg"] / m_beam

    def frequency_equation(lam: float) -> float:
        return 1 + math.cos(lam) * math.cosh(lam) + lam * mu * (math.cos(lam) * math.sinh(lam)
                                                                - math.sin(lam) * math.cosh(lam))

    lam = brentq(frequency_equation, 0.1, 1.8752)
    f_closed = lam**2 * math.sqrt(E * sec.Iz / (m_beam * L**3)) / (2 * math.pi)
    assert f_fe == pytest.approx(f_closed, rel=0.01)
    fe, ids = shield_fe(PAR)
    held = fe.constrained([ids[0], *ids[2:]])
    load = np.zeros(held.n_dofs)
    load[held.dof_map[ids[1], 1]] = 1.0
    u = np.linalg.solve(held.K.toarray(), load)[held.dof_map[ids[1], 1]]
    G = E / (2 * (1 + PAR.nu_shield))
    assert u == pytest.approx(L**3 / (3 * E * sec.Iz) + L / (G * sec.Asy), rel=1e-9)
