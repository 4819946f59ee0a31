"""Modelling API: array connectors, hierarchy, outside connectors, signals, steady-state start."""

import numpy as np
import pytest

import flexlib as fl
from flexlib import Connector, Flow, Input, Output, Parameter, Potential, Variable, der, eq


class Point(Connector):
    """3D point connector: position/force vectors and a strain/stress-like 3×3 matrix pair."""

    r = Potential(unit="m", shape=3)
    f = Flow(unit="N", shape=3)
    E = Potential(unit="1", shape=(3, 3))
    S = Flow(unit="N.m", shape=(3, 3))


class PointMass(fl.Component):
    """3D point mass; it takes no matrix load (S = 0)."""

    m = Parameter(1.0, unit="kg", min=0.0)
    v = Variable(unit="m/s", shape=3)
    port = Point()

    def equations(self):
        return [eq(der(self.port.r), self.v), eq(self.m * der(self.v), self.port.f), eq(self.port.S, 0.0)]


class Anchor(fl.Component):
    """Fixed point with a prescribed matrix E0."""

    r0 = Parameter(np.zeros(3), unit="m", shape=3)
    E0 = Parameter(np.diag([1.0, 2.0, 3.0]) + np.triu(np.ones((3, 3)), 1), unit="1", shape=(3, 3))
    port = Point()

    def equations(self):
        return [eq(self.port.r, self.r0), eq(self.port.E, self.E0)]


class Spring3D(fl.Component):
    """Linear 3D spring between two points (zero rest length), and a matrix spring S = k·(E_b − E_a)."""

    c = Parameter(1.0, unit="N/m", min=0.0)
    k = Parameter(5.0, unit="N.m", min=0.0)
    port_a = Point()
    port_b = Point()

    def equations(self):
        f = self.c * (self.port_b.r - self.port_a.r)
        s = self.k * (self.port_b.E - self.port_a.E)
        return [eq(self.port_a.f, -f), eq(self.port_b.f, f), eq(self.port_a.S, -s), eq(self.port_b.S, s)]


class Orbit(fl.Model):
    """A 3D isotropic oscillator: r(t) = r0 cos(ωt) + v0/ω sin(ωt), ω = sqrt(c/m)."""

    def __init__(self, c=4.0, m=1.0):
        super().__init__()
        self.anchor = Anchor()
        self.spring = Spring3D(c=c)
        self.mass = PointMass(m=m, init={"v": [0.0, 0.5, 0.1]})
        self.mass.port.set_start("r", [1.0, 0.0, 0.0], fixed=True)
        self.connect(self.anchor.port, self.spring.port_a)
        self.connect(self.spring.port_b, self.mass.port)


def test_array_connectors():
    """Vector and matrix connector variables connect element-wise; motion is the analytic ellipse."""
    res = fl.Simulation(Orbit(), use_cache=False).run(3.0, dt_out=0.1, rtol=1e-10, atol=1e-12)
    t = res.t[:, None]
    expected = np.array([1.0, 0, 0]) * np.cos(2 * t) + np.array([0, 0.5, 0.1]) / 2 * np.sin(2 * t)
    np.testing.assert_allclose(res["mass.port.r"], expected, atol=1e-8)
    E0 = np.diag([1.0, 2.0, 3.0]) + np.triu(np.ones((3, 3)), 1)
    np.testing.assert_allclose(res["mass.port.E"], np.tile(E0, (len(res.t), 1, 1)), atol=1e-12)  # in its shape
    assert "mass.port.E[0,2]" in res and res.final("mass.port.E[0,2]") == pytest.approx(1.0)
    assert res["mass.port.r"].shape == (len(res.t), 3)


class Wrapped(fl.Model):
    """The Orbit's spring and mass inside a sub-model reached through an outside connector."""

    class Sub(fl.Model):
        port = Point()

        def __init__(self):
            super().__init__()
            self.spring = Spring3D(c=4.0)
            self.mass = PointMass(init={"v": [0.0, 0.5, 0.1]})
            self.mass.port.set_start("r", [1.0, 0.0, 0.0], fixed=True)
            self.connect(self.port, self.spring.port_a)
            self.connect(self.spring.port_b, self.mass.port)

    def __init__(self):
        super().__init__()
        self.anchor = Anchor()
        self.sub = Wrapped.Sub()
        self.connect(self.anchor.port, self.sub.port)


def test_outside_connector_signs_and_names():
    """Connecting through a sub-model's own connector gives the same motion; the anchor force is −c·r."""
    res = fl.Simulation(Wrapped(), use_cache=False).run(1.0, dt_out=0.5, rtol=1e-10, atol=1e-12)
    ref = fl.Simulation(Orbit(), use_cache=False).run(1.0, dt_out=0.5, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["sub.mass.port.r"], ref["mass.port.r"], atol=1e-10)
    np.testing.assert_allclose(res["anchor.port.f"], 4.0 * res["sub.mass.port.r"], atol=1e-9)
    np.testing.assert_allclose(res["sub.port.f"], -res["anchor.port.f"], atol=1e-12)


def test_model_instantiated_twice_with_different_parameters():
    """Two instances of one model class with different parameters in one system keep their own values."""

    class Two(fl.Model):
        def __init__(self):
            super().__init__()
            self.a = Orbit(c=4.0)
            self.b = Orbit(c=9.0)

    res = fl.Simulation(Two(), use_cache=False).run(1.0, dt_out=0.25, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["a.mass.port.r[0]"], np.cos(2 * res.t) + 0 * res.t, atol=1e-8)
    np.testing.assert_allclose(res["b.mass.port.r[0]"], np.cos(3 * res.t), atol=1e-8)
    assert res.parameters["b.spring.c"] == (9.0, "N/m")


class Source(fl.Component):
    """y = k·time."""

    k = Parameter(2.0, unit="1/s")
    y = Output(unit="1")

    def equations(self):
        return [eq(self.y, self.k * fl.time)]


class Integrator(fl.Component):
    """der(x) = u."""

    u = Input(unit="1")
    x = Variable(unit="s", start=0.0, fixed=True)

    def equations(self):
        return [eq(der(self.x), self.u)]


def test_signals_connect_and_check():
    class Loop(fl.Model):
        def __init__(self):
            super().__init__()
            self.src = Source()
            self.integ = Integrator()
            self.connect(self.src.y, self.integ.u)

    res = fl.Simulation(Loop(), use_cache=False).run(1.0, dt_out=0.5, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["integ.x"], res.t**2, atol=1e-10)

    class Unfed(fl.Model):
        def __init__(self):
            super().__init__()
            self.integ = Integrator()

    with pytest.raises(fl.ModelError, match=r"input integ\.u \[1\] is not connected"):
        fl.Simulation(Unfed(), use_cache=False)

    class TwoOutputs(fl.Model):
        def __init__(self):
            super().__init__()
            self.a, self.b = Source(), Source()
            self.connect(self.a.y, self.b.y)

    with pytest.raises(fl.ConnectError, match=r"both are sources"):
        TwoOutputs()


class Tank(fl.Model):
    """Hydraulic-like capacitance: C·dp/dt = q_in − p/R, steady state p = q_in·R."""

    C = Parameter(1e-9, unit="m3/Pa")
    R = Parameter(1e9, unit="Pa.s/m3")
    q_in = Parameter(1e-4, unit="m3/s")
    p = Variable(unit="Pa", start=1e5, nominal=1e5)

    def equations(self):
        return [eq(self.C * der(self.p), self.q_in - self.p / self.R)]


def test_steady_state_initialisation():
    """steady_state=True solves der(p) = 0 at t0: p = q_in·R (1e-10 relative), and stays there."""
    res = fl.Simulation(Tank(), use_cache=False).run(1.0, dt_out=0.5, steady_state=True)
    np.testing.assert_allclose(res["p"], 1e5, rtol=1e-10)
    with pytest.raises(fl.InitializationError, match=r"under-specified[\s\S]*\bp\b"):
        fl.Simulation(Tank(), use_cache=False).run(1.0)


class TwoLags(fl.Model):
    """Two first-order lags; the first has an initial equation of its own (x = 0.5 at t0)."""

    x = Variable()
    z = Variable()

    def initial_equations(self):
        return [eq(self.x, 0.5)]

    def equations(self):
        return [eq(der(self.x), 1.0 - self.x), eq(der(self.z), 2.0 - self.z)]


def test_steady_state_complements_initial_equations():
    """steady_state=True adds der(·) = 0 only for states the model's own initial equations leave free:
    x keeps its initial equation (0.5), z starts at its steady state 2 (exact), and x then follows
    1 - 0.5·exp(-t) (1e-7)."""
    res = fl.Simulation(TwoLags(), use_cache=False).run(1.0, dt_out=0.25, steady_state=True, rtol=1e-9, atol=1e-11)
    np.testing.assert_allclose(res["z"], 2.0, rtol=1e-12)
    np.testing.assert_allclose(res["x"], 1.0 - 0.5 * np.exp(-res.t), atol=1e-7)


def test_sub_component_name_clashing_with_a_method():
    """A child named after a method (``root``, ``connect``) would shadow it: clear error naming it."""

    class ShadowsConnect(fl.Model):
        def __init__(self):
            super().__init__()
            self.connect = Source()

    with pytest.raises(fl.ModelError, match=r"'connect' is a method or attribute of ShadowsConnect"):
        ShadowsConnect()
