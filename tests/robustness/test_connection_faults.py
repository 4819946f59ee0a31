"""Connections that cannot hold are named (issue 26, found from outside): two frames fixed in the world connected at
different places raised a raw TypeError ("cannot unpack non-iterable int object") from the redundancy analysis; a
component connected to itself ended in "index reduction did not terminate" without naming anything."""

from __future__ import annotations

import pytest

import flexlib as fl
from flexlib import ConnectError, StructuralSingularityError
from flexlib.components.mechanics.multibody import Fixed, World
from flexlib.components.mechanics.translational import Mass


class TwoFixed(fl.Model):
    def __init__(self, r):
        super().__init__()
        self.world = World()
        self.fixed = Fixed(r=r)
        self.connect(self.world.frame_b, self.fixed.frame_b)


def test_fixed_frames_connected_apart_are_a_connect_error():
    with pytest.raises(ConnectError, match=r"frames fixed in the world are connected but do not coincide "
                                           r"\(world\.frame_b\.r_0 = fixed\.frame_b\.r_0 is off by -1\)"):
        fl.Simulation(TwoFixed([1.0, 0.0, 0.0]), use_cache=False)


def test_fixed_frames_connected_where_they_coincide_run():
    assert fl.Simulation(TwoFixed([0.0, 0.0, 0.0]), use_cache=False).run(0.1).success


class SelfConnected(fl.Model):
    def __init__(self):
        super().__init__()
        self.m = Mass(m=1.0)
        self.connect(self.m.flange_a, self.m.flange_b)


def test_a_component_connected_to_itself_names_the_equations_and_unknowns():
    with pytest.raises(StructuralSingularityError, match=r"(?s)index reduction did not terminate: these equations\n"
                                                         r".*m: \(m\.m\*m\.a\) = 0.*do not determine m\.a.*m\.s"):
        fl.Simulation(SelfConnected(), use_cache=False)
