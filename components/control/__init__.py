"""Signal blocks and controllers after ``Modelica.Blocks``: sources, math, nonlinear blocks, linear systems, LimPID.

Sources ``Constant``, ``Step``, ``Ramp``, ``Trapezoid``, ``Pulse``, ``Sine``, ``TimeTable``, ``KinematicPTP``;
math ``Gain``, ``Add``, ``Feedback``, ``Product``; nonlinear ``Limiter``, ``RateLimiter``, ``DeadZone``, ``Hysteresis``,
``Switch``, ``Tare``; the start-found offset ``Trim``; continuous ``Integrator``, ``FirstOrder``,
``TransferFunction``, ``LimPID``. Outputs are named ``y``, inputs ``u`` / ``u1``, ``u2``, ``u3`` (``u_s``, ``u_m`` on
the PID).
"""

from .add import Add
from .constant import Constant
from .dead_zone import DeadZone
from .feedback import Feedback
from .first_order import FirstOrder
from .gain import Gain
from .hysteresis import Hysteresis
from .integrator import Integrator
from .kinematic_ptp import KinematicPTP
from .lim_pid import LimPID
from .limiter import Limiter
from .product import Product
from .pulse import Pulse
from .ramp import Ramp
from .rate_limiter import RateLimiter
from .sine import Sine
from .step import Step
from .switch import Switch
from .tare import Tare
from .time_table import TimeTable
from .transfer_function import TransferFunction
from .trapezoid import Trapezoid
from .trim import Trim

__all__ = [
    "Add",
    "Constant",
    "DeadZone",
    "Feedback",
    "FirstOrder",
    "Gain",
    "Hysteresis",
    "Integrator",
    "KinematicPTP",
    "LimPID",
    "Limiter",
    "Product",
    "Pulse",
    "Ramp",
    "RateLimiter",
    "Sine",
    "Step",
    "Switch",
    "Tare",
    "TimeTable",
    "TransferFunction",
    "Trapezoid",
    "Trim",
]
