"""Over-determined connectors: the spanning tree of the orientation graph (Modelica spec §9.4).

The orientation of a 3D frame is a record of 9 matrix entries (plus angular velocity) for 3
degrees of freedom. Equating it across every connection would over-determine any closed
kinematic loop. Instead, as in Modelica:

* the *vertices* are the connectors with over-determined potentials;
* *required edges* are the ``branch(a, b)`` declarations of components (a joint computes one
  side's orientation from the other); they must not form loops;
* *optional edges* are the ``connect(a, b)`` statements;
* *definite roots* (``definite_root``) are computed by their component (World); *potential roots*
  (``potential_root``) by a component that has orientation states (a free body), used only for a
  tree that no definite root reaches.

All required edges are taken; optional edges are added while they join different trees (in
declaration order); the others are *broken*: their orientation records are related by the
connector's ``equality_constraint`` (3 equations) instead of full equality. Each tree is then
directed from its root, which tells each component (``rooted``) which side of its branch it
computes from.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import casadi as ca

from flexlib.compile.flatten import FlatEquation
from flexlib.core.component import Component, Connector, Node
from flexlib.errors import ModelError

__all__ = ["OrientationTree", "orientation_tree", "overdetermined_equations", "tell_components"]


@dataclass
class OrientationTree:
    """Result of the spanning-tree construction."""

    depth: dict[int, int] = field(default_factory=dict)
    roots: set[int] = field(default_factory=set)
    tree_edges: list[tuple[Connector, Connector, str]] = field(default_factory=list)
    broken_edges: list[tuple[Connector, Connector, str]] = field(default_factory=list)


def orientation_tree(nodes: list[Node]) -> OrientationTree:
    """Build the spanning forest of over-determined connectors and direct it from its roots."""
    vertices = [n for n in nodes if isinstance(n, Connector) and n.overdetermined]
    result = OrientationTree()
    if not vertices:
        return result
    index = {id(v): k for k, v in enumerate(vertices)}
    parent = list(range(len(vertices) + 1))  # last entry: the virtual super-root of all definite roots
    virtual = len(vertices)

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    adjacency: dict[int, list[int]] = {k: [] for k in range(len(vertices) + 1)}
    definite, potential, required, optional = _declared_edges(nodes, index)
    for k in definite:
        ra, rv = find(k), find(virtual)
        if ra == rv:
            raise ModelError(f"{vertices[k].path}: two definite orientation roots are joined by branches "
                             "(for example two World components rigidly connected)")
        parent[ra] = rv
        adjacency[virtual].append(k)
        adjacency[k].append(virtual)
    for a, b, owner in required:
        ia, ib = index[id(a)], index[id(b)]
        if find(ia) == find(ib):
            raise ModelError(f"{owner.path}: branch({a.path}, {b.path}) closes a loop of rigid branches; "
                             "a kinematic loop must be closed by a connect() between frames")
        parent[find(ia)] = find(ib)
        adjacency[ia].append(ib)
        adjacency[ib].append(ia)
    for a, b, owner_path in optional:
        ia, ib = index[id(a)], index[id(b)]
        if find(ia) != find(ib):
            parent[find(ia)] = find(ib)
            adjacency[ia].append(ib)
            adjacency[ib].append(ia)
            result.tree_edges.append((a, b, owner_path))
        else:
            result.broken_edges.append((a, b, owner_path))

    depth = _directed_depths(adjacency, virtual, definite, potential, vertices, result)
    missing = [v.path for k, v in enumerate(vertices) if k not in depth]
    if missing:
        shown = ", ".join(missing[:8]) + (" …" if len(missing) > 8 else "")
        raise ModelError(f"the orientation of frames {shown} is not determined: connect them to a World "
                         "(or a fixed frame), or to a body that can move freely")
    result.depth = {id(vertices[k]): d for k, d in depth.items() if k != virtual}
    return result


def _declared_edges(nodes: list[Node], index: dict[int, int]) -> tuple[
        list[int], list[tuple[int, int, int]], list[tuple[Connector, Connector, Component]],
        list[tuple[Connector, Connector, str]]]:
    """The definite roots, potential roots (priority, order, vertex), branches and connections of the components."""
    definite: list[int] = []
    potential: list[tuple[int, int, int]] = []  # (priority, order, vertex)
    required: list[tuple[Connector, Connector, Component]] = []
    optional: list[tuple[Connector, Connector, str]] = []
    for node in nodes:
        if not isinstance(node, Component):
            continue
        for conn in node.__dict__.get("_od_roots", []):
            definite.append(index[id(conn)])
        for conn, prio in node.__dict__.get("_od_potential_roots", []):
            potential.append((prio, len(potential), index[id(conn)]))
        for a, b in node.__dict__.get("_od_branches", []):
            required.append((a, b, node))
        for a, b in node._connections:
            if a[0] == "connector" and a[1].overdetermined:
                optional.append((a[1], b[1], node.path))
    return definite, potential, required, optional


def _directed_depths(adjacency: dict[int, list[int]], virtual: int, definite: list[int],
                     potential: list[tuple[int, int, int]], vertices: list[Connector],
                     result: OrientationTree) -> dict[int, int]:
    """Depth of each vertex from its root, by breadth-first search from the definite roots, then the potential ones."""
    depth: dict[int, int] = {}

    def bfs(start: int, d0: int) -> None:
        depth[start] = d0
        queue = deque([start])
        while queue:
            v = queue.popleft()
            for w in adjacency[v]:
                if w not in depth:
                    depth[w] = depth[v] + 1
                    queue.append(w)

    if definite:
        bfs(virtual, -1)
        result.roots.update(id(vertices[k]) for k in definite)
    for _, _, k in sorted(potential):
        if k not in depth:
            bfs(k, 0)
            result.roots.add(id(vertices[k]))
    return depth


def tell_components(nodes: list[Node], tree: OrientationTree) -> None:
    """Give every component the tree's depths and roots, which :meth:`~flexlib.core.component.Component.rooted`
    and :meth:`~flexlib.core.component.Component.is_root` read while the model is flattened."""
    for node in nodes:
        if isinstance(node, Component):
            node.__dict__["_od_depth"] = tree.depth
            node.__dict__["_od_selected_roots"] = tree.roots


def overdetermined_equations(tree: OrientationTree, equations: list[FlatEquation]) -> None:
    """Full equality of over-determined records along tree connections; equality constraints on broken ones."""
    for a, b, owner in tree.tree_edges:
        for name, decl in a._decls.items():
            if getattr(decl, "overdetermined", False):
                diff = a._symbol(name) - b._symbol(name)
                label = f"{a._label(name)} = {b._label(name)}"
                for k in range(diff.numel()):
                    equations.append(FlatEquation(diff.nz[k], owner, label, "connect"))
    for a, b, owner in tree.broken_edges:
        residue = ca.vec(ca.SX(a.equality_constraint(b)))
        label = f"loop closure {a.path} ~ {b.path}"
        for k in range(residue.numel()):
            equations.append(FlatEquation(residue[k], owner, f"{label} [{k}]", "loop closure",
                                          ("orientation", a, b, k)))
