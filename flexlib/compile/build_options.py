"""How a model is compiled, as one record: :class:`BuildOptions`.

``Simulation(model, build=BuildOptions(explicit=False))`` and ``flexlib.build(model, options=BuildOptions(...))``
take it. A field left None takes its documented default, which an environment variable may set
(:mod:`flexlib.compile.environment`); :meth:`BuildOptions.resolved` reads those defaults once and gives the complete
record that the pipeline passes to every stage that depends on an option (the domain passes, the constant
elimination, the explicit-algebraics stage) and puts into the cache key.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from flexlib.compile.environment import TREE_FRAMES, env_default
from flexlib.compile.explicit import explicit_mode
from flexlib.errors import RunArgumentError

__all__ = ["BuildOptions", "check_build_options"]


@dataclass(frozen=True)
class BuildOptions:
    """How a model is compiled: ``Simulation(model, build=BuildOptions(codegen=False))``.

    Each field left None takes its documented default, which an environment variable may set; :meth:`resolved`
    reads them.

    Attributes
    ----------
    codegen : bool or "auto"
        Generate C for the residual and Jacobian (``"auto"``: above 300 unknowns, compiled in the background).
    use_cache : bool
        Use the disk cache (``$FLEXLIB_CACHE_DIR``, default ``~/.cache/flexlib``).
    zero_geometry : bool or None
        Treat zero-valued geometry parameters of frame components as the constant 0 (default: True unless
        ``FLEXLIB_ZERO_GEOMETRY=0``); see :func:`flexlib.build`.
    explicit : bool, "all" or None
        Solve the explicit algebraic unknowns outside IDA (default: True unless ``FLEXLIB_EXPLICIT=0``;
        ``"all"`` as ``FLEXLIB_EXPLICIT=all``, also those inside IDA's error test); see
        :mod:`flexlib.compile.explicit`.
    tree_frames : {"auto", "tear", "keep"} or None
        Tear the spanning tree's frame equations or keep them (default ``"auto"``, or ``FLEXLIB_TREE_FRAMES``);
        see :mod:`flexlib.compile.passes.multibody.tearing`.
    """

    codegen: bool | str = "auto"
    use_cache: bool = True
    zero_geometry: bool | None = None
    explicit: bool | str | None = None
    tree_frames: str | None = None

    def __post_init__(self) -> None:
        if self.explicit not in (None, True, False, "all"):
            raise RunArgumentError(f"BuildOptions(explicit={self.explicit!r}): must be True, False, 'all' or None")
        if self.tree_frames is not None and self.tree_frames not in TREE_FRAMES:
            raise RunArgumentError(f"BuildOptions(tree_frames={self.tree_frames!r}): must be 'auto', 'tear', "
                                   "'keep' or None")

    @classmethod
    def from_arguments(cls, codegen: Any, use_cache: Any, assume_zero_geometry: Any, build: Any,
                       where: str) -> BuildOptions:
        """The record of a caller's build arguments: the keywords ``codegen``, ``use_cache``,
        ``assume_zero_geometry``, or a record ``build`` given instead of them (``where``: the caller, for messages).

        Raises
        ------
        RunArgumentError
            ``build`` is not a BuildOptions, both the record and a keyword are given, or a value is not one of its
            accepted ones (:func:`check_build_options`).
        """
        if build is None:
            build = cls(codegen, use_cache, assume_zero_geometry)
        else:
            if not isinstance(build, BuildOptions):
                raise RunArgumentError(f"{where}: build = {build!r:.80} is invalid: must be a "
                                       "flexlib.BuildOptions(...)")
            if not (isinstance(codegen, str) and codegen == "auto" and use_cache is True
                    and assume_zero_geometry is None):
                raise RunArgumentError(f"{where}: give the build options either as build=BuildOptions(...) "
                                       "or as keywords, not both")
        check_build_options(build.codegen, build.use_cache, build.zero_geometry, where)
        return build

    def resolved(self) -> BuildOptions:
        """The complete record: every field left None replaced by its environment default, read now
        (:func:`flexlib.compile.environment.env_default`), ``codegen`` and ``use_cache`` normalised.

        Raises
        ------
        RunArgumentError
            An environment variable holds a value its option does not accept.
        """
        codegen = "auto" if isinstance(self.codegen, str) else bool(self.codegen)
        zero = env_default("zero_geometry") if self.zero_geometry is None else bool(self.zero_geometry)
        explicit = env_default("explicit") if self.explicit is None else self.explicit
        tree_frames = env_default("tree_frames") if self.tree_frames is None else self.tree_frames
        return dataclasses.replace(self, codegen=codegen, use_cache=bool(self.use_cache), zero_geometry=zero,
                                   explicit=explicit, tree_frames=tree_frames)

    @property
    def explicit_mode(self) -> str:
        """``"off"``, ``"error-test"`` (only unknowns outside IDA's error test) or ``"all"``: the explicit-algebraics
        stage as :func:`flexlib.compile.explicit.explicit_mode` names it (None: the environment default)."""
        return explicit_mode(self.explicit)


def _bool_option(where: str, name: str, value: Any, allowed: str, allow_none: bool = False) -> None:
    if (value is None and allow_none) or isinstance(value, (bool, np.bool_)):
        return
    raise RunArgumentError(f"{where}: {name} = {value!r} is invalid: must be {allowed} (got a {type(value).__name__}; "
                           "a string such as 'False' would count as true)")


def check_build_options(codegen: Any, use_cache: Any, assume_zero_geometry: Any, where: str = "build()") -> None:
    """Check the build options of :func:`flexlib.build` / ``Simulation(...)``: ``codegen`` True, False or
    ``"auto"``, ``use_cache`` True or False, ``assume_zero_geometry`` True, False or None. A string such as ``"no"``
    or ``"False"`` is refused (it is true in Python: ``codegen="no"`` compiled C, ``use_cache="False"`` used the
    cache). Raises :class:`~flexlib.errors.RunArgumentError` naming the option and the value."""
    if not (isinstance(codegen, str) and codegen == "auto"):
        _bool_option(where, "codegen", codegen, "True, False or 'auto'")
    _bool_option(where, "use_cache", use_cache, "True or False")
    _bool_option(where, "assume_zero_geometry", assume_zero_geometry, "True, False or None", allow_none=True)
