"""The inertial frame and the uniform gravity field (MSL ``MultiBody.World``)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Component, Parameter, eq
from flexlib.errors import ModelError, ParameterError
from flexlib.units import g_n

from .interfaces import Frame

__all__ = ["World", "gravity_of"]


class World(Component):
    """Inertial frame at the origin and uniform gravity ``g_0 = g·n`` [m/s²] in world coordinates.

    As MSL's ``World``: ``g`` defaults to standard gravity (:data:`flexlib.units.g_n`, 9.80665 m/s²) and ``n`` to
    ``−y``; a model that wants another value says so (``World(g=9.81)``).

    ``frame_b`` is the world frame (a definite orientation root), at rest, its origin's acceleration less gravity
    ``a = −g_0`` (gravity enters the recursive kinematics there, :class:`~.interfaces.Frame`). Bodies find the
    World of their model and use its gravity.

    Connectors
    ----------
    frame_b : Frame
        The world frame.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.MultiBody.World``.
    """

    g = Parameter(g_n, unit="m/s2", min=0.0,
                  doc="Gravity acceleration magnitude (default standard gravity 9.80665, MSL's ``Constants.g_n``)")
    n = Parameter([0.0, -1.0, 0.0], unit="1", shape=3, doc="Direction of gravity resolved in world (normalised)")
    frame_b = Frame(doc="World frame")
    #: Not geometry: the planar-model analysis (``flexlib/compile/constants.py``) never assumes the gravity
    #: magnitude zero, so a run may change it
    non_geometric_parameters = ("g",)

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.definite_root(self.frame_b)

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        n = values.get("n")
        if n is not None and not np.linalg.norm(n) > 1e-12:  # g·n/|n| was NaN: "non-finite values" at initialisation
            raise ParameterError(f"{self.where}: gravity direction n = {np.asarray(n).tolist()} has zero length "
                                 "(for no gravity set g = 0)")

    def gravity(self) -> ca.SX:
        """Gravity acceleration resolved in world [m/s2]."""
        return self.g * self.n / ca.norm_2(self.n)

    def equations(self):
        fb = self.frame_b
        return [eq(fb.r_0, 0.0), eq(fb.T, ca.SX.eye(3)), eq(fb.w, 0.0)]


def gravity_of(component: Component) -> ca.SX:
    """Gravity acceleration (world-resolved) of the model ``component`` belongs to."""
    worlds = [n for n in component.root.walk() if isinstance(n, World)]
    if not worlds:
        raise ModelError(f"{component.path}: the model has no World (it provides gravity and the inertial frame)")
    if len(worlds) > 1:
        raise ModelError(f"{component.path}: the model has {len(worlds)} World components; use one")
    return worlds[0].gravity()
