"""Engine tests on textbook DAEs written as raw equations (no component library).

References: the exact period of the planar pendulum, T = 4·sqrt(L/g)·K(sin²(θ0/2))
(e.g. Landau & Lifshitz, Mechanics §11, problem 1); rigid-body motion under constant torque.
"""

import casadi as ca
import numpy as np
import pytest
from scipy.special import ellipk

import flexlib as fl
from flexlib import Parameter, Variable, der, eq
from flexlib.models.reference.cartesian_pendulum import CartesianPendulum

THETA0 = 0.5


def _pendulum() -> CartesianPendulum:
    return CartesianPendulum(init={"x": np.sin(THETA0), "u": 0.0}, guess={"y": -np.cos(THETA0)})


def _crossings(t: np.ndarray, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """Upward zero crossings of x by cubic Hermite interpolation between output points."""
    out = []
    for k in np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0)):
        h = t[k + 1] - t[k]
        p0, p1, m0, m1 = x[k], x[k + 1], xd[k] * h, xd[k + 1] * h
        coeffs = [2 * p0 - 2 * p1 + m0 + m1, -3 * p0 + 3 * p1 - 2 * m0 - m1, m0, p0]
        roots = [r.real for r in np.roots(coeffs) if abs(r.imag) < 1e-12 and -1e-9 <= r.real <= 1 + 1e-9]
        out.append(t[k] + h * roots[0])
    return np.array(out)


def test_pendulum_index3_constraint_energy_period():
    """Index-3 pendulum, 10 s at rtol 1e-8: |x²+y²−L²| ≤ 1e-8 (the requested tolerance) at every step, energy
    drift ≤ 1e-6 relative, period = exact large-amplitude period (complete elliptic integral) to 1e-6."""
    sim = fl.Simulation(_pendulum(), use_cache=False)
    rep = sim.report
    assert rep.index == 3
    assert sorted(n for _, _, n in rep.differentiated) == [1, 1, 2]  # der(x)=u, der(y)=v once; constraint twice
    assert len(sim.states) == 2
    steps = sim.run(10.0, rtol=1e-8, atol=1e-10)  # every internal step
    x, y, u, v = (steps[k] for k in "xyuv")
    assert np.max(np.abs(x**2 + y**2 - 1.0)) <= 1e-8
    g = 9.81
    energy = 0.5 * (u**2 + v**2) + g * y
    assert np.max(np.abs(energy - energy[0])) / abs(energy[0]) <= 1e-6
    grid = sim.run(10.0, dt_out=1e-3, rtol=1e-8, atol=1e-10)
    crossings = _crossings(grid.t, grid["x"], grid["u"])
    periods = np.diff(crossings)
    exact = 4.0 * np.sqrt(1.0 / g) * ellipk(np.sin(THETA0 / 2) ** 2)
    assert len(periods) >= 3
    np.testing.assert_allclose(periods, exact, rtol=1e-6)


class TwoRigidInertias(fl.Model):
    """Two inertias whose angles are equal (a rigid coupling) driven by a torque on the first: index 2."""

    J1 = Parameter(1.0, unit="kg.m2", doc="First inertia")
    J2 = Parameter(3.0, unit="kg.m2", doc="Second inertia")
    tau = Parameter(2.0, unit="N.m", doc="Driving torque")
    phi1 = Variable(unit="rad")
    w1 = Variable(unit="rad/s")
    phi2 = Variable(unit="rad")
    w2 = Variable(unit="rad/s")
    tc = Variable(unit="N.m", doc="Coupling torque")

    def equations(self):
        return [
            eq(der(self.phi1), self.w1), eq(self.J1 * der(self.w1), self.tau - self.tc),
            eq(der(self.phi2), self.w2), eq(self.J2 * der(self.w2), self.tc),
            eq(self.phi1, self.phi2),
        ]


def test_rigidly_coupled_inertias_index2():
    """Rigid coupling: w(t) = tau·t/(J1+J2) and tc = J2·tau/(J1+J2) (rigid-body statics), 1e-8."""
    sim = fl.Simulation(TwoRigidInertias(init={"phi1": 0.0, "w1": 0.0}), use_cache=False)
    assert sim.report.index == 2
    assert len(sim.states) == 2
    res = sim.run(2.0, dt_out=0.1, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["w2"], 2.0 * res.t / 4.0, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(res["tc"], 3.0 * 2.0 / 4.0, rtol=1e-8)


def test_state_selection_honours_preference():
    """state_select='prefer' on the second inertia makes its variables the states."""

    class Preferring(TwoRigidInertias):
        phi2 = Variable(unit="rad", state_select="prefer")
        w2 = Variable(unit="rad/s", state_select="prefer")

    sim = fl.Simulation(Preferring(init={"phi2": 0.0, "w2": 0.0}), use_cache=False)
    assert sorted(sim.states) == ["phi2", "w2"]
    res = sim.run(1.0, dt_out=0.5, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["w1"][-1], 0.5, rtol=1e-8)


class PrescribedMass(fl.Model):
    """A mass whose position is prescribed as s = A sin(ωt): the force needs d²/dt² of the source."""

    m = Parameter(2.0, unit="kg")
    A = Parameter(0.1, unit="m")
    omega = Parameter(3.0, unit="rad/s")
    s = Variable(unit="m")
    v = Variable(unit="m/s")
    f = Variable(unit="N")
    s_ref = Variable(unit="m")

    def equations(self):
        return [eq(self.s_ref, self.A * ca.sin(self.omega * fl.time)),
                eq(self.s, self.s_ref), eq(der(self.s), self.v), eq(self.m * der(self.v), self.f)]


def test_prescribed_position_differentiated_twice():
    """f = m·s'' = −m A ω² sin(ωt) (analytic), 1e-6 relative to the amplitude."""
    sim = fl.Simulation(PrescribedMass(), use_cache=False)
    counts = {text: n for _, text, n in sim.report.differentiated}
    assert max(counts.values()) == 2
    res = sim.run(2.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    expected = -2.0 * 0.1 * 9.0 * np.sin(3.0 * res.t)
    np.testing.assert_allclose(res["f"], expected, atol=1e-6 * 1.8)


def test_index_report_names_components():
    """The report names differentiated equations by component path and lists states/dummies."""

    class PendulumHolder(fl.Model):
        def __init__(self):
            super().__init__()
            self.pend = _pendulum()

    sim = fl.Simulation(PendulumHolder(), use_cache=False)
    text = str(sim.report)
    assert "pend:" in text
    assert "pend.x" in sim.states
    assert any(d.startswith("der(pend.") for d in sim.report.dummy_derivatives)


def test_rerun_from_cache(tmp_path, monkeypatch):
    """A second Simulation of the same structure skips stages 1–5 (loaded from the disk cache)."""
    from flexlib.compile import codegen

    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    first = fl.Simulation(_pendulum())
    assert not first.build_info["cached"]
    before = codegen.COMPILE_COUNT[0]
    second = fl.Simulation(_pendulum())
    assert second.build_info["cached"]
    assert codegen.COMPILE_COUNT[0] == before
    r1 = first.run(1.0, dt_out=0.1)
    r2 = second.run(1.0, dt_out=0.1)
    assert not first.init_cached and second.init_cached  # stage 4 is cached too
    np.testing.assert_array_equal(r1.values, r2.values)


def test_codegen_matches_virtual_machine(tmp_path, monkeypatch):
    """C code generation (gcc) gives the same trajectory as CasADi's SX virtual machine (1e-12)."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    vm = fl.Simulation(_pendulum(), codegen=False).run(1.0, dt_out=0.1, rtol=1e-8, atol=1e-10)
    c = fl.Simulation(_pendulum(), codegen=True)
    assert c.compiled.library is not None
    rc = c.run(1.0, dt_out=0.1, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(rc.values, vm.values, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("value", [0.5, 2.0])
def test_parameter_change_reuses_compiled_model(value):
    """Changing a parameter between runs does not recompile: w(1) = tau/(J1+J2)."""
    from flexlib.compile import codegen

    sim = fl.Simulation(TwoRigidInertias(init={"phi1": 0.0, "w1": 0.0}), use_cache=False)
    before = codegen.COMPILE_COUNT[0]
    res = sim.run(1.0, dt_out=0.5, params={"J1": value}, rtol=1e-10, atol=1e-12)
    assert codegen.COMPILE_COUNT[0] == before
    np.testing.assert_allclose(res["w1"][-1], 2.0 / (value + 3.0), rtol=1e-8)
    assert res.parameters["J1"][0] == value


def test_dynamic_state_selection_full_rotations():
    """A Cartesian pendulum looping over the top (u0 = 8 m/s > sqrt(4gL)): x and y both pass through
    zero, so every static choice of states becomes singular. The run re-selects states as it goes;
    |x²+y²−L²| ≤ 1e-8 (10·rtol) at every step and energy drift ≤ 1e-6 relative (conservative system) over 10 s."""
    sim = fl.Simulation(CartesianPendulum(init={"x": 0.0, "u": 8.0}, guess={"y": -1.0}), use_cache=False)
    res = sim.run(10.0, rtol=1e-9, atol=1e-11)
    assert res.stats["state_switches"] >= 4
    assert any(text.startswith("state selection") for _, text in res.events)
    x, y, u, v = (res[k] for k in "xyuv")
    assert np.max(np.abs(x**2 + y**2 - 1.0)) <= 1e-8
    energy = 0.5 * (u**2 + v**2) + 9.81 * y
    assert np.max(np.abs(energy - energy[0])) / abs(energy[0]) <= 1e-6
    turns = np.unwrap(np.arctan2(x, -y))
    assert turns[-1] > 4 * 2 * np.pi  # several full revolutions
