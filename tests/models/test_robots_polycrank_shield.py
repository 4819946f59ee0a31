"""Flexible shield 5 of the POLYCRANK fragment (issue 30, seed 002 §4.1): its FE model's mass properties and
frames, its shell against beam theory, and the locked frequencies against the rigid shield's.

References: the Euler–Bernoulli cantilever with a tip mass ``M``, frequency equation
``1 + cos λ cosh λ + λ (M / m) (cos λ sinh λ − sin λ cosh λ) = 0``, ``ω = λ² √(E I / (m L³))`` with the beam's
mass ``m`` (R. D. Blevins, *Formulas for Natural Frequency and Mode Shape*, Van Nostrand 1979, tab. 8-8); the
Timoshenko cantilever's tip compliance ``L³/(3 E I) + L/(G A_s)`` (S. Timoshenko, J. M. Gere, *Mechanics of
Materials*, 1972, §9.9); Rayleigh's theorem on constraints (a constrained system's k-th natural frequency is at
least the unconstrained one's: L. Meirovitch, *Fundamentals of Vibrations*, McGraw-Hill 2001, §7.14) — the rigid
shield is the flexible one with its modal coordinates held at zero, with the same mass properties; Dunkerley's
formula for springs in series carrying one mass (Meirovitch 2001, §8.8).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as la
from scipy.optimize import brentq

import flexlib as fl
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.fe import planar_modes
from flexlib.models.robots.polycrank import PolycrankParameters, preload_params
from flexlib.models.robots.polycrank_shield import shield_fe, shield_modal_data, shield_shell_section
from flexlib.models.robots.polycrank_study import LOCKED, PRELOAD, no_friction

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


def _cantilever_frequency() -> float:
    """Lowest in-plane frequency [Hz] of the shield's FE model held at its flange (``A1`` and the pins) and
    carrying at ``A2``, along ``y``, what the fragment hangs there: the load, the two grip discs and a third of
    each of the twelve body-5 links (each turns about its pin at ``A1``: ``m L²/3``); ``A2`` held along ``x``
    (the links keep its distance from ``A1``)."""
    fe, ids = shield_fe(PAR)
    held = fe.constrained([ids[0], *ids[2:]]).constrained([ids[1]], ["ux"])
    M, K = held.M.toarray(), held.K.toarray()
    row = held.dof_map[ids[1], 1]
    M[row, row] += PAR.m_load + 2 * PAR.m_disc + 12 * PAR.m_link / 3
    return math.sqrt(la.eigh(K, M, eigvals_only=True)[0]) / (2 * math.pi)


def test_a_flexible_shield_lowers_each_locked_frequency(polycrank_flexible, polycrank_flexible_shield):
    """Flexible pull rods mounted for the study's 500 N, drives locked, no friction, hanging pose. (1) Each of the
    three lowest frequencies with the flexible shield is at most the rigid shield's (to 1e-9: Rayleigh's theorem
    on constraints). (2) The lowest — shield 5 with the load turning about ``A1`` on the outer rods' axial
    stiffness, 109.4 Hz with the rigid shield — becomes that spring in series with the shield's bending: Dunkerley's
    ``f⁻² = f_rigid⁻² + f_cantilever⁻²``, with the shield's own frequency as a cantilever from its flange carrying
    the grip (:func:`_cantilever_frequency`, 336.2 Hz), to 1 % (measured 104.02 Hz against 104.06 Hz): this
    also checks which parts the fragment hangs on which of the shield's frames. The two builds are the session's
    (``tests/models/conftest.py``)."""
    out = {}
    for name, (model, sim) in (("rigid", polycrank_flexible), ("flexible", polycrank_flexible_shield)):
        modes = fl.modal_analysis(sim, lock=LOCKED, steady_state=True,
                                  params={**no_friction(), **preload_params(model, PRELOAD)})
        out[name] = np.sort(modes.frequencies[modes.oscillatory])[:3]
    assert isinstance(polycrank_flexible_shield[0].shield5, FlexibleBody)
    assert np.all(out["flexible"] <= out["rigid"] * (1 + 1e-9)), out
    dunkerley = (out["rigid"][0] ** -2 + _cantilever_frequency() ** -2) ** -0.5
    assert out["flexible"][0] == pytest.approx(dunkerley, rel=0.01), out
