"""Test benches shared by the hydraulics tests (models, not tests)."""

from __future__ import annotations

import flexlib as fl
from flexlib.components.control import Step
from flexlib.components.hydraulics import DirectionalValve43, PressureSource, Tank


class ValveBench(fl.Model):
    """4/3 valve between four pressure sources, commanded by a step of the spool command."""

    def __init__(self, p_P: float, p_A: float, p_B: float, u: float, t_step: float = 0.0, **valve) -> None:
        super().__init__()
        self.supply, self.load_A, self.load_B = PressureSource(p=p_P), PressureSource(p=p_A), PressureSource(p=p_B)
        self.tank = Tank()
        self.command = Step(height=u, start_time=t_step)
        self.valve = DirectionalValve43(**valve)
        self.connect(self.command.y, self.valve.u)
        self.connect(self.supply.port, self.valve.port_P)
        self.connect(self.tank.port, self.valve.port_T)
        self.connect(self.load_A.port, self.valve.port_A)
        self.connect(self.load_B.port, self.valve.port_B)
