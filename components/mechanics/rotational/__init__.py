"""1D rotational mechanics after ``Modelica.Mechanics.Rotational``.

Connector :class:`Flange` (angle ``phi`` [rad], flow ``tau`` [N.m], positive into the
component); components, sources and sensors with MSL names and equations.
"""

from .acc_sensor import AccSensor
from .angle_sensor import AngleSensor
from .constant_torque import ConstantTorque
from .damper import Damper
from .elasto_backlash import ElastoBacklash, ElastoBacklash2
from .fixed import Fixed
from .friction import BearingFriction, Brake, Clutch, OneWayClutch
from .ideal_gear import IdealGear
from .ideal_planetary import IdealPlanetary
from .inertia import Inertia
from .interfaces import Flange
from .lossy_gear import LossyGear
from .position import Position
from .quadratic_speed_dependent_torque import QuadraticSpeedDependentTorque
from .relative_angle_sensor import RelativeAngleSensor
from .relative_speed_sensor import RelativeSpeedSensor
from .speed import Speed
from .speed_sensor import SpeedSensor
from .spring import Spring
from .spring_damper import SpringDamper
from .torque import Torque
from .torque_sensor import TorqueSensor
from .torque_step import TorqueStep

__all__ = [
    "AccSensor",
    "AngleSensor",
    "BearingFriction",
    "Brake",
    "Clutch",
    "ConstantTorque",
    "Damper",
    "ElastoBacklash",
    "ElastoBacklash2",
    "Fixed",
    "Flange",
    "IdealGear",
    "IdealPlanetary",
    "Inertia",
    "LossyGear",
    "OneWayClutch",
    "Position",
    "QuadraticSpeedDependentTorque",
    "RelativeAngleSensor",
    "RelativeSpeedSensor",
    "Speed",
    "SpeedSensor",
    "Spring",
    "SpringDamper",
    "Torque",
    "TorqueSensor",
    "TorqueStep",
]
