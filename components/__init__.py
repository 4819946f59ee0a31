"""Component libraries of flexlib (installed as ``flexlib.components``).

``blocks`` (signal sources and math, after ``Modelica.Blocks``) and ``mechanics`` (1D
rotational and translational mechanics, after ``Modelica.Mechanics``).
"""

from . import blocks, mechanics

__all__ = ["blocks", "mechanics"]
