"""Bad FE files for the ANSYS / Nastran importers: each a clear error naming the file and the matrix, card, grid
or argument at fault (ModalFileError for the file's content, ValueError for arguments, ImportError naming the
extra to install)."""

from __future__ import annotations

import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from flexlib import ModalFileError
from flexlib.fe import beam_mesh, read_ansys_full, read_nastran_dmig, read_nastran_op4, rectangle


@pytest.fixture(scope="module")
def beam():
    return beam_mesh((0, 0, 0), (1.0, 0, 0), 2, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)


# ------------------------------------------------------------------------------------------------------- Nastran
@pytest.fixture(scope="module")
def op4():
    return pytest.importorskip("pyNastran.op4.op4", reason="optional extra 'nastran' (pyNastran) not installed")


def op4_file(op4, path: Path, matrices: dict) -> Path:
    with open(path, "w") as f:
        op4.OP4().write_op4(f, {k: (2, np.asarray(v)) for k, v in matrices.items()}, is_binary=False,
                            precision="double")
    return path


def nonsymmetric(A: np.ndarray) -> np.ndarray:
    A = A.copy()
    A[0, 1] += 0.01 * abs(A).max()
    return A



OP4_CASES = {
    "missing stiffness matrix": (lambda M, K: {"MAA": M, "KXX": K}, {}, ["'KAA'", "KXX"]),
    "missing mass matrix": (lambda M, K: {"MAA": M, "KAA": K}, {"mass": "MGG"}, ["'MGG'", "MAA"]),
    "non-symmetric stiffness": (lambda M, K: {"MAA": M, "KAA": nonsymmetric(K)}, {}, ["'KAA'", "not symmetric"]),
    "rectangular stiffness": (lambda M, K: {"MAA": M, "KAA": K[:, :-1]}, {}, ["'KAA'", "not square"]),
    "complex mass": (lambda M, K: {"MAA": M * (1 + 1j), "KAA": K}, {}, ["'MAA'", "complex"]),
    "sizes differ": (lambda M, K: {"MAA": M[:-6, :-6], "KAA": K}, {"nodes": np.zeros((2, 3))},
                     ["'MAA'", "'KAA'", "differ"]),
    "dof_map beyond the matrix": (lambda M, K: {"MAA": M, "KAA": K}, {"dof_map": np.arange(18).reshape(3, 6) + 1},
                                  ["'dof_map'", "row 18"]),
    "dof_map of the wrong shape": (lambda M, K: {"MAA": M, "KAA": K}, {"dof_map": np.arange(18).reshape(6, 3)},
                                   ["'dof_map'", "shape"]),
}


@pytest.mark.parametrize("case", list(OP4_CASES))
def test_bad_op4(op4, beam, tmp_path, case):
    make, kwargs, culprits = OP4_CASES[case]
    path = op4_file(op4, tmp_path / "bad.op4", make(beam.M.toarray(), beam.K.toarray()))
    kwargs = {"nodes": beam.nodes, **kwargs}
    with pytest.raises(ModalFileError) as info:
        read_nastran_op4(path, **kwargs)
    message = str(info.value)
    assert str(path) in message
    for culprit in culprits:
        assert culprit in message, message


def test_op4_overflowing_mass_term(op4, beam, tmp_path):
    """A mass term written as 1.0E+999 (overflow to inf; pyNastran's writer drops NaN, so the file is edited)."""
    path = op4_file(op4, tmp_path / "bad.op4", {"KAA": beam.K.toarray(), "MAA": beam.M.toarray()})
    text = path.read_text()
    start = text.index("MAA")
    term = re.compile(r"[ -]\d\.\d{16}E[+-]\d\d").search(text, start)
    path.write_text(text[:term.start()] + " 1." + "0" * 15 + "E+999" + text[term.end():])
    with pytest.raises(ModalFileError, match="matrix 'MAA' has non-finite entries") as info:
        read_nastran_op4(path, nodes=beam.nodes)
    assert str(path) in str(info.value)


def test_op4_that_is_not_an_op4(op4, tmp_path):
    path = tmp_path / "notes.op4"
    path.write_text("this is not an OUTPUT4 file\n")
    with pytest.raises(ModalFileError, match="not readable as a Nastran OP4 file") as info:
        read_nastran_op4(path, nodes=np.zeros((1, 3)))
    assert str(path) in str(info.value)


def test_op4_missing_file(op4, tmp_path):
    with pytest.raises(ModalFileError, match="no such OP4 file") as info:
        read_nastran_op4(tmp_path / "absent.op4", nodes=np.zeros((1, 3)))
    assert "absent.op4" in str(info.value)


@pytest.fixture(scope="module")
def bdf():
    return pytest.importorskip("pyNastran.bdf.bdf", reason="optional extra 'nastran' (pyNastran) not installed")


def deck(bdf, path: Path, fe, *, grids: int | None = None, cards=None, cd: int = 0, coord=None,
         extra: dict | None = None) -> Path:
    """GRIDs 1..N (or the first ``grids``) and symmetric DMIGs MAAX, KAAX (lower triangles) plus ``extra[name]``
    terms ``((grid_j, comp_j), (grid_i, comp_i), value)``; ``cards(model)`` adds cards."""
    model = bdf.BDF(debug=None)
    if coord is not None:
        coord(model)
    n = fe.nodes.shape[0] if grids is None else grids
    for i in range(n):
        model.add_grid(1 + i, list(fe.nodes[i]), cd=cd)
    label = {int(fe.dof_map[p, c]): (1 + p, c + 1) for p in range(fe.nodes.shape[0]) for c in range(6)}
    for name, A in (("MAAX", fe.M), ("KAAX", fe.K)):
        L = sp.tril(A).tocoo()
        terms = [(label[int(c)], label[int(r)], float(v)) for r, c, v in zip(L.row, L.col, L.data)]
        terms += (extra or {}).get(name, [])
        model.add_dmig(name, 6, 2, 0, 0, None, [t[0] for t in terms], [t[1] for t in terms], [t[2] for t in terms])
    if cards is not None:
        cards(model)
    model.write_bdf(str(path), size=16, is_double=True)
    return path


def complex_dmig(model) -> None:
    model.add_dmig("KCPX", 6, 3, 0, 0, None, [(1, 1)], [(1, 1)], [1.0], Complex=[0.5])


DMIG_CASES = {
    "missing DMIG": ({}, ("MAAX", "KBBX"), ["'KBBX'", "KAAX", "MAAX"]),
    "grid without GRID card": ({"grids": 2}, ("MAAX", "KAAX"), ["grids [3]", "no GRID card"]),
    # row (1, 2) x column (1, 6) mirrors the lower-triangle term (uy-rz bending coupling) already given
    "both triangles of a symmetric DMIG": ({"extra": {"KAAX": [((1, 6), (1, 2), 1.0)]}}, ("MAAX", "KAAX"),
                                           ["'KAAX'", "grid 1, component 2", "grid 1, component 6",
                                            "both triangles"]),
    "scalar point": ({"extra": {"MAAX": [((1, 1), (900, 0), 1.0)]}}, ("MAAX", "KAAX"),
                     ["'MAAX'", "grid 900, component 0"]),
    "complex DMIG": ({"cards": complex_dmig}, ("MAAX", "KCPX"), ["'KCPX'", "complex"]),
    "cylindrical CD": ({"cd": 5, "coord": lambda m: m.add_cord2c(5, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0],
                                                                     [1.0, 0.0, 0.0])},
                       ("MAAX", "KAAX"), ["GRID 1", "CD = 5", "CORD2C"]),
}


@pytest.mark.parametrize("case", list(DMIG_CASES))
def test_bad_dmig(bdf, beam, tmp_path, case):
    options, names, culprits = DMIG_CASES[case]
    path = deck(bdf, tmp_path / "bad.bdf", beam, **options)
    with pytest.raises(ModalFileError) as info:
        read_nastran_dmig(path, *names)
    message = str(info.value)
    assert str(path) in message
    for culprit in culprits:
        assert culprit in message, message


def test_dmig_partial_triplet_in_a_rotated_cd(bdf, tmp_path):
    """Rotating to basic needs all three translations of a grid with a rectangular CD."""
    model = bdf.BDF(debug=None)
    model.add_cord2r(3, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0])
    model.add_grid(1, [0.0, 0.0, 0.0], cd=3)
    model.add_dmig("MAAX", 6, 2, 0, 0, None, [(1, 1)], [(1, 1)], [2.0])
    model.add_dmig("KAAX", 6, 2, 0, 0, None, [(1, 1)], [(1, 1)], [5.0])
    path = tmp_path / "partial.bdf"
    model.write_bdf(str(path), size=16, is_double=True)
    with pytest.raises(ModalFileError, match="GRID 1 \\(CD = 3\\) has only some of its translation") as info:
        read_nastran_dmig(path, "MAAX", "KAAX")
    assert str(path) in str(info.value)


def test_bdf_that_is_not_bulk_data(bdf, tmp_path):
    path = tmp_path / "bad.bdf"
    path.write_text("GRID,1,,0.,0.,0.\nDMIG,KAAX,0,6,2,0\nDMIG,KAAX,1,1,,1,1,not-a-number\n")
    with pytest.raises(ModalFileError, match="not readable as Nastran bulk data") as info:
        read_nastran_dmig(path, "MAAX", "KAAX")
    assert str(path) in str(info.value)


def test_bdf_missing_file(bdf, tmp_path):
    with pytest.raises(ModalFileError, match="cannot read the bulk data file") as info:
        read_nastran_dmig(tmp_path / "absent.bdf", "MAAX", "KAAX")
    assert "absent.bdf" in str(info.value)


# --------------------------------------------------------------------------------------------------------- ANSYS
@pytest.fixture(scope="module")
def ansys():
    pytest.importorskip("ansys.mapdl.reader", reason="optional extra 'ansys' (ansys-mapdl-reader) not installed")
    from ansys.mapdl.reader import examples

    return examples


def test_ansys_result_file_is_not_a_full_file(ansys):
    with pytest.raises(ModalFileError, match="not a full file") as info:
        read_ansys_full(ansys.rstfile)
    assert "file.rst" in str(info.value)


def test_ansys_garbage_file(ansys, tmp_path):
    path = tmp_path / "job.full"
    path.write_bytes(b"\x00\x01 not an ANSYS binary file" * 40)
    with pytest.raises(ModalFileError, match="not readable as an ANSYS binary file") as info:
        read_ansys_full(path, nodes=np.zeros((1, 3)))
    assert str(path) in str(info.value)


@pytest.mark.parametrize("length", [200_000, 600_000, 801_000])
def test_ansys_truncated_full_file(ansys, tmp_path, length):
    """Cut inside the matrices (the file's records end at byte 801 596): refused before the reader's compiled
    parser runs past the end of the data (which can abort the process)."""
    path = tmp_path / "job.full"
    path.write_bytes(Path(ansys.fullfile).read_bytes()[:length])
    with pytest.raises(ModalFileError, match="truncated or damaged full file") as info:
        read_ansys_full(path, nodes=np.zeros((321, 3)))
    assert str(path) in str(info.value)


def test_ansys_full_file_without_coordinates(ansys, tmp_path):
    path = tmp_path / "job.full"
    shutil.copy(ansys.fullfile, path)
    with pytest.raises(ValueError, match=r"no result file job\.rst beside it: pass nodes=") as info:
        read_ansys_full(path)
    assert str(path) in str(info.value)


def test_ansys_nodes_missing_from_the_coordinates(ansys):
    table = np.column_stack([np.arange(1, 301), np.zeros((300, 3))])  # nodes 301..321 absent
    with pytest.raises(ModalFileError, match=r"nodes \[301, 302, .* have no coordinates in array") as info:
        read_ansys_full(ansys.fullfile, nodes=table)
    assert "file.full" in str(info.value)


def test_ansys_coordinate_array_of_the_wrong_length(ansys):
    with pytest.raises(ModalFileError, match="nodes has 10 rows for the full file's 321 nodes"):
        read_ansys_full(ansys.fullfile, nodes=np.zeros((10, 3)))


def test_ansys_coordinate_array_of_the_wrong_shape(ansys):
    with pytest.raises(ValueError, match=r"nodes must be a path or an array \(N, 3\) or \(N, 4\), got shape"):
        read_ansys_full(ansys.fullfile, nodes=np.zeros((321, 2)))


def test_ansys_unreadable_coordinate_file(ansys, tmp_path):
    bad = tmp_path / "other.rst"
    bad.write_bytes(b"garbage" * 100)
    with pytest.raises(ModalFileError, match="cannot read node coordinates") as info:
        read_ansys_full(ansys.fullfile, nodes=bad)
    assert str(bad) in str(info.value)


def test_ansys_missing_file(ansys, tmp_path):
    with pytest.raises(ModalFileError, match="no such ANSYS full file") as info:
        read_ansys_full(tmp_path / "absent.full")
    assert "absent.full" in str(info.value)


# --------------------------------------------------------------------------------------------- absent extras
@pytest.mark.parametrize(("reader", "module", "extra"), [
    (lambda p: read_ansys_full(p), "ansys.mapdl.reader", "ansys"),
    (lambda p: read_nastran_op4(p, nodes=np.zeros((1, 3))), "pyNastran.op4.op4", "nastran"),
    (lambda p: read_nastran_dmig(p, "MAAX", "KAAX"), "pyNastran.bdf.bdf", "nastran"),
], ids=["ansys", "op4", "dmig"])
def test_missing_optional_package_names_the_extra(monkeypatch, tmp_path, reader, module, extra):
    monkeypatch.setitem(sys.modules, module, None)  # import of a None entry raises ImportError
    with pytest.raises(ImportError, match=rf"pip install 'flexlib\[{extra}\]'"):
        reader(tmp_path / "any.file")
