"""Bad input to the pump-truck model and its scenarios: ``ParameterError`` naming the argument, the joint and the
bad value (no model is built); the flexible variant is refused with ``NotImplementedError``."""

from __future__ import annotations

import pytest

import flexlib as fl
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


@pytest.mark.parametrize(("modes", "match"), [
    ("all", r"modes must be 'mpf', a count or a mapping of section to mode indices, got 'all'"),
    (0, r"modes must be at least 1 per section, got 0"),
    ({1: [1]}, r"modes must give every section 1-5 \(missing \[2, 3, 4, 5\], unknown \[\]\)"),
    ({k: ["a"] for k in range(1, 6)}, r"modes must map section numbers 1-5 to lists of mode indices"),
])
def test_bad_flexible_modes_are_named(modes, match):
    with pytest.raises(ParameterError, match=match):
        PumpTruck(flexible=True, modes=modes, slewing=False)


def test_a_mode_the_section_does_not_have_is_named():
    with pytest.raises(fl.ModelError, match=r"modes \[999\] are not in the modal data 'pump-truck boom section 5' "
                                            r"\(18 modes: 0\.\.17\)"):
        PumpTruck(flexible=True, modes={1: [1], 2: [1], 3: [1], 4: [1], 5: [999]}, slewing=False)


def test_unknown_scenario_data_is_named():
    with pytest.raises(ParameterError, match=r"scenario 'mine': unknown data speed; known: pose, targets, commands"):
        _factory(Scenario("mine", data={"speed": 2.0}))
