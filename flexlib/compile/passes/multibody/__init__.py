"""The multibody pass: what the compiler needs to know of 3D frames (connectors with an over-determined
orientation record ``T``, ``w`` and an origin ``r_0``).

- :mod:`.kinematics` — which of the frames' and joints' kinematic unknowns IDA's error test leaves out;
- :mod:`.tree` — the spanning tree of the orientation graph (Modelica's ``Connections.branch/root/rooted``),
  the rows equating the records along it and the loop-closure rows where it is broken;
- :mod:`.redundancy` — redundant loop-closure rows found by rank and replaced by zero indeterminate reactions;
- :mod:`.indeterminate` — the variables (cut forces and torques) those dropped rows leave statically indeterminate;
- :mod:`.tearing` — the explicit frame kinematics substituted along the tree, or kept as unknowns in deep
  open chains;
- :mod:`.zero_geometry` — the frame components' parameters that make a mechanism planar where they are zero.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from flexlib.compile.passes.base import Pass
from flexlib.compile.passes.multibody.indeterminate import indeterminate_reactions
from flexlib.compile.passes.multibody.kinematics import (
    acceleration_marks,
    declare_frame_kinematics,
    frame_kinematics_declaration,
    tree_kinematics,
)
from flexlib.compile.passes.multibody.redundancy import remove_redundant
from flexlib.compile.passes.multibody.tearing import tear_or_keep_frames
from flexlib.compile.passes.multibody.tree import (
    OrientationTree,
    orientation_tree,
    overdetermined_equations,
    tell_components,
)
from flexlib.compile.passes.multibody.zero_geometry import frame_parameters

if TYPE_CHECKING:
    from flexlib.compile.build_options import BuildOptions
    from flexlib.compile.flatten import FlatEquation
    from flexlib.compile.simplify import SimpleSystem
    from flexlib.core.component import Node
    from flexlib.core.variables import Declaration

__all__ = ["MultibodyPass"]


class MultibodyPass(Pass):
    """Orientation tree, loop closures, redundant loop rows, frame tearing and planar geometry of 3D frames."""

    name = "multibody"

    def __init__(self) -> None:
        self.tree = OrientationTree()
        self.nodes: list[Node] = []

    @classmethod
    def applies_to(cls, connector_cls: type) -> bool:
        """True for a connector class that declares over-determined potentials (a 3D frame)."""
        return any(getattr(v, "overdetermined", False) for k in connector_cls.__mro__ for v in vars(k).values())

    @classmethod
    def declaration(cls, node: Node, name: str) -> tuple[Declaration, str | None] | None:
        """A frame's ``v``, ``a`` or ``z`` (:func:`.kinematics.frame_kinematics_declaration`)."""
        return frame_kinematics_declaration(node, name, cls.applies_to)

    @classmethod
    def key_options(cls, options: BuildOptions) -> dict[str, Any]:
        return {"tree_frames": options.tree_frames}

    def broken_connections(self) -> set[frozenset[int]]:
        return {frozenset((id(a), id(b))) for a, b, _ in self.tree.broken_edges}

    def structure(self, nodes: list[Node]) -> None:
        self.nodes = nodes
        declare_frame_kinematics(nodes, self.applies_to)
        self.tree = orientation_tree(nodes)
        tell_components(nodes, self.tree)

    def connection_equations(self, equations: list[FlatEquation]) -> None:
        """The rows along the tree and at its loop closures, and the frames' ``v``, ``a``, ``z`` for the roots and
        for joints written with MSL's rows only (:func:`.kinematics.tree_kinematics`)."""
        tree_kinematics(self.nodes, self.tree.depth, self.tree.roots, equations)
        overdetermined_equations(self.tree, equations)

    def marks(self, nodes: list[Node], equations: list[FlatEquation]) -> tuple[set[int], set[int]]:
        """The frames' velocities and accelerations carried along the tree, and the joints' accelerations
        (:func:`.kinematics.acceleration_marks`)."""
        return acceleration_marks(nodes, equations, self.applies_to)

    def after_simplify(self, simple: SimpleSystem, params: dict[int, float]) -> SimpleSystem:
        """Redundant loop rows removed (:mod:`.redundancy`), then the frame kinematics torn or kept
        (:mod:`.tearing`) and the reactions the dropped rows leave indeterminate found (:mod:`.indeterminate`)."""
        simple = tear_or_keep_frames(remove_redundant(simple, params), params, self.options.tree_frames)
        return indeterminate_reactions(simple, params)

    def geometric_parameters(self, simple: SimpleSystem) -> set[int]:
        return frame_parameters(simple)
