"""The disk cache: keys, loads and stores (the stages themselves run in :mod:`flexlib.compile.pipeline`).

**Key.** A hash of what determines the equations: for every node of the instance tree its class (the source
files of the packages of its class hierarchy, so helper modules count too; for a class without a source
file — defined in a REPL, ``python -c`` or a notebook cell — the code of every function in its class dict,
see :func:`code_digest`), its declarations (names, shapes, units, ``fixed`` flags, state selection), its
plain-data structural attributes, :meth:`Component.structure_key` and its connections; plus flexlib's own
compiler sources and the build options. Parameter values and start values are *not* in the key: they are
run-time inputs, read from the model at every run. (A component must therefore use parameter values only
inside its equations, not to decide which equations to write; structural choices are constructor
arguments.)

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

import dataclasses
import enum
import hashlib
import inspect
import io
import json
import os
import re
import shutil
import stat
import sys
import tempfile
import time
import types
import uuid
import warnings
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.integrity import deserialize_function, file_problem
from flexlib.core.component import Component, Node
from flexlib.core.variables import Declaration, Parameter
from flexlib.errors import CacheWarning, ModelError

__all__ = ["CacheEntryError", "cache_dir", "code_digest", "load", "model_key", "store",
           "usable_cache_dir"]

#: version of the on-disk format (part of every entry's metadata)
FORMAT = 2  # 2: IndexReport.explicit (explicit algebraics eliminated, compile/explicit.py)
_FILE_HASHES: dict[str, str] = {}
_ENGINE_HASH: list[str] = []
_CLASS_HASHES: dict[type, str | None] = {}
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


def _file_hash(path: str) -> str:
    h = _FILE_HASHES.get(path)
    if h is None:
        h = hashlib.sha256(Path(path).read_bytes()).hexdigest()
        _FILE_HASHES[path] = h
    return h


def _source_file(klass: type) -> str | None:
    try:
        src = inspect.getsourcefile(klass)
    except (TypeError, OSError):
        return None
    if src is None or not Path(src).is_file():
        return None
    return src


def _class_hash(cls: type) -> str | None:
    """Hash of the code of ``cls`` and its bases: source files where they exist, else :func:`code_digest`."""
    if cls in _CLASS_HASHES:
        return _CLASS_HASHES[cls]
    parts = []
    for klass in cls.__mro__:
        if klass in (object, Node, Component) or klass.__module__ == "builtins":
            continue
        src = _source_file(klass)
        if src is None:
            digest = code_digest(klass)
            if digest is None:
                _CLASS_HASHES[cls] = None
                return None
            parts.append(f"{klass.__module__}.{klass.__qualname__}:code:{digest}")
            continue
        # the class's module and its sibling modules (helpers such as frames.py are imported, not inherited)
        package = sorted(str(f) for f in Path(src).parent.glob("*.py"))
        parts.append(f"{klass.__module__}.{klass.__qualname__}:" + ",".join(_file_hash(f) for f in package))
    _CLASS_HASHES[cls] = "|".join(parts)
    return _CLASS_HASHES[cls]


_SKIP_CLASS_ATTRS = {"__module__", "__qualname__", "__doc__", "__dict__", "__weakref__", "__firstlineno__",
                     "__static_attributes__", "__annotations__", "__orig_bases__", "__parameters__",
                     "__dataclass_fields__", "__dataclass_params__", "__match_args__", "__slotnames__"}


def code_digest(cls: type) -> str | None:
    """Hash of a class by its code, for a class without a source file (REPL, ``python -c``, notebook cell).

    Covers every function in the class dict (methods, static/class methods, properties), recursively
    through nested code objects (inner functions, lambdas, comprehensions), closures and default values,
    plus the functions, classes and plain constants that the code reads from its module's globals when
    that module has no source file either (helpers defined in the same REPL session). Each code object
    contributes its bytecode, constants, names and variable names — not its file name or line numbers, so
    the same class defined again in a new cell keys the same. The Python version is part of the digest
    (bytecode differs between versions). Returns None if some class attribute cannot be represented.
    """
    h = hashlib.sha256(f"{sys.implementation.name}-{sys.version_info[:3]}".encode())
    try:
        _digest_class(h, cls, set())
    except _Unkeyable:
        return None
    return h.hexdigest()


class _Unkeyable(Exception):
    pass


def _digest_class(h: Any, cls: type, seen: set[int]) -> None:
    if id(cls) in seen:
        h.update(f"<class {cls.__qualname__}>".encode())
        return
    seen.add(id(cls))
    h.update(f"class {cls.__qualname__}({','.join(b.__qualname__ for b in cls.__bases__)})".encode())
    for name, value in sorted(vars(cls).items()):
        if name in _SKIP_CLASS_ATTRS:
            continue
        h.update(f"\n{name}=".encode())
        _digest_value(h, value, seen, cls.__module__)


def _digest_value(h: Any, value: Any, seen: set[int], module: str) -> None:
    if isinstance(value, (staticmethod, classmethod)):
        h.update(type(value).__name__.encode())
        value = value.__func__
    if isinstance(value, property):
        for part in (value.fget, value.fset, value.fdel):
            _digest_value(h, part, seen, module)
        return
    if isinstance(value, types.FunctionType):
        _digest_function(h, value, seen, module)
        return
    if isinstance(value, (Declaration, Node)):  # keyed by model_key through the instance tree
        h.update(f"<{type(value).__module__}.{type(value).__qualname__}>".encode())
        return
    if isinstance(value, type):
        if value.__module__ == module and _source_file(value) is None:
            _digest_class(h, value, seen)
        else:
            h.update(f"<type {value.__module__}.{value.__qualname__}>".encode())
        return
    plain = _plain(value)
    if plain is _SKIP:
        raise _Unkeyable
    h.update(repr(plain).encode())


def _digest_function(h: Any, fn: types.FunctionType, seen: set[int], module: str) -> None:
    if id(fn) in seen:
        h.update(f"<fn {fn.__qualname__}>".encode())
        return
    seen.add(id(fn))
    _digest_code(h, fn.__code__)
    for part in (fn.__defaults__ or (), *(fn.__kwdefaults__ or {}).items()):
        _digest_value(h, part, seen, module)
    for cell in fn.__closure__ or ():
        try:
            content = cell.cell_contents
        except ValueError:  # an empty cell
            h.update(b"<empty cell>")
            continue
        if isinstance(content, type) and content.__module__ != module:
            h.update(f"<type {content.__module__}.{content.__qualname__}>".encode())
        elif _plain(content) is _SKIP and not isinstance(content, (types.FunctionType, type)):
            h.update(f"<cell {type(content).__qualname__}>".encode())
        else:
            _digest_value(h, content, seen, module)
    # helpers and constants of a module without source (the same REPL session / notebook)
    mod = sys.modules.get(fn.__module__)
    if fn.__module__ == module and (mod is None or not getattr(mod, "__file__", None)):
        for name in sorted(_global_names(fn.__code__)):
            if name not in fn.__globals__:
                continue
            g = fn.__globals__[name]
            if isinstance(g, (types.FunctionType, type)) and getattr(g, "__module__", None) == module:
                h.update(f"\nglobal {name}=".encode())
                _digest_value(h, g, seen, module)
            elif not isinstance(g, (types.ModuleType, types.BuiltinFunctionType, type, types.FunctionType)):
                plain = _plain(g)
                if plain is not _SKIP:
                    h.update(f"\nglobal {name}={plain!r}".encode())


def _data_digest(cls: type) -> str:
    """Hash of the data the methods of ``cls`` (and its bases) read that no source file holds: the contents of their
    closure cells and the plain-data module globals they name.

    A class made inside a factory function (``def make(k): class M(fl.Model): ... -k * x ...``) has the same source
    for every ``k``, and a module constant computed at import (``K = float(open("k.txt").read())``) is not in the
    source either: without this, a model built with ``k = 5`` found the cached build of ``k = 1`` and ran it. Not
    cached: a module global may be reassigned between builds (a notebook).
    """
    h = hashlib.sha256()
    seen: set[int] = set()
    for klass in cls.__mro__:
        if klass in (object, Node, Component) or klass.__module__ == "builtins":
            continue
        for name, value in sorted(vars(klass).items()):
            fn = value.__func__ if isinstance(value, (staticmethod, classmethod)) else value
            parts = (fn.fget, fn.fset, fn.fdel) if isinstance(fn, property) else (fn,)
            for part in parts:
                if isinstance(part, types.FunctionType):
                    h.update(f"\n{klass.__qualname__}.{name}:".encode())
                    _digest_data(h, part, seen)
    return h.hexdigest()[:16]


def _digest_data(h: Any, fn: types.FunctionType, seen: set[int]) -> None:
    if id(fn) in seen:
        return
    seen.add(id(fn))
    for cell in fn.__closure__ or ():
        try:
            content = cell.cell_contents
        except ValueError:  # an empty cell
            continue
        if isinstance(content, types.FunctionType):
            _digest_data(h, content, seen)
            continue
        plain = _plain(content)
        h.update(repr(plain if plain is not _SKIP else f"<{type(content).__qualname__}>").encode())
    for name in sorted(_global_names(fn.__code__)):
        g = fn.__globals__.get(name, _SKIP)
        if g is _SKIP or isinstance(g, (types.ModuleType, type, types.FunctionType, types.BuiltinFunctionType)):
            continue
        plain = _plain(g)
        if plain is not _SKIP:
            h.update(f"\nglobal {name}={plain!r}".encode())


def _global_names(code: types.CodeType) -> set[str]:
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            names |= _global_names(const)
    return names


def _digest_code(h: Any, code: types.CodeType) -> None:
    h.update(code.co_code)
    h.update(repr((code.co_names, code.co_varnames, code.co_freevars, code.co_cellvars, code.co_argcount,
                   code.co_kwonlyargcount, code.co_flags)).encode())
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            _digest_code(h, const)
        else:
            h.update(repr((type(const).__name__, const)).encode())


def _engine_hash() -> str:
    if not _ENGINE_HASH:
        root = Path(__file__).resolve().parent.parent
        files = sorted([*root.glob("core/*.py"), *root.glob("compile/*.py")])
        _ENGINE_HASH.append(hashlib.sha256("".join(_file_hash(str(f)) for f in files).encode()).hexdigest())
    return _ENGINE_HASH[0]


def _plain(value: Any) -> Any:
    """``value`` as hashable plain data for the key, or ``_SKIP`` if it cannot be represented."""
    if isinstance(value, (bool, int, float, str, type(None))):
        return value
    if isinstance(value, (bytes, bytearray, memoryview)):
        return ("bytes", hashlib.sha256(value).hexdigest())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, np.ndarray):
        if value.dtype.hasobject:
            return _plain(value.tolist())
        return ("ndarray", value.dtype.str, value.shape,
                hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest())
    if isinstance(value, Node):  # a reference to a node of the tree (its own entry is keyed separately)
        return ("node", value.path)
    if isinstance(value, (tuple, list, set, frozenset)):
        items = [_plain(v) for v in value]
        if any(i is _SKIP for i in items):
            return _SKIP
        return (type(value).__name__, tuple(sorted(items, key=repr) if isinstance(value, (set, frozenset)) else items))
    if isinstance(value, dict):
        items = [(repr(_plain(k)), _plain(v)) for k, v in value.items()]
        return _SKIP if any(i is _SKIP for _, i in items) else ("dict", tuple(sorted(items)))
    if dataclasses.is_dataclass(value) and not isinstance(value, type):  # e.g. a fluid record
        items = [(f.name, _plain(getattr(value, f.name))) for f in dataclasses.fields(value)]
        if any(i is _SKIP for _, i in items):
            return _SKIP
        return (type(value).__module__, type(value).__qualname__, tuple(items))
    if isinstance(value, enum.Enum):
        return (type(value).__qualname__, value.name)
    return _SKIP


_SKIP = object()


def model_key(root: Component, options: dict[str, Any]) -> str | None:
    """Hash of the model structure and build options, or None if the model cannot be keyed.

    Raises
    ------
    ModelError
        A component's :meth:`~flexlib.core.component.Component.structure_key` returned something other
        than plain data.
    """
    h = hashlib.sha256()
    h.update(_engine_hash().encode())
    h.update(f"format {FORMAT}; casadi {ca.__version__}".encode())
    h.update(repr(sorted(options.items())).encode())
    data: dict[type, str] = {}
    for node in root.walk():
        ch = _class_hash(type(node))
        if ch is None:
            return None
        if type(node) not in data:
            data[type(node)] = _data_digest(type(node))
        h.update(f"{node.path}|{ch}|{data[type(node)]}".encode())
        if isinstance(node, Component):
            extra = node.structure_key()
            pv = _plain(extra)
            if pv is _SKIP:
                raise ModelError(f"{node.path or type(node).__name__}.structure_key() must return plain data "
                                 f"(numbers, strings, bytes, arrays, tuples, lists, dicts), got {extra!r}")
            h.update(repr(("structure_key", pv)).encode())
        for name, decl in node._decls.items():
            item = (name, decl.kind.value, decl.shape, decl.unit)
            if not isinstance(decl, Parameter):
                given = node._starts.get(name)  # only whether the start is fixed enters the key
                item += (decl.fixed if given is None else given[1], decl.nominal, int(node.state_select_of(name)))
            h.update(repr(item).encode())
        for name, value in sorted(node.__dict__.items()):
            if name.startswith("_") or isinstance(value, Node):
                continue
            pv = _plain(value)
            if pv is _SKIP:  # an attribute the key cannot represent: do not risk a wrong cache hit
                return None
            h.update(repr((name, pv)).encode())
        for a, b in node._connections:
            h.update(repr((_conn_label(a), _conn_label(b))).encode())
    return h.hexdigest()[:32]


def _conn_label(item: tuple) -> str:
    if item[0] == "connector":
        return item[1].path
    return item[1].node._label(item[1].name)


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
    if not path.exists() and not path.is_symlink():
        return None
    raw = _read_checked(path, limit=1 << 30)
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            out = {k: np.array(data[k], dtype=float) for k in ("y", "yp", "p", "residual")}
    except Exception as exc:
        raise CacheEntryError(path, f"unreadable initial values ({type(exc).__name__}: {exc})") from None
    return out


def store_init(path: Path, **arrays: np.ndarray) -> None:
    """Write initial values atomically (a temporary file renamed into place)."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
