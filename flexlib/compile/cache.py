"""The disk cache: keys, loads and stores (the stages themselves run in :mod:`flexlib.compile.pipeline`).

**Key.** :func:`flexlib.compile.cache_key.model_key`: what determines the equations, not parameter or start
values (they are read from the model at every run).

**Format.** An entry is a directory ``<Model>-<key>/`` holding ``model.json`` (metadata, the CasADi
serialized strings of the SX functions, and the manifest: SHA-256 and size of ``arrays.npz`` and of the
compiled library ``lib/flexlib_<sha256>.so`` if any) and ``arrays.npz`` (read with ``allow_pickle=False``).
Nothing in the cache is unpickled; every file is checked against the manifest before it is read or
loaded, and every deserialized function against its expected name and signature. An entry is written into
a temporary directory and renamed into place, so concurrent processes see a whole entry or none.

**Trust.** The cache directory (and its ``lib/`` and entry directories) must be owned by this user and
not writable by others (group/other write permission without the sticky bit); files must be owned by this
user and not writable by others. Otherwise, or when the directory cannot be created or written, a
:class:`~flexlib.errors.CacheWarning` names the directory and the reason, and the model is built without
the cache. A damaged entry is reported once (a ``CacheWarning`` naming the file), removed and rebuilt.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import re
import shutil
import stat
import tempfile
import time
import uuid
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.integrity import deserialize_function, file_problem
from flexlib.errors import CacheWarning

__all__ = ["CacheEntryError", "cache_dir", "load", "load_arrays", "store",
           "usable_cache_dir"]

#: version of the on-disk format (part of every entry's metadata)
FORMAT = 3  # 2: IndexReport.explicit (explicit algebraics eliminated, compile/explicit.py); 3: row definitions
_WARNED: set[tuple[str, str]] = set()


class CacheEntryError(Exception):
    """A cache entry that cannot be used; ``path`` names the offending file."""

    def __init__(self, path: Path, reason: str) -> None:
        super().__init__(f"{path}: {reason}")
        self.path, self.reason = path, reason


def cache_dir() -> Path:
    """Cache directory: ``$FLEXLIB_CACHE_DIR`` or ``~/.cache/flexlib``, as an absolute path.

    ``~`` and ``$VARIABLE`` in the value are expanded (a value written in a file that no shell expanded, such as
    ``~/cache``, made a directory named ``~`` in the working directory), a relative path is taken from the working
    directory at the time of the call (a later ``chdir`` does not move the cache of a running build), and an empty
    value counts as unset (it put the cache, ``lib/`` and every entry into the working directory)."""
    raw = os.environ.get("FLEXLIB_CACHE_DIR", "")
    if not raw.strip():
        return Path.home() / ".cache" / "flexlib"
    return Path(os.path.expandvars(os.path.expanduser(raw))).absolute()


def warn_once(where: Path | str, reason: str) -> None:
    """One :class:`CacheWarning` per place and reason in this process."""
    if (str(where), reason) in _WARNED:
        return
    _WARNED.add((str(where), reason))
    warnings.warn(f"flexlib cache {where}: {reason}", CacheWarning, stacklevel=3)


def dir_problem(path: Path, follow: bool = False) -> str | None:
    """Why ``path`` is not a safe cache directory (None if it is); ``follow``: a symbolic link to one is fine."""
    try:
        st = path.stat() if follow else path.lstat()
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc})"
    if not stat.S_ISDIR(st.st_mode):
        return "is not a directory" + (" (a symbolic link)" if stat.S_ISLNK(st.st_mode) else "")
    if hasattr(os, "getuid") and st.st_uid != os.getuid():
        return f"is owned by uid {st.st_uid}, not by this user (uid {os.getuid()}); other users could plant code"
    if st.st_mode & 0o022 and not st.st_mode & stat.S_ISVTX:
        return (f"is writable by other users (mode {stat.filemode(st.st_mode)}) without the sticky bit; "
                "they could plant code")
    if not os.access(path, os.W_OK | os.X_OK):
        return "is not writable by this user"
    return None


def usable_cache_dir() -> Path | None:
    """The cache directory, created if missing, or None (after one :class:`CacheWarning`) if it cannot be used."""
    path = cache_dir()
    try:
        path.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError as exc:
        warn_once(path, f"cannot be created ({exc.strerror or exc}); building without the cache")
        return None
    problem = dir_problem(path, follow=True)
    if problem is None:
        lib = path / "lib"
        try:
            lib.mkdir(mode=0o700, exist_ok=True)
        except OSError as exc:
            problem = f"cannot create {lib} ({exc.strerror or exc})"
        else:
            problem = dir_problem(lib)
            problem = None if problem is None else f"{lib} {problem}"
    if problem is not None:
        warn_once(path, f"{problem}; building without the cache")
        return None
    return path


# -- entries: load and store ---------------------------------------------------------------------------------
_NAME = re.compile(r"[^A-Za-z0-9_]")
_LIB_NAME = re.compile(r"lib/flexlib_[0-9a-f]{32}\.so")


def entry_path(directory: Path, name: str, key: str) -> Path:
    """The entry directory of model class ``name`` with key ``key``."""
    return directory / f"{_NAME.sub('_', name)[:80]}-{key}"


def _read_checked(path: Path, limit: int = 1 << 31) -> bytes:
    """Bytes of a file in the cache that must be a regular file of this user, not writable by others."""
    problem = file_problem(path)
    if problem is not None:
        raise CacheEntryError(path, problem)
    data = path.read_bytes()
    if len(data) > limit:
        raise CacheEntryError(path, f"{len(data)} bytes, more than expected")
    return data


def load(entry: Path) -> CompiledModel | None:
    """The compiled model stored in ``entry``, or None if there is no entry.

    Raises
    ------
    CacheEntryError
        The entry exists but is damaged, untrusted or from another format (``err.path`` names the file).
    """
    meta_path = entry / "model.json"
    if not entry.exists() and not entry.is_symlink():
        return None
    problem = dir_problem(entry)
    if problem is not None:
        raise CacheEntryError(entry, problem)
    if not meta_path.exists():
        raise CacheEntryError(meta_path, "missing")
    try:
        doc = json.loads(_read_checked(meta_path).decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as exc:
        raise CacheEntryError(meta_path, f"unreadable metadata ({exc})") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise CacheEntryError(meta_path, f"format {doc.get('format') if isinstance(doc, dict) else '?'} "
                                         f"is not {FORMAT}")
    manifest = doc.get("manifest")
    if not isinstance(manifest, dict) or not isinstance(manifest.get("arrays.npz"), dict):
        raise CacheEntryError(meta_path, "no manifest")
    arrays_path = entry / "arrays.npz"
    arr_entry = manifest["arrays.npz"]
    raw = _read_checked(arrays_path)
    if len(raw) != arr_entry.get("size") or hashlib.sha256(raw).hexdigest() != arr_entry.get("sha256"):
        raise CacheEntryError(arrays_path, "size or SHA-256 differs from the manifest")
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except Exception as exc:
        raise CacheEntryError(arrays_path, f"unreadable arrays ({type(exc).__name__}: {exc})") from None
    meta = doc.get("model")
    lib = meta.get("library") if isinstance(meta, dict) else None
    if lib is not None:
        lib_entry = manifest.get(lib) if isinstance(lib, str) else None
        if not isinstance(lib, str) or not _LIB_NAME.fullmatch(lib) or not isinstance(lib_entry, dict):
            raise CacheEntryError(meta_path, f"library {lib!r} is not a compiled-model library of this cache")
        lib_path = entry.parent / lib
        problem = file_problem(lib_path, str(lib_entry.get("sha256")), lib_entry.get("size", -1))
        if problem is not None:
            raise CacheEntryError(lib_path, problem)
        meta = dict(meta, library=str(lib_path), library_sha256=lib_entry["sha256"], library_size=lib_entry["size"])
    functions = manifest.get("functions")
    try:
        model = CompiledModel.from_data(meta, arrays)
        if not isinstance(functions, dict) or set(functions) != set(model.serialized):
            raise ValueError("no manifest of the functions")
        for name, text in model.serialized.items():
            if hashlib.sha256(text.encode()).hexdigest() != functions[name]:
                raise ValueError(f"function {name!r}: SHA-256 differs from the manifest")
        # deserialize and check now what every run needs anyway (a bad one is a damaged entry)
        for name in model.functions_needed():
            f = deserialize_function(model.serialized[name], f"flexlib_{name}")
            model.check_function(name, f)
            model._sx[name] = f
    except (ValueError, TypeError, KeyError, RuntimeError) as exc:
        raise CacheEntryError(meta_path, f"invalid metadata ({exc})") from None
    model.stats["cache_entry"] = str(entry)
    return model


def store(entry: Path, model: CompiledModel, *, replace: bool = False) -> None:
    """Write ``model`` as the entry ``entry`` (atomically: a temporary directory renamed into place).

    The compiled library (if any) is moved into ``lib/`` of the cache directory under its content-derived
    name; its SHA-256 and size come from the process that compiled it. If another process stored the same
    entry first, that entry is kept, unless ``replace`` (the same model with its library compiled in the
    background since: the old entry is swapped out).
    """
    meta, arrays = model.to_data()
    manifest: dict[str, dict[str, Any]] = {}
    directory = entry.parent
    if model.library is not None:
        src = Path(model.library)
        rel = f"lib/{src.name}"
        if not _LIB_NAME.fullmatch(rel) or model.library_sha256 is None:
            raise CacheEntryError(src, "not a library compiled by this process")
        dest = directory / rel
        if src.resolve() != dest.resolve():
            tmp = dest.with_name(f".{dest.name}.{uuid.uuid4().hex}.tmp")
            shutil.copyfile(src, tmp)
            os.chmod(tmp, 0o700)
            problem = file_problem(tmp, model.library_sha256, model.library_size)
            if problem is not None:
                tmp.unlink(missing_ok=True)
                raise CacheEntryError(src, problem)
            os.replace(tmp, dest)
            model.library = str(dest)
        meta["library"] = rel
        manifest[rel] = {"sha256": model.library_sha256, "size": model.library_size}
    meta["library_sha256"], meta["library_size"] = None, 0  # the manifest is authoritative
    remove_stale(directory)
    tmp_dir = Path(tempfile.mkdtemp(prefix=f".{entry.name}.", suffix=".tmp", dir=directory))
    try:
        np.savez(tmp_dir / "arrays.npz", **arrays)
        data = (tmp_dir / "arrays.npz").read_bytes()
        manifest["arrays.npz"] = {"sha256": hashlib.sha256(data).hexdigest(), "size": len(data)}
        manifest["functions"] = {k: hashlib.sha256(t.encode()).hexdigest() for k, t in meta["serialized"].items()}
        doc = {"format": FORMAT, "model": meta, "manifest": manifest}
        (tmp_dir / "model.json").write_text(json.dumps(doc))
        try:
            os.rename(tmp_dir, entry)
        except OSError:
            if not entry.exists():
                raise
            if replace:  # swap: the old entry moves aside (a reader has it open or reads the new one whole)
                trash = entry.with_name(f".{entry.name}.{uuid.uuid4().hex}.trash")
                os.rename(entry, trash)
                os.rename(tmp_dir, entry)
                shutil.rmtree(trash, ignore_errors=True)
            # otherwise another process stored the entry first: keep it
    finally:
        shutil.rmtree(tmp_dir, ignore_errors=True)


#: temporary files and directories older than this [s] are left over from a killed process
STALE_AGE = 3600.0


def remove_stale(directory: Path, age: float = STALE_AGE) -> None:
    """Remove temporary items (``.*.tmp``, ``.*.trash``) older than ``age`` seconds from the cache directory
    and its ``lib/``: left behind by processes killed while writing (a live writer's items are newer)."""
    now = time.time()
    for folder in (directory, directory / "lib"):
        try:
            items = [p for p in folder.iterdir() if p.name.startswith(".") and p.name.endswith((".tmp", ".trash"))]
        except OSError:
            continue
        for item in items:
            try:
                if now - item.lstat().st_mtime < age:
                    continue
                if item.is_dir() and not item.is_symlink():
                    shutil.rmtree(item, ignore_errors=True)
                else:
                    item.unlink()
            except OSError:
                pass


def discard(path: Path) -> None:
    """Remove a damaged entry directory or file (renamed away first, so readers see it whole or not at all)."""
    try:
        if path.is_dir() and not path.is_symlink():
            trash = path.with_name(f".{path.name}.{uuid.uuid4().hex}.trash")
            os.rename(path, trash)
            shutil.rmtree(trash, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)
    except OSError:
        pass


def load_init(path: Path) -> dict[str, np.ndarray] | None:
    """Cached initial values (``y``, ``yp``, ``p``, ``residual``) from ``path``, or None if there are none.

    Raises
    ------
    CacheEntryError
        The file exists but is damaged or untrusted.
    """
    data = load_arrays(path, {"y": float, "yp": float, "p": float, "residual": float}, "initial values")
    return data


def load_arrays(path: Path, kinds: dict[str, type], what: str) -> dict[str, np.ndarray] | None:
    """The arrays ``kinds`` (name: dtype) of the ``.npz`` file ``path`` kept beside an entry (``what`` it holds, for
    messages), or None if there is none.

    Raises
    ------
    CacheEntryError
        The file exists but is damaged or untrusted.
    """
    if not path.exists() and not path.is_symlink():
        return None
    raw = _read_checked(path, limit=1 << 30)
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            out = {k: np.array(data[k], dtype=dtype) for k, dtype in kinds.items()}
    except Exception as exc:
        raise CacheEntryError(path, f"unreadable {what} ({type(exc).__name__}: {exc})") from None
    return out


def store_init(path: Path, **arrays: np.ndarray) -> None:
    """Write arrays (initial values, row definitions) atomically beside an entry (a temporary file renamed into
    place)."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
