"""The interface of a domain compile pass: what one connector family teaches the generic compiler.

The generic stages (:mod:`flexlib.compile.flatten`, :mod:`flexlib.compile.simplify`, index reduction, code
generation) know connectors, potentials, flows and equations, and nothing of any physical domain. A domain whose
connectors need more — the multibody frames' orientation tree, their loop closures, their explicit kinematics and
the geometry parameters that make a mechanism planar — supplies it as a :class:`Pass`. The pipeline asks every
registered pass class whether it applies to a connector class of the model (:meth:`Pass.applies_to`) and runs
the hooks of those that do, in registration order, at these points:

=========================  ===================================================================================
hook                       where it runs
=========================  ===================================================================================
``structure(nodes)``       stage 1, before the declarations are read (components may then declare quantities
                           that depend on the structure the pass found, in ``on_structure``)
``broken_connections()``   stage 1, connection equations: connections whose potentials give loop-closure rows
``connection_equations``   stage 1, after the generic connection equations: the pass's own rows
``marks``                  stage 1, after all rows: unknowns kept out of the error test, kinematic intermediates
``after_simplify``         stage 2, after alias elimination: rewrite the simplified system
``geometric_parameters``   stage 2, constant elimination: parameters that may be assumed zero where zero
``key_options(options)``   the disk-cache key: the build options the pass reads
``declaration(node, name)`` a variable the pass declares on a node of its family (a frame's ``v``), asked on demand
                           when a start value or an equation names it before the model is flattened
=========================  ===================================================================================

A new pass subclasses :class:`Pass`, overrides the hooks it needs and is registered with
:func:`flexlib.compile.passes.register`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from flexlib.compile.build_options import BuildOptions
    from flexlib.compile.flatten import FlatEquation
    from flexlib.compile.simplify import SimpleSystem
    from flexlib.core.component import Node
    from flexlib.core.variables import Declaration

__all__ = ["Pass"]


class Pass:
    """A domain pass: hooks the pipeline runs for a model that has one of the connector classes it applies to.

    One instance serves one build (stages 1–2 of one model), so a hook may keep what an earlier hook found
    (the multibody pass keeps its orientation tree from :meth:`structure` for :meth:`connection_equations`).
    Every hook's default does nothing.
    """

    #: Short name shown in reports.
    name: str = ""
    #: The build's options, resolved (no field None), set by :func:`flexlib.compile.passes.active_passes` before
    #: the first hook runs; an option a hook reads must also be named by :meth:`key_options`.
    options: BuildOptions

    @classmethod
    def applies_to(cls, connector_cls: type) -> bool:
        """True if this pass handles models that contain a connector of class ``connector_cls``."""
        return False

    @classmethod
    def declaration(cls, node: Node, name: str) -> tuple[Declaration, str | None] | None:
        """A variable ``name`` this pass declares on ``node`` (a connector of its family) and the name of the
        declaration it follows, or None. Declared through
        :meth:`~flexlib.core.component.Node.add_pass_declaration`: not part of the class's declarations."""
        return None

    @classmethod
    def key_options(cls, options: BuildOptions) -> dict[str, Any]:
        """The values of the build ``options`` (resolved) this pass reads, part of every model's cache key."""
        return {}

    def structure(self, nodes: list[Node]) -> None:
        """Stage 1, before the declarations: find the structure the pass needs (all nodes of the model)."""

    def broken_connections(self) -> set[frozenset[int]]:
        """Stage 1: connections (``frozenset`` of the two connectors' ``id``) whose potentials are related by
        loop-closure rows instead of connection rows."""
        return set()

    def connection_equations(self, equations: list[FlatEquation]) -> None:
        """Stage 1: append the pass's rows for its connectors to ``equations``."""

    def marks(self, nodes: list[Node], equations: list[FlatEquation]) -> tuple[set[int], set[int]]:
        """Stage 1, after all rows: symbol hashes of the unknowns to keep out of IDA's local error test, and of the
        kinematic intermediates (eliminated where a row gives them; :mod:`flexlib.compile.scaling`)."""
        return set(), set()

    def after_simplify(self, simple: SimpleSystem, params: dict[int, float]) -> SimpleSystem:
        """Stage 2, after alias elimination: the rewritten system (``params``: values by symbol hash)."""
        return simple

    def geometric_parameters(self, simple: SimpleSystem) -> set[int]:
        """Stage 2: hashes of the parameters that the constant elimination may assume zero where they are zero."""
        return set()
