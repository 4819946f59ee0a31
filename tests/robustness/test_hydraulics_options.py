"""Bad structural options and parameters of the hydraulic chambers, the valve and the cylinder: each raises a
FlexlibError subclass whose message names the component (class or instance path) and the option/parameter."""

from __future__ import annotations

import pytest

import flexlib as fl
from flexlib.components.hydraulics import DirectionalValve43, DoubleActingCylinder, Line, Volume

CYL = {"d_bore": 0.063, "d_rod": 0.036, "stroke": 0.4, "m": 8.0}


@pytest.mark.parametrize(
    ("factory", "error", "match"),
    [(lambda: Volume(V=1e-3, chamber_form="pressures"), fl.ModelError, r"Volume: chamber_form must be one of"),
     (lambda: Line(L=1.0, d=0.01, chamber_form="volume"), fl.ModelError, r"Line: chamber_form must be one of"),
     (lambda: DoubleActingCylinder(chamber_form="", **CYL), fl.ModelError,
      r"DoubleActingCylinder: chamber_form must be one of"),
     (lambda: DoubleActingCylinder(p_amb=-1.0, **CYL), fl.ParameterError,
      r"DoubleActingCylinder: p_amb = -1.0 \[Pa\] is below its minimum"),
     (lambda: DoubleActingCylinder(p_amb=float("nan"), **CYL), fl.ParameterError, r"p_amb"),
     (lambda: DirectionalValve43(ideal_spool=True, Q_nom=-1.0), fl.ParameterError, r"DirectionalValve43: Q_nom")],
    ids=["volume-form", "line-form", "cylinder-form", "p_amb-negative", "p_amb-nan", "ideal-valve-Q_nom"],
)
def test_bad_hydraulic_options(factory, error, match):
    with pytest.raises(error, match=match):
        factory()


def test_p_amb_negative_at_run_time_names_the_instance():
    """A negative ambient pressure given through run(params=...) is refused naming the instance path."""
    from flexlib.components.hydraulics import Tank
    from flexlib.components.mechanics.translational import Fixed

    class CylinderModel(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.tank, self.ground = Tank(), Fixed()
            self.cyl = DoubleActingCylinder(x_start=0.1, **CYL)
            self.connect(self.tank.port, self.cyl.port_A, self.cyl.port_B)
            self.connect(self.ground.flange, self.cyl.flange_a)

    with pytest.raises(fl.ParameterError, match=r"cyl\.p_amb = -5\.0 \[Pa\] is below its minimum"):
        fl.Simulation(CylinderModel(), use_cache=False).run(0.01, params={"cyl.p_amb": -5.0})
