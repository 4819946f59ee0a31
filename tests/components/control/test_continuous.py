"""Tests of ``FirstOrder`` and ``TransferFunction`` (MSL ``Modelica.Blocks.Continuous``).

References: the analytic first-order step response, and ``scipy.signal.step`` / ``lsim``
(matrix-exponential discretisation, exact for step and piecewise-linear inputs sampled at their
corners) for the transfer functions. Runs at rtol = 1e-8, atol = 1e-10; tolerances in each test.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

import flexlib as fl
from flexlib.components.control import Constant, FirstOrder, Ramp, Step, TransferFunction

TOL = {"rtol": 1e-8, "atol": 1e-10}
DT = 1.0 / 64.0


def run(model: fl.Model, t_end: float, **kw) -> fl.Result:
    return fl.Simulation(model, use_cache=False).run(t_end, dt_out=DT, **TOL, **kw)


class Driven(fl.Model):
    """One block fed by a source."""

    def __init__(self, source: fl.Component, block: fl.Component) -> None:
        super().__init__()
        self.source = source
        self.block = block
        self.connect(self.source.y, self.block.u)


def test_first_order_step_response():
    """y = y_start e^(−t/T) + k h (1 − e^(−(t − ts)/T)) for t ≥ ts. Reference: analytic; 1e-7 of k h."""
    k, T, h, ts, y0 = 2.5, 0.3, 0.8, 0.25, -0.4
    res = run(Driven(Step(height=h, start_time=ts), FirstOrder(k=k, T=T, y_start=y0)), 1.5)
    after = np.clip(res.t - ts, 0.0, None)
    expected = y0 * np.exp(-res.t / T) + k * h * (1.0 - np.exp(-after / T))
    np.testing.assert_allclose(res["block.y"], expected, rtol=0, atol=1e-7 * k * h)


def test_first_order_ramp_matches_lsim():
    """Ramp input from rest. Reference: scipy.signal.lsim of k/(T s + 1) (exact for a piecewise-linear
    input with its corners on the grid); tolerance 1e-7 of the final value."""
    k, T = 1.5, 0.2
    res = run(Driven(Ramp(height=2.0, duration=0.5, start_time=0.25), FirstOrder(k=k, T=T)), 1.5)
    t = np.arange(0.0, 1.5 + DT / 2, DT)
    u = 2.0 * np.clip((t - 0.25) / 0.5, 0.0, 1.0)
    _, y_ref, _ = signal.lsim(([k], [T, 1.0]), u, t)
    np.testing.assert_allclose(res.value("block.y", t), y_ref, rtol=0, atol=1e-7 * 3.0)


def test_first_order_initialisation_options():
    """``steady_state``: der(y) = 0, so y = k u from the start; ``no_init`` needs a condition from the
    model (error naming ``block.y``, or ``init={"y": ...}``). Reference: the definitions; 1e-10."""
    res = run(Driven(Constant(k=0.6), FirstOrder(k=2.0, T=0.1, init_type="steady_state")), 0.5)
    np.testing.assert_allclose(res["block.y"], 1.2, rtol=0, atol=1e-10)
    with pytest.raises(fl.InitializationError, match=r"block\.y"):
        run(Driven(Constant(k=0.6), FirstOrder(k=2.0, T=0.1, init_type="no_init")), 0.5)
    res = run(Driven(Constant(k=0.6), FirstOrder(k=2.0, T=0.1, init_type="no_init", init={"y": 0.5})), 0.5)
    assert res["block.y"][0] == pytest.approx(0.5, abs=1e-12)
    with pytest.raises(fl.ParameterError, match=r"T must be != 0"):
        FirstOrder(T=0.0)
    with pytest.raises(fl.ModelError, match=r"init_type='initial'"):
        FirstOrder(T=1.0, init_type="initial")


B3, A3 = [0.5, 2.0, 1.0], [1.0, 2.0, 3.0, 1.5]  # stable third order (Routh: 2·3 > 1.5)


def test_transfer_function_step_matches_scipy():
    """Third-order strictly proper b(s)/a(s), unit step at t = 0.25 from rest.

    Reference: scipy.signal.step for y = b/a u and for the canonical states x[-1] = u/a(s),
    x[0] = s² u/a(s) (MSL's unscaled x); tolerance 1e-7 [1].
    """
    res = run(Driven(Step(height=1.0, start_time=0.25), TransferFunction(b=B3, a=A3)), 4.0)
    t = 0.25 + np.arange(0.0, 3.75 + DT / 2, DT)
    for name, num in (("block.y", B3), ("block.x[2]", [1.0]), ("block.x[0]", [1.0, 0.0, 0.0])):
        _, ref = signal.step((num, A3), T=t - 0.25)
        np.testing.assert_allclose(res.value(name, t[1:]), ref[1:], rtol=0, atol=1e-7, err_msg=name)
    assert np.all(res.value("block.y", [0.0, 0.125, 0.2]) == 0.0)


def test_transfer_function_biproper_and_run_time_coefficients():
    """MSL's example (2 s + 4)/(s + 3) with a ramp input: direct feed-through d = 2. Then new
    coefficients through ``params`` (no recompile): (s + 1)/(0.5 s + 1).

    Reference: scipy.signal.lsim (exact for the piecewise-linear input); tolerance 1e-7 [1]."""
    sim = fl.Simulation(Driven(Ramp(height=1.0, duration=0.5, start_time=0.25), TransferFunction(b=[2, 4], a=[1, 3])),
                        use_cache=False)
    t = np.arange(0.0, 2.0 + DT / 2, DT)
    u = np.clip((t - 0.25) / 0.5, 0.0, 1.0)
    for params, tf in (({}, ([2.0, 4.0], [1.0, 3.0])), ({"block.b": [1.0, 1.0], "block.a": [0.5, 1.0]},
                                                       ([1.0, 1.0], [0.5, 1.0]))):
        res = sim.run(2.0, dt_out=DT, params=params, **TOL)
        _, y_ref, _ = signal.lsim(tf, u, t)
        np.testing.assert_allclose(res.value("block.y", t), y_ref, rtol=0, atol=1e-7)


def test_transfer_function_initialisation_options():
    """Constant input c = 0.8. ``steady_state``: y = b[-1]/a[-1] c from the start; ``initial_output``:
    y(0) = y_start with the higher states at rest; ``initial_state``: x(0) = x_start. Static gain:
    y = b/a u. Reference: the definitions; tolerance 1e-10."""
    c = 0.8
    res = run(Driven(Constant(k=c), TransferFunction(b=B3, a=A3, init_type="steady_state")), 1.0)
    np.testing.assert_allclose(res["block.y"], B3[-1] / A3[-1] * c, rtol=0, atol=1e-10)
    res = run(Driven(Constant(k=c), TransferFunction(b=B3, a=A3, init_type="initial_output", y_start=0.3)), 0.1)
    assert res["block.y"][0] == pytest.approx(0.3, abs=1e-10)
    assert (res["block.x[0]"][0], res["block.x[1]"][0]) == pytest.approx((0.0, 0.0), abs=1e-10)
    x0 = [0.1, -0.2, 0.3]
    res = run(Driven(Constant(k=c), TransferFunction(b=B3, a=A3, x_start=x0)), 0.1)
    np.testing.assert_allclose([res[f"block.x[{i}]"][0] for i in range(3)], x0, rtol=0, atol=1e-12)
    res = run(Driven(Constant(k=c), TransferFunction(b=[3.0], a=[2.0])), 0.1)
    np.testing.assert_allclose(res["block.y"], 1.5 * c, rtol=0, atol=1e-12)


def test_bad_transfer_functions_are_rejected():
    """Bad input: improper b/a, a[0] = 0, x_start of the wrong length, unknown init_type."""
    with pytest.raises(fl.ParameterError, match=r"not proper: len\(b\) = 3 > len\(a\) = 2"):
        TransferFunction(b=[1.0, 2.0, 3.0], a=[1.0, 1.0])
    with pytest.raises(fl.ParameterError, match=r"a\[0\] must be != 0"):
        TransferFunction(b=[1.0], a=[0.0, 1.0])
    with pytest.raises(fl.ParameterError, match=r"shape"):
        TransferFunction(b=[1.0], a=[1.0, 2.0, 1.0], x_start=[0.0])
    with pytest.raises(fl.ModelError, match=r"init_type='zero'"):
        TransferFunction(b=[1.0], a=[1.0, 1.0], init_type="zero")


def test_integrator_of_a_sine():
    """``der(y) = k u`` of ``u = A sin(2π f t)`` from ``y_start``: ``y = y_start + k A (1 − cos 2π f t)/(2π f)``.
    Reference: analytic; 1e-7 of the swing."""
    from flexlib.components.control import Integrator, Sine

    k, A, f, y0 = 1.5, 0.8, 2.0, -0.3
    res = run(Driven(Sine(amplitude=A, f=f), Integrator(k=k, y_start=y0)), 1.0)
    w = 2 * np.pi * f
    np.testing.assert_allclose(res["block.y"], y0 + k * A * (1.0 - np.cos(w * res.t)) / w, rtol=0,
                               atol=1e-7 * 2 * k * A / w)


def test_integrator_initialisation_options():
    """``no_init`` takes its start from ``init={"y": ...}``; ``steady_state`` with a nonzero input has no
    equilibrium (an error naming ``block.y``). Reference: the definitions; 1e-10."""
    from flexlib.components.control import Integrator

    res = run(Driven(Constant(k=2.0), Integrator(k=0.5, init_type="no_init", init={"y": 1.0})), 0.5)
    np.testing.assert_allclose(res["block.y"], 1.0 + res.t, rtol=0, atol=1e-10)
    with pytest.raises(fl.InitializationError, match=r"block\.y"):
        run(Driven(Constant(k=2.0), Integrator(init_type="steady_state")), 0.5)
