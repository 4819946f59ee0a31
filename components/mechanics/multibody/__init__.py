"""3D rigid multibody library in the shape of MSL ``Modelica.Mechanics.MultiBody``."""

from .body import Body
from .fixed import Fixed
from .fixed_translation import FixedTranslation
from .interfaces import Frame, PartialTwoFrames
from .prismatic import Prismatic
from .revolute import Revolute
from .spherical import Spherical
from .world import World

__all__ = ["Body", "Fixed", "FixedTranslation", "Frame", "PartialTwoFrames", "Prismatic", "Revolute", "Spherical",
           "World"]
