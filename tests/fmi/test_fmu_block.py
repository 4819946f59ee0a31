"""A co-simulation FMU as a block of a flexlib model (``flexlib.fmi.FMU``, issue 32): a controller delivered as an
FMU driving a flexlib model, tested with a unit flexlib exported itself.

References and tolerances: an integrator unit (``y = ∫u dt``, exported with h = 1 ms) sampled every T = 10 ms and
driven by a sine: its held output is the left Riemann sum of the sampled input, one sample late (the co-simulation
master's Jacobi order), ``y_k = T·Σ_{j<k} u(t_j)``, to 1e-8; closed around ``x' = −y`` (``x'' = −x`` with the loop
sampled: ``x = cos t`` as T → 0) the deviation from ``cos t`` over one period falls linearly with T (the ratio of two
halvings 1.8 … 2.2) and is below 0.04 at T = 10 ms.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib import Input, Output, Variable, der, eq
from flexlib.components.control import Sine
from flexlib.fmi import FMU, export_fmu

pytest.importorskip("fmpy")


class Integrator(fl.Model):
    """The controller: ``y = ∫ u dt``."""

    u = Input(unit="1", start=0.0)
    y = Output(unit="1")
    x = Variable(unit="1", start=0.0, fixed=True)

    def equations(self):
        return [eq(der(self.x), self.u), eq(self.y, self.x)]


@pytest.fixture(scope="module")
def integrator_unit(tmp_path_factory):
    return export_fmu(fl.Simulation(Integrator()), tmp_path_factory.mktemp("fmu") / "integrator.fmu", h=1e-3)


class Driven(fl.Model):
    def __init__(self, unit, step):
        super().__init__()
        self.src = Sine(amplitude=1.0, f=1.0)
        self.ctl = FMU(unit, step=step)
        self.connect(self.src.y, self.ctl.u)


class Closed(fl.Model):
    """``x' = −y``, ``y`` the unit's integral of ``x``."""

    x = Variable(unit="1", start=1.0, fixed=True)
    out = Output(unit="1")

    def __init__(self, unit, step):
        super().__init__()
        self.ctl = FMU(unit, step=step)
        self.connect(self.out, self.ctl.u)

    def equations(self):
        return [eq(der(self.x), -self.ctl.y), eq(self.out, self.x)]


def test_the_block_has_the_units_inputs_and_outputs(integrator_unit):
    block = FMU(integrator_unit, step=0.01)
    assert block.fmi_names == {"u": ("u", 0, "input"), "y": ("y", 1, "output")}
    assert block.step == 0.01 and FMU(integrator_unit).step == 1e-3  # default: the unit's stepSize


def test_sampled_output_is_the_left_riemann_sum_one_sample_late(integrator_unit):
    T = 0.01
    res = fl.Simulation(Driven(integrator_unit, T)).run(1.0, dt_out=T, progress=False)
    assert res.stats["samples"] == 101
    t = np.arange(100) * T
    expected = np.concatenate([[0.0], np.cumsum(T * np.sin(2 * np.pi * t))[:-1]])
    held = res.value("ctl.y", t)  # at each sample: the right value, held until the next
    assert np.max(np.abs(held - expected)) < 1e-8


def test_a_loop_closed_through_the_block_converges_to_the_continuous_loop(integrator_unit):
    errors = []
    for T in (0.01, 0.005):
        res = fl.Simulation(Closed(integrator_unit, T)).run(2 * np.pi, dt_out=0.01, progress=False)
        errors.append(np.max(np.abs(res["x"] - np.cos(res.t))))
    assert errors[0] < 0.04
    assert 1.8 < errors[0] / errors[1] < 2.2


def test_not_a_unit_is_refused_by_name(tmp_path):
    bad = tmp_path / "not.fmu"
    bad.write_bytes(b"not a zip")
    with pytest.raises(fl.ModelError, match="not a readable FMI unit"):
        FMU(bad)
