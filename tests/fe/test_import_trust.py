"""FE matrix import and the beam mesher, as a user who hand-edits or mis-exports FE files meets them: each bad file or
argument gets a flexlib error naming the file, the DOF (node and component) or the argument, and a lumped mass
matrix without rotary inertia — valid FE output — is reduced correctly.

Lumped masses without rotary inertia (zero diagonal on the rotations, e.g. Nastran ``PARAM,COUPMASS,-1`` exports)
are checked against theory, not only against a second run:

- the massless rotations are condensed statically (Guyan, exact for massless DOFs), so the Craig–Bampton
  frequencies must equal those of the whole lumped FE model condensed independently here (dense numpy), to the
  reduction's truncation error (30 fixed-interface modes: 1.2e-6 measured; 1e-5 allowed);
- the lumped mass is the consistent kinetic energy integrated by the nodal (trapezoidal) rule, whose error is
  ``-(h^2/12) [d(w^2)/dx]_0^L``: with the stiffness the same, the Rayleigh quotient predicts the lumped frequencies
  below the consistent ones by ``h^2 [w w']_0^L / (12 int w^2)`` (analytic Euler–Bernoulli mode ``w``); the
  neglected terms are relatively O((beta h)^2), the tolerance used (measured 0.1-0.9 %);
- that error is O(h^2): halving h divides it by 4 (3.9-4.1 allowed; measured 3.99), and Richardson extrapolation
  ``(4 f_40 - f_20) / 3`` leaves the O(h^4) level of the consistent model (measured 4e-6 on the Euler–Bernoulli
  frequencies; 2e-5 allowed);
- the rigid-body invariants follow from the same rule exactly: equal mass and first moment, ``Iyy``, ``Izz`` larger by
  ``rho A L h^2 / 6`` (the trapezoidal error of ``int x^2``, exact for a quadratic), and ``Ixx`` without the
  consistent ``rho Ip L`` (no rotary inertia).
"""

from __future__ import annotations

import math
import re
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.linalg as la
import scipy.sparse as sp
from scipy.integrate import quad

from flexlib import ModalFileError, RunArgumentError
from flexlib.fe import (
    Section,
    beam_mesh,
    box,
    circle,
    craig_bampton,
    i_section,
    modal_data_from_fe,
    read_ansys_full,
    read_fe,
    read_matrix_market,
    read_nastran_dmig,
    read_nastran_op4,
    rectangle,
)

L, E, RHO = 2.0, 2.1e11, 7850.0
SECTION = rectangle(0.02, 0.03)


def mesh(n: int = 4, **kw):
    return beam_mesh((0, 0, 0), (L, 0, 0), n, SECTION, E=E, rho=RHO, **kw)


def plain(fe):
    """The matrices as an importer gives them (no Gauss-point mass description or element data)."""
    return replace(fe, mass_points=None, beam=None, unit_loads=None)


def lumped(fe, polar: bool = False) -> sp.csr_matrix:
    """Translational row-sum lumping of the consistent mass, no rotary inertia (or only the polar ``rho Ip`` per
    nodal length): the lumped export of a beam model."""
    d = np.zeros(fe.n_dofs)
    for a in range(3):
        rows = fe.dof_map[:, a]
        d[rows] = fe.M[rows] @ fe.translation_field(np.eye(3)[a])
    if polar:
        n = fe.nodes.shape[0] - 1
        length = np.full(n + 1, L / n)
        length[[0, -1]] /= 2
        d[fe.dof_map[:, 3]] = RHO * SECTION.Ip * length
    return sp.diags(d).tocsr()


def mtx(path: Path, A) -> Path:
    scipy.io.mmwrite(path, A)
    return path


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """M.mtx, K.mtx of a 4-element beam (5 nodes, 30 DOFs) and the model."""
    d = tmp_path_factory.mktemp("mm")
    fe = mesh()
    return d, mtx(d / "M.mtx", fe.M), mtx(d / "K.mtx", fe.K), fe


def edited(A, changes: dict) -> sp.csr_matrix:
    A = sp.lil_matrix(A)
    for (i, j), v in changes.items():
        A[i, j] = v
    return A.tocsr()


# ------------------------------------------------------------------------------------------ lumped mass: physics
def rotation_block_edited(A, fe, node: int, block: np.ndarray) -> sp.csr_matrix:
    """``A`` with the 3 x 3 block of ``node``'s rotational DOFs (``fe.dof_map``) replaced by ``block``."""
    r = fe.dof_map[node, 3:]
    return edited(A, {(int(r[i]), int(r[j])): block[i, j] for i in range(3) for j in range(3)})


def cantilever_mode(beta_L: float):
    b = beta_L / L
    s = (math.cosh(beta_L) + math.cos(beta_L)) / (math.sinh(beta_L) + math.sin(beta_L))
    w = lambda x: math.cosh(b * x) - math.cos(b * x) - s * (math.sinh(b * x) - math.sin(b * x))  # noqa: E731
    dw = lambda x: b * (math.sinh(b * x) + math.sin(b * x) - s * (math.cosh(b * x) - math.cos(b * x)))  # noqa: E731
    return w, dw


def free_mode(beta_L: float):
    b = beta_L / L
    s = (math.cosh(beta_L) - math.cos(beta_L)) / (math.sinh(beta_L) - math.sin(beta_L))
    w = lambda x: math.cosh(b * x) + math.cos(b * x) - s * (math.sinh(b * x) + math.sin(b * x))  # noqa: E731
    dw = lambda x: b * (math.sinh(b * x) - math.sin(b * x) - s * (math.cosh(b * x) + math.cos(b * x)))  # noqa: E731
    return w, dw


def trapezoid_shift(mode, n: int) -> float:
    """Relative frequency change of nodal (trapezoidal) mass lumping: -h^2 [w w']_0^L / (12 int w^2)."""
    w, dw = mode
    h = L / n
    return -h**2 * (w(L) * dw(L) - w(0) * dw(0)) / (12 * quad(lambda x: w(x) ** 2, 0, L)[0])


CANTILEVER_BETA_L = (1.8751040687, 4.6940911330)


def euler_bernoulli(beta_L: float, second_moment: float) -> float:
    return beta_L**2 / (2 * math.pi) * math.sqrt(E * second_moment / (RHO * SECTION.A * L**4))


@pytest.fixture(scope="module")
def cantilevers(tmp_path_factory):
    """Lumped (no rotary inertia, through Matrix Market files) and consistent cantilevers clamped at node 0, n = 20
    and 40 elements, 30 fixed-interface modes."""
    d = tmp_path_factory.mktemp("lumped")
    out = {}
    for n in (20, 40):
        fe = mesh(n)
        imported = read_matrix_market(mtx(d / f"M{n}.mtx", lumped(fe)), mtx(d / f"K{n}.mtx", fe.K), fe.nodes)
        out[n] = (imported, modal_data_from_fe(imported, [n], 30, reference_node=0),
                  modal_data_from_fe(fe, [n], 30, reference_node=0))
    return out


def test_lumped_mass_without_rotary_inertia_reduces_like_the_whole_condensed_model(cantilevers):
    imported, data, _ = cantilevers[20]
    assert data.provenance["n_massless_dofs_condensed"] == 3 * 20  # the rotations of the 20 free nodes
    held = imported.constrained([0])
    m = held.M.diagonal()
    z = m == 0
    K = held.K.toarray()
    Kc = K[np.ix_(~z, ~z)] - K[np.ix_(~z, z)] @ np.linalg.solve(K[np.ix_(z, z)], K[np.ix_(z, ~z)])
    full = np.sqrt(la.eigh(Kc, np.diag(m[~z]), eigvals_only=True, subset_by_index=[0, 3])) / (2 * math.pi)
    np.testing.assert_allclose(data.frequencies[:4], full, rtol=1e-5)


def test_lumped_cantilever_frequencies_against_consistent_mass_and_euler_bernoulli(cantilevers):
    analytic = np.sort([euler_bernoulli(bl, i) for bl in CANTILEVER_BETA_L for i in (SECTION.Iy, SECTION.Iz)])
    modes = [cantilever_mode(bl) for bl in CANTILEVER_BETA_L for _ in range(2)]
    betas = np.repeat(CANTILEVER_BETA_L, 2)
    f = {}
    for n, (_, lump, consistent) in cantilevers.items():
        f[n] = lump.frequencies[:4]
        predicted = np.array([trapezoid_shift(mode, n) for mode in modes])
        shift = lump.frequencies[:4] / consistent.frequencies[:4] - 1
        assert np.all(np.abs(shift / predicted - 1) < (betas / n) ** 2), (n, shift, predicted)  # (beta h)^2
    ratio = (f[20] / analytic - 1) / (f[40] / analytic - 1)
    assert np.all((3.9 < ratio) & (ratio < 4.1)), ratio
    np.testing.assert_allclose((4 * f[40] - f[20]) / 3, analytic, rtol=2e-5)


def test_lumped_cantilever_rigid_body_invariants(cantilevers):
    """Mass and first moment equal (the clamped node's mass is kept); the second moments as the trapezoidal rule."""
    n = 20
    _, lump, consistent = cantilevers[n]
    a, c = lump.invariants, consistent.invariants
    assert a["I1"] == pytest.approx(RHO * SECTION.A * L, rel=1e-12)
    assert a["I1"] == pytest.approx(c["I1"], rel=1e-12)
    np.testing.assert_allclose(a["I2"], c["I2"], rtol=1e-12, atol=1e-12)
    h = L / n
    trapezoid = RHO * SECTION.A * L * h**2 / 6
    expected = c["I7"] + np.diag([-RHO * SECTION.Ip * L, trapezoid, trapezoid])
    np.testing.assert_allclose(a["I7"], expected, rtol=1e-10, atol=1e-12 * np.abs(c["I7"]).max())


def test_free_free_beam_with_lumped_translations_and_polar_inertia():
    """Bending rotations massless, torsion with its rho Ip: free-free, rigid modes removed, same checks."""
    n = 20
    fe = mesh(n)
    lump = modal_data_from_fe(replace(plain(fe), M=lumped(fe, polar=True)), [0, n], 30)
    consistent = modal_data_from_fe(fe, [0, n], 30)
    predicted = trapezoid_shift(free_mode(4.7300407448), n)
    shift = lump.frequencies[:2] / consistent.frequencies[:2] - 1
    np.testing.assert_allclose(shift, predicted, rtol=(4.73 / n) ** 2)
    assert lump.invariants["I1"] == pytest.approx(consistent.invariants["I1"], rel=1e-12)
    np.testing.assert_allclose(lump.invariants["I7"][0, 0], consistent.invariants["I7"][0, 0], rtol=1e-12)


def test_lumped_sparse_eigensolver_path_matches_dense(monkeypatch):
    """Above 400 massive interior DOFs the condensed eigenproblem runs by shift-invert Lanczos on operators."""
    import flexlib.fe.reduction as reduction

    fe = mesh(140)
    model = replace(plain(fe), M=lumped(fe))
    sparse = modal_data_from_fe(model, [140], 6, reference_node=0)
    monkeypatch.setattr(reduction, "_DENSE_LIMIT", 10**6)
    dense = modal_data_from_fe(model, [140], 6, reference_node=0)
    np.testing.assert_allclose(sparse.frequencies, dense.frequencies, rtol=1e-8)


# ------------------------------------------------------------------------------------------- issue items: files
def test_node_missing_from_the_node_list(files):
    _d, M, K, fe = files
    with pytest.raises(ModalFileError, match=re.escape(f"{M}, {K}: matrix rows 24..29 (of 30) belong to no node in "
                                                       "the node list argument 'nodes' (4 nodes)") + r".*nodes 4"):
        read_matrix_market(M, K, fe.nodes[:-1])


def test_line_of_lumped_masses_without_rotary_inertia_as_a_free_body(files):
    """A free straight beam of point masses has no inertia about its axis: named, with the remedies."""
    d, _M, K, fe = files
    Ml = mtx(d / "lumped.mtx", lumped(fe))
    with pytest.raises(ModalFileError, match=re.escape(str(Ml)) + r": a motion has neither mass nor stiffness .*"
                                             r"the rigid-body rotation about x.*rotary inertia"):
        modal_data_from_fe(read_matrix_market(Ml, K, fe.nodes), [0, 4], 4)


def test_negative_lumped_mass_names_the_file_and_dof(files):
    d, _M, K, fe = files
    bad = mtx(d / "neg.mtx", edited(lumped(fe), {(13, 13): -1.0}))
    with pytest.raises(ModalFileError, match=re.escape(str(bad)) + r": matrix 'M' has a negative diagonal term -1 at "
                                             r"node 2 uy \(row 13\)"):
        read_matrix_market(bad, K, fe.nodes)


def test_mass_matrix_not_semidefinite_by_a_two_by_two_minor(files):
    """A zero rotational diagonal with a nonzero coupling term: not a lumped mass, not positive semi-definite."""
    d, _M, K, fe = files
    bad = mtx(d / "minor.mtx", edited(lumped(fe), {(9, 7): 0.1, (7, 9): 0.1}))
    with pytest.raises(ModalFileError, match=re.escape(str(bad)) + r": matrix 'M' is not positive semi-definite: the "
                                             r"term 0\.1 at \(node 1 (uy|rx) .*node 1 (uy|rx)"):
        read_matrix_market(bad, K, fe.nodes)


def test_mass_matrix_not_semidefinite_beyond_two_by_two(files):
    """Every 2 x 2 minor fine, a 3 x 3 rotational block indefinite: found by the reduction, named with its file."""
    d, _M, K, fe = files
    r = fe.dof_map[2, 3:]
    J = float(fe.M.diagonal()[r].max())
    block = np.array([[1, 0.9, 0.9], [0.9, 1, -0.9], [0.9, -0.9, 1]]) * J  # eigenvalues -0.8, 1.9, 1.9 (x J)
    bad = mtx(d / "block.mtx", rotation_block_edited(fe.M, fe, 2, block))
    model = read_matrix_market(bad, K, fe.nodes)
    with pytest.raises(ModalFileError, match=re.escape(str(bad)) + r": the mass matrix on the interior DOFs is not "
                                             r"positive definite: the first failing leading minor is at node 2 r"):
        modal_data_from_fe(model, [4], 4, reference_node=0)


def test_non_square_mass_is_reported_under_its_own_file(files):
    d, _M, K, fe = files
    bad = mtx(d / "rect.mtx", fe.M[:, :-1])
    with pytest.raises(ModalFileError, match=re.escape(f"{bad}: matrix 'M' is not square: shape (30, 29)")):
        read_matrix_market(bad, K, fe.nodes)


def test_negative_stiffness_term_names_the_file_and_dof(files):
    d, M, _K, fe = files
    bad = mtx(d / "kneg.mtx", edited(fe.K, {(8, 8): -fe.K[8, 8]}))
    with pytest.raises(ModalFileError, match=re.escape(str(bad)) + r": matrix 'K' has a negative diagonal term .* at "
                                             r"node 1 uz \(row 8\)"):
        read_matrix_market(M, bad, fe.nodes)


def test_indefinite_stiffness_with_a_positive_diagonal_names_the_file_and_dof(files):
    d, M, _K, fe = files
    r = fe.dof_map[2, 3:]
    k = fe.K.diagonal()[r]
    block = np.array([[0, 0.9, 0.9], [0.9, 0, -0.9], [0.9, -0.9, 0]]) * np.sqrt(np.outer(k, k)) + np.diag(k)
    bad = mtx(d / "kind.mtx", rotation_block_edited(fe.K, fe, 2, block))
    with pytest.raises(ModalFileError, match=re.escape(str(bad)) + r": K is not positive semi-definite: a "
                                             r"fixed-interface mode has negative stiffness .* at node 2 r"):
        modal_data_from_fe(read_matrix_market(M, bad, fe.nodes), [4], 4, reference_node=0)


def test_nan_mesh_end_point_names_the_argument():
    with pytest.raises(RunArgumentError, match=r"beam_mesh: argument 'end' has a non-finite coordinate: \[nan, 0\.0"):
        beam_mesh((0, 0, 0), (float("nan"), 0, 0), 4, SECTION, E=E, rho=RHO)


def test_read_fe_of_a_npy_says_which_formats_it_reads(files, tmp_path):
    path = tmp_path / "M.npy"
    np.save(path, files[3].M.toarray())
    with pytest.raises(ModalFileError, match=re.escape(str(path)) + r": a single numpy array \(\.npy\), not an FE "
                                             r"model archive: read_fe reads a \.npz .*read_matrix_market"):
        read_fe(path)


# -------------------------------------------------------------------------------------------- beam_mesh arguments
BEAM_CASES = {
    "nu = -1": ({"nu": -1}, r"Poisson's ratio nu must be in \(-1, 0\.5\] .* got -1\.0"),
    "nu above 0.5": ({"nu": 0.6}, r"Poisson's ratio nu must be in \(-1, 0\.5\] .* got 0\.6"),
    "nu as a string": ({"nu": "0.3"}, r"nu must be Poisson's ratio, .* got str '0\.3'"),
    "E as a bool": ({"E": True}, r"E must be a positive finite number \[Pa\], got bool True"),
    "E as a string": ({"E": "2.1e11"}, r"E must be a positive finite number \[Pa\], got str '2\.1e11'"),
    "negative density": ({"rho": -7850.0}, r"rho must be a positive finite number \[kg/m3\], got -7850\.0"),
    "infinite G": ({"G": math.inf}, r"G must be a positive finite number \[Pa\], got float inf"),
    "zero G": ({"G": 0.0}, r"G must be a positive finite number \[Pa\], got 0\.0"),
    "start equals end": ({"end": (0, 0, 0)}, r"start and end coincide \(\[0\.0, 0\.0, 0\.0\]\)"),
    "end with two coordinates": ({"end": (2.0, 0)}, r"argument 'end' must be three numbers \(x, y, z\), got shape"),
    "start as a string": ({"start": "origin"}, r"argument 'start' must be three numbers \(x, y, z\), got 'origin'"),
    "fractional element count": ({"n": 2.5}, r"n_elements must be a positive integer .* got 2\.5"),
    "bool element count": ({"n": True}, r"n_elements must be a positive integer .* got True"),
    "section not a Section": ({"section": 0.02}, r"argument 'section' must be a Section .* got float 0\.02"),
    "section function failing": ({"section": lambda s: rectangle(0.02, 0.03 * (1 - s))},
                                 r"argument 'section' at position fraction s = 1: rectangle section: h must be a "
                                 r"positive finite length \[m\], got 0\.0"),
    "rotary_inertia as a string": ({"rotary_inertia": "False"}, r"rotary_inertia must be True, False or None"),
    "zero y_axis": ({"y_axis": (0, 0, 0)}, r"argument 'y_axis' must be a nonzero direction"),
    "y_axis along the beam": ({"y_axis": (3, 0, 0)}, r"y_axis \[3\.0, 0\.0, 0\.0\] is parallel to the beam axis"),
    "nodes_at as a number": ({"nodes_at": 0.5}, r"nodes_at' must be a sequence .* \(for one node: \[0\.5\]\)"),
    "theory misspelt": ({"theory": "timo"}, r"theory must be 'euler-bernoulli' or 'timoshenko', got 'timo'"),
}


@pytest.mark.parametrize("case", list(BEAM_CASES))
def test_bad_beam_mesh_argument(case):
    kwargs, pattern = BEAM_CASES[case]
    kwargs = dict(kwargs)
    args = (kwargs.pop("start", (0, 0, 0)), kwargs.pop("end", (L, 0, 0)), kwargs.pop("n", 4),
            kwargs.pop("section", SECTION))
    with pytest.raises(RunArgumentError, match=r"beam_mesh: .*" + pattern):
        beam_mesh(*args, **{"E": E, "rho": RHO, **kwargs})


SECTION_CASES = {
    "rectangle width as a string": (lambda: rectangle("0.02", 0.03), r"rectangle section: b must be a positive "
                                                                     r"finite length \[m\], got '0\.02'"),
    "rectangle with nu = -1": (lambda: rectangle(0.02, 0.03, nu=-1.0), r"rectangle section: Poisson's ratio nu"),
    "circle of diameter True": (lambda: circle(True), r"circle section: d must be a positive finite length \[m\], "
                                                      r"got True"),
    "box without a hollow": (lambda: box(0.1, 0.1, 0.05), r"box section: wall thickness t=0\.05 m leaves no hollow"),
    "I section web wider than flange": (lambda: i_section(0.1, 0.2, 0.2, 0.01), r"I section: flanges .* do not fit"),
    "Section with negative area": (lambda: Section(A=-1e-4, Iy=1e-8, Iz=1e-8, J=1e-8, name="edited"),
                                   r"section 'edited': A must be a positive number, got -0\.0001"),
}


@pytest.mark.parametrize("case", list(SECTION_CASES))
def test_bad_section(case):
    make, pattern = SECTION_CASES[case]
    with pytest.raises(RunArgumentError, match=pattern):
        make()


# ---------------------------------------------------------------------------------------- Matrix Market and tables
def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def table_with(path: Path, table: np.ndarray, at: tuple[int, int], value: float) -> Path:
    """``table`` with the one entry ``at`` set to ``value``, saved as text at ``path``."""
    edited_table = table.copy()
    edited_table[at] = value
    np.savetxt(path, edited_table)
    return path


def mm_case(name, d, M, K, fe):
    """(mass, stiffness, nodes, dof_map, the culprit file, pattern) of a hand-edited or mis-exported case."""
    n = fe.nodes
    table = np.column_stack([np.arange(1, 6), n])
    if name == "not Matrix Market":
        return write(d / "notes.mtx", "stiffness of the boom\n1 2 3\n"), K, n, None, "notes.mtx", \
            r"cannot read matrix 'M' as Matrix Market \(argument 'mass'\): .*banner"
    if name == "empty file":
        return M, write(d / "empty.mtx", ""), n, None, "empty.mtx", r"the file is empty .*argument 'stiffness'"
    if name == "directory":
        (d / "folder.mtx").mkdir(exist_ok=True)
        return d / "folder.mtx", K, n, None, "folder.mtx", r"is a directory, not a Matrix Market file of matrix 'M'"
    if name == "wrong path":
        return M, d / "absent.mtx", n, None, "absent.mtx", r"no such file \(a Matrix Market file of matrix 'K'"
    if name == "complex matrix":
        return mtx(d / "cplx.mtx", fe.M * (1 + 0.5j)), K, n, None, "cplx.mtx", r"a Matrix Market 'complex' matrix"
    if name == "pattern matrix":
        path = d / "pattern.mtx"
        scipy.io.mmwrite(path, sp.coo_matrix(fe.K), field="pattern")
        return M, path, n, None, "pattern.mtx", r"'pattern' matrix \(a sparsity pattern without values\)"
    if name == "truncated file":
        lines = Path(K).read_text().splitlines()
        return M, write(d / "cut.mtx", "\n".join(lines[: len(lines) // 2]) + "\n"), n, None, "cut.mtx", \
            r"cannot read matrix 'K' .*Truncated"
    if name == "non-symmetric stiffness":
        return M, mtx(d / "nsym.mtx", edited(fe.K, {(0, 7): fe.K[0, 7] + 1e6})), n, None, "nsym.mtx", \
            r"matrix 'K' is not symmetric .* at \(node 0 ux \(row 0\), node 1 uy \(row 7\)\)"
    if name == "NaN entry":
        return M, mtx(d / "nan.mtx", edited(fe.K, {(15, 15): np.nan})), n, None, "nan.mtx", \
            r"matrix 'K' has non-finite entries \(NaN or inf\): nan at \(node 2 rx \(row 15\)"
    if name == "sizes differ":
        return mtx(d / "small.mtx", fe.M[:24, :24]), K, n, None, "small.mtx", \
            r"'M' \(24, 24\) and 'K' \(30, 30\) differ"
    if name == "DOF count not a multiple of 6":
        return (mtx(d / "M29.mtx", fe.M[:29, :29]), mtx(d / "K29.mtx", fe.K[:29, :29]), n[:4], None, "K29.mtx",
                r"rows 24..28 \(of 29\) belong to no node .* 29 rows are not six per node — pass dof_map")
    if name == "DOF map gives a row twice":
        dm = np.arange(30).reshape(5, 6)
        dm[3, 2] = 8
        return M, K, n, dm, "K.mtx", r"'dof_map' gives row 8 to node 1 uz and node 3 uz"
    if name == "DOF map with -2":
        dm = np.arange(30).reshape(5, 6)
        dm[4, 5] = -2
        return M, K, n, dm, "K.mtx", r"'dof_map' holds -2 at node 4 rz: rows are >= 0, or -1"
    if name == "DOF map file with fractions":
        path = d / "dofs.txt"
        np.savetxt(path, np.arange(30).reshape(5, 6) + 0.5)
        return M, K, n, path, "dofs.txt", r"'dof_map' must hold whole numbers, got 0\.5"
    if name == "node file with a header line":
        return M, K, write(d / "hdr.txt", "x y z\n" + "\n".join(" ".join(map(str, r)) for r in n)), None, \
            "hdr.txt", r"'nodes' line 1: 'x' is not a number \(a header line\? start it with #\)"
    if name == "node file with a NaN coordinate":
        path = table_with(d / "nan_nodes.txt", n, (3, 1), np.nan)
        return M, K, path, None, "nan_nodes.txt", r"node 3 \(row 3\) has a non-finite coordinate \[1\.5, nan, 0\.0\]"
    if name == "node file with a duplicate id":
        return M, K, table_with(d / "dup.txt", table, (4, 0), 2), None, "dup.txt", \
            r"node id 2 appears 2 times \(rows \[1, 4\]\)"
    if name == "node file with a fractional id":
        return M, K, table_with(d / "frac.txt", table, (2, 0), 3.5), None, "frac.txt", \
            r"'nodes' row 2: node id 3\.5 is not a whole number"
    if name == "node file with ragged rows":
        return M, K, write(d / "ragged.txt", "0 0 0\n0.5 0 0\n1.0 0\n1.5 0 0\n2 0 0\n"), None, "ragged.txt", \
            r"'nodes' line 3 has 2 columns, line 1 has 3"
    if name == "node file with two columns":
        path = d / "xy.txt"
        np.savetxt(path, n[:, :2])
        return M, K, path, None, "xy.txt", r"'nodes' must be a table \(N, 3\) \[x, y, z\] or \(N, 4\)"
    raise KeyError(name)


MM_CASES = ["not Matrix Market", "empty file", "directory", "wrong path", "complex matrix", "pattern matrix",
            "truncated file", "non-symmetric stiffness", "NaN entry", "sizes differ", "DOF count not a multiple of 6",
            "DOF map gives a row twice", "DOF map with -2", "DOF map file with fractions",
            "node file with a header line", "node file with a NaN coordinate", "node file with a duplicate id",
            "node file with a fractional id", "node file with ragged rows", "node file with two columns"]


@pytest.mark.parametrize("case", MM_CASES)
def test_bad_matrix_market_input(files, case):
    d, M, K, fe = files
    mass, stiffness, nodes, dof_map, culprit, pattern = mm_case(case, d, M, K, fe)
    with pytest.raises(ModalFileError) as info:
        read_matrix_market(mass, stiffness, nodes, dof_map)
    message = str(info.value)
    assert culprit in message, message
    assert re.search(pattern, message), message


def test_dense_and_symmetric_matrix_market_files_and_an_id_column_are_read_alike(files):
    """Array (dense) storage, one stored triangle and a node table [id, x, y, z] give the same model."""
    d, _M, _K, fe = files
    dense = d / "dense.mtx"
    scipy.io.mmwrite(dense, fe.M.toarray())
    sym = d / "sym.mtx"
    scipy.io.mmwrite(sym, sp.coo_matrix(fe.K), symmetry="symmetric")
    table = d / "ids.txt"
    np.savetxt(table, np.column_stack([np.arange(101, 106), fe.nodes]), header="id x y z")
    model = read_matrix_market(dense, sym, table)
    assert scipy.io.mminfo(dense)[3] == "array" and scipy.io.mminfo(sym)[5] == "symmetric"
    assert abs(model.M - fe.M).max() == 0 and abs(model.K - fe.K).max() <= 1e-15 * abs(fe.K).max()
    assert model.node_ids.tolist() == [101, 102, 103, 104, 105]
    assert model.dof_label(27) == "node 105 rx (row 27)"


def test_node_coordinates_given_as_strings(files):
    _d, M, K, _fe = files
    with pytest.raises(RunArgumentError, match=r"argument 'nodes' must be an array of numbers or a path to a table"):
        read_matrix_market(M, K, [["0", "0", "0"], ["x", "0", "0"]])


# ----------------------------------------------------------------------------------------------------- .npz files
def npz_case(name, d, fe):
    fe.write_npz(d / "good.npz")
    arrays = dict(np.load(d / "good.npz"))
    if name == "CSR index pointer cut":
        arrays["M_indptr"] = arrays["M_indptr"][:-2]
        pattern = r"the CSR arrays M_data, M_indices, M_indptr, M_shape do not form a matrix"
    elif name == "element with a node out of range":
        arrays["elements"] = np.array([[0, 1], [1, 99]])
        pattern = r"'elements' must be rows of node indices 0\.\.4, got .* values 0\.\.99"
    elif name == "fractional node ids":
        arrays["node_ids"] = np.array([1.5, 2, 3, 4, 5])
        pattern = r"array 'node_ids' must hold whole numbers, got 1\.5"
    elif name == "one-number M_shape":
        arrays["M_shape"] = np.array([30])
        pattern = r"array 'M_shape' must be two sizes \(rows, columns\), got \[30\]"
    elif name == "empty file":
        path = d / "empty.npz"
        path.write_bytes(b"")
        return path, r"the file is empty \(an FE model \.npz archive"
    elif name == "Matrix Market file":
        path = d / "M.mtx"
        scipy.io.mmwrite(path, fe.M)
        return path, r"a Matrix Market file, not an FE model archive: .*read_matrix_market\(mass, stiffness"
    elif name == "directory":
        (d / "dir.npz").mkdir(exist_ok=True)
        return d / "dir.npz", r"is a directory, not an FE model \.npz archive"
    else:
        raise KeyError(name)
    path = d / "bad.npz"
    np.savez(path, **arrays)
    return path, pattern


NPZ_CASES = ["CSR index pointer cut", "element with a node out of range", "fractional node ids", "one-number M_shape",
             "empty file", "Matrix Market file", "directory"]


@pytest.mark.parametrize("case", NPZ_CASES)
def test_bad_npz(files, tmp_path, case):
    path, pattern = npz_case(case, tmp_path, files[3])
    with pytest.raises(ModalFileError, match=re.escape(str(path)) + ": " + pattern):
        read_fe(path)


# ------------------------------------------------------------------------------------------- reduction arguments
@pytest.fixture(scope="module")
def beam():
    return mesh()


REDUCTION_CASES = {
    "n_modes as a bool": (lambda fe: modal_data_from_fe(fe, [0, 4], True), RunArgumentError,
                          r"n_modes must be a whole number >= 0, got True"),
    "negative n_modes": (lambda fe: modal_data_from_fe(fe, [0, 4], -1), RunArgumentError,
                         r"n_modes must be a whole number >= 0, got -1"),
    "more modes than massive interior DOFs": (
        lambda fe: modal_data_from_fe(replace(plain(fe), M=lumped(fe)), [4], 13, reference_node=0), RunArgumentError,
        r"n_modes must be an integer in 0\.\.9 \(of the 18 interior DOFs, 9 have no mass and no modes\), got 13"),
    "interface node not in the mesh": (lambda fe: modal_data_from_fe(fe, [0, 9], 2), KeyError,
                                       r"argument 'interface_nodes': node 9 is not in the FE model \(5 nodes, ids "
                                       r"0\.\.4, FE model from flexlib beam_mesh\)"),
    "repeated interface node": (lambda fe: modal_data_from_fe(fe, [0, 4, 4], 2), RunArgumentError,
                                r"argument 'interface_nodes' gives node 4 more than once"),
    "interface node as a bare int": (lambda fe: modal_data_from_fe(fe, 4, 2), RunArgumentError,
                                     r"'interface_nodes' must be a list of node ids, got 4 \(for one node: \[4\]\)"),
    "fractional interface node": (lambda fe: modal_data_from_fe(fe, [0, 3.7], 2), RunArgumentError,
                                  r"'interface_nodes': node id 3\.7 is not a whole number"),
    "free body without interface": (lambda fe: modal_data_from_fe(fe, [], 2), RunArgumentError,
                                    r"interface_nodes is empty, but a free body \(free=True\) needs interface nodes"),
    "free body declared held, no interface": (lambda fe: modal_data_from_fe(fe, [], 2, free=False), RunArgumentError,
                                              r"K_ii is singular .* a mechanism .* pass free=True for a floating "
                                              r"body, or reference_node="),
    "free body declared held": (lambda fe: modal_data_from_fe(fe, [4], 2, free=False), RunArgumentError,
                                r"6 mode\(s\) have zero frequency .*: the FE model is not held, but free=False"),
    "held body declared free": (lambda fe: modal_data_from_fe(fe.constrained([0]), [4], 2), RunArgumentError,
                                r"K does not annihilate the rigid-body modes: the translation along x .* largest at "
                                r"node 1 ux .* pass free=False"),
    "interface holding no rotation about the axis": (
        lambda fe: craig_bampton(fe.M, fe.K, fe.dofs([0, 4], ["ux", "uy", "uz"]), 2,
                                 rigid_body_modes=fe.rigid_body_modes()),
        RunArgumentError, r"interface DOFs do not restrain all rigid-body motions .*the rotation about x moves none"),
    "reference node not in the mesh": (lambda fe: modal_data_from_fe(fe, [4], 2, reference_node=7), KeyError,
                                       r"argument 'reference_node': node 7 is not in the FE model"),
    "fractional reference node": (lambda fe: modal_data_from_fe(fe, [4], 2, reference_node=0.5), RunArgumentError,
                                  r"argument 'reference_node': node id 0\.5 is not a whole number"),
    "support node not in the mesh": (lambda fe: modal_data_from_fe(fe, [0, 4], 2, geometric_stiffening=True,
                                                                   support_nodes=[11]), KeyError,
                                     r"argument 'support_nodes': node 11 is not in the FE model"),
    "a path instead of an FE model": (lambda fe: modal_data_from_fe("boom.npz", [0, 4], 2), RunArgumentError,
                                      r"argument 'fe' must be an FEModel .* got str 'boom\.npz'"),
    "free as a string": (lambda fe: modal_data_from_fe(fe, [0, 4], 2, free="no"), RunArgumentError,
                         r"argument 'free' must be True or False, got 'no'"),
    "stress fibre of three numbers": (lambda fe: modal_data_from_fe(fe, [0, 4], 2, stress_fibre=(0.01, 0.01, 0.0)),
                                      RunArgumentError, r"'stress_fibre' must be two finite numbers \(y, z\) \[m\]"),
    "unconnected DOF": (lambda fe: modal_data_from_fe(replace(plain(fe), K=edited(fe.K, {(15, k): 0.0 for k in
                                                                                         range(30)} | {
        (k, 15): 0.0 for k in range(30)})), [4], 2, reference_node=0), RunArgumentError,
                        r"node 2 rx \(row 15\) has no stiffness at all \(a zero row of K\): an unconnected DOF"),
    "raw basis with a massless interface rotation": (
        lambda fe: modal_data_from_fe(replace(plain(fe), M=lumped(fe)), [4], 2, reference_node=0,
                                      orthogonalize=False), RunArgumentError,
        r"orthogonalize=False keeps the raw Craig–Bampton basis, and a combination of its modes carries no mass "
        r"\(moving most at node 4 rx"),
    "craig_bampton interface row out of range": (lambda fe: craig_bampton(fe.M, fe.K, [0, 30], 2), RunArgumentError,
                                                 r"craig_bampton: interface_dofs must be rows in 0\.\.29, got 30"),
}


@pytest.mark.parametrize("case", list(REDUCTION_CASES))
def test_bad_reduction_argument(beam, case):
    call, cls, pattern = REDUCTION_CASES[case]
    with pytest.raises(cls, match=pattern) as info:
        call(beam)
    assert isinstance(info.value, RunArgumentError)  # a flexlib error (an unknown node is also a KeyError)


def test_held_model_without_interface_gives_its_fixed_base_modes(beam):
    """Zero interface on a clamped model is valid (free=False): the modes are the clamped beam's own."""
    held = beam.constrained([0])
    data = modal_data_from_fe(held, [], 6, free=False)
    full = np.sqrt(la.eigh(held.K.toarray(), held.M.toarray(), eigvals_only=True, subset_by_index=[0, 5]))
    np.testing.assert_allclose(data.frequencies, full / (2 * math.pi), rtol=1e-10)


# ------------------------------------------------------------------------------------------------------ importers
def test_ansys_reader_missing_names_the_extra_and_the_alternative(tmp_path):
    """ansys-mapdl-reader is an optional extra (not installed in the test environment)."""
    try:
        __import__("ansys.mapdl.reader")
    except ImportError:
        pass
    else:
        pytest.skip("ansys-mapdl-reader is installed")
    with pytest.raises(ImportError, match=re.escape(f"read_ansys_full ({tmp_path / 'job.full'}): "
                                                    "ansys-mapdl-reader is needed") +
                       r".*pip install 'flexlib\[ansys\]'.*read_matrix_market"):
        read_ansys_full(tmp_path / "job.full")


@pytest.fixture(scope="module")
def op4():
    return pytest.importorskip("pyNastran.op4.op4", reason="optional extra 'nastran' (pyNastran) not installed")


def test_op4_empty_file_and_directory(op4, tmp_path):
    empty = write(tmp_path / "empty.op4", "")
    with pytest.raises(ModalFileError, match=re.escape(str(empty)) + r": the file is empty \(a Nastran OUTPUT4 file"):
        read_nastran_op4(empty, nodes=np.zeros((1, 3)))
    with pytest.raises(ModalFileError, match=re.escape(str(tmp_path)) + r": is a directory, not an OP4 file"):
        read_nastran_op4(tmp_path, nodes=np.zeros((1, 3)))


def test_op4_grid_table_with_a_nan_coordinate(op4, beam, tmp_path):
    path = tmp_path / "beam.op4"
    with open(path, "w") as f:
        op4.OP4().write_op4(f, {"MAA": (6, beam.M.toarray()), "KAA": (6, beam.K.toarray())}, is_binary=False,
                            precision="double")
    table = np.column_stack([np.arange(101, 106), beam.nodes])
    table[2, 3] = np.inf
    with pytest.raises(RunArgumentError, match=r"argument 'nodes': node 103 \(row 2\) has a non-finite coordinate"):
        read_nastran_op4(path, nodes=table)
    with pytest.raises(RunArgumentError, match=r"'nodes' has an id column and node_ids is given too"):
        read_nastran_op4(path, nodes=np.column_stack([np.arange(101, 106), beam.nodes]), node_ids=range(5))


@pytest.fixture(scope="module")
def bdf():
    return pytest.importorskip("pyNastran.bdf.bdf", reason="optional extra 'nastran' (pyNastran) not installed")


def test_dmig_empty_file(bdf, tmp_path):
    path = write(tmp_path / "empty.bdf", "\n")
    with pytest.raises(ModalFileError, match=re.escape(str(path)) + r": the bulk data file is empty"):
        read_nastran_dmig(path, "MAAX", "KAAX")


def test_dmig_negative_lumped_mass_names_the_grid(bdf, tmp_path):
    """A CONM2-style lumped DMIG with a sign slip: named by grid id and component."""
    model = bdf.BDF(debug=None)
    for g in (7, 8):
        model.add_grid(g, [float(g - 7), 0.0, 0.0])
    rows = [(g, c) for g in (7, 8) for c in range(1, 7)]
    kterms = [((g, c), (g, c), 1e6) for g, c in rows]
    kterms += [((8, c), (7, c), -1e6) for c in range(1, 7)]
    mass = [((g, c), (g, c), 2.0 if c <= 3 else 0.0) for g, c in rows]
    mass[7] = ((8, 2), (8, 2), -2.0)
    model.add_dmig("MAAX", 6, 2, 0, 0, None, [t[0] for t in mass], [t[1] for t in mass], [t[2] for t in mass])
    model.add_dmig("KAAX", 6, 2, 0, 0, None, [t[0] for t in kterms], [t[1] for t in kterms], [t[2] for t in kterms])
    path = tmp_path / "lumped.bdf"
    model.write_bdf(str(path), size=16, is_double=True)
    with pytest.raises(ModalFileError, match=re.escape(str(path)) + r": matrix 'MAAX' has a negative diagonal term -2 "
                                             r"at node 8 uy \(row 7\)"):
        read_nastran_dmig(path, "MAAX", "KAAX")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX permissions")
def test_unreadable_node_file(files, tmp_path):
    _d, M, K, fe = files
    path = tmp_path / "locked.txt"
    np.savetxt(path, fe.nodes)
    path.chmod(0)
    try:
        path.read_bytes()
    except PermissionError:
        pass
    else:  # running as root: permissions do not apply
        path.chmod(0o644)
        pytest.skip("permissions are not enforced for this user")
    try:
        with pytest.raises(ModalFileError, match=re.escape(str(path)) + r": cannot read 'nodes': .*Permission denied"):
            read_matrix_market(M, K, path)
    finally:
        path.chmod(0o644)
