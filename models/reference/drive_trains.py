"""Drive trains with stick/slip friction: MSL's ``Rotational.Examples.CoupledClutches``.

Its reference result (the Modelica Association's, ``tests/data/msl``) is compared in ``tests/msl``; the fixed-step
integrator's tests and ``benchmarks/friction.py`` run it too.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.components.control import Sine, Step
from flexlib.components.mechanics.rotational import Clutch, Fixed, Inertia, Torque

__all__ = ["CoupledClutches"]


class CoupledClutches(fl.Model):
    """``Modelica.Mechanics.Rotational.Examples.CoupledClutches``: a sine torque drives J1 (started at 10 rad/s), three
    clutches couple J1…J4 in series; clutch 1 engaged by a slow cosine (free while it is negative), clutches 2 and
    3 by steps at 0.4 s and 0.9 s.

    Parameters
    ----------
    clutch : callable
        Makes each clutch from MSL's ``peak=1.1, fn_max=20`` [1], [N] (default :class:`Clutch`; a benchmark passes a
        regularised peer with the same connectors).
    """

    def __init__(self, clutch: Callable[..., Any] = Clutch) -> None:
        super().__init__()
        self.J1 = Inertia(J=1.0, init={"phi": 0.0, "w": 10.0})
        self.J2, self.J3, self.J4 = (Inertia(J=1.0, init={"phi": 0.0, "w": 0.0}) for _ in range(3))
        self.torque = Torque(use_support=True)
        self.clutch1, self.clutch2, self.clutch3 = (clutch(peak=1.1, fn_max=20.0) for _ in range(3))
        self.sin1 = Sine(amplitude=10.0, f=5.0)
        self.sin2 = Sine(amplitude=1.0, f=0.2, phase=np.pi / 2)
        self.step1, self.step2 = Step(start_time=0.4), Step(start_time=0.9)
        self.fixed = Fixed()
        self.connect(self.torque.flange, self.J1.flange_a)
        self.connect(self.J1.flange_b, self.clutch1.flange_a)
        self.connect(self.clutch1.flange_b, self.J2.flange_a)
        self.connect(self.J2.flange_b, self.clutch2.flange_a)
        self.connect(self.clutch2.flange_b, self.J3.flange_a)
        self.connect(self.J3.flange_b, self.clutch3.flange_a)
        self.connect(self.clutch3.flange_b, self.J4.flange_a)
        self.connect(self.sin1.y, self.torque.tau)
        self.connect(self.sin2.y, self.clutch1.f_normalized)
        self.connect(self.step1.y, self.clutch2.f_normalized)
        self.connect(self.step2.y, self.clutch3.f_normalized)
        self.connect(self.fixed.flange, self.torque.support)
