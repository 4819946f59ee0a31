"""Bad input gets a clear error that names the component and the variable; nothing is lost."""

import numpy as np
import pytest

import flexlib as fl
from flexlib import Connector, Flow, Parameter, Potential, Variable, der, eq
from flexlib.models.reference.blow_up import BlowUp
from flexlib.models.reference.mass_spring_damper import Oscillator


class RotFlange(Connector):
    """Rotational flange."""

    phi = Potential(unit="rad")
    tau = Flow(unit="N.m")


class TransFlange(Connector):
    """Translational flange."""

    s = Potential(unit="m")
    f = Flow(unit="N")


class Disk(fl.Component):
    """Inertia with one flange."""

    J = Parameter(1.0, unit="kg.m2", min=0.0)
    w = Variable(unit="rad/s")
    flange = RotFlange()

    def equations(self):
        return [eq(der(self.flange.phi), self.w), eq(self.J * der(self.w), self.flange.tau)]


class Block(fl.Component):
    """Point mass with one flange."""

    m = Parameter(1.0, unit="kg", min=0.0)
    v = Variable(unit="m/s")
    flange = TransFlange()

    def equations(self):
        return [eq(der(self.flange.s), self.v), eq(self.m * der(self.v), self.flange.f)]


def test_connect_incompatible_connectors():
    class Mismatched(fl.Model):
        def __init__(self):
            super().__init__()
            self.disk = Disk()
            self.block = Block()
            self.connect(self.disk.flange, self.block.flange)

    with pytest.raises(fl.ConnectError, match=r"disk\.flange.*block\.flange.*incompatible"):
        Mismatched()


def test_unbalanced_component_names_it():
    class Leaky(fl.Component):
        w = Variable(unit="rad/s")
        flange = RotFlange()

        def equations(self):
            return [eq(der(self.flange.phi), self.w)]  # missing the torque balance

    class LeakyTop(fl.Model):
        def __init__(self):
            super().__init__()
            self.leaky = Leaky()

    with pytest.raises(fl.BalanceError, match=r"component leaky \(Leaky\) has 1 equations but needs 2"):
        fl.Simulation(LeakyTop(), use_cache=False)


def test_unbalanced_model_names_culprits():
    """A model-level extra equation: the over-determined part names the equations and components."""

    class Over(fl.Model):
        x = Variable(unit="m")
        y = Variable(unit="m")

        def equations(self):
            return [eq(der(self.x), 1.0), eq(self.y, 2 * self.x), eq(self.y, 3.0, label="extra constraint on y")]

    with pytest.raises(fl.BalanceError, match=r"3 equations for 2 unknowns") as err:
        fl.Simulation(Over(), use_cache=False)
    assert "extra constraint on y" in str(err.value)
    assert err.value.excess_equations

    class Under(fl.Model):
        x = Variable(unit="m")
        z = Variable(unit="m")

        def equations(self):
            return [eq(der(self.x), 1.0)]

    with pytest.raises(fl.BalanceError, match=r"under-determined[\s\S]*\bz\b"):
        fl.Simulation(Under(), use_cache=False)


def test_structurally_singular_model():
    class Singular(fl.Model):
        a = Variable()
        b = Variable()
        c = Variable()

        def equations(self):
            return [eq(self.a + self.b, 1.0, label="e1"), eq(self.a - self.b, 0.0, label="e2"),
                    eq(2 * self.a, 3.0, label="e3 uses only a")]

    with pytest.raises(fl.StructuralSingularityError, match=r"structurally singular[\s\S]*\bc\b"):
        fl.Simulation(Singular(), use_cache=False)


def test_overspecified_initial_conditions():
    with pytest.raises(fl.InitializationError, match=r"over-specified"):
        # three conditions for two states: x, v and der(x) via v... the third on an alias of v
        class Osc3(Oscillator):
            a = Variable(unit="m/s2")

            def equations(self):
                return [*super().equations(), eq(self.a, der(self.v))]

        fl.Simulation(Osc3(init={"x": 1.0, "v": 0.0, "a": 0.0}), use_cache=False).run(1.0)
    with pytest.raises(fl.InitializationError, match=r"under-specified[\s\S]*\bv\b"):
        fl.Simulation(Oscillator(init={"x": 1.0}), use_cache=False).run(1.0)


def test_unknown_parameter_name():
    with pytest.raises(fl.ParameterError, match=r"unknown parameter 'Jx'.*did you mean J"):
        Disk(Jx=2.0)
    with pytest.raises(fl.ParameterError, match=r"disk\.J = -1"):

        class LeakyTop(fl.Model):
            def __init__(self):
                super().__init__()
                self.disk = Disk(init={"w": 0.0, "flange.phi": 0.0} if False else {"w": 0.0})
                self.disk.J = -1.0

        LeakyTop()

    class Top2(fl.Model):
        def __init__(self):
            super().__init__()
            self.disk = Disk(init={"w": 0.0})
            self.disk.flange.set_start("phi", 0.0)

    sim = fl.Simulation(Top2(), use_cache=False)
    with pytest.raises(fl.ParameterError, match=r"unknown parameter 'disk\.j'.*disk\.J"):
        sim.run(1.0, params={"disk.j": 2.0})
    with pytest.raises(fl.ParameterError, match=r"disk\.J.*minimum"):
        sim.run(1.0, params={"disk.J": -2.0})


def test_solver_failure_keeps_and_saves_results(tmp_path):
    path = tmp_path / "failed.h5"
    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"at t = 0\.9") as err:
        sim.run(2.0, dt_out=0.01, result_file=str(path))
    res = err.value.result
    assert res.status == "failed"
    assert 0.9 < res.t[-1] < 1.0
    early = res.t < 0.9
    np.testing.assert_allclose(res["x"][early], 1 / (1 - res.t[early]), rtol=1e-3)
    saved = fl.load_result(path)
    assert saved.status == "failed" and "at t = 0.9" in saved.message
    np.testing.assert_array_equal(saved["x"], res["x"])


def test_interrupt_keeps_results(monkeypatch, tmp_path):
    """Ctrl-C during a run: SimulationInterrupted carries the result up to the interrupt, saved."""
    from flexlib.solve import sundae_callbacks

    sim = fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    calls = {"n": 0}
    original = sundae_callbacks.Callbacks.resfn

    def interrupting(self, t, y, yp, r):
        calls["n"] += 1
        if calls["n"] == 300:
            raise KeyboardInterrupt
        original(self, t, y, yp, r)

    monkeypatch.setattr(sundae_callbacks.Callbacks, "resfn", interrupting)
    from flexlib.solve import native

    advance = native.Driver.advance

    def interrupting_blocks(self, *args):  # the C driver: Ctrl-C reaches Python when a block of steps returns
        out = advance(self, *args)
        calls["n"] += 150
        if calls["n"] == 300:
            raise KeyboardInterrupt
        return out

    monkeypatch.setattr(native.Driver, "advance", interrupting_blocks)
    path = tmp_path / "interrupted.h5"
    with pytest.raises(fl.SimulationInterrupted) as err:
        sim.run(100.0, dt_out=0.01, result_file=str(path))
    res = err.value.result
    assert res.status == "interrupted" and 0 < res.t[-1] < 100
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-4)
    assert fl.load_result(path).status == "interrupted"
