"""Domain compile passes (:mod:`.base` has the interface) and the registry the pipeline reads.

:func:`active_passes` gives, for the nodes of one model, a fresh instance of every registered pass that applies
to one of the model's connector classes. The multibody pass (:mod:`.multibody`: orientation tree, loop
closures, explicit frame kinematics, planar geometry) is registered here; another domain adds its own with
:func:`register`.
"""

from __future__ import annotations

from flexlib.compile.build_options import BuildOptions
from flexlib.compile.passes.base import Pass
from flexlib.compile.passes.multibody import MultibodyPass
from flexlib.core.component import PASS_DECLARATIONS, Connector, Node

__all__ = ["Pass", "active_passes", "key_options", "register", "registered"]

_REGISTERED: list[type[Pass]] = [MultibodyPass]
PASS_DECLARATIONS.append(MultibodyPass.declaration)


def register(pass_cls: type[Pass]) -> type[Pass]:
    """Add a pass class to the pipeline (after those already registered); returns it (usable as a decorator)."""
    if not (isinstance(pass_cls, type) and issubclass(pass_cls, Pass)):
        raise TypeError(f"register(): {pass_cls!r} is not a subclass of flexlib.compile.passes.Pass")
    if pass_cls not in _REGISTERED:
        _REGISTERED.append(pass_cls)
        PASS_DECLARATIONS.append(pass_cls.declaration)
    return pass_cls


def registered() -> tuple[type[Pass], ...]:
    """The registered pass classes, in the order their hooks run."""
    return tuple(_REGISTERED)


def active_passes(nodes: list[Node], options: BuildOptions | None = None) -> list[Pass]:
    """A new instance of each registered pass that applies to a connector class among ``nodes``, each given the
    build's resolved ``options`` (:attr:`Pass.options`; None: :class:`BuildOptions` with the environment defaults)."""
    options = (options or BuildOptions()).resolved()
    classes = {type(n) for n in nodes if isinstance(n, Connector)}
    passes = [cls() for cls in _REGISTERED if any(cls.applies_to(c) for c in classes)]
    for p in passes:
        p.options = options
    return passes


def key_options(options: BuildOptions) -> dict[str, object]:
    """The options every registered pass reads, for the cache key (``options``: the build's, resolved)."""
    out: dict[str, object] = {}
    for cls in _REGISTERED:
        out.update(cls.key_options(options))
    return out
