"""Drawing a flexible body with matplotlib: stills and animations of the deformed mesh coloured by displacement or
von Mises stress (the "nephogram" of commercial codes). VTK output for ParaView is :mod:`.vtk_series`.

The fields come from :mod:`.output` (a body's :class:`~flexlib.fe.ModalData` and the
time series of its motion, ``q(t)``, ``r_0(t)``, ``T(t)``; ``FlexibleBody.motion(result)`` gives them).
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np

from flexlib.errors import ResultFileError, RunArgumentError

from .modal_data import ModalData
from .output import field_values, motion_series
from .vtk_series import output_path

__all__ = ["animate", "plot_frame"]


# ---------------------------------------------------------------------------------------------- matplotlib
_LABELS = {"displacement": "elastic displacement |u| [m]", "von_mises": "von Mises stress [Pa]"}
_MAX_PIXELS = 2**23  # matplotlib's Agg limit on an image's width and height [pixels]


def _colour_values(s: dict[str, Any], color: str, func: str) -> np.ndarray:
    if not isinstance(color, str) or color not in _LABELS:
        raise RunArgumentError(f"{func}: argument 'color' must be one of {list(_LABELS)}, got {color!r}")
    v = field_values(s, color, func)
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
    p = output_path(func, path)
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
               title: str | None = None, loads: Any = None) -> Any:
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
    loads : array_like (nt, C), optional
        Load-case amplitudes (``body.load_amplitudes(result)``): recovered as :func:`~flexlib.fe.node_displacements`;
        default plain modal superposition.

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
    s = motion_series(func, data, times, q, r_0, T, scale, loads)
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
            figsize: tuple[float, float] = (6.4, 5.2), dpi: int = 80, title: str | None = None,
            loads: Any = None) -> Any:
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
        Number of frames spread evenly over the samples, or sample indices; default every sample, at most 200.
    fps : float
        Frames per second of the written file [1/s].
    cmap, figsize, dpi : str, (float, float), int
        matplotlib colour map, figure size [inch], resolution [dots per inch].
    title : str, optional
        Title before the time (default the data's title).
    loads : array_like (nt, C), optional
        Load-case amplitudes (``body.load_amplitudes(result)``): recovered as :func:`~flexlib.fe.node_displacements`;
        default plain modal superposition.

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
    s = motion_series(func, data, times, q, r_0, T, scale, loads)
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


