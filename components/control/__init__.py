"""Signal blocks and controllers after ``Modelica.Blocks``: sources (``Constant``, ``Step``, ``Ramp``, ``Sine``)
and math (``Gain``, ``Add``, ``Feedback``). Outputs are named ``y``, inputs ``u`` / ``u1``, ``u2``.
"""

from .add import Add
from .constant import Constant
from .feedback import Feedback
from .gain import Gain
from .ramp import Ramp
from .sine import Sine
from .step import Step

__all__ = ["Add", "Constant", "Feedback", "Gain", "Ramp", "Sine", "Step"]
