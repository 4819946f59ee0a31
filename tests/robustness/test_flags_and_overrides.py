"""On/off options and single-element parameter overrides given as strings (issue 26).

``bool("False")`` is True: ``Limiter(strict="False")`` switched events off and ``Torque(use_support="no")`` added a
support flange. Every structural flag of the control and mechanics libraries is now read by
``flexlib.core.component.flag``, as the hydraulics library's flags are; an element override
``params={"plant.k[1]": "1.5"}`` went through ``float(np.asarray(..., dtype=float))`` and was accepted.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib import ParameterError, Variable, der, eq
from flexlib.components.control import Limiter, LimPID, RateLimiter, TransferFunction
from flexlib.components.mechanics.rotational import Torque
from flexlib.components.mechanics.translational import Force

FLAGS = [
    (lambda v: Limiter(u_max=1.0, strict=v), "Limiter: strict"),
    (lambda v: RateLimiter(rising=1.0, strict=v), "RateLimiter: strict"),
    (lambda v: LimPID(y_max=1.0, strict=v), "LimPID: strict"),
    (lambda v: LimPID(y_max=1.0, use_feed_forward=v), "LimPID: use_feed_forward"),
    (lambda v: Torque(use_support=v), "Torque: use_support"),
    (lambda v: Force(use_support=v), "Force: use_support"),
]


@pytest.mark.parametrize("value", ["False", "no", None, 2, 0.5])
@pytest.mark.parametrize(("make", "where"), FLAGS, ids=[w for _, w in FLAGS])
def test_flag_given_a_non_bool_is_refused_naming_the_option(make, where, value):
    with pytest.raises(ParameterError, match=rf"{where} must be True or False, got {value!r}"):
        make(value)


@pytest.mark.parametrize(("make", "where"), FLAGS, ids=[w for _, w in FLAGS])
def test_flag_takes_bools_and_0_1(make, where):
    for value in (True, False, 0, 1, np.bool_(True)):
        make(value)


@pytest.mark.parametrize("bad", [{"x": 1.0}.items(), [("x", 1.0)], "x=1"])
def test_transfer_function_start_values_must_be_a_dict(bad):
    with pytest.raises(ParameterError, match=r"TransferFunction: init must be a dict"):
        TransferFunction(b=[1.0], a=[1.0, 1.0], init=bad)


class VectorRatePlant(fl.Model):
    """x' = -k[0] x + k[1]."""

    k = fl.Parameter(np.array([1.0, 2.0]), unit="1/s", shape=2)
    x = Variable()

    def equations(self):
        return [eq(der(self.x), -self.k[0] * self.x + self.k[1])]


@pytest.fixture(scope="module")
def sim():
    return fl.Simulation(VectorRatePlant(init={"x": 0.0}), use_cache=False)


@pytest.mark.parametrize(("value", "why"), [("1.5", "a string"), (True, "a bool"), (None, "None"),
                                            (1 + 2j, "complex"), ([1.0, 2.0], "an array")])
def test_element_override_that_is_not_a_number_is_refused(sim, value, why):
    with pytest.raises(ParameterError, match=rf"k\[1\]: parameter value .*{why}"):
        sim.run(0.1, params={"k[1]": value})


def test_element_override_with_a_number_runs(sim):
    res = sim.run(1.0, params={"k[1]": 3.0}, rtol=1e-9, atol=1e-12)
    assert res["x"][-1] == pytest.approx(3.0 * (1.0 - np.exp(-1.0)), rel=1e-7)
