"""Mode selection in the library (issue 30, item 3): the modes that move a body in one plane of its axes
(``flexlib.fe.planar_modes``, ``FlexibleBody(..., plane=)``), and seed 001's modal participation factor method from
a body's own loads in a run (``FlexibleBody.participation``, passed back as ``modes=``); and the advice on the basis
(item 2): a clamped basis on a free hinge warns, naming the joint and the pinned attachment.

References: a planar beam's in-plane modes have no out-of-plane translation or rotation about the in-plane axes
(Euler–Bernoulli: bending in ``x–y`` and ``x–z`` and torsion decouple for a doubly symmetric section); the MPF method
of Cuadrado et al. (seed 001) on the pinned-free beam, whose analytic rigid-body loads at the critical instant are
``models.pinned_free_beam.participation_table`` (loads assembled on the FE DOFs: an independent route).
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib import ModalDataWarning, ModalFileError, ModelError, RunArgumentError
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.fe import beam_mesh, modal_data_from_fe, planar_modes, rectangle, select_modes
from flexlib.models.pinned_free_beam import PinnedFreeBeam, beam_modal_data, bending_modes, participation_table


@pytest.fixture(scope="module")
def strip():
    """A 1.5 m steel strip of 28.9 × 3.46 mm (the seed-001 beam's A and Iz as a rectangle): the in-plane (x–y)
    bending modes are low, the out-of-plane bending 8.3× and the torsion modes in between (45 Hz is torsion)."""
    h = (12e-10 / 1e-4) ** 0.5
    fe = beam_mesh((0, 0, 0), (1.5, 0, 0), 16, rectangle(1e-4 / h, h), E=2e11, rho=8000.0)
    return modal_data_from_fe(fe, [16], 12, reference_node=0, attachment="pinned")


def _out_of_plane_share(data, k, normal):
    T, R = data.translational_modes[k], data.rotational_modes[k]
    L = np.linalg.norm(data.coordinates, axis=1).max()
    rot = [a for a in range(3) if a != normal]
    return (np.sum(T[:, normal] ** 2) + L**2 * np.sum(R[:, rot] ** 2)) / (np.sum(T**2) + L**2 * np.sum(R**2))


def test_planar_modes_move_the_body_in_its_plane_only(strip):
    """Every mode is in exactly one of the lists 'xy' and 'out of xy'; the in-plane ones carry ≤ 1e-6 of their squared
    amplitude out of the plane (measured ~1e-30), the others more than 1e-2; the count by frequency takes an
    out-of-plane mode as the 4th, ``plane="xy"`` does not."""
    xy = planar_modes(strip, "xy")
    assert xy == sorted(xy, key=lambda k: strip.frequencies[k])
    assert all(_out_of_plane_share(strip, k, 2) <= 1e-6 for k in xy)
    others = [k for k in range(strip.n_modes) if k not in xy]
    assert others and all(_out_of_plane_share(strip, k, 2) > 1e-2 for k in others)
    lowest4 = list(np.argsort(strip.frequencies)[:4])
    assert any(k in others for k in lowest4)  # the reason for the option
    assert planar_modes(strip, "yx") == xy
    body = FlexibleBody(strip, modes=4, plane="xy")
    np.testing.assert_array_equal(body.modal_data.frequencies, strip.frequencies[xy[:4]])
    assert np.abs(body.modal_data.translational_modes[:, :, 2]).max() <= 1e-9
    assert select_modes(strip, count=4, plane="xy").frequencies.tolist() == strip.frequencies[xy[:4]].tolist()
    assert FlexibleBody(strip, plane="xy").n_modes == len(xy)
    assert FlexibleBody(strip, modes=0, plane="xy").n_modes == 0


def test_bad_plane_and_mode_arguments_are_named(strip):
    """An unknown plane, a plane with a list of indices, more planar modes than the data hold, and a participation
    table of other data are refused with the argument named."""
    with pytest.raises(RunArgumentError, match="plane must be one of"):
        planar_modes(strip, "xq")
    with pytest.raises(ModelError, match="FlexibleBody: plane must be one of"):
        FlexibleBody(strip, modes=2, plane="z")
    with pytest.raises(ModelError, match="give modes as a count"):
        FlexibleBody(strip, modes=[0, 1], plane="xy")
    n = len(planar_modes(strip, "xy"))
    with pytest.raises(ModelError, match=f"only {n}"):
        FlexibleBody(strip, modes=n + 1, plane="xy")
    beam = beam_modal_data(16)
    with pytest.raises(ModelError, match="participation table has"):
        FlexibleBody(strip, modes=participation_table(beam)[0])


@pytest.fixture(scope="module")
def rigid_run():
    """The seed-001 beam as a rigid body (no modes) under its bang-bang torque, 2 s."""
    data = beam_modal_data(32)
    model = PinnedFreeBeam(data, [], True, frames=[0, 32])
    return data, model, fl.Simulation(model).run(2.0, dt_out=0.01, progress=False)


def test_participation_from_a_rigid_run_equals_the_analytic_table(rigid_run):
    """The body's own loads in a rigid run (pin cut load + inertia loads through the stored static modal loads) at its
    most critical instant give seed 001's table from the analytic rigid motion on the FE DOFs to 1e-9 of the largest
    share (measured 7e-17), keep the same five modes (out-of-plane ones at round-off), and ``modes=table`` keeps
    them."""
    data, model, res = rigid_run
    analytic, t_crit = participation_table(data)
    table = model.beam.participation(res)
    bending = bending_modes(data)
    np.testing.assert_allclose(table.shares[bending], analytic.shares, atol=1e-9 * 100.0)
    assert table.kept == [bending[k] for k in analytic.kept] and len(table.kept) == 5
    out_of_plane = [k for k in range(data.n_modes) if k not in planar_modes(data, "xy")]
    assert np.all(table.shares[out_of_plane] <= 1e-9)  # planar loads: round-off only (measured 6e-11 %)
    at_crit = model.beam.participation(res, at=t_crit)
    np.testing.assert_allclose(at_crit.shares, table.shares, atol=1e-9 * 100.0)
    kept = FlexibleBody(data, modes=table)
    np.testing.assert_array_equal(kept.modal_data.frequencies, data.frequencies[table.kept])


def test_participation_refuses_bad_instants_and_data_without_static_loads(rigid_run):
    """``at`` outside the run or not a time, and modal data without static load responses, are named errors."""
    _data, model, res = rigid_run
    with pytest.raises(RunArgumentError, match="outside the run"):
        model.beam.participation(res, at=3.0)
    with pytest.raises(RunArgumentError, match="at must be a time"):
        model.beam.participation(res, at="1.0")
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 4, rectangle(0.02, 0.01), E=2e11, rho=8000.0)
    bare = modal_data_from_fe(fe, [4], 3, reference_node=0, attachment="pinned", static_loads=False)
    body = FlexibleBody(bare, modes=0)
    with pytest.raises((ModalFileError, RunArgumentError)):
        body.participation(res)


def _hinged(data, drive: str | None):
    """World, a revolute about z at the body's reference node (``drive``: None no flange, "torque" a torque source
    on its flange, "position" a position source), the body with two modes."""
    from flexlib.components.control import Constant
    from flexlib.components.mechanics.multibody import Revolute, World
    from flexlib.components.mechanics.rotational import Position, Torque

    class Hinged(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World()
            self.pin = Revolute(n=[0, 0, 1], use_axis_flange=drive is not None, init={"phi": 0.0, "w": 0.0})
            self.arm = FlexibleBody(data, modes=2)
            self.connect(self.world.frame_b, self.pin.frame_a)
            self.connect(self.pin.frame_b, self.arm.frame_a)
            if drive is not None:
                self.source = Torque() if drive == "torque" else Position()
                self.signal = Constant(k=0.0)
                self.connect(self.signal.y, self.source.tau if drive == "torque" else self.source.phi_ref)
                self.connect(self.source.flange, self.pin.axis)

    return Hinged()


@pytest.mark.parametrize("drive", [None, "torque"])
def test_a_clamped_basis_on_a_free_hinge_warns_on_every_build(drive, tmp_path, monkeypatch):
    """The default (clamped) basis at a reference node on a revolute that takes no moment from a position (no flange,
    or a torque on it) warns at the build, naming the body, the joint and ``attachment='pinned'`` — also when the
    compiled model comes from the disk cache (the second build)."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 4, rectangle(0.02, 0.01), E=2e11, rho=8000.0)
    clamped = modal_data_from_fe(fe, [4], 2, reference_node=0)
    for cached in (False, True):
        with pytest.warns(ModalDataWarning, match=r"arm: .* clamped basis .* free revolute pin .*attachment='pinned'"):
            build = fl.Simulation(_hinged(clamped, drive), codegen=False).build
        assert build.cached is cached


def test_the_right_basis_or_a_held_hinge_is_not_warned_about():
    """No advice for the pinned basis on a free hinge, nor for the clamped basis on a position-driven hinge (the pin
    tangent is held there: cantilever modes fit)."""
    import warnings

    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 4, rectangle(0.02, 0.01), E=2e11, rho=8000.0)
    clamped = modal_data_from_fe(fe, [4], 2, reference_node=0)
    pinned = modal_data_from_fe(fe, [4], 2, reference_node=0, attachment="pinned")
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModalDataWarning)
        _hinged(pinned, None).arm.advise()
        _hinged(pinned, "torque").arm.advise()
        _hinged(clamped, "position").arm.advise()
