"""Consistent starts kept in the disk cache, keyed by the build, the parameter vector, the start values and the
options, and used again only where the model's residual at the run's parameters is as small as when they were
stored (a damaged file or a failed check gives one :class:`~flexlib.errors.CacheWarning` naming the file).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from flexlib.compile import cache
from flexlib.compile.codegen import CompiledModel

__all__ = ["load_start", "store_start"]


def load_start(key: str | None, m: CompiledModel, t0: float, p: np.ndarray, starts: dict,
               steady: bool) -> tuple[Path | None, tuple[np.ndarray, np.ndarray] | None]:
    """The cache file of this start (None without a usable cache) and the cached ``(y, yp)`` if they may be used
    (``p``'s relation values are then set from the file)."""
    directory = cache.usable_cache_dir() if key else None
    if directory is None:
        return None, None
    h = hashlib.sha256(p.tobytes() + repr((sorted(starts.items()), steady, t0)).encode()).hexdigest()[:24]
    path = cache.entry_path(directory, m.name, f"{key}-init-{h}").with_suffix(".npz")
    try:
        data = cache.load_init(path)
        if data is not None:
            problem = cached_start_problem(m, t0, p, data)
            if problem is not None:
                raise cache.CacheEntryError(path, problem)
            p[:] = data["p"]
            return path, (data["y"].copy(), data["yp"].copy())
    except cache.CacheEntryError as err:
        cache.warn_once(err.path, f"damaged cached initial values ({err.reason}); removing them and "
                                  "initialising afresh")
        cache.discard(err.path)
    return path, None


def store_start(path: Path | None, m: CompiledModel, t0: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> None:
    """Keep a fresh consistent start (with its residual) in ``path`` (nothing without a path)."""
    if path is None:
        return
    try:
        cache.store_init(path, y=y, yp=yp, p=p, residual=np.array([residual_norm(m, t0, y, yp, p)]))
    except OSError as exc:
        cache.warn_once(path, f"cannot store initial values ({exc})")


def residual_norm(m: CompiledModel, t0: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> float:
    """Largest absolute residual of ``m`` at ``(t0, y, yp)``."""
    F = np.asarray(m.function("res")(t0, y, yp, p), dtype=float).ravel()
    return float(np.max(np.abs(F))) if F.size else 0.0


def cached_start_problem(m: CompiledModel, t0: float, p: np.ndarray, data: dict[str, np.ndarray]) -> str | None:
    """Why cached initial values must not be used for a run with parameter vector ``p`` (None: usable)."""
    y, yp, pc, stored = data["y"], data["yp"], data["p"], data["residual"]
    if y.shape != (m.n,) or yp.shape != (m.n,) or pc.shape != p.shape or stored.shape != (1,):
        return "sizes do not match the model"
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(yp)) and np.all(np.isfinite(pc))):
        return "non-finite values"
    trial = np.concatenate([p[:m.n_params], pc[m.n_params:]])  # the run's parameters, cached relations
    residual = residual_norm(m, t0, y, yp, trial)
    limit = max(1e-10, 10.0 * float(stored[0]))
    if not residual <= limit:
        return f"largest residual {residual:.3g} at the run's parameters exceeds {limit:.3g}"
    return None
