"""The build pipeline (stages 1–5) with a disk cache keyed by the model's structure.

The key is a hash of what determines the equations: for every node of the instance tree
its class (and the source files of the packages of its class hierarchy, so helper modules count
too), its declarations (names, shapes,
units, ``fixed`` flags, state selection), its plain-data structural attributes and its
connections; plus flexlib's own compiler sources and the build options. Parameter values
and start values are *not* in the key: they are run-time inputs, read from the model at
every run. (A component must therefore use parameter values only inside its equations,
not to decide which equations to write; structural choices are constructor arguments.)
"""

from __future__ import annotations

import dataclasses
import enum
import hashlib
import inspect
import logging
import os
import pickle
import tempfile
import time as _time
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.compile.codegen import CompiledModel, compile_dae
from flexlib.compile.flatten import FlatSystem, check_balance, flatten
from flexlib.compile.index_reduction import reduce_index
from flexlib.compile.redundancy import remove_redundant
from flexlib.compile.simplify import SimpleSystem, simplify
from flexlib.compile.tearing import eliminate_frame_kinematics
from flexlib.core.component import Component, Node
from flexlib.core.variables import Parameter

__all__ = ["build", "cache_dir", "gather_values", "model_key"]

log = logging.getLogger(__name__)
_FILE_HASHES: dict[str, str] = {}
_ENGINE_HASH: list[str] = []


def cache_dir() -> Path:
    """Cache directory: ``$FLEXLIB_CACHE_DIR`` or ``~/.cache/flexlib``."""
    return Path(os.environ.get("FLEXLIB_CACHE_DIR", Path.home() / ".cache" / "flexlib"))


def _file_hash(path: str) -> str:
    h = _FILE_HASHES.get(path)
    if h is None:
        h = hashlib.sha256(Path(path).read_bytes()).hexdigest()
        _FILE_HASHES[path] = h
    return h


def _class_hash(cls: type) -> str | None:
    parts = []
    for klass in cls.__mro__:
        if klass in (object, Node, Component) or klass.__module__ == "builtins":
            continue
        try:
            src = inspect.getsourcefile(klass)
        except TypeError:
            return None
        if src is None or not Path(src).exists():
            return None
        # the class's module and its sibling modules (helpers such as frames.py are imported, not inherited)
        package = sorted(str(f) for f in Path(src).parent.glob("*.py"))
        parts.append(f"{klass.__module__}.{klass.__qualname__}:" + ",".join(_file_hash(f) for f in package))
    return "|".join(parts)


def _engine_hash() -> str:
    if not _ENGINE_HASH:
        root = Path(__file__).resolve().parent.parent
        files = sorted([*root.glob("core/*.py"), *root.glob("compile/*.py")])
        _ENGINE_HASH.append(hashlib.sha256("".join(_file_hash(str(f)) for f in files).encode()).hexdigest())
    return _ENGINE_HASH[0]


def _plain(value: Any) -> Any:
    if isinstance(value, (bool, int, float, str, type(None))):
        return value
    if isinstance(value, np.ndarray):
        return ("ndarray", value.shape, hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest())
    if isinstance(value, (tuple, list)):
        items = [_plain(v) for v in value]
        return None if any(i is _SKIP for i in items) else tuple(items)
    if isinstance(value, dict):
        items = [(str(k), _plain(v)) for k, v in value.items()]
        return None if any(i is _SKIP for _, i in items) else tuple(sorted(items))
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
    """Hash of the model structure and build options, or None if the model cannot be keyed."""
    h = hashlib.sha256()
    h.update(_engine_hash().encode())
    h.update(repr(sorted(options.items())).encode())
    for node in root.walk():
        ch = _class_hash(type(node))
        if ch is None:
            return None
        h.update(f"{node.path}|{ch}".encode())
        for name, decl in node._decls.items():
            item = (name, decl.kind.value, decl.shape, decl.unit)
            if not isinstance(decl, Parameter):
                item += (node.start_of(name)[1], decl.nominal, int(decl.state_select))
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


def gather_values(root: Component) -> tuple[dict[str, float], dict[str, tuple[float, bool]]]:
    """Current parameter values and start values of every scalar, by hierarchical name."""
    params: dict[str, float] = {}
    starts: dict[str, tuple[float, bool]] = {}
    for node in root.walk():
        for name, decl in node._decls.items():
            labels = decl.element_names(node._label(name))
            if isinstance(decl, Parameter):
                value = node.parameter_value(name)
                if value is None:
                    continue
                flat = np.asarray(value, dtype=float).flatten(order="F")
                params.update({lab: float(flat[k]) for k, (lab, _) in enumerate(labels)})
            else:
                value, fixed = node.start_of(name)
                flat = np.asarray(value, dtype=float).flatten(order="F")
                starts.update({lab: (float(flat[k]), fixed) for k, (lab, _) in enumerate(labels)})
    return params, starts


def prepare(flat: FlatSystem, params: dict[int, float]) -> SimpleSystem:
    """Stage 2: alias elimination, redundant loop constraints, explicit frame kinematics."""
    return eliminate_frame_kinematics(remove_redundant(simplify(flat), params))


def build(root: Component, *, codegen: bool | str = "auto", use_cache: bool = True) -> tuple[CompiledModel, dict]:
    """Run stages 1–5 (or load them from the cache).

    Parameters
    ----------
    root : Component
        The top-level model.
    codegen : bool or "auto"
        Generate and compile C code; ``"auto"`` does so above 300 unknowns after alias elimination,
        with gcc in the background (see :func:`flexlib.compile.codegen.compile_dae`).
    use_cache : bool
        Read and write the disk cache.

    Returns
    -------
    CompiledModel, dict
        The compiled model and build timings (``{"cached": bool, "flatten": s, ...}``).
    """
    timings: dict[str, Any] = {"cached": False}
    t0 = _time.perf_counter()
    key = model_key(root, {"codegen": codegen}) if use_cache else None
    timings["key"] = _time.perf_counter() - t0
    timings["model_key"] = key
    path = cache_dir() / f"{type(root).__name__}-{key}.pkl" if key else None
    if path is not None and path.exists():
        try:
            with path.open("rb") as fh:
                model = pickle.load(fh)
            if model.library is None or Path(model.library).exists():
                timings["cached"] = True
                timings["total"] = _time.perf_counter() - t0
                return model, timings
        except Exception as exc:  # a corrupt or stale cache entry is rebuilt
            log.warning("ignoring unreadable cache entry %s: %s", path, exc)
    t = _time.perf_counter()
    flat = flatten(root, check=False)
    has_loops = any(e.origin == "loop closure" for e in flat.equations)
    if not has_loops:  # diagnostics in the user's own equations; loops are checked once redundancy is removed
        check_balance(flat.name, flat.variables, flat.equations)
    timings["flatten"] = _time.perf_counter() - t
    t = _time.perf_counter()
    params = {q.sym.element_hash(): q.value for q in flat.parameters}
    simple = prepare(flat, params)
    if has_loops:
        check_balance(flat.name, simple.variables, simple.equations)
    timings["simplify"] = _time.perf_counter() - t
    t = _time.perf_counter()
    dae = reduce_index(simple, params)
    timings["index_reduction"] = _time.perf_counter() - t
    t = _time.perf_counter()
    use_c: bool | str = "auto" if codegen == "auto" else bool(codegen)
    build_dir = cache_dir() if key else None
    model = compile_dae(flat, simple, dae, codegen=use_c, build_dir=build_dir)
    use_c = model.library is not None
    timings["compile"] = _time.perf_counter() - t
    model.stats = {"n_flat_equations": len(flat.equations), "n_aliases": simple.n_eliminated,
                   "n_unknowns": model.n, "n_states": int(model.differential.sum()),
                   "jac_nnz": len(model.jac_row), "codegen": use_c}
    if path is not None:
        _atomic_pickle(model, path)
    timings["total"] = _time.perf_counter() - t0
    return model, timings


def _atomic_pickle(obj: Any, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            pickle.dump(obj, fh, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
