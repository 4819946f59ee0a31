"""MSL's translational examples translated to flexlib, against the Modelica Association's reference results
(as ``test_msl_rotational_examples.py``: rtol 1e-6, every comparison signal within 1e-3 of its range)."""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.control import Sine
from flexlib.components.mechanics.translational import Damper, ElastoGap, Fixed, Force, Mass, Rod, Spring, SpringDamper
from tests.msl.reference import reference, worst_deviation


class ElastoGapExample(fl.Model):
    """``Modelica.Mechanics.Translational.Examples.ElastoGap``: a mass between two spring-dampers and the same mass
    between two elasto-gaps (contact below 1.5 m of compression each side), both released from 2 m."""

    def __init__(self) -> None:
        super().__init__()
        self.fixed = Fixed()
        self.rod1, self.rod2 = Rod(L=2.0), Rod(L=2.0)
        # MSL's start attributes (fixed=false) are guesses here
        self.springDamper1 = SpringDamper(c=10.0, s_rel0=1.0, d=1.5, guess={"s_rel": 1.0})
        self.springDamper2 = SpringDamper(c=10.0, s_rel0=1.0, d=1.5, guess={"s_rel": 1.0})
        self.mass1 = Mass(m=1.0, L=0.0, init={"s": 2.0, "v": 0.0})
        self.elastoGap1 = ElastoGap(c=10.0, s_rel0=1.5, d=1.5, guess={"s_rel": 1.5})
        self.elastoGap2 = ElastoGap(c=10.0, s_rel0=1.5, d=1.5, guess={"s_rel": 1.5})
        self.mass2 = Mass(m=1.0, L=0.0, init={"s": 2.0, "v": 0.0})
        self.connect(self.rod1.flange_b, self.fixed.flange, self.rod2.flange_a)
        self.connect(self.springDamper1.flange_a, self.rod1.flange_a, self.elastoGap1.flange_a)
        self.connect(self.springDamper2.flange_b, self.rod2.flange_b, self.elastoGap2.flange_b)
        self.connect(self.springDamper1.flange_b, self.mass1.flange_a)
        self.connect(self.mass1.flange_b, self.springDamper2.flange_a)
        self.connect(self.elastoGap1.flange_b, self.mass2.flange_a)
        self.connect(self.mass2.flange_b, self.elastoGap2.flange_a)


def test_elasto_gap_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range; while mass 2 is between −0.5 m and 0.5 m both gaps are
    open: no force on it, a constant speed."""
    ref = reference("translational_elasto_gap")
    res = fl.Simulation(ElastoGapExample()).run(5.0, dt_out=0.005, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst
    free = np.abs(res["mass2.s"]) < 0.49
    assert free.any()
    np.testing.assert_allclose(res["elastoGap1.f"][free], 0.0, atol=1e-12)
    np.testing.assert_allclose(res["elastoGap2.f"][free], 0.0, atol=1e-12)


class Oscillator(fl.Model):
    """``Modelica.Mechanics.Translational.Examples.Oscillator``: two 1 kg masses on springs of 10 kN/m driven at
    their resonance (a unit sine at 15.9155 Hz, MSL's default amplitude), the second damped (10 N s/m)."""

    def __init__(self) -> None:
        super().__init__()
        self.mass1 = Mass(m=1.0, L=1.0, init={"s": -0.5, "v": 0.0})
        self.spring1 = Spring(s_rel0=1.0, c=10000.0)
        self.fixed1 = Fixed(s0=1.0)
        self.force1, self.sine1 = Force(), Sine(f=15.9155)
        self.mass2 = Mass(m=1.0, L=1.0, init={"s": -0.5, "v": 0.0})
        self.spring2 = Spring(s_rel0=1.0, c=10000.0)
        self.fixed2 = Fixed(s0=1.0)
        self.force2, self.sine2 = Force(), Sine(f=15.9155)
        self.damper1 = Damper(d=10.0)
        self.connect(self.mass1.flange_b, self.spring1.flange_a)
        self.connect(self.spring1.flange_b, self.fixed1.flange)
        self.connect(self.mass2.flange_b, self.spring2.flange_a, self.damper1.flange_a)
        self.connect(self.damper1.flange_b, self.spring2.flange_b, self.fixed2.flange)
        self.connect(self.sine1.y, self.force1.f)
        self.connect(self.sine2.y, self.force2.f)
        self.connect(self.force1.flange, self.mass1.flange_a)
        self.connect(self.force2.flange, self.mass2.flange_a)


def test_oscillator_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range (the undamped mass's amplitude grows linearly at resonance)."""
    ref = reference("translational_oscillator")
    res = fl.Simulation(Oscillator()).run(1.0, dt_out=0.0005, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst


class DamperExample(fl.Model):
    """``Modelica.Mechanics.Translational.Examples.Damper``: three 1 kg masses thrown at 10 m/s against a damper
    (25 N s/m), the damper beside a spring (1 N/m), and a spring-damper with both."""

    def __init__(self) -> None:
        super().__init__()
        for k in (1, 2, 3):
            setattr(self, f"mass{k}", Mass(m=1.0, L=1.0, init={"s": 3.0, "v": 10.0}))
            setattr(self, f"fixed{k}", Fixed(s0=4.5))
        self.damper1, self.damper2 = Damper(d=25.0), Damper(d=25.0)
        self.spring2 = Spring(s_rel0=1.0, c=1.0)
        self.springDamper3 = SpringDamper(s_rel0=1.0, d=25.0, c=1.0)
        self.connect(self.mass1.flange_b, self.damper1.flange_a)
        self.connect(self.damper1.flange_b, self.fixed1.flange)
        self.connect(self.mass2.flange_b, self.damper2.flange_a, self.spring2.flange_a)
        self.connect(self.damper2.flange_b, self.spring2.flange_b, self.fixed2.flange)
        self.connect(self.mass3.flange_b, self.springDamper3.flange_a)
        self.connect(self.springDamper3.flange_b, self.fixed3.flange)


def test_damper_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range."""
    ref = reference("translational_damper")
    res = fl.Simulation(DamperExample()).run(1.0, dt_out=0.0005, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst
