"""Flexible-body output: nodal deformation and stress, von Mises, VTK series read back by an independent reader,
matplotlib still and GIF animation.

The independent reader is a hand parse of the written XML with ``xml.etree`` and of the VTK binary arrays after
Kitware's *VTK File Formats* ("binary" inline data: a base64 header of UInt32 ``[blocks, block size, last block
size, compressed sizes...]`` encoded on its own, then the base64 of the zlib-compressed blocks) — not meshio,
which wrote them. (The ``vtk`` wheel, 140 MB, was judged too heavy for a test extra.)
"""

from __future__ import annotations

import base64
import json
import math
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path

import numpy as np
import pytest

from flexlib.fe import (
    ModalData,
    animate,
    beam_mesh,
    deformed_positions,
    energies,
    modal_data_from_fe,
    nodal_stress,
    node_displacements,
    node_rotations,
    plot_frame,
    rectangle,
    von_mises,
    write_vtk_series,
)
from flexlib.units import g_n

L_BEAM = 1.5  # [m]
N_EL = 10
TIP = N_EL  # node id of the free end
H, B = 0.02, 0.01  # section height (y) and width (z) [m]


@pytest.fixture(scope="module")
def data() -> ModalData:
    """A free steel beam along x, 10 Euler–Bernoulli elements, frames at both ends, stress at the top fibre."""
    fe = beam_mesh((0, 0, 0), (L_BEAM, 0, 0), N_EL, rectangle(H, B), E=2e11, rho=8000.0)
    return modal_data_from_fe(fe, [0, TIP], 2, title="test beam", stress_fibre=(H / 2, B / 2))


def rotation_z(theta: np.ndarray) -> np.ndarray:
    """World -> body orientation of a frame turned by ``theta`` about z: v_body = T @ v_world."""
    c, s = np.cos(theta), np.sin(theta)
    T = np.zeros((theta.size, 3, 3))
    T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1], T[:, 2, 2] = c, s, -s, c, 1.0
    return T


@pytest.fixture(scope="module")
def motion(data: ModalData) -> dict[str, np.ndarray]:
    """q(t): each mode a sinusoid; r_0(t): a line in x-y with a z offset; T(t): rotation about z at 0.8 rad/s."""
    t = np.linspace(0.0, 1.0, 6)
    amp = 1e-3 * (1.0 + np.arange(data.n_modes))
    q = np.sin(2 * math.pi * np.outer(t, 1.0 + 0.5 * np.arange(data.n_modes))) * amp
    r_0 = np.stack([0.5 * t, 0.2 * t, np.full_like(t, 0.3)], axis=1)
    return {"t": t, "q": q, "r_0": r_0, "T": rotation_z(0.8 * t), "theta": 0.8 * t}


# ---------------------------------------------------------------------------------------------- (0) energy
# energy conservation holds in any basis: the strip keeps the clamped one the build advises against
@pytest.mark.filterwarnings("ignore:.*clamped basis.*free revolute:flexlib.errors.ModalDataWarning")
def test_energies_of_a_swinging_flexible_pendulum_are_conserved_and_start_at_the_rigid_potential():
    """A 1 m aluminium strip (20 × 5 mm, 4 modes, no modal damping) on a revolute swings from −1 rad under gravity
    and bends; the sum of :func:`energies` (kinetic from the inertia invariants, strain ½qᵀKq, potential) is a
    conserved quantity of FlexibleBody's equations (they are its Lagrange equations): constant to 1e-8 of the
    exchanged energy. Reference at the start (at rest, undeformed): the rigid strip's ``m g (L/2) sin(−1)``."""
    import flexlib as fl
    from flexlib.components.mechanics.flexible import FlexibleBody
    from flexlib.components.mechanics.multibody import Revolute, World

    L, b, h, rho = 1.0, 0.02, 0.005, 2700.0
    strip = modal_data_from_fe(beam_mesh((0, 0, 0), (L, 0, 0), 10, rectangle(b, h), E=7e10, rho=rho), [0], 4,
                               reference_node=0, title="strip")

    class StripPendulum(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.world = World()
            self.j = Revolute(n=[0, 0, 1], init={"phi": -1.0, "w": 0.0})
            self.strip = FlexibleBody(strip, damping={k: 0.0 for k in range(4)})
            self.connect(self.world.frame_b, self.j.frame_a)
            self.connect(self.j.frame_b, self.strip.frame_a)

    res = fl.Simulation(StripPendulum()).run(2.0, dt_out=0.01, rtol=1e-9, atol=1e-11, progress=False)
    n = len(res.t)
    E = energies(strip, res["strip.q"], res["strip.qd"], res["strip.r_0"], res["strip.v_0"], res["strip.w"],
                 res["strip.frame_a.T"].reshape(n, 3, 3, order="F"))
    m = rho * b * h * L
    assert E["potential"][0] == pytest.approx(m * g_n * L / 2 * math.sin(-1.0), rel=1e-9)
    assert E["kinetic"].max() > 0.2 and E["strain"].max() > 1e-4  # it swings and bends
    assert np.ptp(E["total"]) < 1e-8 * np.ptp(E["potential"])


def test_energies_refuse_bad_shapes(data, motion):
    q = motion["q"]
    with pytest.raises(Exception, match="argument 'w' has shape"):
        energies(data, q, q, motion["r_0"], motion["r_0"], np.zeros((2, 3)), motion["T"])


# ---------------------------------------------------------------------------------------- (1) deformation
def test_deformed_position_of_the_tip_equals_a_hand_computation(data, motion):
    """Reference: r = r_0 + T^T (s + sum_j q_j phi_j), written out for a rotation about z (x_w = c b_x - s b_y,
    y_w = s b_x + c b_y, z_w = b_z); node looked up by hand in the mode arrays. Tolerance 1e-13 m."""
    P = deformed_positions(data, motion["q"], motion["r_0"], motion["T"], nodes=[TIP])
    assert P.shape == (6, 1, 3)
    i = int(np.flatnonzero(data.node_ids == TIP)[0])
    for k in range(6):
        u = sum(motion["q"][k, j] * data.translational_modes[j, i] for j in range(data.n_modes))
        b = data.coordinates[i] + u
        c, s = math.cos(motion["theta"][k]), math.sin(motion["theta"][k])
        expected = motion["r_0"][k] + np.array([c * b[0] - s * b[1], s * b[0] + c * b[1], b[2]])
        np.testing.assert_allclose(P[k, 0], expected, rtol=0, atol=1e-13)
    # the undeformed tip turns with the frame: at q = 0 it sits at r_0 + L (cos, sin, 0)
    P0 = deformed_positions(data, np.zeros(data.n_modes), motion["r_0"][-1], motion["T"][-1], nodes=[TIP])
    th = motion["theta"][-1]
    np.testing.assert_allclose(P0[0], motion["r_0"][-1] + L_BEAM * np.array([math.cos(th), math.sin(th), 0.0]),
                               rtol=0, atol=1e-13)


def test_node_displacements_and_rotations_superpose_the_modes(data, motion):
    """Reference: the sum over modes by loop; single instant (M,) gives (n, 3). Tolerance 1e-15 m / rad."""
    q = motion["q"]
    u = node_displacements(data, q)
    th = node_rotations(data, q, nodes=[0, TIP])
    assert u.shape == (6, data.n_nodes, 3) and th.shape == (6, 2, 3)
    for k in (1, 4):
        ref_u = sum(q[k, j] * data.translational_modes[j] for j in range(data.n_modes))
        ref_r = sum(q[k, j] * data.rotational_modes[j][[0, TIP]] for j in range(data.n_modes))
        np.testing.assert_allclose(u[k], ref_u, rtol=0, atol=1e-15)
        np.testing.assert_allclose(th[k], ref_r, rtol=0, atol=1e-15)
        np.testing.assert_allclose(node_displacements(data, q[k], nodes=[3]), ref_u[[3]], rtol=0, atol=1e-15)
    # with scale, only the elastic part is magnified: deformed - undeformed positions scale linearly
    P1 = deformed_positions(data, q, motion["r_0"], motion["T"])
    P5 = deformed_positions(data, q, motion["r_0"], motion["T"], scale=5.0)
    P0 = deformed_positions(data, np.zeros_like(q), motion["r_0"], motion["T"])
    np.testing.assert_allclose(P5 - P0, 5.0 * (P1 - P0), rtol=0, atol=1e-14)


# ---------------------------------------------------------------------------------------- (2) stress
def test_von_mises_closed_forms():
    """Uniaxial s -> |s|; pure shear tau -> sqrt(3) tau (each shear component); hydrostatic -> 0; a general state
    against the principal-stress form sqrt(((s1-s2)^2 + (s2-s3)^2 + (s3-s1)^2)/2) from the eigenvalues.
    Tolerance 1e-12 relative."""
    s = 123.4e6
    for c in range(3):
        state = np.zeros(6)
        state[c] = -s
        assert von_mises(state) == pytest.approx(s, rel=1e-12)
    for c in range(3, 6):
        state = np.zeros(6)
        state[c] = s
        assert von_mises(state) == pytest.approx(math.sqrt(3.0) * s, rel=1e-12)
    assert von_mises(np.array([s, s, s, 0, 0, 0])) == pytest.approx(0.0, abs=1e-12 * s)
    rng = np.random.default_rng(7)
    states = rng.normal(scale=1e8, size=(5, 4, 6))
    vm = von_mises(states)
    assert vm.shape == (5, 4)
    for idx in np.ndindex(5, 4):
        sxx, syy, szz, sxy, syz, szx = states[idx]
        p = np.linalg.eigvalsh(np.array([[sxx, sxy, szx], [sxy, syy, syz], [szx, syz, szz]]))
        ref = math.sqrt(((p[0] - p[1]) ** 2 + (p[1] - p[2]) ** 2 + (p[2] - p[0]) ** 2) / 2)
        assert vm[idx] == pytest.approx(ref, rel=1e-12)


def test_nodal_stress_superposes_stress_modes_and_beam_von_mises_is_the_normal_stress(data, motion):
    """Reference: sum_j q_j S_j by loop (1e-6 Pa); the beam stress modes are uniaxial along the beam axis (x), so
    von Mises = |sxx| (1e-12 relative)."""
    q = motion["q"]
    sigma = nodal_stress(data, q)
    assert sigma.shape == (6, data.n_nodes, 6)
    ref = sum(q[3, j] * data.stress_modes[j] for j in range(data.n_modes))
    np.testing.assert_allclose(sigma[3], ref, rtol=0, atol=1e-6)
    assert np.abs(sigma[..., 1:]).max() == 0.0
    np.testing.assert_allclose(von_mises(sigma), np.abs(sigma[..., 0]), rtol=1e-12, atol=0)
    assert np.abs(sigma[..., 0]).max() > 1e5  # the chosen amplitudes bend the beam noticeably
    np.testing.assert_allclose(nodal_stress(data, q[3], nodes=[TIP, 2]), ref[[TIP, 2]], rtol=0, atol=1e-6)


# ---------------------------------------------------------------------------------------- (3) VTK series
def _decode(da: ET.Element, header_type: np.dtype, compressed: bool) -> np.ndarray:
    dtype = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt8": "u1"}[da.get("type")]
    text = "".join((da.text or "").split())
    if da.get("format") == "ascii":
        return np.array((da.text or "").split(), dtype=dtype)
    assert da.get("format") == "binary"
    hsize = header_type.itemsize
    if compressed:
        first = base64.b64decode(text[: 4 * math.ceil(hsize / 3)])[:hsize]  # the header is encoded on its own
        n_blocks = int(np.frombuffer(first, header_type)[0])
        n_header = 4 * math.ceil((3 + n_blocks) * hsize / 3)
        header = np.frombuffer(base64.b64decode(text[:n_header])[: (3 + n_blocks) * hsize], header_type)
        raw = base64.b64decode(text[n_header:])
        out, pos = b"", 0
        for size in header[3:]:
            out += zlib.decompress(raw[pos: pos + int(size)])
            pos += int(size)
        assert len(out) == (n_blocks - 1) * int(header[1]) + int(header[2])
    else:
        raw = base64.b64decode(text)
        n = int(np.frombuffer(raw[:hsize], header_type)[0])
        out = raw[hsize: hsize + n]
    return np.frombuffer(out, dtype=dtype).copy()


def read_vtu(path: Path) -> dict[str, np.ndarray]:
    """Points, cells and point data of a .vtu (UnstructuredGrid, one piece), parsed by hand."""
    root = ET.parse(path).getroot()
    assert root.get("type") == "UnstructuredGrid" and root.get("byte_order") == "LittleEndian"
    header_type = np.dtype({"UInt32": "<u4", "UInt64": "<u8"}[root.get("header_type", "UInt32")])
    compressed = root.get("compressor") is not None
    if compressed:
        assert root.get("compressor") == "vtkZLibDataCompressor"
    piece = root.find("UnstructuredGrid/Piece")
    n_points, n_cells = int(piece.get("NumberOfPoints")), int(piece.get("NumberOfCells"))

    def arrays(tag: str) -> dict[str, np.ndarray]:
        out = {}
        for da in piece.find(tag).findall("DataArray"):
            a = _decode(da, header_type, compressed)
            k = int(da.get("NumberOfComponents", "1"))
            out[da.get("Name")] = a.reshape(-1, k) if k > 1 else a
        return out

    result = {"points": arrays("Points")["Points"], **{f"cell_{k}": v for k, v in arrays("Cells").items()}}
    result |= {f"point_{k}": v for k, v in arrays("PointData").items()}
    assert result["points"].shape == (n_points, 3) and result["cell_types"].shape == (n_cells,)
    return result


def test_vtk_series_read_back_by_an_independent_reader(data, motion, tmp_path):
    """Reference: the pvd's times are the given times (exact), each frame's points the deformed_positions
    (1e-15 m: float64 stored bit-exact), displacement the world-resolved node_displacements, von Mises from
    nodal_stress; cells are VTK_LINE (type 3) with the elements' connectivity."""
    path = write_vtk_series(tmp_path / "beam.pvd", data, motion["t"], motion["q"], motion["r_0"], motion["T"])
    assert path == tmp_path / "beam.pvd"
    coll = ET.parse(path).getroot()
    assert coll.get("type") == "Collection"
    sets = coll.findall("Collection/DataSet")
    np.testing.assert_array_equal([float(d.get("timestep")) for d in sets], motion["t"])
    P = deformed_positions(data, motion["q"], motion["r_0"], motion["T"])
    u_world = np.einsum("tji,tnj->tni", motion["T"], node_displacements(data, motion["q"]))
    vm = von_mises(nodal_stress(data, motion["q"]))
    for k, ds in enumerate(sets):
        frame = read_vtu(path.parent / ds.get("file"))
        np.testing.assert_allclose(frame["points"], P[k], rtol=0, atol=1e-15)
        np.testing.assert_array_equal(frame["cell_types"], np.full(N_EL, 3))
        np.testing.assert_array_equal(frame["cell_connectivity"].reshape(-1, 2), data.elements)
        np.testing.assert_array_equal(frame["cell_offsets"], 2 * np.arange(1, N_EL + 1))
        np.testing.assert_array_equal(frame["point_node_id"], data.node_ids)
        np.testing.assert_allclose(frame["point_displacement"], u_world[k], rtol=0, atol=1e-15)
        np.testing.assert_allclose(frame["point_displacement_magnitude"], np.linalg.norm(u_world[k], axis=1),
                                   rtol=0, atol=1e-15)
        np.testing.assert_allclose(frame["point_von_mises"], vm[k], rtol=1e-13, atol=1e-6)
    leftovers = sorted(p.name for p in tmp_path.iterdir())
    assert leftovers == ["beam.pvd", "beam.pvd.d"]  # no temporary files


def test_vtu_series_json_with_all_fields_and_rewrite_in_place(data, motion, tmp_path):
    """The ParaView ``.vtu.series`` JSON gives names and times; fields 'rotation' and 'stress' are written (checked
    against node_rotations / nodal_stress, 1e-15 rad, 1e-6 Pa); writing again over an existing series with fewer
    frames replaces it whole (no stale frame files)."""
    args = (data, motion["t"], motion["q"], motion["r_0"], motion["T"])
    path = write_vtk_series(tmp_path / "b.vtu.series", *args, fields=("displacement", "rotation", "stress"))
    series = json.loads(path.read_text())
    assert series["file-series-version"] == "1.0"
    np.testing.assert_array_equal([f["time"] for f in series["files"]], motion["t"])
    frame = read_vtu(path.parent / series["files"][2]["name"])
    rot = np.einsum("ji,nj->ni", motion["T"][2], node_rotations(data, motion["q"][2]))
    np.testing.assert_allclose(frame["point_rotation"], rot, rtol=0, atol=1e-15)
    sigma = nodal_stress(data, motion["q"][2])
    for c, comp in enumerate(("sxx", "syy", "szz", "sxy", "syz", "szx")):
        np.testing.assert_allclose(frame[f"point_stress_{comp}"], sigma[:, c], rtol=1e-13, atol=1e-6)
    assert "point_von_mises" not in frame
    write_vtk_series(path, data, motion["t"][:3], motion["q"][:3], motion["r_0"][:3], motion["T"][:3])
    assert len(json.loads(path.read_text())["files"]) == 3
    assert len(list((tmp_path / "b.vtu.series.d").iterdir())) == 3
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.vtu.series", "b.vtu.series.d"]


def test_series_without_stress_modes_writes_displacement_only(data, motion, tmp_path):
    """Default fields: von Mises only when the data has stress modes."""
    from dataclasses import replace

    plain = replace(data, stress_modes=None)
    path = write_vtk_series(tmp_path / "p.pvd", plain, motion["t"], motion["q"], motion["r_0"], motion["T"])
    frame = read_vtu(path.parent / ET.parse(path).getroot().find("Collection/DataSet").get("file"))
    assert {k for k in frame if k.startswith("point_")} == {"point_node_id", "point_displacement",
                                                            "point_displacement_magnitude"}


# ---------------------------------------------------------------------------------------- (4) matplotlib
def test_animation_gif_has_one_frame_per_sample_and_png_still(data, motion, tmp_path):
    """The GIF (Pillow writer) has as many frames as samples asked for (counted by PIL); the PNG still is a
    non-blank image of the requested size."""
    from PIL import Image

    args = (data, motion["t"], motion["q"], motion["r_0"], motion["T"])
    gif = animate(*args, path=tmp_path / "beam.gif", color="von_mises", scale=20.0, figsize=(3.2, 2.6), dpi=40)
    assert gif == tmp_path / "beam.gif" and gif.stat().st_size > 0
    with Image.open(gif) as im:
        assert im.format == "GIF" and im.n_frames == len(motion["t"])
    gif4 = animate(*args, path=tmp_path / "four.gif", frames=4, figsize=(3.2, 2.6), dpi=40)
    with Image.open(gif4) as im:
        assert im.n_frames == 4
    png = plot_frame(*args, index=2, path=tmp_path / "still.png", color="displacement", scale=20.0,
                     figsize=(4.0, 3.0), dpi=50)
    with Image.open(png) as im:
        assert im.format == "PNG" and im.size == (200, 150)
        extrema = im.convert("L").getextrema()
        assert extrema[1] - extrema[0] > 100  # something is drawn
    assert sorted(p.name for p in tmp_path.iterdir()) == ["beam.gif", "four.gif", "still.png"]


def test_animation_and_figure_returned_without_a_path(data, motion):
    """Without ``path``: plot_frame returns the Figure (3D axes and colour bar), animate the FuncAnimation."""
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure

    args = (data, motion["t"], motion["q"], motion["r_0"], motion["T"])
    fig = plot_frame(*args, color="von_mises", figsize=(3.0, 2.5))
    assert isinstance(fig, Figure) and len(fig.axes) == 2  # the 3D axes and the colour bar
    assert fig.axes[1].get_ylabel() == "von Mises stress [Pa]"
    anim = animate(*args, frames=[0, 5], figsize=(3.0, 2.5))
    assert isinstance(anim, FuncAnimation)
    html = anim.to_jshtml()  # renders both frames (and keeps matplotlib from warning about an unused animation)
    assert html.count("data:image/png;base64") == 2


def test_faces_are_written_as_surface_cells_and_drawn(data, motion, tmp_path):
    """Faces (here two triangles over beam nodes) become VTK_TRIANGLE cells (type 5) after the lines, with their
    connectivity; the still draws them as polygons (a Poly3DCollection on the axes)."""
    from dataclasses import replace

    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    faces = np.array([[0, 1, 2], [2, 3, 4]])
    body = replace(data, faces=faces)
    path = write_vtk_series(tmp_path / "f.pvd", body, motion["t"][:2], motion["q"][:2], motion["r_0"][:2],
                            motion["T"][:2])
    frame = read_vtu(path.parent / ET.parse(path).getroot().find("Collection/DataSet").get("file"))
    np.testing.assert_array_equal(frame["cell_types"], [3] * N_EL + [5, 5])
    np.testing.assert_array_equal(frame["cell_connectivity"][2 * N_EL:], faces.ravel())
    fig = plot_frame(body, motion["t"], motion["q"], motion["r_0"], motion["T"], figsize=(3.0, 2.5))
    assert sum(isinstance(c, Poly3DCollection) for c in fig.axes[0].collections) == 1


def test_model_vtk_series_draws_flexible_meshes_and_rigid_sticks(tmp_path):
    """A flexible arm (16 elements, 4 modes) on a hinge with a rigid offset arm: write_model_vtk writes one frame
    per output instant whose points, read back by the independent reader, are the arm's deformed_positions
    (recovered by the mode-acceleration method, as every output of a body and its result: 4e-7 m from plain
    superposition at the start, where q = 0 and the arm sags under its weight) followed by the stick figure's frame
    origins from the result (1e-15 m), with part ids 0 / 1, the arm's line cells and one line per stick segment, and
    the arm's recovered elastic displacement magnitude as point data."""
    import flexlib as fl
    from flexlib.components.mechanics.flexible import FlexibleBody
    from flexlib.components.mechanics.multibody import FixedTranslation, Revolute, World
    from flexlib.fe import write_model_vtk

    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 16, rectangle(0.02, 0.01), E=2.1e11, rho=7850.0)
    arm_data = modal_data_from_fe(fe, [16], 4, reference_node=0)

    class FlexibleArm(fl.Model):
        def __init__(self):
            super().__init__()
            self.world = World()
            self.hinge = Revolute(n=[0, 0, 1], init={"phi": 0.0, "w": 0.0})
            self.arm = FlexibleBody(arm_data, modes=4)
            self.lever = FixedTranslation(r=[0.0, 0.3, 0.0])
            self.connect(self.world.frame_b, self.hinge.frame_a)
            self.connect(self.hinge.frame_b, self.arm.frame_a, self.lever.frame_a)

    model = FlexibleArm()
    res = fl.Simulation(model, use_cache=False).run(0.2, dt_out=0.05, progress=False)
    path = write_model_vtk(tmp_path / "arm.pvd", model, res, lines={"lever": ["hinge.frame_b", "lever.frame_b"]})
    sets = ET.parse(path).getroot().findall("Collection/DataSet")
    assert len(sets) == len(res.t)
    P = deformed_positions(model.arm, res)  # recovered (mode acceleration), as the series draws it
    U = node_displacements(model.arm, res)
    _t, q, r_0, T = model.arm.motion(res)
    assert np.abs(P - deformed_positions(model.arm.modal_data, q, r_0, T)).max() > 1e-7  # not plain superposition
    for k in (0, len(sets) - 1):
        frame = read_vtu(path.parent / sets[k].get("file"))
        sticks = np.vstack([res["hinge.frame_b.r_0"][k], res["lever.frame_b.r_0"][k]])
        np.testing.assert_allclose(frame["points"], np.vstack([P[k], sticks]), rtol=0, atol=1e-15)
        np.testing.assert_array_equal(frame["point_part"], [0] * 17 + [1, 1])
        assert frame["cell_types"].size == 16 + 1
        np.testing.assert_allclose(frame["point_displacement_magnitude"][:17], np.linalg.norm(U[k], axis=-1),
                                   rtol=0, atol=1e-15)
    with pytest.raises(Exception, match="line 'bad'"):
        write_model_vtk(tmp_path / "bad.pvd", model, res, lines={"bad": ["hinge.frame_b", "nowhere.frame_b"]})
