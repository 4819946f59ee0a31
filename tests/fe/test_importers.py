"""FE matrix importers: Nastran OP4 and DMIG through pyNastran, ANSYS full files through ansys-mapdl-reader.

References and tolerances
-------------------------
- Nastran: a free-free 3D beam from flexlib's mesher (8 elements, skewed axis, 6 DOFs per node) is written by
  pyNastran itself (``OP4.write_op4``, ``BDF.add_grid``/``add_dmig``/``write_bdf``) and read back through the
  importer (binary OP4, which pyNastran cannot write, is written by the test per the OUTPUT4 description).
  OP4 files keep full double precision: matrices round-trip to 1e-12 relative and the free-free
  frequencies of ``modal_data_from_fe`` on the imported model match those on the beam built directly to 1e-9.
  A DMIG term sits in a 16-character large field (about 10 significant digits), so the round-trip is checked
  to 1e-12 on matrices rounded to 9 significant digits (exactly representable there) and, for the unrounded
  beam, the frequencies to 1e-6 (measured 1.4e-7: the field's rounding perturbs the terms at 1e-10, which no
  longer annihilate the exact rigid-body modes, and the free-free projection amplifies that by ||K|| / omega^2).
- ANSYS: the full file shipped in ``ansys-mapdl-reader`` (``examples.fullfile``: a 1 x 1 x 5 block of 40
  SOLID186 elements, 321 nodes, clamped on its z = 0 face) with its results file ``file.rst`` for the node
  coordinates. The imported matrices equal the package's own unsorted ``load_km()`` matrices (mirrored, placed by
  the package's (node, DOF) reference) exactly, and the lowest frequencies equal scipy's on those (constrained
  rows dropped by their zero diagonal) to 1e-7: the dense generalised eigensolver's accuracy on the lowest
  modes of this stiff solid model is eps * lambda_max / lambda_min = 1.4e-8.
"""

from __future__ import annotations

import struct
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp

from flexlib.fe import (
    beam_mesh,
    craig_bampton,
    modal_data_from_fe,
    read_ansys_full,
    read_nastran_dmig,
    read_nastran_op4,
    rectangle,
)

GRID0 = 101  # Nastran grid id of the beam's node 0


@pytest.fixture(scope="module")
def beam():
    """Free-free steel beam 1.6 x 0.4 x 0.2 m (skewed axis, so all six components couple), 8 elements; node
    coordinates are multiples of 0.2/0.05/0.025 m, exact in a Nastran field."""
    fe = beam_mesh((0, 0, 0), (1.6, 0.4, 0.2), 8, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    # the plain matrices as an importer sees them (no Gauss-point mass description or beam element data)
    return replace(fe, mass_points=None, beam=None, unit_loads=None)


def free_free_frequencies(fe):
    return modal_data_from_fe(fe, [int(fe.node_ids[0]), int(fe.node_ids[-1])], 6).frequencies


def rel(A, B) -> float:
    return float(abs(sp.csr_matrix(A) - sp.csr_matrix(B)).max() / abs(sp.csr_matrix(B)).max())


# ------------------------------------------------------------------------------------------------------- Nastran
@pytest.fixture(scope="module")
def pynastran():
    return pytest.importorskip("pyNastran", reason="optional extra 'nastran' (pyNastran) not installed")


def write_op4(path: Path, matrices: dict, sparse: bool) -> Path:
    from pyNastran.op4.op4 import OP4

    with open(path, "w") as f:  # text OP4 (pyNastran's binary OP4 writer fails in 1.3.4 and 1.4.1)
        OP4().write_op4(f, {k: (6, sp.coo_matrix(v) if sparse else v.toarray()) for k, v in matrices.items()},
                        is_binary=False, precision="double")
    return path


@pytest.mark.parametrize("sparse", [False, True], ids=["dense", "sparse"])
def test_op4_round_trip_and_free_free_frequencies(pynastran, beam, tmp_path, sparse):
    """OP4 (dense and sparse text records) written by pyNastran: M and K round-trip to 1e-12 and the free-free
    frequencies (6 modes, interface at both ends) equal the directly built beam's to 1e-9."""
    path = write_op4(tmp_path / "beam.op4", {"MAA": beam.M, "KAA": beam.K, "XYZ": sp.eye(3)}, sparse)
    fe = read_nastran_op4(path, nodes=beam.nodes)
    assert rel(fe.M, beam.M) <= 1e-12 and rel(fe.K, beam.K) <= 1e-12
    assert np.array_equal(fe.dof_map, beam.dof_map)
    assert fe.info["format"] == "Nastran OUTPUT4" and fe.info["matrices"] == ["MAA", "KAA"]
    f_ref = free_free_frequencies(beam)
    assert np.allclose(free_free_frequencies(fe), f_ref, rtol=1e-9, atol=0)
    assert f_ref[0] > 10.0  # elastic modes only: the six rigid-body modes are removed


def test_op4_named_matrices_dof_map_and_ids_from_text_files(pynastran, beam, tmp_path):
    """Other matrix names, node coordinates and DOF map from text files, a reordered DOF map: the importer puts
    each row where the map says (checked against the permuted beam to 1e-12) and keeps the grid ids."""
    rng = np.random.default_rng(3)
    perm = rng.permutation(beam.n_dofs)  # file row r holds beam DOF perm[r]
    P = sp.csr_matrix((np.ones(beam.n_dofs), (np.arange(beam.n_dofs), perm)))
    path = write_op4(tmp_path / "beam.op4", {"MHH": P @ beam.M @ P.T, "KHH": P @ beam.K @ P.T}, sparse=False)
    inverse = np.argsort(perm)
    dof_map = inverse[beam.dof_map]
    np.savetxt(tmp_path / "dof_map.txt", dof_map, fmt="%d")
    np.savetxt(tmp_path / "nodes.csv", beam.nodes, delimiter=",", fmt="%.17g")
    fe = read_nastran_op4(path, mass="MHH", stiffness="KHH", nodes=tmp_path / "nodes.csv",
                          dof_map=tmp_path / "dof_map.txt", node_ids=GRID0 + np.arange(9))
    assert list(fe.node_ids) == list(range(GRID0, GRID0 + 9))
    back = sp.csr_matrix((np.ones(beam.n_dofs), (inverse, np.arange(beam.n_dofs))))  # beam DOF <- file row
    assert rel(back.T @ fe.K @ back, beam.K) <= 1e-12 and rel(back.T @ fe.M @ back, beam.M) <= 1e-12
    assert np.allclose(free_free_frequencies(fe), free_free_frequencies(beam), rtol=1e-9, atol=0)


def write_binary_op4(path: Path, matrices: dict) -> Path:
    """A binary OP4 per the OUTPUT4 description (MSC Nastran DMAP Programmer's Guide, OUTPUT4, non-sparse):
    little-endian Fortran unformatted records (byte count before and after): a header (NCOL, NROW, form 6
    symmetric, type 2 real double, 8-character name), one record per nonzero column (ICOL, first nonzero IROW,
    number of words, the values from IROW to the last nonzero), and a closing record with ICOL = NCOL + 1.
    pyNastran cannot write one (its binary writer fails in 1.3.4 and 1.4.1), so the test writes it."""
    def record(payload: bytes) -> bytes:
        n = struct.pack("<i", len(payload))
        return n + payload + n

    with open(path, "wb") as f:
        for name, A in matrices.items():
            A = sp.csc_matrix(A).toarray()
            nrow, ncol = A.shape
            f.write(record(struct.pack("<4i8s", ncol, nrow, 6, 2, name.ljust(8).encode())))
            for j in range(ncol):
                nz = np.flatnonzero(A[:, j])
                if nz.size:
                    values = A[nz[0]:nz[-1] + 1, j].astype("<f8")
                    f.write(record(struct.pack("<3i", j + 1, nz[0] + 1, 2 * values.size) + values.tobytes()))
            f.write(record(struct.pack("<3id", ncol + 1, 1, 2, 1.0)))
    return path


def test_binary_op4(pynastran, beam, tmp_path):
    """Binary OP4 (read by pyNastran's binary reader behind the importer): M and K round-trip to 1e-12 and the
    free-free frequencies equal the directly built beam's to 1e-9."""
    path = write_binary_op4(tmp_path / "beam.op4", {"KAA": beam.K, "MAA": beam.M})
    fe = read_nastran_op4(path, nodes=beam.nodes)
    assert rel(fe.M, beam.M) <= 1e-12 and rel(fe.K, beam.K) <= 1e-12
    assert np.allclose(free_free_frequencies(fe), free_free_frequencies(beam), rtol=1e-9, atol=0)


def dmig_deck(path: Path, fe, matrices: dict, *, cd_beta: np.ndarray | None = None, mixed: bool = False) -> Path:
    """A bulk data file written by pyNastran: one GRID per node (ids from 101) and a symmetric (IFO 6) real
    double DMIG per matrix with one term of each off-diagonal pair (lower triangle, or a random mix of both
    triangles if ``mixed``). ``cd_beta``: rows are the axes of a rectangular CORD2R used as every grid's CD, in
    which the matrices are then expressed."""
    from pyNastran.bdf.bdf import BDF

    model = BDF(debug=None)
    cd = 0
    if cd_beta is not None:
        cd = 7
        model.add_cord2r(cd, [0.0, 0.0, 0.0], list(cd_beta[2]), list(cd_beta[0]))  # origin, z axis, point in xz
    for i, xyz in enumerate(fe.nodes):
        model.add_grid(GRID0 + i, list(xyz), cd=cd)
    label = {int(fe.dof_map[n, c]): (GRID0 + n, c + 1) for n in range(fe.nodes.shape[0]) for c in range(6)}
    rng = np.random.default_rng(7)
    for name, A in matrices.items():
        L = sp.tril(A).tocoo()
        swap = mixed & (rng.random(L.nnz) < 0.5)
        rows, cols = np.where(swap, L.col, L.row), np.where(swap, L.row, L.col)
        model.add_dmig(name, 6, 2, 0, 0, None, [label[int(c)] for c in cols], [label[int(r)] for r in rows],
                       [float(v) for v in L.data])
    model.write_bdf(str(path), size=16, is_double=True)
    return path


def round_sig(A: sp.spmatrix, digits: int = 9) -> sp.csr_matrix:
    A = sp.csr_matrix(A, copy=True)
    A.data = np.array([float(f"{v:.{digits - 1}e}") for v in A.data])
    return A


@pytest.mark.parametrize("mixed", [False, True], ids=["lower-triangle", "mixed-triangles"])
def test_dmig_round_trip_on_representable_matrices(pynastran, beam, tmp_path, mixed):
    """Matrices rounded to 9 significant digits (exact in the DMIG field): round-trip to 1e-12 whichever triangle
    each term is given in, grids -> nodes in id order at the GRID positions, components 1-6 -> ux..rz, and the
    free-free frequencies equal those of the same (rounded) matrices built directly to 1e-9."""
    direct = replace(beam, M=round_sig(beam.M), K=round_sig(beam.K))
    path = dmig_deck(tmp_path / "beam.bdf", beam, {"MAAX": direct.M, "KAAX": direct.K}, mixed=mixed)
    fe = read_nastran_dmig(path, "MAAX", "KAAX")
    assert rel(fe.M, direct.M) <= 1e-12 and rel(fe.K, direct.K) <= 1e-12
    assert list(fe.node_ids) == list(range(GRID0, GRID0 + 9))
    assert np.abs(fe.nodes - beam.nodes).max() <= 1e-15 and np.array_equal(fe.dof_map, beam.dof_map)
    assert np.allclose(free_free_frequencies(fe), free_free_frequencies(direct), rtol=1e-9, atol=0)


def test_dmig_full_precision_beam_frequencies(pynastran, beam, tmp_path):
    """The unrounded beam through DMIG: matrices within the large field's precision (2e-10 of the largest term)
    and free-free frequencies within 1e-6 of the beam built directly (module docstring: why not 1e-9)."""
    path = dmig_deck(tmp_path / "beam.bdf", beam, {"MAAX": beam.M, "KAAX": beam.K})
    fe = read_nastran_dmig(path, "MAAX", "KAAX")
    assert rel(fe.M, beam.M) <= 2e-10 and rel(fe.K, beam.K) <= 2e-10
    assert np.allclose(free_free_frequencies(fe), free_free_frequencies(beam), rtol=1e-6, atol=0)


def test_dmig_in_a_rectangular_displacement_system_is_rotated_to_basic(pynastran, beam, tmp_path):
    """Every grid with CD = a rotated CORD2R and the matrices expressed in it (T M T^T, T K T^T with T the
    direction cosines per node): the importer rotates them back to the basic system (1e-9 of the largest term,
    the DMIG field's precision) and the frequencies match the basic beam's to 1e-6."""
    c, s = np.cos(0.6), np.sin(0.6)
    beta = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.array([[1, 0, 0], [0, c, s], [0, -s, c]])
    T = sp.block_diag([beta] * (2 * beam.nodes.shape[0])).tocsr()  # u_cd = T u_basic (rows of beta: CD axes)
    path = dmig_deck(tmp_path / "beam.bdf", beam, {"MAAX": T @ beam.M @ T.T, "KAAX": T @ beam.K @ T.T},
                     cd_beta=beta)
    fe = read_nastran_dmig(path, "MAAX", "KAAX")
    assert rel(fe.M, beam.M) <= 1e-9 and rel(fe.K, beam.K) <= 1e-9
    assert np.allclose(free_free_frequencies(fe), free_free_frequencies(beam), rtol=1e-6, atol=0)


# --------------------------------------------------------------------------------------------------------- ANSYS
@pytest.fixture(scope="module")
def ansys_example():
    reader = pytest.importorskip("ansys.mapdl.reader", reason="optional extra 'ansys' (ansys-mapdl-reader) not "
                                                              "installed")
    from ansys.mapdl.reader import examples

    return reader, examples


def test_ansys_full_file_shipped_with_the_reader(ansys_example):
    """The shipped full file: symmetric positive definite M and K (clamped block), DOF map UX UY UZ -> ux uy uz
    with no rotations, the 21 fully held nodes exactly the z = 0 face of the coordinates from file.rst, the
    matrices identical to the reader's own unsorted ones placed by its (node, DOF) reference, and the lowest ten
    frequencies equal to scipy's on those to 1e-7."""
    reader, examples = ansys_example
    fe = read_ansys_full(examples.fullfile)
    assert fe.n_dofs == 900 and fe.nodes.shape == (321, 3) and list(fe.node_ids) == list(range(1, 322))
    assert abs(fe.K - fe.K.T).max() == 0.0 and abs(fe.M - fe.M.T).max() == 0.0
    K, M = fe.K.toarray(), fe.M.toarray()
    assert np.linalg.eigvalsh(M).min() > 0 and np.linalg.eigvalsh(K).min() > 0
    assert np.all(fe.dof_map[:, 3:] == -1)
    held = np.all(fe.dof_map < 0, axis=1)
    assert np.all((fe.dof_map[:, :3] >= 0) == ~held[:, None])
    assert held.sum() == 21 and np.all(fe.nodes[held, 2] == 0.0) and np.all(fe.nodes[~held, 2] > 0.0)
    assert fe.info["constrained"] == [{"nodes": list(range(1, 22)), "components": ["ux", "uy", "uz"]}]
    assert fe.info["coordinates"].endswith("file.rst") and fe.info["ansys_version"] == "15.0"

    # independent path: the package's unsorted matrices (solver ordering), mirrored; each row placed by the
    # package's own (node, DOF) reference must give exactly our matrices, constrained rows being all zero
    dof_ref, k, m = reader.read_binary(examples.fullfile).load_km(sort=False)
    k = (k + sp.triu(k, 1).T).toarray()
    m = (m + sp.triu(m, 1).T).toarray()
    node_row = {int(n): r for r, n in enumerate(fe.node_ids)}
    ours = np.array([fe.dof_map[node_row[int(n)], int(d)] for n, d in dof_ref])
    live = ours >= 0
    assert np.all(k[~live] == 0.0) and np.all(m[~live] == 0.0)
    order = np.argsort(ours[live])
    k_live, m_live = k[np.ix_(live, live)][np.ix_(order, order)], m[np.ix_(live, live)][np.ix_(order, order)]
    assert np.array_equal(k_live, K) and np.array_equal(m_live, M)
    # frequencies from scipy on the package's matrices restricted to the rows with a nonzero diagonal (no use of
    # our DOF map): 1e-7, the dense generalised eigensolver's accuracy on the lowest modes here
    # (eps * lambda_max / lambda_min = 1.4e-8)
    nz = np.flatnonzero(np.diag(k) != 0.0)
    w_ref = la.eigh(k[np.ix_(nz, nz)], m[np.ix_(nz, nz)], eigvals_only=True, subset_by_index=[0, 9])
    w = la.eigh(K, M, eigvals_only=True, subset_by_index=[0, 9])
    assert np.allclose(w, w_ref, rtol=1e-7, atol=0)
    f = np.sqrt(w) / (2 * np.pi)
    assert abs(f[1] / f[0] - 1) < 1e-9  # square section: the two first bending modes coincide

    # the import feeds the reduction: Craig-Bampton with the tip node as interface gives upper bounds close to
    # the full model's lowest frequencies (Rayleigh-Ritz)
    tip = int(fe.node_ids[np.argmax(fe.nodes[:, 2])])
    cb = craig_bampton(fe.M, fe.K, fe.dofs([tip]), 20)
    assert np.all(cb.frequencies[:4] >= f[:4] * (1 - 1e-9)) and np.allclose(cb.frequencies[:4], f[:4], rtol=1e-3)


def test_ansys_node_coordinates_from_an_array(ansys_example, tmp_path):
    """Coordinates given as an (N, 4) [node, x, y, z] array in any row order, or (N, 3) in node order, give the
    same model as the results file."""
    reader, examples = ansys_example
    mesh = reader.read_binary(examples.rstfile).mesh
    table = np.column_stack([mesh.nnum, mesh.nodes[:, :3]])[::-1]
    by_rst = read_ansys_full(examples.fullfile)
    by_table = read_ansys_full(examples.fullfile, nodes=table)
    by_xyz = read_ansys_full(examples.fullfile, nodes=mesh.nodes[:, :3])
    for fe in (by_table, by_xyz):
        assert np.array_equal(fe.nodes, by_rst.nodes) and np.array_equal(fe.dof_map, by_rst.dof_map)
        assert rel(fe.K, by_rst.K) == 0.0


def test_dmig_in_a_full_input_deck_with_grids_in_a_shifted_cp(pynastran, beam, tmp_path):
    """A whole input deck (executive and case control, BEGIN BULK) with the grids given in a shifted CORD2R
    (CP = 3, origin (1, 2, 3) m) and a CBAR whose PBAR is absent: only grids and coordinate systems are
    cross-referenced, the nodes come out at their basic positions (1e-12 m) and the matrices at the DMIG field's
    precision (2e-10)."""
    from pyNastran.bdf.bdf import BDF

    shift = np.array([1.0, 2.0, 3.0])
    model = BDF(debug=None)
    model.add_cord2r(3, list(shift), list(shift + np.eye(3)[2]), list(shift + np.eye(3)[0]))
    for i, xyz in enumerate(beam.nodes):
        model.add_grid(GRID0 + i, list(xyz - shift), cp=3)
    model.add_cbar(1, 99, [GRID0, GRID0 + 1], [0.0, 0.0, 1.0], None)
    label = {int(beam.dof_map[n, c]): (GRID0 + n, c + 1) for n in range(beam.nodes.shape[0]) for c in range(6)}
    for name, A in (("MAAX", beam.M), ("KAAX", beam.K)):
        L = sp.tril(A).tocoo()
        model.add_dmig(name, 6, 2, 0, 0, None, [label[int(c)] for c in L.col], [label[int(r)] for r in L.row],
                       [float(v) for v in L.data])
    bulk = tmp_path / "bulk.bdf"
    model.write_bdf(str(bulk), size=16, is_double=True)
    path = tmp_path / "arm.bdf"
    path.write_text("SOL 103\nCEND\nTITLE = arm\nBEGIN BULK\n" + bulk.read_text())
    fe = read_nastran_dmig(path, "MAAX", "KAAX")
    assert np.abs(fe.nodes - beam.nodes).max() <= 1e-12
    assert rel(fe.M, beam.M) <= 2e-10 and rel(fe.K, beam.K) <= 2e-10


def test_ansys_solid_model_to_modal_data(ansys_example):
    """modal_data_from_fe on the imported 20-node-hexahedron model: row-sum lumping gives negative corner masses
    there, so the lumped mass points fall back to HRZ (diagonal scaled to the same total): all masses >= 0, the
    total equal to the row-sum total t^T M t (1e-12), the centre of mass on the square section's axis
    x = y = 0.5 (1e-12), and the frequencies those of craig_bampton on the same matrices (1e-12)."""
    _, examples = ansys_example
    fe = read_ansys_full(examples.fullfile)
    points = fe.lumped_mass_points()
    assert points.description.startswith("lumped (HRZ") and points.masses.min() >= 0.0
    t = fe.translation_field([1.0, 0.0, 0.0])
    assert abs(points.masses.sum() / (t @ fe.M @ t) - 1) <= 1e-12
    tip = int(fe.node_ids[np.argmax(fe.nodes[:, 2])])
    data = modal_data_from_fe(fe, [tip], 12, free=False, title="ANSYS example")
    assert abs(data.mass / points.masses.sum() - 1) <= 1e-12
    assert np.allclose(data.center_of_mass[:2], 0.5, rtol=0, atol=1e-12)
    cb = craig_bampton(fe.M, fe.K, fe.dofs([tip]), 12)
    assert np.allclose(data.frequencies, cb.frequencies, rtol=1e-12, atol=0)
