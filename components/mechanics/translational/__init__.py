"""1D translational mechanics after ``Modelica.Mechanics.Translational``.

Connector :class:`Flange` (position ``s`` [m], flow ``f`` [N], positive into the
component); components, sources and sensors with MSL names and equations.
"""

from .acc_sensor import AccSensor
from .constant_force import ConstantForce
from .damper import Damper
from .elasto_gap import ElastoGap
from .fixed import Fixed
from .force import Force
from .force_sensor import ForceSensor
from .friction import Brake, SupportFriction
from .interfaces import Flange
from .mass import Mass
from .mass_with_stop_and_friction import MassWithStopAndFriction
from .position import Position
from .position_sensor import PositionSensor
from .relative_position_sensor import RelativePositionSensor
from .relative_speed_sensor import RelativeSpeedSensor
from .rod import Rod
from .speed import Speed
from .speed_sensor import SpeedSensor
from .spring import Spring
from .spring_damper import SpringDamper

__all__ = [
    "AccSensor",
    "Brake",
    "ConstantForce",
    "Damper",
    "ElastoGap",
    "Fixed",
    "Flange",
    "Force",
    "ForceSensor",
    "Mass",
    "MassWithStopAndFriction",
    "Position",
    "PositionSensor",
    "RelativePositionSensor",
    "RelativeSpeedSensor",
    "Rod",
    "Speed",
    "SpeedSensor",
    "Spring",
    "SpringDamper",
    "SupportFriction",
]
