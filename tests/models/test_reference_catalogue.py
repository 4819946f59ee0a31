"""Every model of the reference catalogue (flexlib.models.reference) runs its short case and meets its invariants
and closed-form references within the bounds the catalogue states; each case is registered."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import flexlib as fl
from flexlib import registry
from flexlib.models.reference import CASES
from flexlib.models.reference.closed_form import pendulum_angle, pendulum_period


@pytest.mark.parametrize("name", sorted(CASES))
def test_case_meets_its_invariants_and_references(name):
    case = CASES[name]
    model = case.build()
    run = dict(case.run)
    res = fl.Simulation(model, codegen=False).run(run.pop("t_end"), progress=False, **run)
    errors = case.check(model, res)
    assert set(errors) == set(case.tolerances)
    for key, err in errors.items():
        assert np.isfinite(err) and err <= case.tolerances[key], f"{name}: {key} = {err:.3g}"


def test_every_case_is_registered():
    for name, case in CASES.items():
        entry = registry.get_model(f"reference-{name}")
        assert entry.doc == case.doc


def test_pendulum_angle_is_the_libration():
    """The closed-form angle (Jacobi sn) against solve_ivp of θ'' = −(g/L) sin θ (rtol 1e-12): 1e-9 rad over a
    period, and it returns to θ0 after pendulum_period."""
    L, g, th0 = 0.7, 9.81, 1.2
    t = np.linspace(0.0, 3.0, 61)
    sol = solve_ivp(lambda _, y: [y[1], -g / L * np.sin(y[0])], (0.0, 3.0), [th0, 0.0], t_eval=t, rtol=1e-12,
                    atol=1e-12)
    np.testing.assert_allclose(pendulum_angle(t, L, g, th0), sol.y[0], atol=1e-9)
    assert pendulum_angle(np.array([pendulum_period(L, g, th0)]), L, g, th0)[0] == pytest.approx(th0, abs=1e-9)
