"""Malformed modal files and FE matrix files: each a ModalFileError naming the file and the dataset."""

from __future__ import annotations

import os
import re
from pathlib import Path

import h5py
import numpy as np
import pytest

from flexlib import FlexlibError, ModalFileError
from flexlib.fe import ModalData, beam_mesh, modal_data_from_fe, read_fe, rectangle
from tests.robustness.helpers import edited_h5


@pytest.fixture(scope="module")
def good(tmp_path_factory) -> Path:
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 6, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    data = modal_data_from_fe(fe, [0, 6], 4, title="good", geometric_stiffening=True)
    return data.write(tmp_path_factory.mktemp("modal") / "good.h5")


def replace_dataset(f: h5py.File, name: str, value) -> None:
    del f[name]
    f.create_dataset(name, data=value)


def modify(name: str, change):
    def edit(f: h5py.File) -> None:
        value = np.array(f[name][()])
        replace_dataset(f, name, change(value))
    return edit


def nan_at_first(a: np.ndarray) -> np.ndarray:
    a = a.astype(float)
    a.flat[5] = np.nan
    return a


def unsymmetric(a: np.ndarray) -> np.ndarray:
    a = a.copy()
    a[0, 1] += 0.1
    return a


CASES = {
    "missing dataset": (lambda f: f.__delitem__("modes/frequencies"), "/modes/frequencies", "missing"),
    "missing invariant": (lambda f: f.__delitem__("invariants/I9"), "/invariants/I9", "missing"),
    "NaN in mode shapes": (modify("modes/translational", nan_at_first), "/modes/translational", "non-finite"),
    "non-symmetric mass": (modify("modes/generalized_mass", unsymmetric), "/modes/generalized_mass", "not symmetric"),
    "indefinite mass": (modify("modes/generalized_mass", lambda a: -a), "/modes/generalized_mass",
                        "not positive definite"),
    "non-symmetric inertia": (modify("body/inertia", unsymmetric), "/body/inertia", "not symmetric"),
    "wrong shape coordinates": (modify("nodes/coordinates", lambda a: a[:, :2]), "/nodes/coordinates",
                                "wrong shape"),
    "wrong shape rotational modes": (modify("modes/rotational", lambda a: a[:, :-1]), "/modes/rotational",
                                     "wrong shape"),
    "string where a number is": (lambda f: replace_dataset(f, "body/mass", "heavy"), "/body/mass",
                                 "must be real numbers"),
    "negative mass": (modify("body/mass", lambda a: -a), "/body/mass", "must be positive"),
    "inconsistent frequencies": (modify("modes/frequencies", lambda a: a * 1.01), "/modes/frequencies",
                                 "contradicts"),
    "invariant contradicts mass": (modify("invariants/I1", lambda a: a * 1.5), "/invariants/I1", "contradicts"),
    "unknown interface node": (modify("interface/node_ids", lambda a: a + 100), "/interface/node_ids",
                               "not in '/nodes/ids'"),
    "element index out of range": (modify("nodes/elements", lambda a: a + 50), "/nodes/elements", "out of range"),
    "wrong shape section forces": (modify("modes/section_forces", lambda a: a[:, :-1]), "/modes/section_forces",
                                   "wrong shape"),
    "non-symmetric geometric stiffness": (modify("geometric_stiffness/omega_zz", unsymmetric),
                                          "/geometric_stiffness/omega_zz", "not symmetric"),
    "non-SI units": (lambda f: f["units"].attrs.__setitem__("length", "mm"), "/units", "must be SI"),
    "future format version": (lambda f: f.attrs.__setitem__("format_version", 99), "format_version",
                              "newer than the supported"),
    "not a modal file": (lambda f: f.attrs.__setitem__("format", "something-else"), "'format'",
                         "not a flexlib modal file"),
    "missing header": (lambda f: f.__delitem__("header"), "/header", "missing"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_malformed_file_names_file_and_dataset(good, tmp_path, case):
    edit, dataset, problem = CASES[case]
    path = edited_h5(good, tmp_path, edit, "bad.h5")
    with pytest.raises(ModalFileError) as info:
        ModalData.read(path)
    message = str(info.value)
    assert str(path) in message
    assert dataset in message
    assert problem in message
    assert isinstance(info.value, FlexlibError) and isinstance(info.value, ValueError)


def test_truncated_file(good, tmp_path):
    path = tmp_path / "truncated.h5"
    path.write_bytes(good.read_bytes()[: os.path.getsize(good) // 2])
    with pytest.raises(ModalFileError, match=re.escape(str(path)) + ".*(truncated|damaged)"):
        ModalData.read(path)


def test_missing_file(tmp_path):
    with pytest.raises(ModalFileError, match=re.escape(str(tmp_path / "nope.h5")) + ": no such modal file"):
        ModalData.read(tmp_path / "nope.h5")


def test_not_hdf5(tmp_path):
    path = tmp_path / "text.h5"
    path.write_text("modal data, honestly\n")
    with pytest.raises(ModalFileError, match=re.escape(str(path)) + ": not a readable HDF5"):
        ModalData.read(path)


def test_write_into_missing_directory(good, tmp_path):
    data = ModalData.read(good)
    target = tmp_path / "no" / "such" / "dir" / "m.h5"
    with pytest.raises(ModalFileError, match=re.escape(str(target)) + ": cannot write"):
        data.write(target)


def test_constructor_rejects_bad_arrays(good):
    """The in-memory record validates too: a non-symmetric generalised stiffness names its dataset."""
    from dataclasses import replace

    data = ModalData.read(good)
    K = np.array(data.generalized_stiffness)
    K[0, 1] += 1.0
    with pytest.raises(ModalFileError, match=r"ModalData: dataset '/modes/generalized_stiffness': not symmetric"):
        replace(data, generalized_stiffness=K)


def test_fe_npz_missing_array_and_unsymmetric_matrix(tmp_path):
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 3, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    fe.write_npz(tmp_path / "fe.npz")
    arrays = dict(np.load(tmp_path / "fe.npz"))
    del arrays["dof_map"]
    np.savez(tmp_path / "no_map.npz", **arrays)
    with pytest.raises(ModalFileError, match=r"no_map.npz: array 'dof_map' is missing"):
        read_fe(tmp_path / "no_map.npz")
    arrays = dict(np.load(tmp_path / "fe.npz"))
    M = fe.M.toarray()
    M[0, 1] += 1.0
    del arrays["M_data"], arrays["M_indices"], arrays["M_indptr"], arrays["M_shape"]
    np.savez(tmp_path / "unsym.npz", M=M, **arrays)
    with pytest.raises(ModalFileError, match=r"unsym.npz: matrix 'M' is not symmetric"):
        read_fe(tmp_path / "unsym.npz")


def test_reduction_and_mesher_input_errors():
    """Bad reduction/mesher arguments: ValueError naming the argument or the cause."""
    from flexlib.fe import craig_bampton

    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 4, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    with pytest.raises(ValueError, match="interface DOFs do not restrain all rigid-body motions"):
        craig_bampton(fe.M, fe.K, fe.dofs([0], ["ux", "uy"]), 2, rigid_body_modes=fe.rigid_body_modes())
    clamped = fe.constrained([0])
    with pytest.raises(ValueError, match="K does not annihilate the rigid-body modes"):
        craig_bampton(clamped.M, clamped.K, clamped.dofs([4]), 2,
                      rigid_body_modes=np.ones((clamped.n_dofs, 1)))
    with pytest.raises(ValueError, match=r"n_modes must be an integer in 0\.\.18"):
        craig_bampton(clamped.M, clamped.K, clamped.dofs([4]), 19)
    with pytest.raises(ValueError, match=r"K_ii is singular|not positive definite"):
        craig_bampton(fe.M, fe.K, fe.dofs([4], ["uy"]), 2)
    with pytest.raises(KeyError, match="no node with id 9"):
        fe.dofs([9])
    with pytest.raises(ValueError, match="n_elements must be a positive integer"):
        beam_mesh((0, 0, 0), (1.0, 0, 0), 0, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    with pytest.raises(ValueError, match="beam_mesh: E must be a positive finite number"):
        beam_mesh((0, 0, 0), (1.0, 0, 0), 2, rectangle(0.02, 0.03), E=float("nan"), rho=7850.0)
    with pytest.raises(TypeError, match=r"section at position fraction 0.* must be a Section"):
        beam_mesh((0, 0, 0), (1.0, 0, 0), 2, lambda s: 0.02, E=2.1e11, rho=7850.0)
