"""Mode-acceleration recovery: the static load responses stored with the modal data and the residual
(left-out-mode) part of them.

References: the elastic static response of a body is ``G f`` with ``G = sum_k phi_k phi_k^T / omega_k^2`` over all
its elastic eigenmodes (mass-normalised, rigid-body modes excluded: inertia relief), and the mode-acceleration
method adds ``(G - Phi K^-1 Phi^T) f`` to a truncated modal superposition (Craig & Kurdila, *Fundamentals of
Structural Dynamics*, 2006, §10.4). Beam statics: the cantilever's tip deflection ``P L^3 / 3 E I``, its own-weight
sag ``rho A g L^4 / 8 E I``, and the root bending stress ``P L (h/2) / I`` (Euler–Bernoulli).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse.linalg as spla

import flexlib as fl
from flexlib import ModalFileError
from flexlib.fe import (
    ModalData,
    Section,
    beam_mesh,
    beam_stress_modes,
    deformed_positions,
    elastic_static_responses,
    modal_data_from_fe,
    nodal_stress,
    node_displacements,
    rectangle,
    von_mises,
)
from flexlib.fe.geometric import inertial_load_cases, interface_load_cases
from tests.components.mechanics.flexible.benches import TipLoaded

QUIET = {"progress": False}


def _dense_elastic_flexibility(fe, n_rigid: int) -> np.ndarray:
    """``sum phi phi^T / omega^2`` over all elastic eigenmodes of the (small) FE model, dense."""
    w2, V = la.eigh(fe.K.toarray(), fe.M.toarray())
    assert np.all(np.abs(w2[:n_rigid]) < 1e-6 * w2[n_rigid])  # the rigid modes are exactly the n_rigid lowest
    V, w2 = V[:, n_rigid:], w2[n_rigid:]
    return (V / w2) @ V.T


@pytest.mark.parametrize("attachment", ["free", "pinned", "clamped"])
def test_static_responses_equal_the_sum_over_all_elastic_modes(attachment):
    """``elastic_static_responses`` (sparse saddle-point solve with inertia relief) equals the dense sum over all
    elastic eigenmodes, 1e-8 relative, for a free body (six rigid modes), one pinned at a node (three rotations)
    and one clamped there (none)."""
    fe = beam_mesh((0, 0, 0), (1.5, 0, 0), 12, Section(A=1e-4, Iy=2e-10, Iz=1e-10, J=3e-10), E=2e11, rho=8000.0)
    if attachment == "free":
        rigid = fe.rigid_body_modes()
    elif attachment == "pinned":
        fe = fe.constrained([0], ("ux", "uy", "uz"))
        from flexlib.fe.reduction import rotations_about

        rigid = rotations_about(fe, fe.nodes[0])
    else:
        fe = fe.constrained([0])
        rigid = None
    cases = inertial_load_cases(fe) | interface_load_cases(fe, [12])
    F = np.column_stack(list(cases.values()))
    u = elastic_static_responses(fe, F, rigid)
    G = _dense_elastic_flexibility(fe, 0 if rigid is None else rigid.shape[1])
    ref = G @ F
    assert np.abs(u - ref).max() <= 1e-8 * np.abs(ref).max()


def test_all_craig_bampton_modes_leave_no_residual_for_interface_loads():
    """On a body clamped at its reference node, Craig–Bampton holds the exact static response to loads at the other
    interface nodes (its constraint modes), so with every mode kept the residual of each interface load case
    vanishes (1e-9 of the static response); with the lowest four kept it does not. (On a free body the inertia
    relief is a distributed load, outside the Craig–Bampton span: there the residual stays.)"""
    fe = beam_mesh((0, 0, 0), (2.0, 0, 0), 16, rectangle(0.02, 0.04), E=2.1e11, rho=7850.0)
    data = modal_data_from_fe(fe, [8, 16], 6, reference_node=0)
    R = data.residual_fields()
    iface = [k for k, c in enumerate(R["cases"]) if c.startswith("F")]
    assert len(iface) == 12  # six at node 8, six at node 16 (node 0 is clamped: no load DOFs)
    scale = np.abs(data.static_translations[iface]).max()
    assert np.abs(R["translations"][iface]).max() <= 1e-9 * scale
    assert np.abs(data.select(range(4)).residual_fields()["translations"][iface]).max() > 1e-3 * scale


def _bending_y(data: ModalData, n: int) -> list[int]:
    """The ``n`` lowest modes bending in body y (largest tip translation along y)."""
    tip = data.node_index(int(data.node_ids[np.argmax(data.coordinates[:, 0])]))
    along_y = [j for j in range(data.n_modes) if np.argmax(np.abs(data.translational_modes[j, tip])) == 1]
    return along_y[:n]


def test_one_mode_with_mode_acceleration_recovers_statics_exactly(tmp_path):
    """A cantilever (Craig–Bampton, tip interface node) with only its lowest y-bending mode kept, statics by
    steady-state initialisation under a tip load P and its own weight. Plain superposition misses the tip
    deflection by ~3 % and the root stress by more; the mode-acceleration recovery gives PL³/3EI + ρAgL⁴/8EI within
    1e-6 and the full FE model's static root stress within 1e-6 (which is beam theory's (P·L + ρAgL²/2)·(h/2)/I
    up to the element's fixed-end moment ρAg·l²/12, 4e-5 of it: end forces recovered from nodal displacements)."""
    b, h, L, P, Ey, rho, g = 0.02, 0.04, 1.0, 500.0, 2.1e11, 7850.0, 9.81
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 16, rectangle(b, h), E=Ey, rho=rho)
    data = modal_data_from_fe(fe, [16], 8, reference_node=0, stress_fibre=(h / 2, 0.0))
    modes = _bending_y(data, 1)

    model = TipLoaded(data, P, g=g, modes=modes, frames=[0, 16])
    res = fl.Simulation(model, use_cache=False).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    Iz, A = b * h**3 / 12, b * h
    tip_exact = -(P * L**3 / (3 * Ey * Iz) + rho * A * g * L**4 / (8 * Ey * Iz))
    root_exact = (P * L + rho * A * g * L**2 / 2) * (h / 2) / Iz
    sel = model.beam.modal_data
    _t, q, _r0, _T = model.beam.motion(res)
    loads = model.beam.load_amplitudes(res)
    plain = node_displacements(sel, q, [16])[0, 0, 1]
    recovered = node_displacements(sel, q, [16], loads=loads)[:, 0, 1]
    assert abs(plain / tip_exact - 1) > 0.01
    np.testing.assert_allclose(recovered, tip_exact, rtol=1e-6)
    root_plain = von_mises(nodal_stress(sel, q[:1], nodes=[0]))[0, 0]
    root = von_mises(nodal_stress(sel, q, nodes=[0], loads=loads))[:, 0]
    assert abs(root_plain / root_exact - 1) > 0.02
    held = fe.constrained([0])
    f = held.gravity_load([0.0, -g, 0.0])
    f[held.dofs([16], ["uy"])] -= P
    u = spla.spsolve(held.K.tocsc(), f)
    fe_root = von_mises(beam_stress_modes(held, u[:, None], (h / 2, 0.0))[0, :1])[0]
    assert fe_root == pytest.approx(root_exact, rel=1e-4)
    np.testing.assert_allclose(root, fe_root, rtol=1e-6)


def test_static_loads_round_trip_and_enter_the_hash(tmp_path):
    """The static load responses survive the HDF5 file bit for bit, select() keeps them consistent, and a change
    of one stored response changes the content hash (the compiled-model cache keys on it)."""
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 8, rectangle(0.02, 0.04), E=2.1e11, rho=7850.0)
    data = modal_data_from_fe(fe, [8], 4, reference_node=0)
    back = ModalData.read(data.write(tmp_path / "b.h5"))
    assert back.load_cases == data.load_cases
    np.testing.assert_array_equal(back.static_translations, data.static_translations)
    assert back.content_hash() == data.content_hash()
    sub = data.select([2, 0])
    np.testing.assert_array_equal(sub.static_modal_loads, data.static_modal_loads[:, [2, 0]])
    bumped = data.static_translations.copy()
    bumped[0, 3, 1] += 1e-12
    from dataclasses import replace

    assert replace(data, static_translations=bumped).content_hash() != data.content_hash()


def test_bad_static_loads_are_named():
    """Static responses without case names, or of the wrong shape, are refused naming the dataset; recovery from
    data without them says how to make them."""
    from dataclasses import replace

    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 8, rectangle(0.02, 0.04), E=2.1e11, rho=7850.0)
    data = modal_data_from_fe(fe, [8], 4, reference_node=0)
    with pytest.raises(ModalFileError, match=r"static_loads/translations.*wrong shape"):
        replace(data, static_translations=data.static_translations[:, :-1])
    with pytest.raises(ModalFileError, match=r"static_loads/translations.*without the load case names"):
        replace(data, load_cases=None)
    with pytest.raises(ModalFileError, match=r"static_loads.*names a load case twice"):
        replace(data, load_cases=(data.load_cases[0],) * len(data.load_cases))
    bare = modal_data_from_fe(fe, [8], 4, reference_node=0, static_loads=False)
    with pytest.raises(ValueError, match=r"static_loads=True"):
        bare.residual_fields()
    with pytest.raises(ModalFileError, match=r"node_displacements.*static_loads=True"):
        node_displacements(bare, np.zeros(bare.n_modes), loads=np.zeros(3))
    with pytest.raises(fl.RunArgumentError, match=r"loads.*shape"):
        node_displacements(data, np.zeros((2, data.n_modes)), loads=np.zeros((2, 3)))


def test_participation_from_load_cases_equals_the_fe_loads_route():
    """MPF from load-case amplitudes (a tip force, a root torque and gravity at one instant; the same at twice
    the size at another) equals the MPF of the same loads assembled on the FE DOFs and projected on the modes
    (modal_participation), to 1e-9 in every share."""
    from flexlib.fe import modal_participation, participation_from_load_cases

    fe = beam_mesh((0, 0, 0), (2.0, 0, 0), 16, rectangle(0.02, 0.04), E=2.1e11, rho=7850.0)
    data = modal_data_from_fe(fe, [16], 6, reference_node=0, attachment="pinned")
    held = fe.constrained([0], ("ux", "uy", "uz"))
    cases = inertial_load_cases(held) | interface_load_cases(held, [0, 16])
    a = np.zeros(len(data.load_cases))
    for name, value in (("F16_uy", -50.0), ("F0_rz", 12.0), ("acc_y", 9.81)):
        a[data.load_cases.index(name)] = value
    f = sum(value * cases[name] for name, value in zip(data.load_cases, a, strict=True) if value)
    modes = held.dof_fields(data.translational_modes, data.rotational_modes)
    ref = modal_participation(modes, data.generalized_stiffness, np.column_stack([f, 2 * f]))
    got = participation_from_load_cases(data, np.vstack([a, 2 * a]))
    np.testing.assert_allclose(got.shares, ref.shares, rtol=1e-9, atol=1e-9)
    assert got.kept == ref.kept
    with pytest.raises(ValueError, match="one per load case"):
        participation_from_load_cases(data, np.zeros(3))


def test_a_body_and_its_result_are_recovered_by_default():
    """Issue 30: the output functions given the body and its run's result (``node_displacements(model.beam, res)``)
    recover by default — the cantilever above with one mode kept: the tip deflection is beam theory's
    PL³/3EI + ρAgL⁴/8EI within 1e-6 without any load amplitudes assembled by hand, and so is the tip's world position
    (``deformed_positions(model.beam, res)``); ``loads=False`` gives plain superposition (off by > 1 %), as does
    modal data made without static responses (nothing to recover, no warning); a body loaded at a node the data
    have no load cases for gives plain superposition with a ModalDataWarning naming the body and the node."""
    import warnings

    b, h, L, P, Ey, rho, g = 0.02, 0.04, 1.0, 500.0, 2.1e11, 7850.0, 9.81
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 16, rectangle(b, h), E=Ey, rho=rho)
    data = modal_data_from_fe(fe, [16], 8, reference_node=0)
    model = TipLoaded(data, P, g=g, modes=_bending_y(data, 1), frames=[0, 16])
    res = fl.Simulation(model, use_cache=False).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    Iz, A = b * h**3 / 12, b * h
    tip_exact = -(P * L**3 / (3 * Ey * Iz) + rho * A * g * L**4 / (8 * Ey * Iz))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # recovered without a word
        recovered = node_displacements(model.beam, res, [16])[:, 0, 1]
        position = deformed_positions(model.beam, res, nodes=[16])[:, 0, 1]
    np.testing.assert_allclose(recovered, tip_exact, rtol=1e-6)
    np.testing.assert_allclose(position, tip_exact, rtol=1e-6)  # the beam's frame sits at the world origin
    plain = node_displacements(model.beam, res, [16], loads=False)[:, 0, 1]
    assert abs(plain[0] / tip_exact - 1) > 0.01
    mid = TipLoaded(data, P, g=g, modes=_bending_y(data, 1), frames=[0, 8])  # loaded at node 8: no load cases
    res_mid = fl.Simulation(mid, use_cache=False).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    with pytest.warns(fl.ModalDataWarning, match=r"node_displacements\(beam\): plain modal superposition.*node 8"):
        np.testing.assert_array_equal(node_displacements(mid.beam, res_mid, [16]),
                                      node_displacements(mid.beam, res_mid, [16], loads=False))
    bare = modal_data_from_fe(fe, [16], 8, reference_node=0, static_loads=False)
    plain_model = TipLoaded(bare, P, g=g, modes=_bending_y(bare, 1), frames=[0, 16])
    res2 = fl.Simulation(plain_model, use_cache=False).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_allclose(node_displacements(plain_model.beam, res2, [16])[:, 0, 1], plain, rtol=1e-9)


def test_vtk_series_and_drawings_recover_with_the_loads(tmp_path):
    """``write_vtk_series``/``plot_frame``/``animate`` from data and ``q`` take ``loads=`` (the body's load-case
    amplitudes): the written points are the recovered world positions (``deformed_positions(body, result)``, tip at
    beam theory's deflection within 1e-6), the displacement field its recovered value; without ``loads`` plain."""
    import meshio

    from flexlib.fe import plot_frame, write_vtk_series

    b, h, L, P, Ey, rho = 0.02, 0.04, 1.0, 500.0, 2.1e11, 7850.0
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 16, rectangle(b, h), E=Ey, rho=rho)
    data = modal_data_from_fe(fe, [16], 8, reference_node=0)
    model = TipLoaded(data, P, modes=_bending_y(data, 1), frames=[0, 16])
    res = fl.Simulation(model, use_cache=False).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    t, q, r0, T = model.beam.motion(res)
    loads = model.beam.load_amplitudes(res)
    sel = model.beam.modal_data
    pvd = write_vtk_series(tmp_path / "beam.pvd", sel, t, q, r0, T, loads=loads)
    first = meshio.read(sorted(pvd.parent.glob("beam*.d/*.vtu"))[0])
    expected = deformed_positions(model.beam, res)[0]
    np.testing.assert_allclose(first.points, expected, atol=1e-12)
    tip_exact = -P * L**3 / (3 * Ey * b * h**3 / 12)
    assert first.point_data["displacement"][-1, 1] == pytest.approx(tip_exact, rel=1e-6)
    plain = write_vtk_series(tmp_path / "plain.pvd", sel, t, q, r0, T)
    plain_first = meshio.read(sorted(plain.parent.glob("plain*.d/*.vtu"))[0])
    assert abs(plain_first.point_data["displacement"][-1, 1] / tip_exact - 1) > 0.01
    fig = plot_frame(sel, t, q, r0, T, loads=loads)
    assert fig.axes
