"""Parts of a truck-mounted concrete-pump boom, each a model of its own with a bench test."""

from .linkage import LeverLink
from .section import BoomSection
from .turret import Turret

__all__ = ["BoomSection", "LeverLink", "Turret"]
