"""Component libraries of flexlib (installed as ``flexlib.components``).

``control`` (signal sources, math and controllers, after ``Modelica.Blocks``),
``mechanics`` (1D rotational and translational, 3D multibody, after ``Modelica.Mechanics``)
and ``hydraulics`` (isothermal-liquid hydraulics with mass-flow ports).
"""

from . import control, hydraulics, mechanics

__all__ = ["control", "hydraulics", "mechanics"]
