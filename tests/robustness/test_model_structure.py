"""Model-structure mistakes a careless user makes, each giving a clear error that names the culprit; per-instance
state selection (Modelica's ``stateSelect`` modifier); joint-angle sensing on a joint's support/axis flanges.

Every bad-input test asserts the error class and that the message names the component path, the connector or the
variable. Correctness references: the closed-form four-bar position analysis (Norton, *Design of Machinery*, §4.5,
in flexlib.models.reference.closed_form) and free fall ``s = g t²/2``.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib.components.control import Constant, Gain, TransferFunction
from flexlib.components.hydraulics import LineCylinder
from flexlib.components.mechanics import rotational as rot
from flexlib.components.mechanics import translational as tr
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Prismatic, Revolute, World
from flexlib.models.reference import closed_form as ref
from flexlib.models.reference.four_bar import A, B, C, D, FourBar
from flexlib.units import g_n


class Leaf(fl.Component):
    """x' = -x with a selectable (bad) way of writing the equation."""

    x = fl.Variable(unit="1", start=1.0, fixed=True)
    k = fl.Parameter(1.0, unit="1/s")

    def __init__(self, how: str = "ok", **kw) -> None:
        super().__init__(**kw)
        self.how = how

    def equations(self):
        x, how = self.x, self.how
        if how == "math.sin":
            return [fl.eq(fl.der(x), -math.sin(x))]
        if how == "math.sqrt":
            return [fl.eq(fl.der(x), -self.k * math.sqrt(x))]
        if how == "nan":
            return [fl.eq(fl.der(x), float("nan"), label="rate")]
        if how == "inf":
            return [fl.eq(fl.der(x), -x + math.inf)]
        if how == "if":
            if x > 0:  # a Python if on a symbol
                return [fl.eq(fl.der(x), -x)]
            return [fl.eq(fl.der(x), x)]
        if how == "and":
            return [fl.eq(fl.der(x), (x > 0 and x < 2) * 1.0)]
        if how == "max":
            return [fl.eq(fl.der(x), -max(x, 0.0))]
        if how == "typo":
            return [fl.eq(fl.der(x), -self.kk * x)]
        return [fl.eq(fl.der(x), -self.k * x)]


class MathInit(fl.Component):
    """An initial equation written with math.exp on a symbol."""

    x = fl.Variable(unit="1", start=1.0)

    def initial_equations(self):
        return [fl.eq(self.x, math.exp(self.x))]

    def equations(self):
        return [fl.eq(fl.der(self.x), -self.x)]


class LeafHolder(fl.Model):
    def __init__(self, how: str = "ok") -> None:
        super().__init__()
        self.inner = Leaf(how=how)


class Outer(fl.Model):
    def __init__(self, how: str) -> None:
        super().__init__()
        self.sub = LeafHolder(how)


# -- connect ----------------------------------------------------------------------------------------------------
class InertiaPair(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.j1 = rot.Inertia(J=1.0)
        self.j2 = rot.Inertia(J=2.0)


class Holding(fl.Model):
    """A model of the components given to its constructor, by name (a one-component model in one line)."""

    def __init__(self, **parts: fl.Component) -> None:
        super().__init__()
        for name, part in parts.items():
            setattr(self, name, part)


def test_connect_connector_to_itself():
    m = InertiaPair()
    with pytest.raises(fl.ConnectError, match=r"j1\.flange_a .*twice; a connector cannot be connected to itself"):
        m.connect(m.j1.flange_a, m.j1.flange_a)


def test_connect_connector_twice_in_one_set():
    m = InertiaPair()
    with pytest.raises(fl.ConnectError, match=r"j2\.flange_b .*twice"):
        m.connect(m.j2.flange_b, m.j1.flange_a, m.j2.flange_b)


def test_connect_signal_to_itself():
    m = InertiaPair()
    m.gain = Gain(k=2.0)
    with pytest.raises(fl.ConnectError, match=r"signal gain\.y twice"):
        m.connect(m.gain.y, m.gain.y)


# -- attribute names --------------------------------------------------------------------------------------------
def test_second_component_under_same_name_is_refused():
    m = InertiaPair()
    with pytest.raises(fl.ModelError, match=r"j1: already holds Inertia j1; assigning Spring \(unnamed\) to the same "
                                            r"name would drop it"):
        m.j1 = rot.Spring(c=1.0)
    assert isinstance(m.j1, rot.Inertia) and m._children["j1"] is m.j1  # nothing lost


def test_second_component_under_same_name_inside_constructor():
    class Careless(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.source = Constant(k=1.0)
            self.source = Constant(k=2.0)

    with pytest.raises(fl.ModelError, match=r"source: already holds Constant source"):
        Careless()


def test_plain_value_over_a_component_name_is_refused():
    m = InertiaPair()
    with pytest.raises(fl.ModelError, match=r"j2: holds Inertia j2; assigning 3\.0 to the same name would hide it"):
        m.j2 = 3.0
    assert isinstance(m.j2, rot.Inertia)


def test_error_in_on_structure_names_the_component():
    class Fragile(fl.Component):
        x = fl.Variable(unit="1")

        def on_structure(self) -> None:
            raise KeyError("missing table")

        def equations(self):
            return [fl.eq(self.x, 1.0)]

    with pytest.raises(fl.ModelError, match=r"^part \(Fragile\)\.on_structure\(\) failed: KeyError: 'missing table'"):
        fl.Simulation(Holding(part=Fragile()), use_cache=False)


def test_reassigning_the_same_component_is_harmless():
    m = InertiaPair()
    j1 = m.j1
    m.j1 = j1
    assert m.j1 is j1 and list(m._children) == ["j1", "j2"]


# -- equations written with the wrong functions -----------------------------------------------------------------
def test_math_sin_on_symbol_names_component_and_suggests_casadi():
    """CasADi's float(SX) is NaN for a symbol, so math.sin(x) used to become a silent NaN constant."""
    with pytest.raises(fl.ModelError, match=r"^inner \(Leaf\)\.equations\(\): float\(\) of the symbolic expression "
                                            r"inner\.x: a function of Python's 'math' module.*casadi \(ca\.sin"):
        fl.Simulation(LeafHolder("math.sin"), use_cache=False)


def test_math_sqrt_on_symbol_in_nested_component_names_full_path():
    with pytest.raises(fl.ModelError, match=r"^sub\.inner \(Leaf\)\.equations\(\): float\(\) of the symbolic "
                                            r"expression sub\.inner\.x"):
        fl.Simulation(Outer("math.sqrt"), use_cache=False)


def test_math_exp_in_initial_equation_is_reported():
    with pytest.raises(fl.ModelError, match=r"^start \(MathInit\)\.initial_equations\(\): float\(\) of the symbolic "
                                            r"expression start\.x"):
        fl.Simulation(Holding(start=MathInit()), use_cache=False)


def test_float_of_constant_sx_is_still_allowed():
    """float() of a constant CasADi expression inside equations() is legitimate and keeps working."""

    class ConstLeaf(fl.Component):
        x = fl.Variable(unit="1", start=1.0, fixed=True)

        def equations(self):
            return [fl.eq(fl.der(self.x), -math.sin(ca.SX(0.5)) * self.x)]

    res = fl.Simulation(Holding(leaf=ConstLeaf()), use_cache=False).run(1.0, dt_out=0.5, rtol=1e-9, atol=1e-11,
                                                                       progress=False)
    np.testing.assert_allclose(res["leaf.x"], np.exp(-math.sin(0.5) * res.t), rtol=1e-6)
    assert float(ca.SX.sym("y")) != float(ca.SX.sym("y"))  # outside equations() CasADi's own behaviour is untouched


def test_nan_constant_names_component_and_equation_label():
    with pytest.raises(fl.ModelError, match=r"^inner \(Leaf\): equation 'rate' contains the constant nan"):
        fl.Simulation(LeafHolder("nan"), use_cache=False)


def test_inf_constant_is_reported():
    with pytest.raises(fl.ModelError, match=r"^inner \(Leaf\): equation .* contains the constant inf"):
        fl.Simulation(LeafHolder("inf"), use_cache=False)


@pytest.mark.parametrize("how", ["if", "and", "max"])
def test_python_truth_value_of_symbol_suggests_if_else(how):
    with pytest.raises(fl.ModelError, match=r"^inner \(Leaf\)\.equations\(\): a Python 'if'.*fl\.if_else"):
        fl.Simulation(LeafHolder(how), use_cache=False)


def test_error_inside_equations_names_the_component():
    with pytest.raises(fl.ModelError, match=r"^sub\.inner \(Leaf\)\.equations\(\) failed: AttributeError: .*'kk'"):
        fl.Simulation(Outer("typo"), use_cache=False)


def test_flexlib_error_in_equations_keeps_its_class_and_gets_the_path():
    class Picky(fl.Component):
        x = fl.Variable(unit="1")

        def equations(self):
            raise fl.ParameterError("table must have two columns")

    with pytest.raises(fl.ParameterError, match=r"^lookup \(Picky\)\.equations\(\): table must have two columns"):
        fl.Simulation(Holding(lookup=Picky()), use_cache=False)


def test_correct_leaf_still_runs():
    """The checks above do not reject a correct model: x' = -x from 1 gives exp(-t) (1e-6)."""
    res = fl.Simulation(LeafHolder("ok"), use_cache=False).run(1.0, dt_out=0.5, rtol=1e-9, atol=1e-11, progress=False)
    np.testing.assert_allclose(res["inner.x"], np.exp(-res.t), rtol=1e-6)


# -- per-instance state selection -------------------------------------------------------------------------------
def test_state_select_unknown_variable_has_did_you_mean():
    with pytest.raises(fl.ModelError, match=r"Revolute .*unknown variable 'ph'; did you mean phi.*state_select"):
        Revolute(state_select={"ph": "always"})


def test_state_select_unknown_variable_on_transfer_function():
    """TransferFunction declares its states in its constructor; state_select is applied after them."""
    with pytest.raises(fl.ModelError, match=r"TransferFunction \(unnamed\): unknown variable 'xs'; did you mean x"):
        TransferFunction(b=[1.0], a=[0.1, 1.0], state_select={"xs": "always"})
    tf = TransferFunction(b=[1.0], a=[0.1, 1.0], state_select={"x_scaled": "avoid"})
    assert tf.state_select_of("x_scaled") is fl.StateSelect.avoid


def test_state_select_passes_through_line_cylinder_to_the_cylinder():
    """A composite that forwards its keyword arguments forwards state_select too; a typo is named."""
    cyl = LineCylinder(d_bore=0.063, d_rod=0.036, stroke=0.4, state_select={"x": "always", "v": "always"})
    assert cyl.cylinder.state_select_of("x") is fl.StateSelect.always
    with pytest.raises(fl.ModelError, match=r"DoubleActingCylinder \(unnamed\): unknown variable 'xx'; did you mean x"):
        LineCylinder(d_bore=0.063, d_rod=0.036, stroke=0.4, state_select={"xx": "always"})


def test_state_select_bad_value_lists_choices():
    with pytest.raises(fl.ModelError, match=r"Revolute: phi: state_select 'allways' is not one of never, avoid, "
                                            r"default, prefer, always"):
        Revolute(state_select={"phi": "allways"})


def test_state_select_on_a_parameter_is_refused():
    with pytest.raises(fl.ModelError, match=r"unknown variable 'mu'"):
        Revolute(state_select={"mu": "always"})


def test_state_select_must_be_a_dict_or_a_joints_single_value():
    """A dict per variable everywhere; one value only where MSL's joints take one (their coordinates); anything
    else is refused, naming the component and the forms it takes."""
    with pytest.raises(fl.ModelError, match=r"Body: state_select must be a dict \{variable: .*\}, got 'always'"):
        Body(m=1.0, state_select="always")
    with pytest.raises(fl.ModelError, match=r"Revolute: state_select must be a dict .* or one value for phi, w"):
        Revolute(state_select=["always"])
    assert Revolute(state_select="always").state_select_of("w") is fl.StateSelect.always


def test_state_select_per_instance_changes_states_and_agrees():
    """Forcing the crank joint's angle and speed to ``always`` makes them the states (the default picks the coupler
    joint, rev2); both runs follow the closed-form position analysis over a full crank turn to 1e-6 rad and agree
    with each other to 1e-6 rad (run at rtol 1e-10: at 1e-9 the forced run's own error is 5e-7 rad on the opt-out
    build, which tested the joint speeds twice, and 9e-7 rad with planar geometry assumed, where the frames'
    angular velocities are aliases of them; docs/engine.md). The per-instance choice is part of the cache key."""
    th2 = 0.3
    th3, th4 = ref.fourbar_angles(A, B, C, D, th2, "open")
    default = fl.Simulation(FourBar(th2, th3, th4, w2=6.0))
    forced_model = FourBar(th2, th3, th4, w2=6.0)
    forced_model.rev1.set_state_select("phi", "always")
    forced_model.rev1.set_state_select("w", fl.StateSelect.always)
    forced = fl.Simulation(forced_model)
    assert default.states == ["rev2.phi", "rev2.w"]
    assert forced.states == ["rev1.phi", "rev1.w"]
    assert not forced.build_info.get("cached")
    assert "rev1.phi" in str(forced.report)
    wrap = lambda x: (x + np.pi) % (2 * np.pi) - np.pi  # noqa: E731
    runs = [s.run(1.2, dt_out=0.01, rtol=1e-10, atol=1e-12, progress=False) for s in (default, forced)]
    for res in runs:
        theta2 = res["rev1.phi"]
        assert theta2[-1] - theta2[0] > 2 * np.pi
        ref3, ref4 = ref.fourbar_angles(A, B, C, D, theta2, "open")
        np.testing.assert_allclose(wrap(theta2 + res["rev2.phi"] - ref3), 0.0, atol=1e-6)
        np.testing.assert_allclose(wrap(res["rev4.phi"] - ref4), 0.0, atol=1e-6)
    np.testing.assert_allclose(runs[0]["rev1.phi"], runs[1]["rev1.phi"], rtol=0, atol=1e-6)


def test_state_select_constructor_argument_matches_method():
    j = Revolute(state_select={"phi": "always", "w": fl.StateSelect.always})
    assert j.state_select_of("phi") is fl.StateSelect.always and j.state_select_of("w") is fl.StateSelect.always
    assert j.state_select_of("a") is fl.StateSelect.default  # the declaration's value where not overridden


# -- joint sensors on support/axis ------------------------------------------------------------------------------
class SensedPendulum(fl.Model):
    """A pendulum (rod 0.5 m, 1 kg at its end) on a Revolute whose angle is read by a 1D RelativeAngleSensor between
    the joint's support and axis flanges."""

    def __init__(self) -> None:
        super().__init__()
        self.world = World()
        self.rev = Revolute(use_axis_flange=True, init={"phi": 0.8, "w": 0.0})
        self.rod = FixedTranslation(r=[0.5, 0, 0])
        self.bob = Body(m=1.0, I=np.diag([1e-3, 1e-3, 1e-3]))
        self.sensor = rot.RelativeAngleSensor()
        self.speed = rot.RelativeSpeedSensor()
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.bob.frame_a)
        self.connect(self.rev.support, self.sensor.flange_a, self.speed.flange_a)
        self.connect(self.rev.axis, self.sensor.flange_b, self.speed.flange_b)


def test_relative_angle_sensor_on_revolute_reads_joint_angle():
    """The support is grounded inside the joint (MSL), so the sensor reads phi to 1e-10 rad and the speed sensor w;
    the pendulum swings (the angle changes sign)."""
    res = fl.Simulation(SensedPendulum(), use_cache=False).run(2.0, dt_out=0.01, rtol=1e-9, atol=1e-11,
                                                               progress=False)
    assert res["rev.phi"].min() < -0.5 < 0.5 < res["rev.phi"].max()
    np.testing.assert_allclose(res["sensor.phi_rel"], res["rev.phi"], rtol=0, atol=1e-10)
    np.testing.assert_allclose(res["speed.w_rel"], res["rev.w"], rtol=0, atol=1e-10)
    np.testing.assert_allclose(res["rev.support.phi"], 0.0, atol=0)


class SensedSlide(fl.Model):
    """A body sliding down a vertical Prismatic joint, its travel read between the joint's support and axis."""

    def __init__(self) -> None:
        super().__init__()
        self.world = World()
        self.slide = Prismatic(n=[0, -1, 0], use_axis_flange=True, init={"s": 0.0, "v": 0.0})
        self.mass = Body(m=2.0)
        self.sensor = tr.RelativePositionSensor()
        self.connect(self.world.frame_b, self.slide.frame_a)
        self.connect(self.slide.frame_b, self.mass.frame_a)
        self.connect(self.slide.support, self.sensor.flange_a)
        self.connect(self.slide.axis, self.sensor.flange_b)


def test_relative_position_sensor_on_prismatic_reads_free_fall():
    """Free fall along the joint: s = g t²/2 (1e-8 m) and the sensor reads s to 1e-10 m."""
    res = fl.Simulation(SensedSlide(), use_cache=False).run(1.0, dt_out=0.1, rtol=1e-10, atol=1e-12,
                                                            progress=False)
    np.testing.assert_allclose(res["slide.s"], 0.5 * g_n * res.t**2, rtol=0, atol=1e-8)
    np.testing.assert_allclose(res["sensor.s_rel"], res["slide.s"], rtol=0, atol=1e-10)


def test_casadi_functions_are_accepted():
    """ca.sin on a symbol (the suggested fix) builds and runs: x' = -sin(x) keeps x in (0, 1]."""

    class SinLeaf(fl.Component):
        x = fl.Variable(unit="1", start=1.0, fixed=True)

        def equations(self):
            return [fl.eq(fl.der(self.x), -ca.sin(self.x))]

    res = fl.Simulation(Holding(leaf=SinLeaf()), use_cache=False).run(1.0, dt_out=0.5, progress=False)
    # x' = -sin x: tan(x/2) = tan(1/2) e^{-t}
    np.testing.assert_allclose(res["leaf.x"], 2 * np.arctan(np.tan(0.5) * np.exp(-res.t)), rtol=1e-5)
