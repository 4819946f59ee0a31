"""Drawing a flexible body: the deformed mesh over time as a VTK series for ParaView, and matplotlib stills and
animations coloured by displacement or von Mises stress (the "nephogram" of commercial codes).

The fields come from :mod:`.output` (a body's :class:`~flexlib.fe.ModalData` and the
time series of its motion, ``q(t)``, ``r_0(t)``, ``T(t)``; ``FlexibleBody.motion(result)`` gives them).

References
----------
- Kitware, *VTK File Formats* (XML ``UnstructuredGrid`` ``.vtu`` and the ``.pvd`` collection); ParaView's
  ``.series`` file format (JSON ``{"file-series-version": "1.0", "files": [{"name", "time"}]}``).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
import uuid
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np

from flexlib.errors import ResultFileError, RunArgumentError

from .modal_data import ModalData
from .output import FIELDS, _field_values, _name, _scale, _series

__all__ = ["animate", "plot_frame", "write_model_vtk", "write_series", "write_vtk_series"]

_ELEMENT_CELLS = {2: "line", 3: "line3", 4: "tetra", 8: "hexahedron", 10: "tetra10", 20: "hexahedron20"}
_FACE_CELLS = {3: "triangle", 4: "quad", 6: "triangle6", 8: "quad8"}


def _cell_type(func: str, arg: str, value: Any) -> None:
    """``element_type`` / ``face_type``: None or the name of a meshio cell type."""
    try:
        from meshio._mesh import topological_dimension as known
    except ImportError:  # another meshio layout: its writer names an unknown type
        known = None
    if value is not None and (not isinstance(value, str) or (known is not None and value not in known)):
        raise RunArgumentError(f"{func}: argument {arg!r} must be a meshio cell type (e.g. 'line', 'triangle', "
                               f"'quad', 'tetra', 'hexahedron'), got {value!r}")


def _path(func: str, path: Any) -> Path:
    """An output path: a str or os.PathLike."""
    if not isinstance(path, str | os.PathLike):
        raise RunArgumentError(f"{func}: argument 'path' must be a file path (str or os.PathLike), got "
                               f"{type(path).__name__} {path!r:.60}")
    return Path(path)


def _cells(data: ModalData, element_type: str | None, face_type: str | None, func: str) -> list[tuple[str, np.ndarray]]:
    _cell_type(func, "element_type", element_type)
    _cell_type(func, "face_type", face_type)
    cells: list[tuple[str, np.ndarray]] = []
    for arg, conn, given, table in (("element_type", data.elements, element_type, _ELEMENT_CELLS),
                                    ("face_type", data.faces, face_type, _FACE_CELLS)):
        if conn is None or conn.shape[0] == 0:
            continue
        kind = given or table.get(conn.shape[1])
        if kind is None:
            raise RunArgumentError(f"{func}: {_name(data)} has cells of {conn.shape[1]} nodes: pass {arg} "
                                   f"(a meshio cell type) to say what they are")
        cells.append((kind, np.asarray(conn, dtype=np.int64)))
    if not cells:  # no connectivity: draw the nodes
        cells.append(("vertex", np.arange(data.n_nodes, dtype=np.int64)[:, None]))
    return cells


def _collection_kind(path: Path, func: str = "write_vtk_series") -> str:
    if path.suffix == ".pvd":
        return "pvd"
    if path.name.endswith(".vtu.series"):
        return "series"
    raise RunArgumentError(f"{func}: argument 'path' {str(path)!r} must end in '.pvd' (ParaView data "
                           "collection, XML) or '.vtu.series' (ParaView file series, JSON)")


def write_vtk_series(path: str | os.PathLike[str], data: ModalData, times: Any, q: Any, r_0: Any, T: Any, *,
                     fields: Sequence[str] | None = None, scale: float = 1.0, element_type: str | None = None,
                     face_type: str | None = None) -> Path:
    """Write the deformed body over time as VTK unstructured grids (one ``.vtu`` per instant, meshio) and a
    ParaView collection file giving each file's time.

    The frames go to a directory ``<collection name>.d/`` beside the collection file, referenced by relative
    names. Writing is atomic: everything is written under temporary names in the target directory, then the
    frame directory and finally the collection file are renamed into place, so an interrupted or failed write
    never leaves a collection that refers to a half-written series (a previous series at the same path stays
    intact until the new one is complete).

    Parameters
    ----------
    path : str or PathLike
        Collection file: ``*.pvd`` (VTK data collection, XML) or ``*.vtu.series`` (ParaView JSON series).
    data : ModalData
        The body's modal data; cells from ``elements`` (lines for beams) and ``faces`` if present.
    times : array_like (nt,)
        Time of each instant [s], non-decreasing.
    q : array_like (nt, M)
        Modal coordinates [1].
    r_0 : array_like (nt, 3) or (3,)
        Origin of the floating frame, world axes [m].
    T : array_like (nt, 3, 3) or (3, 3)
        Orientation of the floating frame, world to body.
    fields : sequence of str, optional
        Point data to write, from ``"displacement"`` (elastic displacement vector in world axes [m] and its
        magnitude ``displacement_magnitude``), ``"rotation"`` (elastic rotation vector in world axes [rad]),
        ``"von_mises"`` [Pa] and ``"stress"`` (``sxx..szx`` in body axes [Pa]); default ``displacement`` and,
        if the data has stress modes, ``von_mises``. ``node_id`` is always written.
    scale : float
        Magnification of the elastic displacement in the written point positions (fields stay true).
    element_type, face_type : str, optional
        meshio cell types of ``elements`` / ``faces`` where the node count is ambiguous (default by count:
        elements 2 ``line``, 3 ``line3``, 4 ``tetra``, 8 ``hexahedron``; faces 3 ``triangle``, 4 ``quad``).

    Returns
    -------
    Path
        The collection file.

    Raises
    ------
    RunArgumentError
        Bad shapes or values of ``times``, ``q``, ``r_0``, ``T``; an unknown field; a bad ``path`` suffix.
    ModalFileError
        ``von_mises`` or ``stress`` requested and the data has no stress modes.
    ResultFileError
        The files cannot be written (the message names the path); nothing is left behind.
    """
    import meshio

    func = "write_vtk_series"
    path = _path(func, path)
    _collection_kind(path)  # checks the suffix before any work
    s = _series(func, data, times, q, r_0, T, scale)
    data = s["data"]
    if fields is None:
        fields = ("displacement",) + (("von_mises",) if data.stress_modes is not None else ())
    elif isinstance(fields, str):
        fields = (fields,)
    elif not isinstance(fields, Sequence) or not all(isinstance(f, str) for f in fields):
        raise RunArgumentError(f"{func}: argument 'fields' must be a field name or a list of them, from "
                               f"{list(FIELDS)}, got {fields!r}")
    _cells(data, element_type, face_type, func)  # the cell types before any work
    point_fields: dict[str, np.ndarray] = {}
    for name in fields:
        values = _field_values(s, name, func)
        if name == "stress":
            for c, comp in enumerate(("sxx", "syy", "szz", "sxy", "syz", "szx")):
                point_fields[f"stress_{comp}"] = values[..., c]
        else:
            point_fields[name] = values
            if name == "displacement":
                point_fields["displacement_magnitude"] = np.linalg.norm(values, axis=-1)
    cells = _cells(data, element_type, face_type, func)
    node_id = np.asarray(data.node_ids, dtype=np.int64)

    def mesh(k: int) -> Any:
        point_data = {"node_id": node_id} | {f: np.ascontiguousarray(v[k]) for f, v in point_fields.items()}
        return meshio.Mesh(np.ascontiguousarray(s["points"][k]), cells, point_data=point_data)

    return write_series(path, s["t"], mesh, func)


def write_series(path: str | os.PathLike[str], times: np.ndarray, mesh: Any, func: str = "write_series") -> Path:
    """Write one meshio mesh per instant (``mesh(k)`` for ``k`` in ``range(len(times))``) as ``.vtu`` files and a
    ParaView collection (``*.pvd`` or ``*.vtu.series``), atomically (see :func:`write_vtk_series`).

    Parameters
    ----------
    path : str or PathLike
        Collection file.
    times : ndarray (nt,)
        Time of each instant [s].
    mesh : callable
        ``mesh(k) -> meshio.Mesh`` of instant ``k``.
    func : str
        Name for error messages.

    Returns
    -------
    Path
        The collection file.
    """
    import meshio

    path = _path(func, path)
    kind = _collection_kind(path, func)
    stem = path.name[: -len(".vtu.series")] if kind == "series" else path.stem
    frames_dir = path.name + ".d"
    names = [f"{frames_dir}/{stem}_{k:06d}.vtu" for k in range(len(times))]
    parent = path.parent
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".tmp", dir=parent))
    except OSError as exc:
        raise ResultFileError(f"{func}: cannot write the VTK series {str(path)!r}: {exc}") from None
    final_dir = parent / frames_dir
    old: Path | None = None
    swapped = False
    try:
        (tmp / frames_dir).mkdir()
        for k, name in enumerate(names):
            meshio.write(tmp / name, mesh(k), file_format="vtu")
        collection = tmp / path.name
        if kind == "pvd":
            _write_pvd(collection, names, times)
        else:
            collection.write_text(json.dumps({"file-series-version": "1.0", "files": [
                {"name": n, "time": float(t)} for n, t in zip(names, times)]}, indent=1))
        if final_dir.exists() or final_dir.is_symlink():  # keep the old series readable until the swap
            old = parent / f".{frames_dir}.{uuid.uuid4().hex[:8]}.old"
            os.replace(final_dir, old)
        os.replace(tmp / frames_dir, final_dir)
        swapped = True
        os.replace(collection, path)
    except OSError as exc:
        if swapped:  # the collection was not replaced: take the new frames out again
            os.replace(final_dir, tmp / frames_dir)
        if old is not None:  # and put the previous series back
            os.replace(old, final_dir)
            old = None
        raise ResultFileError(f"{func}: cannot write the VTK series {str(path)!r}: {exc}") from None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    return path


def _write_pvd(path: Path, names: Sequence[str], times: np.ndarray) -> None:
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    for name, t in zip(names, times):
        ET.SubElement(coll, "DataSet", timestep=repr(float(t)), group="", part="0", file=name)
    ET.indent(root)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)


# ---------------------------------------------------------------------------------------------- matplotlib
_LABELS = {"displacement": "elastic displacement |u| [m]", "von_mises": "von Mises stress [Pa]"}
_MAX_PIXELS = 2**23  # matplotlib's Agg limit on an image's width and height [pixels]


def _colour_values(s: dict[str, Any], color: str, func: str) -> np.ndarray:
    if not isinstance(color, str) or color not in _LABELS:
        raise RunArgumentError(f"{func}: argument 'color' must be one of {list(_LABELS)}, got {color!r}")
    v = _field_values(s, color, func)
    return np.linalg.norm(v, axis=-1) if color == "displacement" else v


def _figure_options(func: str, cmap: Any, figsize: Any, dpi: Any) -> None:
    """``cmap`` a matplotlib colour map name, ``figsize`` two positive sizes [inch], ``dpi`` a positive number."""
    import matplotlib

    if not isinstance(cmap, str) or cmap not in matplotlib.colormaps:
        raise RunArgumentError(f"{func}: argument 'cmap' must be the name of a matplotlib colour map (e.g. 'jet', "
                               f"'viridis'), got {cmap!r}")
    size = np.asarray(figsize, dtype=object).ravel().tolist() if not isinstance(figsize, str) else [figsize]
    if (len(size) != 2 or not all(isinstance(v, int | float | np.integer | np.floating) and not isinstance(v, bool)
                                  and math.isfinite(v) and v > 0 for v in size)):
        raise RunArgumentError(f"{func}: argument 'figsize' must be (width, height), two positive numbers [inch], got "
                               f"{figsize!r}")
    if isinstance(dpi, bool) or not isinstance(dpi, int | float | np.integer | np.floating) or not (
            math.isfinite(dpi) and dpi > 0):
        raise RunArgumentError(f"{func}: argument 'dpi' must be a positive number [dots per inch], got {dpi!r}")
    if max(size) * dpi >= _MAX_PIXELS:
        raise RunArgumentError(f"{func}: figsize {tuple(size)!r} [inch] at dpi={dpi!r} makes an image of "
                               f"{max(size) * dpi:.3g} pixels across; matplotlib draws fewer than {_MAX_PIXELS} "
                               "(2^23): give a smaller figsize or dpi")


def _frame_indices(nt: int, frames: int | Sequence[int] | None, func: str) -> np.ndarray:
    if frames is None:
        frames = min(nt, 200)
    if isinstance(frames, bool | np.bool_):
        raise RunArgumentError(f"{func}: argument 'frames' must be a number of frames (int >= 1) or sample indices, "
                               f"got {frames!r}")
    if isinstance(frames, int | np.integer):
        if frames < 1:
            raise RunArgumentError(f"{func}: argument 'frames' must be at least 1, got {frames}")
        return np.unique(np.round(np.linspace(0, nt - 1, min(int(frames), nt))).astype(np.int64))
    idx = np.asarray(frames).ravel()
    if idx.size == 0 or not np.issubdtype(idx.dtype, np.integer) or idx.min() < -nt or idx.max() >= nt:
        raise RunArgumentError(f"{func}: argument 'frames' must be sample indices in 0..{nt - 1}, got "
                               f"{idx[:5].tolist()}")
    return idx % nt


class _Scene:
    """A 3D axes with the deformed body (lines of the elements, polygons of the faces, the nodes) coloured by
    a nodal field with a fixed colour scale and fixed axis limits over all frames."""

    def __init__(self, s: dict[str, Any], values: np.ndarray, frames: np.ndarray, label: str, cmap: str,
                 figsize: tuple[float, float], title: str | None) -> None:
        from matplotlib import cm, colors
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.s, self.values, self.title = s, values, title
        self.data: ModalData = s["data"]
        self.fig = Figure(figsize=figsize, layout="constrained")
        FigureCanvasAgg(self.fig)
        self.ax = self.fig.add_subplot(projection="3d")
        pts = s["points"][frames]
        lo, hi = pts.reshape(-1, 3).min(axis=0), pts.reshape(-1, 3).max(axis=0)
        centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-9) * 1.05
        for set_lim, c in zip((self.ax.set_xlim, self.ax.set_ylim, self.ax.set_zlim), centre):
            set_lim(c - half, c + half)
        self.ax.set_box_aspect((1, 1, 1))
        self.ax.set_xlabel("x [m]")
        self.ax.set_ylabel("y [m]")
        self.ax.set_zlabel("z [m]")
        vmin, vmax = float(values[frames].min()), float(values[frames].max())
        self.norm = colors.Normalize(vmin, vmax if vmax > vmin else vmin + max(abs(vmin), 1.0) * 1e-12)
        self.mappable = cm.ScalarMappable(norm=self.norm, cmap=cmap)
        self.fig.colorbar(self.mappable, ax=self.ax, shrink=0.7, label=label)
        self.artists: list[Any] = []
        self.draw(int(frames[0]))
        self.fig.canvas.draw()  # lay out once (constrained), then keep the axes still from frame to frame
        self.fig.set_layout_engine("none")

    def draw(self, k: int) -> list[Any]:
        from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

        for a in self.artists:
            a.remove()
        P, v = self.s["points"][k], self.values[k]
        rgba = self.mappable.to_rgba
        arts: list[Any] = []
        el = self.data.elements
        if el.shape[0]:
            ring = np.concatenate([el, el[:, :1]], axis=1) if el.shape[1] > 2 else el
            seg_nodes = np.stack([ring[:, :-1], ring[:, 1:]], axis=-1).reshape(-1, 2)
            segs = P[seg_nodes]
            arts.append(self.ax.add_collection3d(Line3DCollection(segs, colors=rgba(v[seg_nodes].mean(axis=1)),
                                                                  linewidths=2.5)))
        if self.data.faces is not None and self.data.faces.shape[0]:
            f = self.data.faces
            arts.append(self.ax.add_collection3d(Poly3DCollection(P[f], facecolors=rgba(v[f].mean(axis=1)),
                                                                  edgecolors=(0, 0, 0, 0.3), linewidths=0.3)))
        arts.append(self.ax.scatter(P[:, 0], P[:, 1], P[:, 2], c=rgba(v), s=8, depthshade=False))
        t = float(self.s["t"][k])
        head = self.title if self.title is not None else (self.data.title or "flexible body")
        self.ax.set_title(f"{head}   t = {t:.4g} s")
        self.artists = [a for a in arts if a is not None]
        return self.artists


def _check_output_path(path: str | os.PathLike[str], func: str, suffixes: Sequence[str]) -> Path:
    p = _path(func, path)
    if p.suffix.lower() not in suffixes:
        raise RunArgumentError(f"{func}: argument 'path' {str(p)!r} must end in one of {list(suffixes)}")
    if not p.parent.is_dir():
        raise ResultFileError(f"{func}: cannot write {str(p)!r}: directory {str(p.parent)!r} does not exist")
    return p


def _save_atomic(path: Path, func: str, save: Any) -> Path:
    """Call ``save(tmp_path)`` and rename into place; ResultFileError naming ``path`` on failure."""
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
        os.close(fd)
    except OSError as exc:
        raise ResultFileError(f"{func}: cannot write {str(path)!r}: {exc}") from None
    try:
        save(tmp)
        os.replace(tmp, path)
    except OSError as exc:
        raise ResultFileError(f"{func}: cannot write {str(path)!r}: {exc}") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


def plot_frame(data: ModalData, times: Any, q: Any, r_0: Any, T: Any, *, index: int = -1,
               path: str | os.PathLike[str] | None = None,
               color: Literal["displacement", "von_mises"] = "displacement", scale: float = 1.0,
               cmap: str = "jet", figsize: tuple[float, float] = (6.4, 5.2), dpi: int = 100,
               title: str | None = None) -> Any:
    """Draw the deformed body at one instant (matplotlib, Agg), coloured by a nodal field with a colour bar.

    Parameters
    ----------
    data : ModalData
        The body's modal data.
    times : array_like (nt,) or float
        Times [s]; a scalar with ``q`` of shape (M,) for a single instant.
    q : array_like (nt, M) or (M,)
        Modal coordinates [1].
    r_0 : array_like (nt, 3) or (3,)
        Floating-frame origin, world axes [m].
    T : array_like (nt, 3, 3) or (3, 3)
        Floating-frame orientation, world to body.
    index : int
        Which sample to draw (default the last).
    path : str or PathLike, optional
        Image file (``.png``, ``.pdf``, ``.svg``), written atomically; default: return the Figure.
    color : {"displacement", "von_mises"}
        Colour by elastic displacement magnitude [m] or von Mises stress [Pa] (needs stress modes).
    scale : float
        Magnification of the elastic displacement in the drawing (colours stay true).
    cmap : str
        matplotlib colour map.
    figsize : (float, float)
        Figure size [inch].
    dpi : int
        Resolution of a written raster image [dots per inch].
    title : str, optional
        Title before the time (default the data's title).

    Returns
    -------
    matplotlib.figure.Figure or Path
        The Figure, or the written file.

    Raises
    ------
    RunArgumentError
        Bad shapes or values (naming the argument), an index out of range, an unknown ``color``.
    ModalFileError
        ``color="von_mises"`` and the data has no stress modes.
    ResultFileError
        The image cannot be written (names the path).
    """
    func = "plot_frame"
    s = _series(func, data, times, q, r_0, T, scale)
    nt = s["t"].shape[0]
    _figure_options(func, cmap, figsize, dpi)
    if isinstance(index, bool | np.bool_) or not isinstance(index, int | np.integer) or not -nt <= index < nt:
        raise RunArgumentError(f"{func}: argument 'index' must be one sample index in {-nt}..{nt - 1}, got "
                               f"{index!r}")
    k = np.array([int(index) % nt])
    values = _colour_values(s, color, func)
    out = _check_output_path(path, func, (".png", ".pdf", ".svg")) if path is not None else None
    scene = _Scene(s, values, k, _LABELS[color], cmap, figsize, title)
    scene.draw(int(k[0]))
    if out is None:
        return scene.fig
    return _save_atomic(out, func, lambda tmp: scene.fig.savefig(tmp, dpi=dpi))


def animate(data: ModalData, times: Any, q: Any, r_0: Any, T: Any, *, path: str | os.PathLike[str] | None = None,
            color: Literal["displacement", "von_mises"] = "displacement", scale: float = 1.0,
            frames: int | Sequence[int] | None = None, fps: float = 20.0, cmap: str = "jet",
            figsize: tuple[float, float] = (6.4, 5.2), dpi: int = 80, title: str | None = None) -> Any:
    """Animate the deformed body over time (matplotlib, Agg): a colour-contour ("nephogram") animation of the
    elastic displacement or the von Mises stress, with a fixed colour scale and fixed axes.

    Parameters
    ----------
    data : ModalData
        The body's modal data.
    times : array_like (nt,)
        Times [s], non-decreasing.
    q : array_like (nt, M)
        Modal coordinates [1].
    r_0 : array_like (nt, 3) or (3,)
        Floating-frame origin, world axes [m].
    T : array_like (nt, 3, 3) or (3, 3)
        Floating-frame orientation, world to body.
    path : str or PathLike, optional
        ``.gif`` (Pillow writer, always available) or ``.mp4`` (needs ffmpeg), written atomically; default:
        return the ``FuncAnimation`` (its figure is ``anim._fig``; e.g. ``anim.to_jshtml()`` in a notebook).
    color : {"displacement", "von_mises"}
        Field shown by colour: elastic displacement magnitude [m] or von Mises stress [Pa].
    scale : float
        Magnification of the elastic displacement in the drawing.
    frames : int or sequence of int, optional
        Number of frames evenly spread over the samples, or the sample indices; default every sample, at most
        200.
    fps : float
        Frames per second of the written file [1/s].
    cmap : str
        matplotlib colour map.
    figsize : (float, float)
        Figure size [inch].
    dpi : int
        Resolution [dots per inch].
    title : str, optional
        Title before the time (default the data's title).

    Returns
    -------
    Path or matplotlib.animation.FuncAnimation
        The written file, or the animation when ``path`` is None.

    Raises
    ------
    RunArgumentError
        Bad shapes or values, an unknown ``color``, bad ``frames``, a path suffix other than .gif/.mp4.
    ModalFileError
        ``color="von_mises"`` and the data has no stress modes.
    ResultFileError
        The file cannot be written (names the path), or an ``.mp4`` is asked for and ffmpeg is not installed.
    """
    from matplotlib import animation

    func = "animate"
    s = _series(func, data, times, q, r_0, T, scale)
    idx = _frame_indices(s["t"].shape[0], frames, func)
    values = _colour_values(s, color, func)
    _figure_options(func, cmap, figsize, dpi)
    if isinstance(fps, bool) or not (isinstance(fps, int | float) and math.isfinite(fps) and fps > 0):
        raise RunArgumentError(f"{func}: argument 'fps' must be a positive number, got {fps!r}")
    out = _check_output_path(path, func, (".gif", ".mp4")) if path is not None else None
    if out is not None and out.suffix.lower() == ".mp4" and not animation.writers.is_available("ffmpeg"):
        raise ResultFileError(f"{func}: cannot write {str(out)!r}: ffmpeg is not installed; write a .gif instead")
    scene = _Scene(s, values, idx, _LABELS[color], cmap, figsize, title)
    if out is None:
        return animation.FuncAnimation(scene.fig, lambda k: scene.draw(int(k)), frames=idx.tolist(),
                                       interval=1000.0 / fps, blit=False, repeat=True)
    writer = (animation.PillowWriter(fps=fps) if out.suffix.lower() == ".gif"
              else animation.FFMpegWriter(fps=fps))

    def save(tmp: str) -> None:  # one draw per frame (FuncAnimation.save draws each frame twice)
        with writer.saving(scene.fig, tmp, dpi):
            for k in idx:
                scene.draw(int(k))
                writer.grab_frame()

    return _save_atomic(out, func, save)


def write_model_vtk(path: str | os.PathLike[str], model: Any, result: Any, *,
                    lines: dict[str, Sequence[str]] | None = None, scale: float = 1.0, stride: int = 1) -> Path:
    """Write a whole machine over time as one VTK series: every FlexibleBody's deformed mesh and stick figures of
    the rigid parts, for ParaView.

    Parameters
    ----------
    path : str or PathLike
        Collection file (``*.pvd`` or ``*.vtu.series``).
    model : flexlib.Model
        The model the result belongs to (its FlexibleBody components are found by walking it).
    result : Result
        The run.
    lines : mapping of str to sequence of str, optional
        Stick figures of rigid parts: a name and the frame paths (``"joint1.frame_b"``) a polyline joins through
        their origins ``r_0``.
    scale : float
        Magnification of the elastic displacements (drawing only).
    stride : int
        Write every ``stride``-th row of the result (a long run on a fine grid), the last row always.

    Returns
    -------
    Path
        The collection file. Point data: ``part`` (0, 1, … in the order: flexible bodies by path, then
        ``lines``), ``displacement_magnitude`` [m] (elastic, zero on rigid parts).

    Raises
    ------
    RunArgumentError
        No flexible body and no lines, an unknown frame path, a line of fewer than two frames, a bad suffix,
        ``scale`` not a finite number, a ``model`` or ``result`` of the wrong type, a result of another model
        (:meth:`FlexibleBody.motion`).
    ResultFileError
        The files cannot be written (nothing is left behind).
    """
    import meshio

    from flexlib.components.mechanics.flexible.body import FlexibleBody
    from flexlib.core.component import Component
    from flexlib.results.result import Result

    from .output import deformed_positions, node_displacements

    func = "write_model_vtk"
    path = _path(func, path)
    _collection_kind(path, func)
    scale = _scale(func, scale)
    if isinstance(stride, bool | np.bool_) or not isinstance(stride, int | np.integer) or stride < 1:
        raise RunArgumentError(f"{func}: stride must be a positive integer, got {stride!r}")
    if not isinstance(model, Component):
        raise RunArgumentError(f"{func}: argument 'model' must be the flexlib model the result belongs to, got "
                               f"{type(model).__name__}")
    if not isinstance(result, Result):
        raise RunArgumentError(f"{func}: argument 'result' must be a flexlib Result (of Simulation.run or "
                               f"Result.load), got {type(result).__name__}")
    for name, frames in (lines or {}).items():
        if (isinstance(frames, str) or not isinstance(frames, Sequence) or len(frames) < 2
                or not all(isinstance(f, str) for f in frames)):
            raise RunArgumentError(f"{func}: line {name!r} must be a list of at least two frame paths (e.g. "
                                   f"['joint1.frame_b', 'joint2.frame_a']), got {frames!r}")
    t_all = np.asarray(result.t, dtype=float)
    rows = np.unique(np.append(np.arange(0, t_all.size, stride), t_all.size - 1)) if t_all.size else np.zeros(0, int)
    t = t_all[rows]
    nt = t.size
    parts: list[tuple[np.ndarray, np.ndarray, list[tuple[str, np.ndarray]]]] = []  # points, |u|, cells
    bodies = sorted((c for c in model.walk() if isinstance(c, FlexibleBody)), key=lambda c: c.path)
    for body in bodies:
        _t, q, r_0, T = (np.asarray(a)[rows] for a in body.motion(result))
        data = body.modal_data
        pts = deformed_positions(data, q, r_0, T, scale=scale)
        u = np.linalg.norm(node_displacements(data, q), axis=-1) if data.n_modes else np.zeros(pts.shape[:2])
        parts.append((pts, u, _cells(data, None, None, func)))
    for name, frames in (lines or {}).items():
        try:
            pts = np.stack([np.asarray(result[f"{frame}.r_0"], dtype=float).reshape(t_all.size, 3)[rows]
                            for frame in frames], 1)
        except Exception as exc:  # ResultKeyError: say which line and frame
            raise RunArgumentError(f"{func}: line {name!r}: {exc}") from None
        n = len(frames)
        parts.append((pts, np.zeros((nt, n)), [("line", np.column_stack([np.arange(n - 1), np.arange(1, n)]))]))
    if not parts:
        raise RunArgumentError(f"{func}: nothing to draw: the model has no FlexibleBody and no lines were given")

    def mesh(k: int) -> Any:
        points, mags, ids, cells, offset = [], [], [], {}, 0
        for i, (pts, u, part_cells) in enumerate(parts):
            points.append(pts[k])
            mags.append(u[k])
            ids.append(np.full(pts.shape[1], i, dtype=np.int64))
            for kind, conn in part_cells:
                cells.setdefault(kind, []).append(conn + offset)
            offset += pts.shape[1]
        return meshio.Mesh(np.ascontiguousarray(np.vstack(points)),
                           [(kind, np.vstack(c)) for kind, c in cells.items()],
                           point_data={"part": np.concatenate(ids), "displacement_magnitude": np.concatenate(mags)})

    return write_series(path, t, mesh, func)
