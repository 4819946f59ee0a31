"""Flexible bodies end to end, as a new user who mistypes meets them (issue 26, red-team pass): FE models built by
hand, point masses, the matrix readers, the reduction's options, hand-edited modal files, mode selection and MPFs,
FlexibleBody's init/guess and frames, the output and drawing functions and the pinned-free beam model. Each case was
a raw numpy/Python traceback, a silent wrong answer (a string or a bool read as a number, a fractional node id
truncated, an option ignored, the mass and stiffness matrices swapped) or a vague message; now each is a flexlib
error naming the argument, file or dataset and what is accepted, or (where marked) the right behaviour."""

from __future__ import annotations

import re
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.io

from flexlib import ModalFileError, ModelError, RunArgumentError
from flexlib.components.mechanics.flexible import FlexibleBody, cayley_rotation, frame_names
from flexlib.fe import (
    FEModel,
    ModalData,
    Section,
    beam_mesh,
    beam_stress_modes,
    craig_bampton,
    default_damping_ratio,
    deformed_positions,
    elastic_static_responses,
    element_matrices,
    energies,
    geometric_stiffness_matrix,
    inertia_invariants,
    inertial_load_cases,
    modal_damping_matrix,
    modal_data_from_fe,
    modal_participation,
    nodal_generalized_forces,
    node_displacements,
    participation_from_load_cases,
    plot_frame,
    read_ansys_full,
    read_matrix_market,
    read_nastran_dmig,
    read_nastran_op4,
    rectangle,
    section_force_modes,
    select_modes,
    write_model_vtk,
    write_vtk_series,
)
from flexlib.fe.fe_model import UnknownNodeError
from tests.robustness.helpers import edited_h5


@pytest.fixture(scope="module")
def fe():
    return beam_mesh((0, 0, 0), (1.0, 0, 0), 4, rectangle(0.02, 0.01), E=2e11, rho=8000.0)


@pytest.fixture(scope="module")
def data(fe) -> ModalData:
    """8 modes, stress, section-force and static-load data of a 4-element cantilever."""
    return modal_data_from_fe(fe, [4], 2, reference_node=0, title="red beam", stress_fibre=(0.01, 0.005))


@pytest.fixture(scope="module")
def good(data, tmp_path_factory) -> Path:
    return data.write(tmp_path_factory.mktemp("redteam") / "good.h5")


@pytest.fixture(scope="module")
def mtx(fe, tmp_path_factory) -> tuple[Path, Path]:
    d = tmp_path_factory.mktemp("mtx")
    scipy.io.mmwrite(str(d / "M.mtx"), fe.M)
    scipy.io.mmwrite(str(d / "K.mtx"), fe.K)
    return d / "M.mtx", d / "K.mtx"


# --------------------------------------------------------------------------------------------------- FE models
def test_fe_model_from_lists_and_dense_matrices_is_normalised(fe):
    """Lists for the tables and dense matrices were taken as given and failed later (AttributeError 'list' has no
    'ndim', '.tocsr' of an ndarray): now converted where the FEModel is made, and reducible."""
    model = FEModel(fe.M.toarray(), fe.K.toarray(), fe.nodes.tolist(), fe.dof_map.tolist(), list(fe.node_ids))
    assert model.M.format == "csr" and model.dof_map.dtype == np.int64 and model.nodes.dtype == float
    assert modal_data_from_fe(model, [4], 2, reference_node=0).n_modes == 8


FE_MODEL_CASES = {
    "matrix given as a file name": (lambda fe: FEModel("M.mtx", fe.K, fe.nodes, fe.dof_map, fe.node_ids),
                                    r"FEModel: argument 'M' must be a real matrix .* got str 'M\.mtx'; read matrix "
                                    r"files with read_fe or read_matrix_market"),
    "nodes given as a file name": (lambda fe: FEModel(fe.M, fe.K, "nodes.txt", fe.dof_map, fe.node_ids),
                                   r"FEModel: argument 'nodes' must be an array of numbers, got str"),
    "fractional dof map": (lambda fe: FEModel(fe.M, fe.K, fe.nodes, fe.dof_map + 0.5, fe.node_ids),
                           r"FEModel: argument 'dof_map' must hold whole numbers, got 0\.5"),
    "component in capitals": (lambda fe: fe.constrained([0], ["UX"]),
                              r"unknown component 'UX'; components are \['ux', .*\] \(did you mean 'ux'\?\)"),
    "one component as a string": (lambda fe: fe.constrained([0], "ux"),
                                  r"components must be a list .* got the string 'ux' \(for one component: \['ux'\]\)"),
    "unknown component of dofs": (lambda fe: fe.dofs([0], ["uu"]), r"unknown component 'uu'"),
    "gravity as text": (lambda fe: fe.gravity_load("down"), r"FEModel\.gravity_load: argument 'g' must be three "
                                                              r"numbers \(x, y, z\) \[m/s2\]"),
    "gravity of two components": (lambda fe: fe.gravity_load([0, -9.81]), r"argument 'g' .* got shape \(2,\)"),
    "translation of one component": (lambda fe: fe.translation_field([1.0]),
                                     r"FEModel\.translation_field: argument 'vector' .* got shape \(1,\)"),
    "path of the wrong type": (lambda fe: fe.write_npz(123), r"FEModel\.write_npz: argument 'path' must be a path"),
}


@pytest.mark.parametrize("case", list(FE_MODEL_CASES))
def test_bad_fe_model_input_is_named(fe, case):
    call, pattern = FE_MODEL_CASES[case]
    with pytest.raises(RunArgumentError, match=pattern):
        call(fe)


@pytest.mark.parametrize(("node", "pattern"), [
    ("0", r"node id '0' \(str\) is not a node id: ids are whole numbers \(write 0, without quotes\)"),
    (0.5, r"node id 0\.5 \(float\) is not a node id"),  # was node 0, silently (int(0.5))
    (True, r"node id True \(bool\) is not a node id"),
])
def test_node_ids_that_are_not_whole_numbers(fe, node, pattern):
    with pytest.raises(UnknownNodeError, match=pattern):
        fe.constrained([node])
    with pytest.raises(UnknownNodeError, match=pattern):
        fe.node_index([node])
    assert fe.constrained([0.0]).n_dofs == fe.n_dofs - 6  # a whole float from an FE table is the node id


@pytest.mark.parametrize(("kwargs", "pattern"), [
    ({"masses": ["1.5"]}, r"argument 'masses' must be masses \[kg\], numbers, got \['1\.5'\]"),  # was 1.5 kg
    ({"masses": [True]}, r"argument 'masses' must be masses \[kg\], numbers, got \[True\]"),  # was 1 kg
    ({"masses": [1.0], "offsets": [0.0, 0.1]}, r"argument 'offsets' has shape \(2,\), expected \(1, 3\)"),
    ({"masses": [1.0], "inertias": np.eye(2)}, r"argument 'inertias' has shape \(2, 2\), expected \(1, 3, 3\)"),
    ({"masses": [-1.0]}, r"negative mass -1\.0 kg at node 4"),
])
def test_bad_point_masses_are_flexlib_errors(fe, kwargs, pattern):
    with pytest.raises(RunArgumentError, match=r"FEModel\.with_point_masses: " + pattern):
        fe.with_point_masses([4], **kwargs)


def test_npz_into_a_missing_directory_names_the_file(fe, tmp_path):
    target = tmp_path / "no" / "fe.npz"
    with pytest.raises(ModalFileError, match=re.escape(str(target)) + ": cannot write the FE model archive"):
        fe.write_npz(target)
    assert not (tmp_path / "no").exists()


def test_section_name_must_be_text():
    with pytest.raises(RunArgumentError, match=r"Section: name must be a string .* got int 5"):
        Section(1e-4, 1e-9, 1e-9, 1e-9, name=5)


def test_beam_node_positions_as_text():
    """``nodes_at=["0.5"]`` was read as 0.5 m."""
    with pytest.raises(RunArgumentError, match=r"beam_mesh: argument 'nodes_at' must be numbers .* got \['0\.5'\]"):
        beam_mesh((0, 0, 0), (1, 0, 0), 2, rectangle(0.02, 0.01), E=2e11, rho=8e3, nodes_at=["0.5"])


def test_beam_too_large_for_memory_is_refused_before_allocating():
    """``n_elements=10**12`` was a MemoryError from numpy."""
    with pytest.raises(RunArgumentError, match=r"beam_mesh: n_elements=1000000000000 needs about .* GiB .* more than"):
        beam_mesh((0, 0, 0), (1, 0, 0), 10**12, rectangle(0.02, 0.01), E=2e11, rho=8e3)


# --------------------------------------------------------------------------------------------- matrix files
def test_one_matrix_market_file_for_both_matrices(fe, mtx):
    _M, K = mtx
    with pytest.raises(ModalFileError, match=re.escape(str(K)) + r": given as both the mass and the stiffness file"):
        read_matrix_market(K, K, fe.nodes)


def test_swapped_mass_and_stiffness_files(fe, mtx):
    """The stiffness file as the mass was read, and the reduction failed later with 0/0 in the centre of mass."""
    M, K = mtx
    pattern = r": matrix 'M' gives a rigid translation along x no mass .* Are the mass and stiffness matrices swapped"
    with pytest.raises(ModalFileError, match=re.escape(str(K)) + pattern):
        read_matrix_market(K, M, fe.nodes)


def test_swapped_matrices_of_an_fe_model_in_memory(fe):
    swapped = FEModel(fe.K, fe.M, fe.nodes, fe.dof_map, fe.node_ids)
    with pytest.raises(RunArgumentError, match=r"modal_data_from_fe: FE model \(in memory\): matrix 'M' gives a rigid "
                                               r"translation along x no mass"):
        modal_data_from_fe(swapped, [4], 2, reference_node=0)


def test_node_table_of_numbers_as_text(fe, mtx):
    """``[["0", "0", "0"], ...]`` was read as numbers."""
    M, K = mtx
    with pytest.raises(RunArgumentError, match=r"argument 'nodes' must be an array of numbers or a path to a table, "
                                               r"got text"):
        read_matrix_market(M, K, fe.nodes.astype(str).tolist())


@pytest.fixture(scope="module")
def op4_path(fe, tmp_path_factory) -> Path:
    op4 = pytest.importorskip("pyNastran.op4.op4", reason="optional extra 'nastran' (pyNastran) not installed")
    path = tmp_path_factory.mktemp("op4") / "beam.op4"
    with open(path, "w") as f:
        op4.OP4().write_op4(f, {"MAA": (2, fe.M.toarray()), "KAA": (2, fe.K.toarray())}, is_binary=False,
                            precision="double")
    return path


@pytest.mark.parametrize(("call", "pattern"), [
    (lambda p, fe: read_nastran_op4(p, mass="KAA", nodes=fe.nodes),  # was M = K, silently
     r"read_nastran_op4: arguments 'mass' and 'stiffness' name the same matrix 'KAA'"),
    (lambda p, fe: read_nastran_op4(5, nodes=fe.nodes), r"argument 'path' must be a path .* got int 5"),
    (lambda p, fe: read_nastran_op4(p, mass=5, nodes=fe.nodes), r"argument 'mass' must be the name of a matrix"),
    (lambda p, fe: read_nastran_op4(p, nodes=fe.nodes, node_ids=["1", "2", "3", "4", "5"]),
     r"argument 'node_ids' must be an array of numbers or a path to a table, got text"),
])
def test_bad_op4_arguments(op4_path, fe, call, pattern):
    with pytest.raises(RunArgumentError, match=pattern):
        call(op4_path, fe)


def test_ansys_path_of_the_wrong_type():
    """Checked before the optional reader is looked for (it was os.fspath's TypeError once installed)."""
    with pytest.raises(RunArgumentError, match=r"read_ansys_full: argument 'path' must be a path .* got int 5"):
        read_ansys_full(5)


@pytest.mark.parametrize(("args", "kwargs", "pattern"), [
    (("KAAX", "KAAX"), {}, r"arguments 'mass_name' and 'stiffness_name' name the same matrix 'KAAX'"),  # IndexError
    ((None, "KAAX"), {}, r"argument 'mass_name' must be the name of a matrix .* got None"),
    (("MAAX", "KAAX"), {"punch": "yes"}, r"argument 'punch' must be True .* got 'yes'"),  # was truthy
])
def test_bad_dmig_arguments(tmp_path, args, kwargs, pattern):
    pytest.importorskip("pyNastran.bdf.bdf", reason="optional extra 'nastran' (pyNastran) not installed")
    path = tmp_path / "deck.bdf"
    path.write_text("GRID,1,,0.,0.,0.\n")
    with pytest.raises(RunArgumentError, match="read_nastran_dmig: " + pattern):
        read_nastran_dmig(path, *args, **kwargs)
    with pytest.raises(RunArgumentError, match=r"argument 'bdf_path' must be a path .* got int 5"):
        read_nastran_dmig(5, "MAAX", "KAAX")


# ------------------------------------------------------------------------------------------------- reduction
BUILDING_BLOCK_CASES = {
    "static loads of another size": (lambda fe: elastic_static_responses(fe.constrained([0]), np.zeros(5)),
                                     r"elastic_static_responses: argument 'loads' has shape \(5,\), expected \(24,\) "
                                     r"or \(24, k\)"),  # numpy: cannot reshape
    "static loads as text": (lambda fe: elastic_static_responses(fe.constrained([0]), "abc"),
                             r"elastic_static_responses: argument 'loads' must be .* numbers, got 'abc'"),
    "FE model as a path": (lambda fe: inertial_load_cases("fe.npz"),
                           r"inertial_load_cases: argument 'fe' must be an FEModel"),  # AttributeError
    "displacement of another size": (lambda fe: geometric_stiffness_matrix(fe, np.zeros(3)),
                                     r"geometric_stiffness_matrix: argument 'displacement' has shape \(3,\), expected "
                                     r"\(30,\)"),  # IndexError
    "section forces of another size": (lambda fe: section_force_modes(fe, np.zeros((3, 2))),
                                       r"section_force_modes: argument 'modes' has shape \(3, 2\), expected \(30, k\)"),
    "stress fibre as text": (lambda fe: beam_stress_modes(fe, np.zeros((30, 1)), ("a", 0.1)),
                             r"beam_stress_modes: argument 'fibre' must be two finite numbers"),
    "invariants of another size": (lambda fe: inertia_invariants(fe.mass_points, np.zeros((3, 2))),
                                   r"inertia_invariants: argument 'modes' must be finite mode shapes \(30, M\)"),
    "negative element length": (lambda fe: element_matrices(-1.0, lambda s: rectangle(0.02, 0.01), 2e11, 8e10, 8e3,
                                                            timoshenko=False, rotary_inertia=False, lumped=False),
                                r"element_matrices: the element length L must be a positive finite number \[m\], "
                                r"got -1\.0"),  # gave a negative stiffness
    "rotation vector of two components": (lambda fe: cayley_rotation([1.0, 2.0]),
                                          r"cayley_rotation: argument 'theta' must be finite rotation vectors "
                                          r"\(\.\.\., 3\)"),
    "frame count as text": (lambda fe: frame_names("3"), r"frame_names: n must be a number of frames .* got '3'"),
}


@pytest.mark.parametrize("case", list(BUILDING_BLOCK_CASES))
def test_bad_building_block_input_is_named(fe, case):
    call, pattern = BUILDING_BLOCK_CASES[case]
    with pytest.raises(RunArgumentError, match=pattern):
        call(fe)


def test_craig_bampton_flags_and_rigid_modes(fe):
    with pytest.raises(RunArgumentError, match=r"craig_bampton: argument 'orthogonalize' must be True or False, got "
                                               r"'no'"):  # a truthy string orthogonalised
        craig_bampton(fe.M, fe.K, list(range(6)), 2, orthogonalize="no")
    with pytest.raises(RunArgumentError, match=r"craig_bampton: rigid_body_modes must be an array \(30, r\) .* got "
                                               r"'all'"):
        craig_bampton(fe.M, fe.K, list(range(6)), 2, rigid_body_modes="all")


REDUCTION_CASES = {
    "title not text": ({"title": 5}, r"argument 'title' must be a string .* got int 5"),
    "creator None": ({"creator": None}, r"argument 'creator' must be a string"),
    "one damping ratio for all": ({"damping_ratio": 0.02},
                                  r"argument 'damping_ratio' must be one modal damping ratio per mode \(8 modes\).* "
                                  r"pass np\.full\(8, 0\.02\)"),
    "damping ratio as a percentage": ({"damping_ratio": [5.0] * 8},
                                      r"argument 'damping_ratio'\[0\] is 5\.0: .* \(a percentage\? 5 % is 0\.05\)"),
    "damping ratios as text": ({"damping_ratio": ["0.02"] * 8}, r"argument 'damping_ratio'\[0\] is '0\.02'"),
    "damping ratios too few": ({"damping_ratio": [0.02]},
                               r"argument 'damping_ratio' has shape \(1,\), but the reduction gives 8 modes"),
    "stress fibre as text": ({"stress_fibre": ("0.01", 0.005)},  # was read as 0.01 m
                             r"argument 'stress_fibre' must be two finite numbers \(y, z\) \[m\]"),
    "stress fibre with a bool": ({"stress_fibre": (True, 0.005)},  # was 1 m
                                 r"argument 'stress_fibre' must be two finite numbers"),
    "support nodes without stiffening": ({"support_nodes": [2]},  # were ignored
                                         r"support_nodes=\[2\] hold the body for the geometric stiffness load cases, "
                                         r"which are computed only with geometric_stiffening=True"),
    "two reference nodes": ({"reference_node": [0, 4]},  # node 4 was dropped
                            r"argument 'reference_node' must be one node id \(an int\), got \[0, 4\]"),
}


@pytest.mark.parametrize("case", list(REDUCTION_CASES))
def test_bad_reduction_options_are_named(fe, case):
    kwargs, pattern = REDUCTION_CASES[case]
    kwargs = {"reference_node": 0} | kwargs
    with pytest.raises(RunArgumentError, match="modal_data_from_fe: " + pattern):
        modal_data_from_fe(fe, [4], 2, **kwargs)


def test_pinned_attachment_without_a_reference_node(fe):
    """``attachment="pinned"`` without ``reference_node`` gave a floating body, the option ignored."""
    with pytest.raises(RunArgumentError, match=r"attachment='pinned' says how the reference frame is attached at "
                                               r"reference_node, which is not given"):
        modal_data_from_fe(fe, [0, 4], 2, attachment="pinned")


def test_damping_ratios_per_mode_are_stored(fe):
    assert modal_data_from_fe(fe, [4], 2, reference_node=0, damping_ratio=np.full(8, 0.02)).damping_ratio.tolist() \
        == [0.02] * 8


# ----------------------------------------------------------------------------------------------- modal data
@pytest.mark.parametrize(("modes", "pattern"), [
    (1.5, r"modes must be a list of mode indices \(ints\) in 0\.\.7, got 1\.5"),  # was mode 1
    ([True, False], r"modes must be .* got \[True, False\] \(an item True of type bool\)"),  # was modes 1, 0
    (["a"], r"modes must be .* got \['a'\] \(an item 'a' of type str\)"),
    ([0, 0], r"mode indices must be distinct in 0\.\.7, got \[0, 0\]"),
])
def test_select_takes_integer_indices_only(data, modes, pattern):
    with pytest.raises(RunArgumentError, match=r"modal data 'red beam'\.select: " + pattern):
        data.select(modes)


@pytest.mark.parametrize(("node", "pattern"), [
    ("4", r"a node id is one whole number, got '4'"),
    (4.7, r"node id 4\.7 \(float\) is not a node id"),  # was node 4
    (99, r"no node with id 99 \(ids 0\.\.4, 5 nodes\)"),  # was a plain KeyError
])
def test_modal_data_node_index(data, node, pattern):
    with pytest.raises(UnknownNodeError, match=r"modal data 'red beam': " + pattern) as info:
        data.node_index(node)
    assert isinstance(info.value, KeyError)


def test_write_to_a_path_of_the_wrong_type(data):
    with pytest.raises(ModalFileError, match=r"ModalData\.write: path must be the path of the modal file .* got 123"):
        data.write(123)


def twice(f: h5py.File) -> None:
    del f["interface/node_ids"]
    f.create_dataset("interface/node_ids", data=np.array([4, 4]))


def test_interface_node_given_twice_in_a_file(good, tmp_path):
    """Two frames at one node (frame_a and frame_b) were built from it."""
    path = edited_h5(good, tmp_path, twice)
    pattern = re.escape(str(path)) + r": dataset '/interface/node_ids': node 4 is given twice \(\[4, 4\]\)"
    with pytest.raises(ModalFileError, match=pattern):
        ModalData.read(path)
    with pytest.raises(ModalFileError, match=pattern):
        FlexibleBody(path)


def test_provenance_that_is_not_an_object(good, tmp_path):
    path = edited_h5(good, tmp_path, lambda f: f.attrs.__setitem__("provenance", "[1, 2]"))
    with pytest.raises(ModalFileError, match=re.escape(str(path)) + r": dataset '/' attribute 'provenance' must be a "
                                                                    r"JSON object .* got list"):
        ModalData.read(path)


# ------------------------------------------------------------------------------------------- mode selection
SELECTION_CASES = {
    "data as a path": (lambda d, g: select_modes(str(g), count=2), r"select_modes: argument 'data' must be a "
                                                                    r"ModalData \(ModalData\.read\(path\)"),
    "participation as text": (lambda d, g: select_modes(d, participation="x"),
                              r"select_modes: argument 'participation' must be a ParticipationTable"),
    "participation of other modes": (lambda d, g: select_modes(d, participation=modal_participation(
        np.eye(2), [1.0, 4.0], [1.0, 1.0])), r"the participation table has 2 modes, the modal data 8"),
    "threshold as a percentage": (lambda d, g: modal_participation(np.eye(2), [1.0, 4.0], [1.0, 1.0], threshold=5),
                                  r"modal_participation: threshold must be a fraction in \[0, 1\] .* \(a percentage\? "
                                  r"5 % is 0\.05\)"),
    "threshold as text": (lambda d, g: modal_participation(np.eye(2), [1.0, 4.0], [1.0, 1.0], threshold="0.01"),
                          r"threshold must be a fraction in \[0, 1\] \(0\.01 for 1 %\), got '0\.01'"),
    "loads with NaN": (lambda d, g: modal_participation(np.eye(2), [1.0, 4.0], [np.nan, 1.0]),  # shares were 0 %
                       r"modal_participation: argument 'loads' has a non-finite value nan"),
    "loads as text": (lambda d, g: modal_participation(np.eye(2), [1.0, 4.0], ["1", "2"]),
                      r"argument 'loads' must be an array of real numbers"),
    "loads of another size": (lambda d, g: modal_participation(np.eye(2), [1.0, 4.0], [1.0, 1.0, 1.0]),
                              r"argument 'loads' has shape \(3, 1\): it must have one row per DOF"),
    "one frequency short": (lambda d, g: modal_participation(np.eye(2), [1.0, 4.0], [1.0, 1.0], frequencies=[1.0]),
                            r"argument 'frequencies' has shape \(1,\), expected \(2,\)"),
    "nodal loads as a list": (lambda d, g: nodal_generalized_forces(d, [(4, (0, 1, 0, 0, 0, 0))]),
                              r"nodal_generalized_forces: argument 'nodal_loads' must be a mapping"),
    "nodal load as text": (lambda d, g: nodal_generalized_forces(d, {4: ["0", "1", "0", "0", "0", "0"]}),
                           r"argument 'nodal_loads\[4\]' must be an array of real numbers"),
    "nodal load at a fractional node": (lambda d, g: nodal_generalized_forces(d, {4.7: (0, 1, 0, 0, 0, 0)}),
                                        r"node id 4\.7 \(float\) is not a node id"),
    "nodal load at an unknown node": (lambda d, g: nodal_generalized_forces(d, {99: (0, 1, 0, 0, 0, 0)}),
                                      r"no node with id 99"),
    "load-case amplitudes of the wrong shape": (lambda d, g: participation_from_load_cases(d, np.zeros(3)),
                                                r"participation_from_load_cases: amplitudes must be finite, shape "
                                                r"\(k, 18\)"),
    "NaN frequency for the damping rule": (lambda d, g: default_damping_ratio([np.nan]),  # was 100 %
                                           r"default_damping_ratio: argument 'frequencies' has a non-finite value"),
    "damping matrix of a path": (lambda d, g: modal_damping_matrix(str(g)),
                                 r"modal_damping_matrix: argument 'data' must be a ModalData"),
}


@pytest.mark.parametrize("case", list(SELECTION_CASES))
def test_bad_selection_input_is_named(data, good, case):
    call, pattern = SELECTION_CASES[case]
    with pytest.raises(RunArgumentError, match=pattern):
        call(data, good)


def test_participation_of_data_without_static_loads(fe):
    plain = modal_data_from_fe(fe, [4], 2, reference_node=0, static_loads=False)
    with pytest.raises(ModalFileError, match=r"participation_from_load_cases: modal data '' has no static load "
                                             r"responses \(dataset '/static_loads'"):
        participation_from_load_cases(plain, np.zeros(3))


# ------------------------------------------------------------------------------------------- FlexibleBody
@pytest.mark.parametrize(("kwargs", "pattern"), [
    ({"init": "q=0"}, r"init must be a dict \{variable name: start value\}.* got str 'q=0'"),
    ({"guess": [("q", 0.0)]}, r"guess must be a dict .* got list"),
    ({"state_select": "q"}, r"state_select must be a dict \{variable: 'always' \| .* got str 'q'"),
])
def test_start_values_that_are_not_a_dict(data, kwargs, pattern):
    """Were AttributeError: 'str' object has no attribute 'items'."""
    with pytest.raises(ModelError, match="FlexibleBody: " + pattern):
        FlexibleBody(data, **kwargs)


def test_start_value_of_a_frame_variable(data):
    """A dotted name (``frame_b.r_0``) sets a frame's variable, as for every other component (it was 'unknown
    variable')."""
    body = FlexibleBody(data, init={"frame_b.r_0": [1.0, 0.0, 0.0]}, guess={"frame_a.v": [0.0, 2.0, 0.0]})
    start, fixed = body.frame_b.start_of("r_0")
    assert start.tolist() == [1.0, 0.0, 0.0] and fixed is True
    start, fixed = body.frame_a.start_of("v")
    assert start.tolist() == [0.0, 2.0, 0.0] and fixed is False


def test_mode_count_above_the_file_with_a_cut_off(data):
    """``modes=20, max_frequency=...`` kept the file's 8 modes without a word (without the cut-off it was refused)."""
    with pytest.raises(ModelError, match=r"modes=20 asks for the 20 lowest modes, but the modal data 'red beam' has "
                                         r"only 8"):
        FlexibleBody(data, modes=20, max_frequency=1e9)


@pytest.mark.parametrize("node", ["4", 4.7, None])
def test_frame_at_a_node_that_is_not_an_id(data, node):
    """``frame_at("4")`` and ``frame_at(4.7)`` gave the frame at node 4; ``frame_at(None)`` was a TypeError."""
    with pytest.raises(ModelError, match=r"frame_at: node must be a node id \(an int\), got .* frames at nodes "
                                         r"\[0, 4\]"):
        FlexibleBody(data).frame_at(node)


# ---------------------------------------------------------------------------------------- outputs, drawing
def test_output_refuses_complex_reflections_and_overflow(data):
    q = np.zeros((3, data.n_modes))
    with pytest.raises(RunArgumentError, match=r"node_displacements: argument 'q' must be an array of real numbers, "
                                               r"got complex numbers"):
        node_displacements(data, q.astype(complex))
    with pytest.raises(RunArgumentError, match=r"deformed_positions: argument 'T' at index 0 is a reflection"):
        deformed_positions(data, q, np.zeros(3), -np.eye(3))
    with pytest.raises(RunArgumentError, match=r"node_displacements: the result overflows the floating-point range"):
        node_displacements(data, np.full(data.n_modes, 1e308))  # was NaN
    with pytest.raises(RunArgumentError, match=r"energies: argument 'qd' has shape \(2, 8\), but 'q' \(3, 8\)"):
        energies(data, q, q[:2], np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3)), np.eye(3))


def series(data):
    return np.array([0.0, 0.1]), np.zeros((2, data.n_modes)), np.zeros(3), np.eye(3)


DRAWING_CASES = {
    "series path of the wrong type": (lambda d, p: write_vtk_series(123, d, *series(d)),
                                      r"write_vtk_series: argument 'path' must be a file path .* got int 123"),
    "image path of the wrong type": (lambda d, p: plot_frame(d, *series(d), path=123),
                                     r"plot_frame: argument 'path' must be a file path"),
    "fields as a number": (lambda d, p: write_vtk_series(p / "a.pvd", d, *series(d), fields=5),
                           r"argument 'fields' must be a field name or a list of them, from \['displacement'"),
    "fields as a dict": (lambda d, p: write_vtk_series(p / "a.pvd", d, *series(d), fields={"displacement": 1}),
                         r"argument 'fields' must be a field name or a list of them"),
    "unknown cell type": (lambda d, p: write_vtk_series(p / "a.pvd", d, *series(d), element_type="bogus"),
                          r"argument 'element_type' must be a meshio cell type .* got 'bogus'"),  # was KeyError
    "colour as a list": (lambda d, p: plot_frame(d, *series(d), color=["displacement"]),
                         r"plot_frame: argument 'color' must be one of \['displacement', 'von_mises'\]"),
    "image too large": (lambda d, p: plot_frame(d, *series(d), dpi=1e9),
                        r"plot_frame: figsize \(6\.4, 5\.2\) \[inch\] at dpi=1000000000\.0 makes an image of .* "
                        r"pixels across"),
    "model series path suffix": (lambda d, p: write_model_vtk(p / "a.vtu", None, None),
                                 r"write_model_vtk: argument 'path' .* must end in '\.pvd'"),
}


@pytest.mark.parametrize("case", list(DRAWING_CASES))
def test_bad_drawing_input_is_named(data, tmp_path, case):
    call, pattern = DRAWING_CASES[case]
    with pytest.raises(RunArgumentError, match=pattern):
        call(data, tmp_path)
    assert not list(tmp_path.iterdir())  # nothing written


def test_model_series_stride_as_a_numpy_integer(tmp_path):
    """``stride=np.int64(2)`` (from an array) was refused as 'not a positive integer'; now the next check speaks."""
    with pytest.raises(RunArgumentError, match=r"write_model_vtk: argument 'model' must be the flexlib model"):
        write_model_vtk(tmp_path / "m.pvd", None, None, stride=np.int64(2))


# ------------------------------------------------------------------------------------- pinned-free beam model
@pytest.fixture(scope="module")
def beam6():
    from flexlib.models.pinned_free_beam import beam_modal_data

    return beam_modal_data(6, 4)


def test_pinned_free_beam_data_of_the_wrong_type(beam6):
    from flexlib.models import pinned_free_beam as pfb

    for call, where in ((lambda: pfb.bending_modes("x"), "bending_modes"),
                        (lambda: pfb.simulate(0, data="beam.h5"), "simulate"),
                        (lambda: pfb.simulate_modes([0], data=None), "simulate_modes"),
                        (lambda: pfb.participation_table("beam.h5"), "participation_table")):
        with pytest.raises(RunArgumentError, match=where + r": argument 'data' must be the beam's ModalData"):
            call()
    with pytest.raises(RunArgumentError, match=r"simulate_modes: argument 'compiled' must be True or False, got 'no'"):
        pfb.simulate_modes([0], data=beam6, compiled="no")


def test_participation_table_takes_the_mesh_of_its_data(beam6):
    """Data of a 6-element mesh with the default ``n_elements`` (32) was an IndexError of mismatched arrays."""
    from flexlib.models.pinned_free_beam import participation_table

    table, t_critical = participation_table(beam6)
    assert len(table.rows) == 5 and t_critical == pytest.approx(1.0, abs=1e-3)
    with pytest.raises(RunArgumentError, match=r"participation_table: n_elements=32, but the modal data "
                                               r"'seed-001 pinned-free beam' are of a mesh of 6 elements"):
        participation_table(beam6, n_elements=32)


@pytest.mark.parametrize(("z", "z_ref", "pattern"), [
    ([], [], r"z \(0,\) and z_ref \(0,\) must be equal non-empty 1-D shapes"),  # numpy: mean of empty slice
    ([1.0, 2.0], [1.0, 2.0, 3.0], r"z \(2,\) and z_ref \(3,\) must be equal"),  # broadcast ValueError
    ([1.0, 2.0], [0.0, 0.0], r"the reference z_ref is identically zero"),  # divide by zero
    (["1"], [1.0], r"z must be an array of real numbers, got \['1'\]"),  # was read as 1
    ([np.nan], [1.0], r"z has a non-finite value at sample 0"),  # was nan
])
def test_seed_error_arguments(z, z_ref, pattern):
    from flexlib.models.pinned_free_beam import seed_error

    with pytest.raises(RunArgumentError, match="seed_error: " + pattern):
        seed_error(z, z_ref)

