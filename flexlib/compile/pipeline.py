"""The compiler pipeline: model instance → flat system → simplified system → index-1 DAE → compiled model.

One function, :func:`build`, runs the stages (or loads their product from the disk cache) and returns a
:class:`Build` holding every stage's product, so each can be inspected::

    b = flexlib.build(model)
    b.flat        # stage 1: FlatSystem (variables, equations, parameters) — flexlib.compile.flatten
    b.simple      # stage 2: SimpleSystem after alias elimination, redundant loop rows, frame kinematics
    b.dae         # stage 3: DAE after index reduction (b.dae.structure for state re-selection)
    b.compiled    # stage 5: CompiledModel (CasADi functions, optionally compiled C)
    b.timings     # seconds per stage, ``cached``, ``model_key``

``Simulation``, the state-selection monitor's rebuild (:meth:`Build.analyse`) and the tests all call it.
A build loaded from the cache has only ``compiled`` until :meth:`Build.analyse` runs stages 1–3 again.
:mod:`flexlib.compile.cache` only keys, loads and stores.
"""

from __future__ import annotations

import dataclasses
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from flexlib.compile import cache, cache_key
from flexlib.compile.build_options import BuildOptions
from flexlib.compile.codegen import CompiledModel, compile_dae
from flexlib.compile.constants import assumptions_hold, eliminate_constants
from flexlib.compile.flat_checks import check_balance
from flexlib.compile.flatten import FlatSystem, flatten
from flexlib.compile.gcc import earlier_compile, generate_c
from flexlib.compile.index_reduction import DAE, Structure, reduce_index
from flexlib.compile.passes import key_options
from flexlib.compile.scaling import key_nominals
from flexlib.compile.simplify import SimpleSystem, simplify
from flexlib.core.component import Component
from flexlib.errors import ModelTypeError

__all__ = ["Build", "analyse", "build", "build_key", "check_model", "prepare"]


def check_model(model: Any, where: str) -> Component:
    """``model`` if it is a model instance; otherwise :class:`~flexlib.errors.ModelTypeError` naming what was given
    (a model class gets the hint to instantiate it)."""
    if isinstance(model, Component):
        return model
    if isinstance(model, type) and issubclass(model, Component):
        raise ModelTypeError(f"{where}: model = {model.__name__} is a model class, not a model instance; give an "
                             f"instance such as {model.__name__}() (with its parameters and start values)")
    shown = " ".join(repr(model).split())
    shown = shown if len(shown) <= 60 else shown[:57] + "..."
    raise ModelTypeError(f"{where}: model = {shown} (a {type(model).__name__}) is not a flexlib model instance; give "
                         "an instance of a Model or Component subclass")


@dataclass
class Build:
    """The products of the pipeline's stages for one model.

    Attributes
    ----------
    compiled : CompiledModel
        Stage 5, what the solver needs.
    flat, simple, dae : FlatSystem, SimpleSystem, DAE or None
        Stages 1–3 (None for a build loaded from the disk cache until :meth:`analyse` runs).
    timings : dict
        Wall time [s] per stage (``key``, ``flatten``, ``simplify``, ``index_reduction``, ``compile``,
        ``total``), ``cached`` and ``model_key``.
    cached : bool
        True if ``compiled`` was loaded from the disk cache.
    key : str or None
        The cache key (None without the cache or for a model the key cannot represent).
    options : BuildOptions
        The build's options, resolved (no field None); :meth:`analyse` repeats the build's choices.

    Notes
    -----
    ``model, timings = flexlib.build(root)`` still works: a ``Build`` unpacks and indexes as
    ``(compiled, timings)``.
    """

    compiled: CompiledModel
    flat: FlatSystem | None = None
    simple: SimpleSystem | None = None
    dae: DAE | None = None
    timings: dict[str, Any] = field(default_factory=dict)
    cached: bool = False
    key: str | None = None
    options: BuildOptions = field(default_factory=lambda: BuildOptions().resolved())

    @property
    def assume_zero_geometry(self) -> bool:
        """Whether stage 2 assumed the zero-valued frame parameters zero (:mod:`flexlib.compile.constants`)."""
        return bool(self.options.zero_geometry)

    def __iter__(self) -> Any:
        return iter((self.compiled, self.timings))

    def __getitem__(self, index: int) -> Any:
        return (self.compiled, self.timings)[index]

    def __len__(self) -> int:
        return 2

    def analyse(self, root: Component) -> Build:
        """Run stages 1–3 for ``root`` if they are not in memory (a cached build) and return self."""
        if self.dae is None:
            self.flat, self.simple, self.dae, times = analyse(root, options=self.options)
            self.timings.update({f"{k}_analyse": v for k, v in times.items()})
        return self

    def structure(self, root: Component) -> Structure:
        """The index-reduction structure (stage 3) used by the state-selection monitor."""
        if self.compiled._structure is not None:
            return self.compiled._structure
        return self.analyse(root).dae.structure


#: Background gcc runs this process started, by cache entry: a cached load of the same entry before its library
#: is stored shares that compile (``CompiledModel.library_pending``) instead of writing the C again and starting a
#: second gcc beside it, competing for the cores.
_COMPILING: dict[str, str] = {}


def _updater(entry: Any) -> Any:
    """Store a model again once its library, compiled in the background, has been adopted."""

    def update(model: CompiledModel) -> None:
        try:
            cache.store(entry, model, replace=True)
        except (OSError, cache.CacheEntryError) as exc:
            cache.warn_once(entry, f"cannot store the compiled library in the cache ({exc})")

    return update


def prepare(flat: FlatSystem, params: dict[int, float], *, assume_zero_geometry: bool | None = None) -> SimpleSystem:
    """Stage 2: alias elimination, the domain passes' rewrites (the multibody pass: redundant loop constraints,
    explicit frame kinematics), constant unknowns (``assume_zero_geometry``: see :func:`build`)."""
    simple = simplify(flat)
    for p in flat.passes:
        simple = p.after_simplify(simple, params)
    return eliminate_constants(simple, params, assume_zero_geometry=assume_zero_geometry)


def analyse(root: Component, *, assume_zero_geometry: bool | None = None, options: BuildOptions | None = None
            ) -> tuple[FlatSystem, SimpleSystem, DAE, dict[str, float]]:
    """Stages 1–3: flatten, simplify, reduce the index (with the balance check where it belongs).

    A model with closed kinematic loops is balance-checked after the redundant loop rows are removed
    (stage 2), every other model right after flattening, so the diagnostics name the user's equations.
    ``options`` (None: the environment defaults) and ``assume_zero_geometry`` (replaces ``options.zero_geometry``
    where given): see :func:`build`.
    """
    options = (options or BuildOptions()).resolved()
    if assume_zero_geometry is not None:
        options = dataclasses.replace(options, zero_geometry=bool(assume_zero_geometry))
    times: dict[str, float] = {}
    t = _time.perf_counter()
    flat = flatten(root, check=False, options=options)
    has_loops = any(e.origin == "loop closure" for e in flat.equations)
    if not has_loops:
        check_balance(flat.name, flat.variables, flat.equations)
    times["flatten"] = _time.perf_counter() - t
    t = _time.perf_counter()
    params = {q.sym.element_hash(): q.value for q in flat.parameters}
    simple = prepare(flat, params, assume_zero_geometry=options.zero_geometry)
    if has_loops:
        check_balance(flat.name, simple.variables, simple.equations)
    times["simplify"] = _time.perf_counter() - t
    t = _time.perf_counter()
    dae = reduce_index(simple, params, options.explicit_mode)
    times["index_reduction"] = _time.perf_counter() - t
    return flat, simple, dae, times


def build_key(root: Component, options: BuildOptions) -> str | None:
    """The cache key of ``root``'s build: its structure and the resolved build ``options`` that shape the compiled
    model (those the domain passes read included), not its values; None for a model the key cannot represent."""
    return cache_key.model_key(root, {"codegen": options.codegen, "zero_geometry": bool(options.zero_geometry),
                                      "explicit": options.explicit_mode, **key_options(options),
                                      "nominals": key_nominals(root)})


def _load_entry(entry: Path, root: Component, directory: Path) -> tuple[CompiledModel | None, Path | None]:
    """The cached model at ``entry`` with its pending C library attached, or None (absent, damaged, or built under
    parameter assumptions ``root`` breaks, which also drops the entry)."""
    try:
        model = cache.load(entry)
    except cache.CacheEntryError as err:
        cache.warn_once(err.path, f"damaged cache entry ({err.reason}); removing and rebuilding it")
        if err.path.name.endswith(".so"):
            cache.discard(err.path)
        cache.discard(entry)
        model = None
    if model is not None and not assumptions_hold(model.assumed, root):
        return None, None  # built under parameter assumptions this instance breaks: build it for its own values
    if model is not None and model.wants_c and model.library is None:  # stored before its background gcc finished
        pending = _COMPILING.get(str(entry))
        if pending is None:
            texts = (model.serialized["res"], model.serialized["jac"]) if model.serialized else None
            if texts is not None:  # an earlier process's compile of the same C, finished or under way
                pending = earlier_compile(directory / "lib", texts)
            if pending is None:
                pending = generate_c(model.sx_function("res"), model.sx_function("jac"), directory / "lib",
                                     background=True, serialized=texts)
            _COMPILING[str(entry)] = pending
        model.library_pending = pending  # share this process's compile: no second gcc of the same C
        model.on_library = _updater(entry)
    return model, entry


def _store_entry(entry: Path, model: CompiledModel) -> None:
    """Store a fresh build at ``entry`` (a failure warns once) and register its background C compile."""
    try:
        cache.store(entry, model)
    except (OSError, cache.CacheEntryError) as exc:
        cache.warn_once(entry, f"cannot store the compiled model ({exc}); it is used without caching")
    if model.library_pending is not None:
        model.on_library = _updater(entry)
        _COMPILING[str(entry)] = model.library_pending


def build(root: Component, *, codegen: bool | str = "auto", use_cache: bool = True,
          assume_zero_geometry: bool | None = None, options: BuildOptions | None = None) -> Build:
    """Run stages 1–5, or load their product from the disk cache.

    Parameters
    ----------
    root : Component
        The top-level model.
    codegen : bool or "auto"
        Generate and compile C code; ``"auto"`` lets :func:`flexlib.compile.codegen.compile_dae` decide by
        size.
    use_cache : bool
        Read and write the disk cache (``$FLEXLIB_CACHE_DIR``, default ``~/.cache/flexlib``). A cache
        directory that cannot be used gives one :class:`~flexlib.errors.CacheWarning` and a build without
        the cache; a damaged entry gives one ``CacheWarning`` naming the file and is rebuilt.
    assume_zero_geometry : bool or None
        Treat the zero-valued geometry parameters of frame components (in-plane components of joint axes,
        out-of-plane components of rod vectors and centres of mass, products of inertia, out-of-plane gravity)
        as the constant 0 (Modelica's ``Evaluate=true``), so a planar mechanism built from 3D components loses
        its out-of-plane unknowns (:mod:`flexlib.compile.constants`). The assumptions are recorded in
        ``CompiledModel.assumed``: a run whose ``params`` break one raises
        :class:`~flexlib.errors.StructureChangedError` naming the parameter, and a cached build is rebuilt for
        an instance whose values break one. ``False`` keeps every such parameter a run-time parameter (for
        sweeping an out-of-plane offset or axis tilt with ``run(params=...)``). None (default): True unless
        ``FLEXLIB_ZERO_GEOMETRY=0`` is set. Part of the cache key.
    options : BuildOptions, optional
        All build options as one record, instead of the three keywords (it also holds ``explicit`` and
        ``tree_frames``); a field left None takes its environment default, read once here
        (:meth:`BuildOptions.resolved`). Every option that shapes the compiled model is part of the cache key.

    Returns
    -------
    Build
        Every stage's product (unpacks as ``compiled, timings`` like earlier versions); ``Build.options`` the
        resolved options.

    Raises
    ------
    ModelTypeError
        ``root`` is not a model instance (a model class, a name).
    RunArgumentError
        ``codegen``, ``use_cache`` or ``assume_zero_geometry`` is not one of its accepted values (a string
        such as ``"False"`` is refused, not taken as true); ``options`` is given with one of them or is not a
        BuildOptions; an environment variable behind an option left None holds a value it does not accept.
    """
    check_model(root, "build()")
    for node in root.walk():
        if isinstance(node, Component):
            node.advise()
    options = BuildOptions.from_arguments(codegen, use_cache, assume_zero_geometry, options, "build()").resolved()
    timings: dict[str, Any] = {"cached": False}
    t0 = _time.perf_counter()
    directory = cache.usable_cache_dir() if options.use_cache else None
    key = build_key(root, options) if directory else None
    timings["key"] = _time.perf_counter() - t0
    timings["model_key"] = key
    entry = cache.entry_path(directory, type(root).__name__, key) if key else None
    if entry is not None:
        model, entry = _load_entry(entry, root, directory)
        if model is not None:
            timings["cached"] = True
            timings["total"] = _time.perf_counter() - t0
            return Build(compiled=model, timings=timings, cached=True, key=key, options=options)
    flat, simple, dae, times = analyse(root, options=options)
    timings.update(times)
    t = _time.perf_counter()
    model = compile_dae(flat, simple, dae, codegen=options.codegen, build_dir=directory / "lib" if entry else None)
    timings["compile"] = _time.perf_counter() - t
    model.stats = {"n_flat_equations": len(flat.equations), "n_aliases": simple.n_eliminated,
                   "n_unknowns": model.n, "n_states": int(model.differential.sum()),
                   "jac_nnz": len(model.jac_row), "codegen": model.library is not None}
    if entry is not None:
        _store_entry(entry, model)
    timings["total"] = _time.perf_counter() - t0
    return Build(compiled=model, flat=flat, simple=simple, dae=dae, timings=timings, key=key, options=options)
