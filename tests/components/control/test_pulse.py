"""Tests of ``Pulse`` (MSL ``Modelica.Blocks.Sources.Pulse``).

Reference: MSL's definition written with numpy — ``offset + amplitude`` while the phase ``(time − start_time) mod
period`` is below ``width/100 · period``, within ``nperiod`` periods from ``start_time``, else ``offset``. Every edge is
a time event, so the output matches exactly on a dyadic output grid (edges exact in floating point).
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Pulse
from tests.components.control.signals import right_values

DT = 1.0 / 64.0


def reference(t: np.ndarray, amplitude: float, width: float, period: float, nperiod: int, offset: float,
              start_time: float) -> np.ndarray:
    s = t - start_time
    count = np.floor(s / period)
    phase = s - count * period
    on = (s >= 0) & (count < nperiod) & (phase < width / 100 * period)
    return offset + np.where(on, amplitude, 0.0)


CASES = {
    "half": {"amplitude": 1.0, "width": 50.0, "period": 0.5, "nperiod": 3, "offset": 0.0, "start_time": 0.25},
    "quarter": {"amplitude": -2.0, "width": 25.0, "period": 1.0, "nperiod": 2, "offset": 0.5, "start_time": 0.0},
}


class Pulses(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        for name, kw in CASES.items():
            setattr(self, name, Pulse(**kw))


def test_pulse_matches_msl_definition():
    """Both pulses equal the definition at every output time (right values at the edges), to 1e-12."""
    res = fl.Simulation(Pulses(), use_cache=False).run(3.0, dt_out=DT, rtol=1e-8, atol=1e-10, progress=False)
    for name, kw in CASES.items():
        t, y = right_values(res, f"{name}.y")
        np.testing.assert_allclose(y, reference(t, **kw), atol=1e-12, err_msg=name)


@pytest.mark.parametrize("nperiod", [-1, 1.5, "2", True])
def test_pulse_needs_a_whole_number_of_periods(nperiod):
    """MSL's infinitely many periods (−1), a fraction, a string or a bool: refused naming the block."""
    with pytest.raises(fl.ModelError, match="Pulse: nperiod"):
        Pulse(period=1.0, nperiod=nperiod)
