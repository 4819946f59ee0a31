"""Bad pump-truck design records raise ParameterError naming the field (issue 11)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from flexlib.errors import ParameterError
from flexlib.models.pump_truck.parameters import FourBar, PumpTruckParameters

REC = PumpTruckParameters()


@pytest.mark.parametrize(("k", "mass"), [(2, -5.0), (4, 1e5)], ids=["negative", "too_heavy_for_its_box"])
def test_bad_section_mass_names_field(k, mass):
    sections = list(REC.sections)
    sections[k] = replace(sections[k], mass=mass)
    with pytest.raises(ParameterError, match=rf"sections\[{k}\]\.mass"):
        PumpTruckParameters(sections=tuple(sections))


def test_negative_pipe_mass_names_field():
    with pytest.raises(ParameterError, match=r"pipe\.empty_mass_per_m"):
        replace(REC.pipe, empty_mass_per_m=-1.0)


def test_linkage_that_cannot_close_names_joint():
    links = list(REC.linkages)
    links[1] = replace(links[1], s=0.1)
    with pytest.raises(ParameterError, match=r"linkages\[1\] \(joint 3\) cannot reach its range"):
        PumpTruckParameters(linkages=tuple(links))


def test_linkage_range_through_dead_centre_names_joint():
    links = list(REC.linkages)
    links[0] = replace(FourBar.scaled(3.0, +1), q_min=-0.3)  # lever-link near dead centre
    with pytest.raises(ParameterError, match=r"linkages\[0\] \(joint 2\) cannot reach its range"):
        PumpTruckParameters(linkages=tuple(links))


def test_joint1_range_beyond_transmission_limit_names_joint():
    with pytest.raises(ParameterError, match=r"joint1 cannot reach its range: transmission angle"):
        PumpTruckParameters(joint1=replace(REC.joint1, q_max=1.7))
