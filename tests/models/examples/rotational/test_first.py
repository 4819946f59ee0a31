"""The ``FirstDriveTrain`` example against an independent solve and its energy balance.

References: (1) the same drive train written by hand as a 4-state ODE (Newton–Euler for the
two inertias, gear reflected to the motor shaft) and solved with ``scipy.integrate.solve_ivp``
(DOP853, rtol 1e-12); tolerance 1e-6 relative to the peak of each signal. (2) Energy balance:
motor work = kinetic + spring energy + damper dissipation, with the two integrals evaluated
by Simpson's rule on a 1e-4 s grid; tolerance 1e-5 relative to the motor work.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import cumulative_simpson, solve_ivp

import flexlib as fl
from flexlib.models.examples.rotational.first import FirstDriveTrain

P = {"J_motor": 0.1, "J_load": 2.0, "ratio": 10.0, "c": 1e4, "d": 10.0, "amplitude": 10.0, "f": 5.0}


@pytest.fixture(scope="module")
def result() -> fl.Result:
    model = FirstDriveTrain(**P)
    exp = model.experiment
    assert (exp.t_end, exp.dt_out) == (1.0, 1e-3)
    return fl.Simulation(model, use_cache=False).run(exp.t_end, dt_out=1e-4, rtol=1e-9, atol=1e-11)


def reference(t: np.ndarray) -> np.ndarray:
    J1, J2, n, c, d, A, f = (P[k] for k in ("J_motor", "J_load", "ratio", "c", "d", "amplitude", "f"))

    def rhs(tt: float, x: np.ndarray) -> list[float]:
        phi1, w1, phi2, w2 = x
        tau_shaft = c * (phi2 - phi1 / n) + d * (w2 - w1 / n)
        tau_motor = A * np.sin(2 * np.pi * f * tt)
        return [w1, (tau_motor + tau_shaft / n) / J1, w2, -tau_shaft / J2]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0, 0.0, 0.0], method="DOP853", t_eval=t, rtol=1e-12, atol=1e-14)
    assert sol.success
    return sol.y


def test_matches_independent_ode_solution(result):
    """flexlib's DAE (index 2 through the gear) equals a hand-written ODE solved by scipy."""
    t = np.linspace(0.0, 1.0, 201)
    ref = reference(t)
    for row, name in enumerate(("inertia1.phi", "inertia1.w", "inertia2.phi", "inertia2.w")):
        scale = np.max(np.abs(ref[row]))
        np.testing.assert_allclose(result.value(name, t), ref[row], rtol=0, atol=1e-6 * scale, err_msg=name)


def test_energy_balance(result):
    """Work of the motor = kinetic energy + spring energy + energy dissipated in the damper."""
    t = np.linspace(0.0, 1.0, 10001)
    v = {n: result.value(n, t) for n in ("sine.y", "inertia1.w", "inertia2.w", "spring.phi_rel", "damper.w_rel")}
    work = cumulative_simpson(v["sine.y"] * v["inertia1.w"], x=t, initial=0.0)
    dissipated = cumulative_simpson(P["d"] * v["damper.w_rel"] ** 2, x=t, initial=0.0)
    kinetic = 0.5 * P["J_motor"] * v["inertia1.w"] ** 2 + 0.5 * P["J_load"] * v["inertia2.w"] ** 2
    potential = 0.5 * P["c"] * v["spring.phi_rel"] ** 2
    np.testing.assert_allclose(kinetic + potential + dissipated, work, rtol=0, atol=1e-5 * np.max(np.abs(work)))


def test_default_experiment_runs():
    """``Simulation(model).run()`` uses the class experiment (1 s, 1 ms output)."""
    res = fl.Simulation(FirstDriveTrain(), use_cache=False).run()
    assert res.success
    assert res.t[-1] == pytest.approx(1.0)
    assert len(res.t) == 1001
