"""The parameters that make a mechanism planar where they are zero: the multibody pass's part of the constant
elimination (:mod:`flexlib.compile.constants`, ``assume_zero_geometry``).

A planar mechanism built from 3D components is planar because some parameters of its frame components are zero
(in-plane components of joint axes, out-of-plane components of rod vectors and centres of mass, products of
inertia, out-of-plane gravity). :func:`frame_parameters` names them for the generic elimination, which decides
which of them to assume zero.
"""

from __future__ import annotations

from flexlib.compile.simplify import SimpleSystem
from flexlib.core.component import Connector

__all__ = ["frame_parameters"]


def frame_parameters(simple: SimpleSystem) -> set[int]:
    """Hashes of the parameters of components with a 3D frame (over-determined connector): joint axes,
    rod vectors, centres of mass, inertia tensors, the direction of gravity — the parameters that make a mechanism
    planar. A component's ``non_geometric_parameters`` are left out (the World's gravity magnitude ``g``: a run
    may change it, and no row is structurally zero because it is)."""
    out = set()
    frame_owner: dict[int, bool] = {}
    for q in simple.flat.parameters:
        key = id(q.node)
        if key not in frame_owner:
            frame_owner[key] = any(isinstance(c, Connector) and c.overdetermined for c in q.node._children.values())
        if frame_owner[key] and q.decl_name not in getattr(q.node, "non_geometric_parameters", ()):
            out.add(q.sym.element_hash())
    return out
