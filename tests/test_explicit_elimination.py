"""Explicit algebraic unknowns eliminated after index reduction (``flexlib/compile/explicit.py``).

Every comparison is against the same model built with the stage off (``FLEXLIB_EXPLICIT=0``), integrated at the
same tolerances: the two DAEs differ only by exact substitutions, so they agree to the integration tolerance.
"""

from __future__ import annotations

import re
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq, if_else
from flexlib.compile.explicit import eliminate_explicit_algebraics
from flexlib.models.planar_mechanisms import FourBarLinkage

ROOT = Path(__file__).resolve().parent.parent


def build_pair(factory, monkeypatch, mode: str = "1") -> tuple[fl.Simulation, fl.Simulation]:
    """(stage off, stage in ``mode``) simulations of fresh instances, without the disk cache."""
    monkeypatch.setenv("FLEXLIB_EXPLICIT", "0")
    off = fl.Simulation(factory(), use_cache=False)
    monkeypatch.setenv("FLEXLIB_EXPLICIT", mode)
    on = fl.Simulation(factory(), use_cache=False)
    return off, on


def test_fourbar_results_equal_and_eliminated_variables_by_name(monkeypatch, tmp_path):
    """Four-bar of four revolutes, 2 s at rtol 1e-8: the stage removes unknowns (cut forces, accelerations, the
    frames' kinematic intermediates) and leaves every other unknown of the error test in it. Absolute link angles
    of both builds are within 2e-5 rad of the minimal-coordinate ODE
    (``flexlib.models.reference.planar_minimal``, CVODE at rtol 1e-12; measured 1.8e-6 without and 4.6e-6
    with the stage: the global error of the DAE at this tolerance). Every eliminated variable, read by
    name from the result and from its HDF5 file, agrees with the build without the stage to 1e-3 of its range
    (forces and accelerations carry that global error, amplified near the transmission-angle extremes)."""
    from flexlib.models.planar_mechanisms import fourbar_spec
    from flexlib.models.reference.planar_minimal import MinimalODE

    off, on = build_pair(FourBarLinkage, monkeypatch)
    eliminated = on.compiled.report.explicit
    assert eliminated and on.compiled.n == off.compiled.n - len(eliminated)
    assert not set(eliminated) & set(on.compiled.y_names)
    in_test = [{n for n, lev in zip(m.y_names, m.derivative_level, strict=True) if not lev}
               for m in (off.compiled, on.compiled)]
    # the tested unknowns it removes are the frames' kinematic intermediates (velocity and accelerations carried
    # along the tree, ``Variable(intermediate=True)``); every other tested unknown stays
    assert in_test[1] <= in_test[0]
    removed = in_test[0] - in_test[1]
    assert removed <= set(eliminated)
    assert all(re.search(r"frame_\w+\.[vaz]\[\d\]$", n) for n in removed), sorted(removed)
    kw = {"dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10, "progress": False}
    a = off.run(2.0, **kw)
    b = on.run(2.0, result_file=tmp_path / "fourbar.h5", **kw)
    grid = np.linspace(0.0, 2.0, 201)
    ref = MinimalODE(fourbar_spec()).solve(grid, rtol=1e-12)["q"]
    for sim, res in ((off, a), (on, b)):
        q = sim.model.absolute_angles(res)
        for name in ref:
            np.testing.assert_allclose(np.interp(grid, res.t, q[name]), ref[name], rtol=0, atol=2e-5)
    stored = fl.load_result(tmp_path / "fourbar.h5")
    for name in eliminated:
        want = a.value(name, grid)
        scale = 1e-3 * max(1.0, float(np.abs(want).max()))
        np.testing.assert_allclose(b.value(name, grid), want, rtol=0, atol=scale, err_msg=name)
        # the file derives it from the stored rows, the parameters folded into the expression as constants: the
        # same value to round-off (issue 29: 1e-12 relative)
        np.testing.assert_allclose(stored[name], b[name], rtol=1e-12, atol=1e-12 * np.abs(b[name]).max())
    assert "Explicit algebraics eliminated" in str(on.compiled.report)


def _servo():
    from flexlib.models.reference.hydraulic_servo import HydraulicServo

    return HydraulicServo()


@pytest.mark.parametrize("mode", ["1", "all"])
def test_hydraulic_servo_with_events_results_equal(monkeypatch, mode):
    """Pump, relief valve, 4/3 valve, cylinder into its end stops, PID (state and time events), 6 s at rtol 1e-7:
    the piston position agrees with the build without the stage to 1e-6 m (stroke 0.2 m) and the chamber
    pressure to 1e-4 relative; the events are the same. ``all`` also eliminates unknowns that were in the
    error test (flows), so it is compared at the same tolerance."""
    off, on = build_pair(_servo, monkeypatch, mode)
    assert on.compiled.report.explicit and on.compiled.n < off.compiled.n
    kw = {"dt_out": 0.01, "rtol": 1e-7, "atol": 1e-9, "progress": False}
    a, b = off.run(6.0, **kw), on.run(6.0, **kw)
    assert a.stats["state_events"] > 0 and [e for _, e in a.events] == [e for _, e in b.events]
    np.testing.assert_allclose([t for t, _ in b.events], [t for t, _ in a.events], rtol=0, atol=1e-5)
    grid = np.linspace(0.0, 6.0, 601)
    np.testing.assert_allclose(b.value("cylinder.x", grid), a.value("cylinder.x", grid), rtol=0, atol=1e-6)
    p_a = a.value("cylinder.p_A", grid)
    np.testing.assert_allclose(b.value("cylinder.p_A", grid), p_a, rtol=0, atol=1e-4 * np.abs(p_a).max())


class StopOscillator(fl.Model):
    """Mass on a spring with a contact stop at x = −x_stop (a state event): f = −k·x is given explicitly by its
    row with coefficient 1, so ``FLEXLIB_EXPLICIT=all`` eliminates it (it is a position-level unknown, in the
    error test, which the default keeps)."""

    k = Parameter(4.0, unit="N/m")
    m = Parameter(2.0, unit="kg")
    x_stop = Parameter(0.2, unit="m")
    c_stop = Parameter(1e4, unit="N/m")
    x = Variable(unit="m")
    v = Variable(unit="m/s")
    f = Variable(unit="N", doc="Spring force")
    fc = Variable(unit="N", doc="Stop force")

    def equations(self):
        return [eq(der(self.x), self.v),
                eq(self.m * der(self.v), self.f + self.fc),
                eq(self.f, -self.k * self.x),
                eq(self.fc, if_else(self.x < -self.x_stop, -self.c_stop * (self.x + self.x_stop), 0.0))]


def test_fixed_start_on_an_eliminated_variable_becomes_a_condition_on_the_others(monkeypatch):
    """``f`` eliminated (``FLEXLIB_EXPLICIT=all``) with a fixed start value f(0) = 1.2 N: the initial condition
    becomes x(0) = −f/k = −0.3 m. Reference: the build without the stage, which has f as an unknown; x(0)
    exact to 1e-12, trajectories (with the stop contact events; x up to 3.5 m) to 1e-6 m, forces to the
    stiffness times that."""
    off, on = build_pair(lambda: StopOscillator(init={"f": 1.2, "v": 0.0}), monkeypatch, "all")
    assert "f" in on.compiled.report.explicit and "f" not in on.compiled.y_names and "f" in off.compiled.y_names
    kw = {"dt_out": 0.01, "rtol": 1e-9, "atol": 1e-11, "progress": False}
    a, b = off.run(3.0, **kw), on.run(3.0, **kw)
    assert b["f"][0] == pytest.approx(1.2, abs=1e-12) and b["x"][0] == pytest.approx(-0.3, abs=1e-12)
    assert b.stats["state_events"] > 0
    grid = np.linspace(0.0, 3.0, 301)
    for name, tol in (("x", 1e-6), ("f", 4.0 * 1e-6), ("fc", 1e4 * 1e-6)):  # forces: stiffness × 1e-6 m
        np.testing.assert_allclose(b.value(name, grid), a.value(name, grid), rtol=0, atol=tol, err_msg=name)


def test_jacobian_never_denser_on_a_serial_chain(monkeypatch):
    """N-link pendulum, N = 10: the chain where eliminating every explicit unknown made the Jacobian dense
    (``tearing.eliminate_explicit``). With the fill criterion the Jacobian keeps at most its nonzeros and the
    last joint angle agrees with the build without the stage to 1e-7 rad over 1 s at rtol 1e-8."""
    from flexlib.models.n_link_pendulum import NLinkPendulum

    for mode in ("1", "all"):
        off, on = build_pair(lambda: NLinkPendulum(10), monkeypatch, mode)
        assert on.compiled.n < off.compiled.n
        assert len(on.compiled.jac_row) <= len(off.compiled.jac_row)
    kw = {"dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10, "progress": False}
    off.compiled.wait_for_library()
    on.compiled.wait_for_library()
    a, b = off.run(1.0, **kw), on.run(1.0, **kw)
    np.testing.assert_allclose(b["joint10.phi"], a["joint10.phi"], rtol=0, atol=1e-7)


def test_selection_rules_on_a_small_system():
    """Rows ``v1 − x``, ``v2 − v1·sin(x)``, ``2w − v2`` give v1, v2 explicitly (in dependency order);
    ``x·v3 − 1`` (division by a variable) and ``v4 − sqrt(x)`` (an operation that can fail) define nothing; the
    protected w stays. The rows used as definitions then hold exactly (1e-15)."""
    y = ca.SX.sym("y", 6)
    yp = ca.SX.sym("yp", 6)
    x, v1, v2, v3, v4, w = (y[k] for k in range(6))
    rows = [yp[0] - v2 - v3**2 - v4 * w,    # the state x
            v1 - x, v2 - v1 * ca.sin(x), x * v3 - 1.0, v4 - ca.sqrt(x), 2.0 * w - v2]
    differential = np.array([True, False, False, False, False, False])
    protected = np.array([False, False, False, False, False, True])
    kept, elim, values, new = eliminate_explicit_algebraics(rows, y, yp, differential, protected)
    assert sorted(elim) == [1, 2] and {0, 3, 4} <= set(kept) and len(kept) == 4
    # the rows used as definitions hold exactly at any point once the definitions are substituted
    point = ca.substitute([ca.vertcat(*rows)], [ca.vertcat(*[y[k] for k in elim])], [values])[0]
    used = [k for k in range(6) if k not in kept]
    got = np.asarray(ca.Function("f", [y, yp], [ca.vertcat(*[point[k] for k in used])])(
        [0.7, 9, 9, 9, 9, 3.0], np.ones(6))).ravel()
    np.testing.assert_allclose(got, 0.0, atol=1e-15)
    assert not ca.depends_on(new, ca.vertcat(v1, v2))
