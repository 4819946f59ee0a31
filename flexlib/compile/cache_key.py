"""The disk cache's key: a hash of everything that determines a model's compiled equations.

A hash of what determines the equations: for every node of the instance tree its class (the source
files of the packages of its class hierarchy, so helper modules count too; for a class without a source
file — defined in a REPL, ``python -c`` or a notebook cell — the code of every function in its class dict,
see :func:`code_digest`), its declarations (names, shapes, units, ``fixed`` flags, state selection), its
plain-data structural attributes, :meth:`Component.structure_key` and its connections; plus flexlib's own
compiler sources and the build options. Parameter values and start values are *not* in the key: they are
run-time inputs, read from the model at every run. (A component must therefore use parameter values only
inside its equations, not to decide which equations to write; structural choices are constructor
arguments.)
"""

from __future__ import annotations

import dataclasses
import enum
import hashlib
import inspect
import sys
import types
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.cache import FORMAT
from flexlib.core.component import Component, Node
from flexlib.core.variables import Declaration, Parameter
from flexlib.errors import ModelError

__all__ = ["code_digest", "model_key"]

_FILE_HASHES: dict[str, str] = {}
_ENGINE_HASH: list[str] = []
_CLASS_HASHES: dict[type, str | None] = {}


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
        own = node.class_declarations().keys() | node._state_select.keys()
        for name, decl in node._decls.items():
            start = node._starts.get(name)
            if name not in own and (start is None or start[1] is False):
                continue  # a compile pass's declaration (declared by the build itself) with no initial condition
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
