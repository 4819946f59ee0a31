"""Bad input to the pump-truck model and its scenarios: ``ParameterError`` naming the argument, the joint and the
bad value (no model is built); the flexible variant is refused with ``NotImplementedError``."""

from __future__ import annotations

import pytest

from flexlib.errors import ParameterError
from flexlib.models.pump_truck.model import PumpTruck
from flexlib.models.pump_truck.scenarios import _factory
from flexlib.registry import Scenario


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"pose": (0.0, 0.0, 0.0)}, r"pose needs 6 finite angles"),
    ({"pose": (0.0, 0.0, 0.0, float("nan"), 0.0, 0.0)}, r"pose needs 6 finite angles"),
    ({"pose": (0.0, 90.0, 0.0, 0.0, 0.0, 0.0)}, r"pose joint1 = 90\.00 deg is outside its range"),
    ({"pose": (0.0, 0.0, -30.0, 0.0, 0.0, 0.0)}, r"pose joint2 = -30\.00 deg is outside its range"),
    ({"targets": [1, 2]}, r"targets must be a mapping with a time column 't'"),
    ({"targets": {"joint1": [0.0]}}, r"targets must be a mapping with a time column 't'"),
    ({"targets": {"t": [0.0, 2.0, 1.0], "joint1": [0, 1, 2]}}, r"targets\['t'\] must be finite, strictly increasing"),
    ({"targets": {"t": [0.0, 1.0], "joint9": [0, 1]}}, r"targets has unknown joint 'joint9'"),
    ({"targets": {"t": [0.0, 1.0], "joint3": [0.0]}}, r"targets\['joint3'\] needs 2 finite values"),
    ({"targets": {"t": [0.0, 1.0], "joint3": [-10.0, 40.0]}}, r"targets\['joint3'\] leaves the joint's range"),
    ({"commands": {"t": [0.0, 1.0], "joint4": [0.0, 1.5]}}, r"commands\['joint4'\] must stay within -1 \.\.\. 1"),
    ({"commands": {"t": [0.0], "slew": [float("inf")]}}, r"commands\['slew'\] needs 1 finite values"),
    ({"link_plate": -1.0}, r"link_plate must be a positive area"),
    ({"record": "42 m"}, r"record must be a PumpTruckParameters, got str"),
])
def test_bad_model_arguments_name_the_culprit(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        PumpTruck(**kwargs)


def test_flexible_variant_is_refused_clearly():
    with pytest.raises(NotImplementedError, match=r"flexible=True\) is not available yet"):
        PumpTruck(flexible=True)


def test_unknown_scenario_data_is_named():
    with pytest.raises(ParameterError, match=r"scenario 'mine': unknown data speed; known: pose, targets, commands"):
        _factory(Scenario("mine", data={"speed": 2.0}))
