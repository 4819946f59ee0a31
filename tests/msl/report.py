"""The figures of the MSL example tests: per translated example, the worst deviation from the Modelica Association's
reference result (fraction of each comparison signal's range), the largest time between a mode switch and the
reference's, and the state events. Run: ``python -m tests.msl.report`` (repository root). Nothing is asserted here;
the tests (``tests/msl``) assert 1e-3 of range and 1e-5 s.
"""

from __future__ import annotations

import flexlib as fl
import tests.msl.test_msl_multibody_examples as mb
import tests.msl.test_msl_rotational_examples as rot
import tests.msl.test_msl_translational_examples as trans
from flexlib.models.reference.drive_trains import CoupledClutches
from tests.msl.reference import flexlib_name, is_discrete, reference, switch_mismatch, worst_deviation


def main() -> None:
    cases = [
        (CoupledClutches(), "rotational_coupled_clutches", 1.5, 0.0005, None),
        (rot.Friction(), "rotational_friction", 3.0, 0.0005, None),
        (rot.OneWayClutchExample(), "rotational_one_way_clutch", 2.0, 0.0005, None),
        (rot.OneWayClutchDisengaged(), "rotational_one_way_clutch_disengaged", 2.0, 0.0005, None),
        (rot.LossyGearDemo(bearing=False), "rotational_lossy_gear_demo1", 0.5, 0.0005, None),
        (rot.LossyGearDemo(bearing=True), "rotational_lossy_gear_demo2", 0.5, 0.0005, None),
        (rot.LossyGearDemo3(), "rotational_lossy_gear_demo3", 1.0, 0.0005, None),
        (rot.SimpleGearShift(), "rotational_simple_gear_shift", 5.0, 0.005, None),
        (trans.FrictionExample(), "translational_friction", 5.0, 0.0005, None),
        (trans.BrakeExample(), "translational_brake", 2.0, 0.0005, None),
        (trans.PreLoad(), "translational_preload", 100.0, 0.05, None),
        (mb.Fourbar2(), "multibody_fourbar2", 5.0, 0.001, None),
    ]
    for model, name, t_end, dt, until in cases:
        try:
            res = fl.Simulation(model).run(t_end, dt_out=dt, rtol=1e-6, progress=False)
        except fl.SolverError as e:
            res = e.result
        ref = reference(name)
        keep = ref["time"] < (until if until else float("inf"))
        if name == "translational_preload":
            keep &= ref["time"] > 1e-6
        cont = {k: v[keep] for k, v in ref.items() if not is_discrete(k)}
        worst = max(worst_deviation(res, cont).values())
        disc = [switch_mismatch(res, name, k, flexlib_name(k), until or float("inf")) for k in ref if is_discrete(k)]
        late = max(disc) if disc else float("nan")
        print(f"{name:40s} worst {worst:.1e} of range  switches within {late:.1e} s  "
              f"state events {res.stats['state_events']}")


if __name__ == "__main__":
    main()
