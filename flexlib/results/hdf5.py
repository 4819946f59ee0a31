"""Result files (HDF5, self-describing, written atomically). Layout: docs/results.md.

Writing goes to a temporary file ``<name>.<host>.<pid>.<random>.tmp`` in the target directory, renamed over
the target at the end (``os.replace``), so a crash, a kill or Ctrl-C never leaves a half-written file under the
final name; a writer that was killed (SIGKILL) leaves its temporary file behind, and the next save of that
file on the same host removes it once the process named by the pid no longer exists (temporary files of other
hosts, e.g. on a shared file system, are left alone: their pids mean nothing here). Reading checks the file
before trusting it; every problem is a :class:`~flexlib.errors.ResultFileError` naming the path.
"""

from __future__ import annotations

import glob
import json
import os
import re
import socket
import tempfile
import warnings
import zlib
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from flexlib.errors import ResultFileError, ResultKeyError, ResultSaveWarning, RunArgumentError, SimulationInterrupted
from flexlib.results import indeterminate as mark
from flexlib.results.result import Result
from flexlib.results.stored import StoredPart, file_columns, pack_function, unique_columns

__all__ = ["FORMAT", "FORMAT_VERSION", "keep_result", "load_result", "not_a_result", "remove_orphans", "save_result"]

FORMAT = "flexlib-result"
#: Version of the layout written; files with a higher version are refused on reading. 1: every variable stored; 2:
#: the run's rows stored, the other variables derived when read (:mod:`flexlib.results.stored`).
FORMAT_VERSION = 2
#: Rows per chunk of a stored column (a column is read alone; a chunk per column up to this many rows).
_CHUNK_ROWS = 1 << 17
#: Threads compressing a file's chunks.
_WRITERS = 2
_STR = h5py.string_dtype("utf-8")

#: Datasets every result file has (``docs/results.md``).
_REQUIRED = ("time", "variables/values", "variables/names", "variables/units", "variables/docs", "variables/kinds",
             "parameters/names", "parameters/values", "parameters/units", "events/time", "events/text")
_ATTRS = ("model", "status", "message", "index_report", "solver_stats")
_STATUSES = ("success", "failed", "interrupted")


def _as_path(path: Any, what: str) -> Path:
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise RunArgumentError(f"{what}: the path must be a str or os.PathLike, got {path!r} "
                               f"({type(path).__name__})")
    if not os.fspath(path):
        raise RunArgumentError(f"{what}: the path is an empty string")
    return Path(os.fspath(path)).expanduser()


def _reason(err: BaseException) -> str:
    """The OS reason of an error, without a repeated file name."""
    if isinstance(err, OSError) and err.strerror:
        return err.strerror
    return str(err) or type(err).__name__


def _host() -> str:
    """This host's name as it appears in temporary file names (letters, digits and ``-`` only)."""
    return re.sub(r"[^A-Za-z0-9-]", "-", socket.gethostname()) or "host"


def _pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True  # exists (owned by someone else), or cannot tell: keep its file
    return True


def remove_orphans(path: str | os.PathLike) -> list[Path]:
    """Remove the temporary files of ``path`` left by writers that no longer run.

    A temporary file ``<name>.<host>.<pid>.<random>.tmp`` belongs to the process ``pid`` on ``host``; it is
    removed only when ``host`` is this host and that process does not exist any more (a killed writer).
    Files of running writers and of other hosts are kept.

    Returns
    -------
    list of Path
        The files removed.
    """
    path = Path(path)
    pattern = re.compile(re.escape(path.name) + r"\.([A-Za-z0-9-]+)\.(\d+)\.[^.]+\.tmp")
    host = _host()
    removed = []
    try:
        candidates = list(path.parent.glob(glob.escape(path.name) + ".*.tmp"))
    except OSError:
        return removed
    for cand in candidates:
        match = pattern.fullmatch(cand.name)
        if match is None or match.group(1) != host or _pid_alive(int(match.group(2))):
            continue
        try:
            cand.unlink()
            removed.append(cand)
        except OSError:
            pass  # another process removed it first, or no permission: not ours to insist on
    return removed


def save_result(result: Result, path: str | os.PathLike, outputs: str | Sequence[str] | None = None) -> None:
    """Write ``result`` to ``path``: a temporary file in the same directory, then an atomic rename.

    The file stores the run's rows (unknowns, relation values, the model's output function) and derives every other
    variable when it is read (:mod:`flexlib.results.stored`); ``outputs`` names variables to store as columns as
    well (names, array names or patterns with ``*`` and ``?``, for readers without flexlib), ``"all"`` stores every
    variable (a larger file). A result without rows of a run (built from values) stores every variable.

    Raises
    ------
    ResultFileError
        The file cannot be written (directory not creatable, permission, disk full); names the path and
        the reason. Nothing is left behind: no partial file under ``path``, no temporary file.
    RunArgumentError
        ``path`` is not a path.
    """
    path = _as_path(path, "save_result")
    if path.is_dir():
        raise ResultFileError(f"cannot write the result to {path}: it is a directory")
    if path.exists() and not path.is_file():  # the atomic replace would put a regular file in place of a device
        raise ResultFileError(f"cannot write the result to {path}: it exists and is not a regular file (a device, "
                              "pipe or socket); give the name of a file")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise ResultFileError(f"cannot write the result to {path}: cannot create its directory "
                              f"{path.parent}: {_reason(err)}") from None
    remove_orphans(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f"{path.name}.{_host()}.{os.getpid()}.",
                                   suffix=".tmp")
    except OSError as err:
        raise ResultFileError(f"cannot write the result to {path}: {_reason(err)}") from None
    os.close(fd)
    try:
        _write(result, tmp, outputs)
        os.chmod(tmp, _file_mode())  # mkstemp makes it 0600: a result file gets the mode of any file the user writes
        os.replace(tmp, path)
    except BaseException as err:
        Path(tmp).unlink(missing_ok=True)
        if isinstance(err, OSError):
            raise ResultFileError(f"cannot write the result to {path}: {_reason(err)}") from err
        raise


def _file_mode() -> int:
    """``0666`` less the process's umask (what ``open(path, "w")`` would give); read from ``/proc`` where it can be
    (setting the umask to read it changes it for every thread for a moment)."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            mask = next(int(line.split()[1], 8) for line in status if line.startswith("Umask:"))
    except (OSError, StopIteration, ValueError, IndexError):
        mask = os.umask(0)
        os.umask(mask)
    return 0o666 & ~mask


def keep_result(result: Result, path: str | os.PathLike | None,
                outputs: str | Sequence[str] | None = None) -> None:
    """Write a run's ``result`` to ``path`` (if given) without ever losing it: a failed write is a
    :class:`~flexlib.errors.ResultSaveWarning` naming the path and the reason (the warning points at the caller of
    the caller, the user's ``run``); Ctrl-C during the write leaves no file (the write is atomic) and raises
    :class:`~flexlib.errors.SimulationInterrupted` carrying the result. ``outputs`` as :func:`save_result`."""
    if path is None:
        return
    outputs = keep_outputs(result, outputs, path)
    try:
        save_result(result, path, outputs)
    except KeyboardInterrupt:
        raise SimulationInterrupted(f"interrupted while writing the result file {path} (not written; the "
                                    f"result is in err.result)", result) from None
    except Exception as err:  # any failure to write must not hide the result
        reason = str(err) if isinstance(err, ResultFileError) else f"{path}: {type(err).__name__}: {err}"
        warnings.warn(ResultSaveWarning(f"the result was not saved: {reason}; it is kept in memory "
                                        "(returned, or err.result of the solver error)"), stacklevel=3)


def stored_outputs(result: Result, outputs: str | Sequence[str] | None) -> list[int]:
    """The columns of ``result`` that ``outputs`` asks to store (:func:`save_result`), in column order.

    Raises
    ------
    RunArgumentError
        ``outputs`` is neither None, ``"all"``, a name nor a list of names and patterns.
    ResultKeyError
        A name or pattern that matches no variable (names it, with close matches).
    """
    if outputs is None:
        return []
    if isinstance(outputs, str) and outputs == "all":
        return list(range(len(result.names)))
    wanted = [outputs] if isinstance(outputs, str) else outputs
    if not isinstance(wanted, (list, tuple)) or not all(isinstance(w, str) and w for w in wanted):
        raise RunArgumentError(f"outputs must be None (store the run's rows, derive the rest when read), 'all' "
                               f"(store every variable) or a list of variable names and patterns such as "
                               f"['cylinder*.p_A', 'joint*.frame_b.f'], got {outputs!r}")
    from flexlib.results.compare import select

    index = {n: k for k, n in enumerate(result.names)}
    return sorted({index[n] for n in select(result, list(wanted), f"the result of {result.model} (outputs=)")})


def _stored_parts(result: Result) -> list[StoredPart] | None:
    """The result's rows as the file stores them, or None when it has none to store (built from values)."""
    make = getattr(result.source, "stored_parts", None)
    return make() if make is not None and len(result.t) else None


def keep_outputs(result: Result, outputs: str | Sequence[str] | None, path: Any) -> str | list[str] | None:
    """``outputs`` without the names and patterns that match no variable of ``result``, each named in a
    :class:`~flexlib.errors.ResultSaveWarning` (a run's file is written all the same: every variable stays readable,
    derived from the rows)."""
    if outputs is None or isinstance(outputs, str):
        return outputs if outputs in (None, "all") else keep_outputs(result, [outputs], path)
    kept = []
    for pattern in outputs:
        try:
            stored_outputs(result, [pattern])
        except ResultKeyError as err:
            warnings.warn(ResultSaveWarning(f"{path}: outputs {pattern!r} is not stored as a column ({err}); the "
                                            "file is written without it"), stacklevel=4)
        else:
            kept.append(pattern)
    return kept or None


def _write(result: Result, tmp: str, outputs: str | Sequence[str] | None) -> None:
    parts = _stored_parts(result)
    stored = stored_outputs(result, outputs) if parts is not None else list(range(len(result.names)))
    if len(stored) == len(result.names):  # every variable a column: nothing to derive
        parts = None
    with h5py.File(tmp, "w") as f:
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        f.attrs["model"] = result.model
        f.attrs["status"] = result.status
        f.attrs["message"] = result.message
        f.attrs["index_report"] = result.index_report
        f.attrs["indeterminate"] = mark.encode(result.indeterminate)
        for key, val in result.metadata.items():
            f.attrs[f"meta_{key}"] = str(val)
        ds = f.create_dataset("time", data=np.asarray(result.t, dtype=float).reshape(-1))
        ds.attrs["unit"] = "s"
        g = f.create_group("variables")
        if len(stored) == len(result.names):
            values = np.asarray(result.values, dtype=float).reshape(len(result.t), len(result.names))
        else:
            values = result._read(stored)
        _columns(g, "values", values)
        g.create_dataset("stored", data=np.asarray(stored, dtype=np.int64))
        g.create_dataset("names", data=np.array(result.names, dtype=object), dtype=_STR)
        g.create_dataset("units", data=np.array(result.units, dtype=object), dtype=_STR)
        g.create_dataset("docs", data=np.array(result.docs, dtype=object), dtype=_STR)
        g.create_dataset("kinds", data=np.array(result.kinds, dtype=object), dtype=_STR)
        pg = f.create_group("parameters")
        names = list(result.parameters)
        pg.create_dataset("names", data=np.array(names, dtype=object), dtype=_STR)
        pg.create_dataset("values", data=np.array([result.parameters[n][0] for n in names], dtype=float))
        units = np.array([result.parameters[n][1] for n in names], dtype=object)
        pg.create_dataset("units", data=units, dtype=_STR)
        eg = f.create_group("events")
        eg.create_dataset("time", data=np.array([e[0] for e in result.events], dtype=float))
        eg.create_dataset("text", data=np.array([e[1] for e in result.events], dtype=object), dtype=_STR)
        f.attrs["solver_stats"] = json.dumps(result.stats, default=float)
        for k, part in enumerate(parts or []):
            _write_part(f.create_group(f"rows/{k}"), part, len(result.names))


def _columns(group: h5py.Group, name: str, data: np.ndarray) -> None:
    """A 2-D float dataset stored column by column: one chunk per column (of at most :data:`_CHUNK_ROWS` rows), byte
    shuffle then deflate (HDF5's own ``shuffle`` and ``gzip`` filters, level 1: any HDF5 reader decodes it), so one
    column reads alone.

    The chunks are compressed by zlib on :data:`_WRITERS` threads (zlib releases the GIL; HDF5 itself compresses on
    one) and written as they are (``write_direct_chunk``): on the pump truck's 77 MB of unknowns the write takes about
    half the time of ``create_dataset(..., compression="gzip")``, with the same bytes in the file.
    """
    rows, cols = data.shape
    if not (rows and cols):
        group.create_dataset(name, data=data)
        return
    step = min(rows, _CHUNK_ROWS)
    ds = group.create_dataset(name, shape=data.shape, dtype=np.float64, chunks=(step, 1), compression="gzip",
                              compression_opts=1, shuffle=True)
    starts = [(r, j) for j in range(cols) for r in range(0, rows, step)]

    def encode(start: tuple[int, int]) -> bytes:
        r, j = start
        chunk = np.zeros(step)  # an edge chunk is stored whole, padded
        chunk[:min(step, rows - r)] = data[r:r + step, j]
        return zlib.compress(chunk.view(np.uint8).reshape(step, 8).T.tobytes(), 1)  # shuffle: byte k of all, k = 0…7

    with ThreadPoolExecutor(_WRITERS) as pool:
        for start, raw in zip(starts, pool.map(encode, starts), strict=True):
            ds.id.write_direct_chunk(start, raw)


def _write_part(g: h5py.Group, part: StoredPart, n_names: int) -> None:
    """One model's rows (:mod:`flexlib.results.stored`)."""
    omap = part.output_map()
    if len(omap.source) != n_names:
        raise ResultFileError(f"the output function of the rows gives {len(omap.source)} values for {n_names} "
                              "variables")
    kept = np.arange(part.Y.shape[1]) if part.defs is None else part.defs.kept
    keep, index = unique_columns(part.Y[:, kept])
    columns = np.full(part.Y.shape[1], -1, dtype=np.int64)  # -1: given by its row (the definitions), not stored
    columns[kept] = index
    g.create_dataset("rows", data=np.asarray(part.rows, dtype=np.int64))
    _columns(g, "y", np.ascontiguousarray(part.Y[:, kept[keep]]))
    g.create_dataset("y_columns", data=columns)
    if part.defs is not None:
        g.create_dataset("given", data=np.asarray(part.defs.given, dtype=np.int64))
        g.create_dataset("defs", data=pack_function(part.defs.fn))
    _columns(g, "yp", np.ascontiguousarray(part.YP[:, omap.yp_used]))
    g.create_dataset("yp_used", data=omap.yp_used)
    _columns(g, "rel", np.ascontiguousarray(part.rel, dtype=float).reshape(len(part.rows), -1))
    g.create_dataset("p", data=np.asarray(part.pvec, dtype=float))
    g.create_dataset("source", data=omap.source)
    g.create_dataset("constant", data=omap.constant)
    g.create_dataset("out", data=pack_function(part.out))


class _NotText(ValueError):
    """A dataset that should hold text holds something else (numbers)."""


def _strings(ds: h5py.Dataset) -> list[str]:
    if ds.dtype.kind not in "OSU" or (ds.dtype.kind == "O" and h5py.check_string_dtype(ds.dtype) is None):
        raise _NotText(f"{ds.name} holds {ds.dtype} values, not text")
    return [s.decode() if isinstance(s, bytes) else str(s) for s in np.atleast_1d(ds[()])]


def _first_duplicate(names: list[str]) -> str | None:
    seen: set[str] = set()
    for name in names:
        if name in seen:
            return name
        seen.add(name)
    return None


def _what_is(path: Path) -> str:
    """A short description of a file that is not HDF5 (for the error message)."""
    size = path.stat().st_size
    if size == 0:
        return "an empty file"
    with open(path, "rb") as fh:
        head = fh.read(512)
    if head.startswith(b"\x89HDF"):
        return f"a truncated or damaged HDF5 file ({size} bytes)"
    try:
        text = head.decode("utf-8")
    except UnicodeDecodeError:
        return f"not an HDF5 file ({size} bytes of binary data)"
    first = text.splitlines()[0][:60] if text.splitlines() else ""
    kind = "CSV " if "," in first or ";" in first or "\t" in first else ""
    return f"not an HDF5 file but {kind}text ({size} bytes, first line {first!r})"


def not_a_result(path: str | os.PathLike) -> str | None:
    """Why the existing file ``path`` is not a flexlib result file, or None if it is one (or does not exist).

    Reads only the file's head and its ``format`` attribute: cheap enough to ask before overwriting a file
    (``flexlib run --out`` replaces a result file, but not a CSV or another program's HDF5 file).

    Returns
    -------
    str or None
        ``"a directory"``, ``"not an HDF5 file but CSV text (...)"``, ``"an HDF5 file that is not a flexlib
        result (...)"``, ``"a truncated or damaged HDF5 file (...)"``, ...; None for a flexlib result file or a
        path that does not exist.
    """
    path = Path(os.fspath(path)).expanduser()
    if not path.exists():
        return None
    if path.is_dir():
        return "a directory"
    try:
        hdf5 = h5py.is_hdf5(path)
    except OSError as err:
        return f"a file that cannot be read ({_reason(err)})"
    try:
        if not hdf5:
            return _what_is(path)
        try:
            with h5py.File(path, "r") as f:
                fmt = f.attrs.get("format")
        except OSError:
            return _what_is(path)
    except OSError as err:
        return f"a file that cannot be read ({_reason(err)})"
    if isinstance(fmt, bytes):
        fmt = fmt.decode(errors="replace")
    if fmt != FORMAT:
        found = "no 'format' attribute" if fmt is None else f"format attribute {fmt!r}"
        return f"an HDF5 file that is not a flexlib result ({found})"
    return None


def load_result(path: str | os.PathLike) -> Result:
    """Read a result written by :meth:`Result.save`.

    Raises
    ------
    ResultFileError
        The file is missing, not HDF5, truncated or damaged, not a flexlib result, incomplete (a group or
        dataset missing, inconsistent shapes) or from a newer format version; the message names the path
        and the problem.
    RunArgumentError
        ``path`` is not a path.
    """
    path = _as_path(path, "load_result")
    if not path.exists():
        raise ResultFileError(f"cannot read the result file {path}: no such file")
    if path.is_dir():
        raise ResultFileError(f"cannot read the result file {path}: it is a directory")
    try:
        hdf5 = h5py.is_hdf5(path)
    except OSError as err:
        raise ResultFileError(f"cannot read the result file {path}: {_reason(err)}") from None
    if not hdf5:
        raise ResultFileError(f"cannot read the result file {path}: {_what_is(path)}")
    try:
        f = h5py.File(path, "r")
    except OSError as err:
        raise ResultFileError(f"cannot read the result file {path}: {_what_is(path)}: {err}") from None
    try:
        result = _read(f, path)
    except BaseException as err:
        f.close()
        if isinstance(err, (OSError, KeyError, ValueError, TypeError, IndexError)) \
                and not isinstance(err, ResultFileError):
            raise ResultFileError(f"cannot read the result file {path}: damaged ({type(err).__name__}: "
                                  f"{err})") from None
        raise
    if result.source is None:
        f.close()
    return result


def _read(f: h5py.File, path: Path) -> Result:
    def bad(problem: str) -> ResultFileError:
        return ResultFileError(f"cannot read the result file {path}: {problem}")

    fmt = f.attrs.get("format")
    if isinstance(fmt, bytes):
        fmt = fmt.decode(errors="replace")
    if fmt != FORMAT:
        found = "no 'format' attribute" if fmt is None else f"format attribute {fmt!r}"
        raise bad(f"not a flexlib result file ({found}; expected {FORMAT!r})")
    version = f.attrs.get("format_version")
    if version is None or not np.issubdtype(np.asarray(version).dtype, np.integer) or np.asarray(version).ndim:
        raise bad(f"format_version is missing or not an integer ({version!r}); supported: 1 ... {FORMAT_VERSION}")
    if int(version) > FORMAT_VERSION or int(version) < 1:
        raise bad(f"format_version {int(version)} is not supported: this flexlib reads format_version "
                  f"1 ... {FORMAT_VERSION} (a newer flexlib wrote this file; upgrade flexlib to read it)")
    required = _REQUIRED + (("variables/stored",) if int(version) >= 2 else ())
    missing = ["/" + name for name in required if name not in f or not isinstance(f[name], h5py.Dataset)]
    missing += [f"attribute {a!r}" for a in _ATTRS if a not in f.attrs]
    if missing:
        raise bad(f"incomplete flexlib result, missing {', '.join(missing)}")
    t = np.asarray(f["time"][()], dtype=float)
    g, pg, eg = f["variables"], f["parameters"], f["events"]
    try:
        names = _strings(g["names"])
    except _NotText as err:
        raise bad(str(err)) from None
    if t.ndim != 1:
        raise bad(f"/time has shape {t.shape}, expected one dimension")
    if not np.all(np.isfinite(t)):
        raise bad(f"/time holds NaN or inf (first at row {int(np.argmax(~np.isfinite(t)))}); times must be finite")
    if np.any(np.diff(t) < 0):
        k = int(np.argmax(np.diff(t) < 0))
        raise bad(f"/time decreases at row {k + 1} ({t[k]:g} s, then {t[k + 1]:g} s); times must not decrease "
                  "(an event repeats its time once)")
    dup = _first_duplicate(names)
    if dup is not None:
        raise bad(f"/variables/names holds {dup!r} twice; each variable is named once (a column could not be "
                  "told from the other)")
    values, source = None, None
    if int(version) == 1:
        values = np.asarray(g["values"][()], dtype=float)
        if values.shape != (len(t), len(names)):
            raise bad(f"/variables/values has shape {values.shape}, expected {(len(t), len(names))} "
                      "(time points × variable names)")
    else:
        source = file_columns(f, path, len(t), names, bad)
        if source is None:
            values = np.asarray(g["values"][()], dtype=float)
    try:
        meta_lists = {k: _strings(g[k]) for k in ("units", "docs", "kinds")}
        pnames, punits, ev_text = _strings(pg["names"]), _strings(pg["units"]), _strings(eg["text"])
    except _NotText as err:
        raise bad(str(err)) from None
    for key, lst in meta_lists.items():
        if len(lst) != len(names):
            raise bad(f"/variables/{key} has {len(lst)} entries for {len(names)} variables")
    pvalues = np.asarray(pg["values"][()], dtype=float)
    if not len(pnames) == len(pvalues) == len(punits):
        raise bad(f"/parameters has {len(pnames)} names, {len(pvalues)} values and {len(punits)} units")
    dup = _first_duplicate(pnames)
    if dup is not None:
        raise bad(f"/parameters/names holds {dup!r} twice; each parameter is named once")
    ev_t = np.asarray(eg["time"][()], dtype=float)
    if len(ev_t) != len(ev_text):
        raise bad(f"/events has {len(ev_t)} times and {len(ev_text)} texts")
    status, stats = _status_and_stats(f, bad)
    meta = {k[5:]: str(v) for k, v in f.attrs.items() if k.startswith("meta_")}
    return Result(
        model=str(f.attrs["model"]), t=t, names=names, values=values, units=meta_lists["units"],
        docs=meta_lists["docs"], kinds=meta_lists["kinds"],
        parameters={n: (float(v), u) for n, v, u in zip(pnames, pvalues, punits, strict=True)},
        stats=stats, status=status, message=str(f.attrs["message"]),
        events=list(zip(ev_t.tolist(), ev_text, strict=True)), index_report=str(f.attrs["index_report"]),
        metadata=meta, source=source, indeterminate=mark.decode(f.attrs.get("indeterminate"), bad),
    )


def _status_and_stats(f: h5py.File, bad: Any) -> tuple[str, dict[str, Any]]:
    """The run's status and solver statistics of a file, checked."""
    status = str(f.attrs["status"])
    if status not in _STATUSES:
        raise bad(f"status {status!r} is not one of {', '.join(_STATUSES)}")
    try:
        stats = json.loads(f.attrs["solver_stats"])
    except (TypeError, ValueError) as err:
        raise bad(f"the attribute 'solver_stats' is not JSON ({err})") from None
    if not isinstance(stats, dict):
        raise bad(f"the attribute 'solver_stats' must be a JSON object (statistics by name), got "
                  f"{type(stats).__name__} {stats!r:.60}")
    return status, stats
