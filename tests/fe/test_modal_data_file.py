"""The HDF5 modal file: bit-exact round trip, content hash, mode subsets, mode selection and default damping.

References: seed 000 of issue 10 (default modal damping 1 % below 100 Hz, 10 % from 100 to 1000 Hz, 100 %
above); seed 001 (MPF threshold 1 %).
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from flexlib import ModalFileError
from flexlib.fe import (
    ModalData,
    beam_mesh,
    default_damping_ratio,
    modal_damping_matrix,
    modal_data_from_fe,
    modal_participation,
    nodal_generalized_forces,
    rectangle,
    select_modes,
)


@pytest.fixture(scope="module")
def data():
    fe = beam_mesh((0, 0, 0), (1.2, 0, 0), 12, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    return modal_data_from_fe(fe, [0, 12], 8, title="test beam")


def arrays_equal(a: ModalData, b: ModalData) -> None:
    for name, value in a._arrays():
        other = dict(b._arrays())[name]
        if value is None:
            assert other is None, name
        else:
            assert other.dtype == value.dtype and other.shape == value.shape, name
            assert other.tobytes() == value.tobytes(), name  # bit-exact


def test_round_trip_is_bit_exact_and_hash_stable(data, tmp_path):
    """write -> read gives bit-identical arrays, the same header and provenance, and the same content hash;
    writing again gives the same hash (stable across runs: it depends on content only)."""
    path = data.write(tmp_path / "beam.fmod.h5")
    back = ModalData.read(path)
    arrays_equal(data, back)
    assert (back.title, back.creator, back.date) == (data.title, data.creator, data.date)
    assert back.provenance == data.provenance
    assert back.mass_description == "consistent"
    assert back.content_hash() == data.content_hash()
    again = ModalData.read(back.write(tmp_path / "copy.h5"))
    assert again.content_hash() == data.content_hash()
    assert len(data.content_hash()) == 64


def test_optional_datasets_round_trip(data, tmp_path):
    """Optional stress modes, faces and damping ratios are written and read back bit-exactly and enter the hash."""
    from dataclasses import replace

    rng = np.random.default_rng(7)
    full = replace(data, stress_modes=rng.normal(size=(data.n_modes, data.n_nodes, 6)) * 1e6,
                   faces=np.array([[0, 1, 2], [1, 2, 3]]), damping_ratio=np.linspace(0.01, 0.05, data.n_modes))
    back = ModalData.read(full.write(tmp_path / "full.h5"))
    arrays_equal(full, back)
    assert back.content_hash() == full.content_hash() != data.content_hash()
    assert np.array_equal(back.damping_ratios(), full.damping_ratio)


def test_hash_keys_on_content_not_header(data, tmp_path):
    """Another title/creator/date/provenance or file name keeps the hash; any change of an array changes it."""
    from dataclasses import replace

    renamed = replace(data, title="other", creator="someone", date="2000-01-01T00:00:00+00:00",
                      provenance={"note": "re-exported"})
    assert renamed.content_hash() == data.content_hash()
    K = np.array(data.generalized_stiffness)
    K[0, 0] *= 1 + 1e-15
    changed = replace(data, generalized_stiffness=K, frequencies=np.sqrt(np.diag(K)) / (2 * math.pi))
    assert changed.content_hash() != data.content_hash()
    assert replace(data, damping_ratio=np.full(data.n_modes, 0.02)).content_hash() != data.content_hash()


def test_arrays_are_read_only(data):
    """ModalData is immutable: no attribute can be set, no array or invariant replaced or written in place."""
    with pytest.raises(ValueError, match="read-only"):
        data.frequencies[0] = 1.0
    with pytest.raises(TypeError):
        data.invariants["I1"] = np.asarray(0.0)
    with pytest.raises(AttributeError):
        data.mass = 2.0


def test_write_is_atomic(data, tmp_path, monkeypatch):
    """A failed write leaves the previous file intact and no temporary file behind."""
    path = data.write(tmp_path / "beam.h5")
    before = path.read_bytes()

    def broken(self, name, data=None, **kw):
        raise OSError("disk full")

    monkeypatch.setattr(h5py.Group, "create_dataset", broken)
    with pytest.raises(ModalFileError, match=r"beam.h5.*disk full"):
        data.write(path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["beam.h5"]


def test_select_subset_keeps_invariants_consistent(data):
    """Selecting modes slices every per-mode array and invariant (equal to the invariants of the subset)."""
    sub = data.select([2, 0])
    assert sub.n_modes == 2
    assert np.array_equal(sub.frequencies, data.frequencies[[2, 0]])
    assert np.array_equal(sub.invariants["I9"][0, 1], data.invariants["I9"][2, 0])
    assert np.array_equal(sub.invariants["I5"][1, :, 0], data.invariants["I5"][0, :, 2])
    assert sub.mass == data.mass
    assert sub.select([1]).provenance["selected_modes"] == [0]
    with pytest.raises(ValueError, match="mode indices"):
        data.select([0, 99])


def test_select_by_count_and_frequency(data):
    """By count: the lowest n; by cut-off: all modes at or below it; both: the intersection."""
    f = np.sort(data.frequencies)
    assert np.array_equal(select_modes(data, count=3).frequencies, f[:3])
    cut = (f[4] + f[5]) / 2
    assert np.array_equal(select_modes(data, max_frequency=cut).frequencies, f[:5])
    assert select_modes(data, count=2, max_frequency=cut).n_modes == 2


def test_mpf_selection_from_nodal_loads(data):
    """A transverse tip force on the free beam: static modal amplitudes phi^T F / omega^2; the modes kept at 1 %
    are those with share >= 1 %, the shares are 100 % for the largest; modes without y-motion have share 0."""
    Q = nodal_generalized_forces(data, {12: (0, 50.0, 0, 0, 0, 0)})
    omega2 = (2 * math.pi * data.frequencies) ** 2
    table = modal_participation(np.eye(data.n_modes), omega2, Q, frequencies=data.frequencies)
    amp = np.abs(Q / omega2)
    assert table.shares == pytest.approx(amp / amp.max() * 100)
    assert table.kept == [i for i in range(data.n_modes) if amp[i] >= 0.01 * amp.max()]
    chosen = select_modes(data, participation=table)
    assert chosen.n_modes == len(table.kept)
    assert "kept (>= 1 %)" in str(table)


def test_default_damping_by_frequency_band():
    """1 % below 100 Hz, 10 % from 100 to 1000 Hz (both ends), 100 % above; per-mode overrides win."""
    zeta = default_damping_ratio([10.0, 99.99, 100.0, 500.0, 1000.0, 1000.01, 5e4])
    assert zeta.tolist() == [0.01, 0.01, 0.10, 0.10, 0.10, 1.0, 1.0]
    assert default_damping_ratio([10.0, 500.0], {1: 0.03}).tolist() == [0.01, 0.03]
    with pytest.raises(ValueError, match="mode 5"):
        default_damping_ratio([10.0], {5: 0.1})


def test_modal_damping_matrix(data):
    """D = diag(2 zeta omega M_jj) with the default rule, overrides per mode."""
    D = modal_damping_matrix(data, {0: 0.05})
    omega = 2 * math.pi * data.frequencies
    zeta = default_damping_ratio(data.frequencies, {0: 0.05})
    assert np.diag(D) == pytest.approx(2 * zeta * omega * np.diag(data.generalized_mass))
    with pytest.raises(ValueError, match="modal_damping_matrix: override for mode 99"):
        modal_damping_matrix(data, {99: 0.1})


def test_docs_example_runs(tmp_path, monkeypatch, capsys):
    """The example of docs/modal_file.md runs as written (in a scratch directory) and writes a readable file."""
    from pathlib import Path

    doc = (Path(__file__).parents[2] / "docs" / "modal_file.md").read_text()
    code = doc.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/modal_file.md", "exec"), {})
    assert ModalData.read(tmp_path / "boom.fmod.h5").n_modes == 12 + 10 - 6
    assert capsys.readouterr().out.strip()


def test_zero_mode_body_is_valid(tmp_path):
    """One interface node and no fixed-interface modes: the six constraint modes are the rigid motions, so no
    elastic mode is left; the modal data (rigid-body properties only, mass rho A L) write and read back."""
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 4, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    md = modal_data_from_fe(fe, [0], 0)
    assert md.n_modes == 0 and md.provenance["n_rigid_modes_removed"] == 6
    back = ModalData.read(md.write(tmp_path / "rigid.h5"))
    assert back.n_modes == 0 and back.invariants["I9"].shape == (0, 0, 3, 3)
    assert back.mass == pytest.approx(7850.0 * 0.02 * 0.03 * 1.0, rel=1e-12)
    assert back.content_hash() == md.content_hash()
