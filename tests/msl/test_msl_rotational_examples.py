"""MSL's rotational examples translated to flexlib, against the Modelica Association's reference results.

Each example is written as MSL writes it (same parameters, start values and experiment) and run at rtol 1e-6, the
reference's tolerance; every comparison signal must stay within 1e-3 of its range of the reference over the whole
run (issue 31), compared at the reference's output times. The reference data and their source:
``tests/data/msl/README.md``.
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.rotational import ElastoBacklash, Fixed, Inertia, SpringDamper
from tests.msl.reference import reference, worst_deviation


class Backlash(fl.Model):
    """``Modelica.Mechanics.Rotational.Examples.Backlash`` (without ``elastoBacklash2``, MSL's event-driven variant):
    two inertias of 5 kg m² released at 90° on a spring-damper and on the same spring-damper with 45° backlash."""

    def __init__(self) -> None:
        super().__init__()
        self.fixed1, self.fixed2 = Fixed(), Fixed()
        self.springDamper = SpringDamper(c=20e3, d=50.0)
        self.elastoBacklash = ElastoBacklash(c=20e3, d=50.0, b=np.pi / 4)
        self.inertia1 = Inertia(J=5.0, init={"phi": np.pi / 2, "w": 0.0})
        self.inertia2 = Inertia(J=5.0, init={"phi": np.pi / 2, "w": 0.0})
        self.connect(self.fixed1.flange, self.springDamper.flange_a)
        self.connect(self.springDamper.flange_b, self.inertia1.flange_a)
        self.connect(self.fixed2.flange, self.elastoBacklash.flange_a)
        self.connect(self.elastoBacklash.flange_b, self.inertia2.flange_a)


def test_backlash_matches_the_msl_reference():
    """Every comparison signal within 1e-3 of its range; the backlash's contact phases are state events (the
    reference leaves and enters contact at 0.0262 s and 0.0380 s: no torque between them, a constant speed)."""
    ref = reference("rotational_backlash")
    res = fl.Simulation(Backlash()).run(1.0, dt_out=0.0005, rtol=1e-6, progress=False)
    worst = worst_deviation(res, ref)
    assert max(worst.values()) < 1e-3, worst
    free = (res.t > 0.0263) & (res.t < 0.0379)
    np.testing.assert_allclose(res["elastoBacklash.tau"][free], 0.0, atol=1e-12)
    assert np.ptp(res["elastoBacklash.w_rel"][free]) < 1e-9
