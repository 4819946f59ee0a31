"""A build's row definitions (the unknowns its residual rows give explicitly: what a result file derives instead of
storing, :func:`flexlib.results.stored.row_definitions`) kept in the disk cache beside the build's entry.

Finding them walks the residual's expression graph (0.3 s for the rigid pump truck, 0.7 s for the flexible one), once
per build: every later process reads them back (a few milliseconds). The file holds the given unknowns and the
serialized SX function of their definitions; it is checked like an entry's functions (no external code, the expected
name and signature for the model), and a damaged or mismatched file gives one
:class:`~flexlib.errors.CacheWarning` naming it, is removed and made again.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexlib.compile import cache
from flexlib.compile.codegen import CompiledModel
from flexlib.compile.integrity import deserialize_function
from flexlib.results.stored import RowDefinitions, row_definitions

__all__ = ["cached_row_definitions"]

_NAME = "flexlib_row_definitions"


def cached_row_definitions(key: str | None, m: CompiledModel) -> RowDefinitions:
    """The row definitions of the build ``m`` with cache key ``key`` (None: not cached), from the cache if kept."""
    directory = cache.usable_cache_dir() if key else None
    path = None if directory is None else cache.entry_path(directory, m.name, f"{key}-rows").with_suffix(".npz")
    if path is not None:
        try:
            data = cache.load_arrays(path, {"given": np.int64, "fn": np.uint8}, "row definitions")
            if data is not None:
                return _checked(path, m, data)
        except cache.CacheEntryError as err:
            cache.warn_once(err.path, f"damaged cached row definitions ({err.reason}); removing them and making "
                                      "them again")
            cache.discard(err.path)
    defs = row_definitions(m.sx_function("res"), m.sx_function("out"), m.differential)
    if path is not None:
        text = defs.fn.serialize() if defs.fn is not None else ""
        try:
            cache.store_init(path, given=defs.given, fn=np.frombuffer(text.encode("utf-8"), dtype=np.uint8))
        except OSError as exc:
            cache.warn_once(path, f"cannot store row definitions ({exc})")
    return defs


def _checked(path: Path, m: CompiledModel, data: dict[str, np.ndarray]) -> RowDefinitions:
    """The kept definitions, checked against the model (:class:`~flexlib.compile.cache.CacheEntryError` if off)."""
    given = data["given"]
    if given.ndim != 1 or (given.size and (given.min() < 0 or given.max() >= m.n)) or len(set(given.tolist())) != \
            given.size or np.asarray(m.differential, dtype=bool)[given].any():
        raise cache.CacheEntryError(path, "the given unknowns do not fit the model")
    kept = np.setdiff1d(np.arange(m.n), given)
    if not given.size:
        return RowDefinitions(kept, given, None)
    try:
        fn = deserialize_function(data["fn"].tobytes().decode("utf-8"), _NAME)
    except (ValueError, RuntimeError, UnicodeDecodeError) as exc:
        raise cache.CacheEntryError(path, f"the definitions' function cannot be read ({exc})") from None
    res = m.sx_function("res")
    sizes = [fn.numel_in(k) for k in range(fn.n_in())] if fn.n_in() == 4 else []
    if fn.name() != _NAME or sizes != [res.numel_in(k) for k in range(4)] or fn.n_out() != 1 or \
            fn.numel_out(0) != given.size:
        raise cache.CacheEntryError(path, "the definitions' function does not fit the model")
    return RowDefinitions(kept, given, fn)
