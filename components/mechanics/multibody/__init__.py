"""3D rigid multibody library in the shape of MSL ``Modelica.Mechanics.MultiBody``."""

from .body import Body
from .fixed import Fixed
from .fixed_translation import FixedTranslation
from .interfaces import Frame, PartialTwoFrames
from .revolute import Revolute
from .world import World

__all__ = ["Body", "Fixed", "FixedTranslation", "Frame", "PartialTwoFrames", "Revolute", "World"]
