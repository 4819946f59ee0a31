"""3D rigid multibody library in the shape of MSL ``Modelica.Mechanics.MultiBody``."""

from .absolute_angular_velocity import AbsoluteAngularVelocity
from .absolute_position import AbsolutePosition
from .absolute_velocity import AbsoluteVelocity
from .body import Body
from .body_box import BodyBox
from .body_cylinder import BodyCylinder
from .body_shape import BodyShape
from .bushing import Bushing
from .cut_force import CutForce
from .cut_torque import CutTorque
from .cylindrical import Cylindrical
from .distance import Distance
from .fixed import Fixed
from .fixed_rotation import FixedRotation
from .fixed_translation import FixedTranslation
from .free_motion import FreeMotion
from .interfaces import Frame, PartialTwoFrames
from .line_force import LineForce
from .prismatic import Prismatic
from .relative_position import RelativePosition
from .relative_velocity import RelativeVelocity
from .revolute import Revolute
from .spherical import Spherical
from .spring_damper_line import SpringDamperLine
from .universal import Universal
from .universal_spherical import UniversalSpherical
from .world import World
from .world_force import WorldForce
from .world_torque import WorldTorque

__all__ = [
    "AbsoluteAngularVelocity",
    "AbsolutePosition",
    "AbsoluteVelocity",
    "Body",
    "BodyBox",
    "BodyCylinder",
    "BodyShape",
    "Bushing",
    "CutForce",
    "CutTorque",
    "Cylindrical",
    "Distance",
    "Fixed",
    "FixedRotation",
    "FixedTranslation",
    "Frame",
    "FreeMotion",
    "LineForce",
    "PartialTwoFrames",
    "Prismatic",
    "RelativePosition",
    "RelativeVelocity",
    "Revolute",
    "Spherical",
    "SpringDamperLine",
    "Universal",
    "UniversalSpherical",
    "World",
    "WorldForce",
    "WorldTorque",
]
