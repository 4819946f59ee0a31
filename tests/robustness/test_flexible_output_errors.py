"""Bad input to the flexible-body output functions: each a clear error naming the argument (or the data's title
and dataset, or the file), raised before anything is written; a failed write leaves no half series behind."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from flexlib import FlexlibError, ModalFileError, ResultFileError, RunArgumentError
from flexlib.fe import (
    ModalData,
    animate,
    beam_mesh,
    deformed_positions,
    modal_data_from_fe,
    nodal_stress,
    node_displacements,
    node_rotations,
    plot_frame,
    rectangle,
    von_mises,
    write_vtk_series,
)


@pytest.fixture(scope="module")
def data() -> ModalData:
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 4, rectangle(0.02, 0.01), E=2e11, rho=8000.0)
    return modal_data_from_fe(fe, [0, 4], 1, title="err beam", stress_fibre=(0.01, 0.005))


@pytest.fixture(scope="module")
def plain(data) -> ModalData:
    return replace(data, title="no-stress beam", stress_modes=None)


@pytest.fixture(scope="module")
def good(data) -> dict:
    t = np.linspace(0.0, 0.5, 4)
    c, s = np.cos(t), np.sin(t)
    T = np.zeros((4, 3, 3))
    T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1], T[:, 2, 2] = c, s, -s, c, 1.0
    return {"times": t, "q": 1e-3 * np.ones((4, data.n_modes)), "r_0": np.zeros((4, 3)), "T": T}


def with_(good: dict, **change) -> tuple:
    g = good | change
    return g["times"], g["q"], g["r_0"], g["T"]


def bad_cases(M: int) -> dict:
    """name -> (changes to the good series, error class, words the message must contain)."""
    not_orthogonal = np.tile(np.diag([1.0, 1.0, 2.0]), (4, 1, 1))
    return {
        "q columns != modes": ({"q": np.zeros((4, M + 1))}, RunArgumentError, ["'q'", f"{M} modes"]),
        "q 3-D": ({"q": np.zeros((4, M, 1))}, RunArgumentError, ["'q'", "shape"]),
        "q NaN": ({"q": np.full((4, M), np.nan)}, RunArgumentError, ["'q'", "non-finite"]),
        "q text": ({"q": [["a"] * M] * 4}, RunArgumentError, ["'q'", "real numbers"]),
        "T 2x2": ({"T": np.tile(np.eye(2), (4, 1, 1))}, RunArgumentError, ["'T'", "(4, 3, 3)"]),
        "T 3x3 but wrong count": ({"T": np.tile(np.eye(3), (3, 1, 1))}, RunArgumentError, ["'T'", "shape"]),
        "T not orthogonal": ({"T": not_orthogonal}, RunArgumentError, ["'T'", "orthogonal", "index 0"]),
        "r_0 wrong shape": ({"r_0": np.zeros((4, 2))}, RunArgumentError, ["'r_0'", "(4, 3)"]),
        "r_0 inf": ({"r_0": np.full(3, np.inf)}, RunArgumentError, ["'r_0'", "non-finite"]),
        "times length": ({"times": np.arange(3.0)}, RunArgumentError, ["'times'", "(4,)"]),
        "times decreasing": ({"times": np.array([0.0, 0.2, 0.1, 0.3])}, RunArgumentError,
                             ["'times'", "decreases at index 2"]),
    }


def test_node_quantities_name_the_argument(data):
    M = data.n_modes
    with pytest.raises(RunArgumentError, match=rf"node_displacements: argument 'q' has shape \(2, {M + 2}\).*"
                                               rf"'err beam' has {M} modes"):
        node_displacements(data, np.zeros((2, M + 2)))
    with pytest.raises(RunArgumentError, match=r"node_rotations: argument 'nodes': modal data 'err beam' has no "
                                               r"node with id \[99\]"):
        node_rotations(data, np.zeros(M), nodes=[1, 99])
    with pytest.raises(RunArgumentError, match=r"argument 'nodes' must be node ids"):
        node_displacements(data, np.zeros(M), nodes=[1.5])
    with pytest.raises(RunArgumentError, match=r"argument 'data' must be a ModalData, got str"):
        node_displacements("beam.h5", np.zeros(M))
    with pytest.raises(RunArgumentError, match=r"deformed_positions: argument 'T' has shape \(2, 2\)"):
        deformed_positions(data, np.zeros(M), np.zeros(3), np.eye(2))
    with pytest.raises(RunArgumentError, match=r"deformed_positions: argument 'nodes'.*id \[-1\]"):
        deformed_positions(data, np.zeros(M), np.zeros(3), np.eye(3), nodes=[-1])
    with pytest.raises(RunArgumentError, match=r"argument 'scale' has a non-finite value"):
        deformed_positions(data, np.zeros(M), np.zeros(3), np.eye(3), scale=math.nan)
    with pytest.raises(RunArgumentError, match=r"argument 'scale' must be a number"):
        deformed_positions(data, np.zeros(M), np.zeros(3), np.eye(3), scale=[1.0, 2.0])
    with pytest.raises(RunArgumentError, match=r"write_vtk_series: argument 'q' has no samples"):
        write_vtk_series("never.pvd", data, [], np.zeros((0, M)), np.zeros(3), np.eye(3))


@pytest.mark.parametrize("case", list(bad_cases(7)))
def test_bad_series_named_by_every_writer(data, good, tmp_path, case):
    """The same bad input gives the same clear error from deformed_positions, write_vtk_series, plot_frame and
    animate, and nothing is written."""
    change, cls, words = bad_cases(data.n_modes)[case]
    times, q, r_0, T = with_(good, **change)
    calls = [lambda: write_vtk_series(tmp_path / "s.pvd", data, times, q, r_0, T),
             lambda: plot_frame(data, times, q, r_0, T, path=tmp_path / "s.png"),
             lambda: animate(data, times, q, r_0, T, path=tmp_path / "s.gif")]
    if "times" not in change:
        calls.append(lambda: deformed_positions(data, q, r_0, T))
    for call in calls:
        with pytest.raises(cls) as info:
            call()
        assert isinstance(info.value, FlexlibError)
        for w in words:
            assert w in str(info.value), (case, str(info.value))
    assert list(tmp_path.iterdir()) == []


def test_stress_requested_without_stress_modes_names_the_data_and_dataset(plain, good, tmp_path):
    args = with_(good, q=np.zeros((4, plain.n_modes)))
    pattern = r"modal data 'no-stress beam' has no stress modes \(dataset '/modes/stress'\).*stress_fibre"
    with pytest.raises(ModalFileError, match="nodal_stress: " + pattern):
        nodal_stress(plain, np.zeros(plain.n_modes))
    with pytest.raises(ModalFileError, match="write_vtk_series: " + pattern):
        write_vtk_series(tmp_path / "s.pvd", plain, *args, fields=("displacement", "von_mises"))
    with pytest.raises(ModalFileError, match="animate: " + pattern):
        animate(plain, *args, path=tmp_path / "s.gif", color="von_mises")
    with pytest.raises(ModalFileError, match="plot_frame: " + pattern):
        plot_frame(plain, *args, color="von_mises")
    assert list(tmp_path.iterdir()) == []


def test_unknown_options_are_named(data, good, tmp_path):
    args = with_(good)
    with pytest.raises(RunArgumentError, match=r"write_vtk_series: unknown field 'strain'"):
        write_vtk_series(tmp_path / "s.pvd", data, *args, fields=("strain",))
    with pytest.raises(RunArgumentError, match=r"argument 'path' .*s\.vtk.* must end in '\.pvd'"):
        write_vtk_series(tmp_path / "s.vtk", data, *args)
    with pytest.raises(RunArgumentError, match=r"animate: argument 'color' must be one of"):
        animate(data, *args, color="temperature")
    with pytest.raises(RunArgumentError, match=r"animate: argument 'path' .*\.avi.* must end in one of"):
        animate(data, *args, path=tmp_path / "s.avi")
    with pytest.raises(RunArgumentError, match=r"animate: argument 'frames' must be sample indices in 0\.\.3"):
        animate(data, *args, frames=[0, 9])
    with pytest.raises(RunArgumentError, match=r"animate: argument 'frames' must be at least 1"):
        animate(data, *args, frames=0)
    with pytest.raises(RunArgumentError, match=r"animate: argument 'fps' must be a positive number"):
        animate(data, *args, fps=0.0)
    with pytest.raises(RunArgumentError, match=r"plot_frame: argument 'index' must be one sample index in -4\.\.3"):
        plot_frame(data, *args, index=4)
    with pytest.raises(RunArgumentError, match=r"von_mises: argument 'stress' has shape \(3, 5\), expected"):
        von_mises(np.zeros((3, 5)))
    with pytest.raises(RunArgumentError, match=r"has cells of 5 nodes: pass element_type"):
        write_vtk_series(tmp_path / "s.pvd", replace(data, elements=np.zeros((1, 5), dtype=int), section_forces=None,
                                                      static_section_forces=None),
                         *args)
    assert list(tmp_path.iterdir()) == []


def test_unwritable_paths_name_the_file(data, good, tmp_path):
    """A parent that is a file, not a directory: ResultFileError naming the path; nothing left behind."""
    blocker = tmp_path / "file"
    blocker.write_text("x")
    args = with_(good)
    for call, name in ((lambda p: write_vtk_series(p, data, *args), "out.pvd"),
                       (lambda p: animate(data, *args, path=p), "out.gif"),
                       (lambda p: plot_frame(data, *args, path=p), "out.png")):
        with pytest.raises(ResultFileError, match=str(blocker / name).replace(".", r"\.")) as info:
            call(blocker / name)
        assert isinstance(info.value, OSError)
    assert [p.name for p in tmp_path.iterdir()] == ["file"]


def test_mp4_without_ffmpeg_is_a_clear_error(data, good, tmp_path, monkeypatch):
    from matplotlib import animation

    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    with pytest.raises(ResultFileError, match=r"out\.mp4.*ffmpeg is not installed; write a \.gif"):
        animate(data, *with_(good), path=tmp_path / "out.mp4")
    assert list(tmp_path.iterdir()) == []


def test_interrupted_series_write_keeps_the_previous_series(data, good, tmp_path, monkeypatch):
    """A write that fails after two frames (disk full) leaves the earlier complete series and its collection
    file untouched, and no temporary files."""
    import meshio

    path = write_vtk_series(tmp_path / "s.pvd", data, *with_(good))
    before = {p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    real_write, count = meshio.write, [0]

    def failing(filename, mesh, **kw):
        count[0] += 1
        if count[0] == 3:
            raise OSError(28, "No space left on device")
        return real_write(filename, mesh, **kw)

    monkeypatch.setattr(meshio, "write", failing)
    q2 = 2e-3 * np.ones((4, data.n_modes))
    with pytest.raises(ResultFileError, match=r"cannot write the VTK series '.*s\.pvd'.*No space left"):
        write_vtk_series(path, data, *with_(good, q=q2))
    after = {p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert after == before
    files = [d.get("file") for d in ET.parse(path).getroot().iter("DataSet")]
    assert all((tmp_path / f).is_file() for f in files) and len(files) == 4


def test_failed_collection_rename_restores_the_previous_frames(data, good, tmp_path, monkeypatch):
    """If the last step (renaming the collection file into place) fails, the previous frame directory is put
    back, so the old collection still points at its own complete series."""
    import os

    path = write_vtk_series(tmp_path / "s.pvd", data, *with_(good))
    before = {p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    real_replace = os.replace

    def failing(src, dst):
        if Path(dst) == path:
            raise OSError(5, "Input/output error")
        return real_replace(src, dst)

    monkeypatch.setattr(os, "replace", failing)
    with pytest.raises(ResultFileError, match=r"s\.pvd.*Input/output error"):
        write_vtk_series(path, data, *with_(good, q=2e-3 * np.ones((4, data.n_modes))))
    after = {p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert after == before
