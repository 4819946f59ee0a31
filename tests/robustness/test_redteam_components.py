"""Building models from the component library, tried as a new user who mistypes (issue 26, red-team pass).

Declarations (``Parameter(min="0")`` failed in its first comparison, ``min=nan`` was no bound, ``shape="12"`` was
``(1, 2)``, ``Variable(error_test="no")`` switched the option on), expressions (``eq(x, "b")``, ``der("x")`` and
``if_else("x>0", ...)`` were numpy's ValueError, ``eq(None)`` the constant NaN), what ``equations()`` returns (one
equation was Python's "not iterable"; a foreign symbol in an initial equation CasADi's "variables are free" at run
time), component arguments (multibody flags read with ``bool()``, strings parsed as sizes and axes, ``TimeTable(t=
{...})`` and ``Trapezoid(nperiod="1")`` raw errors, a zero gravity direction or gear ratio failing at initialisation,
``Fluid(bulk=...)``), options assigned after construction (``pid.controller_type = "PI"`` ignored, ``strict =
"False"`` switched on), mixed fluids in one circuit (ran), and linear analysis (``sensitivity`` dropped the input
columns of ``D``, ``Modes.dominant(99)`` an IndexError, ``times`` ignored with ``poses``). Each test asserts the
error class and that the message names the culprit; the few runs use models of one or two states.
"""

from __future__ import annotations

import math
import re

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import ConnectError, LinearizationError, ModelError, ParameterError, Variable, der, eq
from flexlib.compile.flatten import flatten
from flexlib.components.control import FirstOrder, Limiter, LimPID, TimeTable, Trapezoid
from flexlib.components.hydraulics import (
    DirectionalValve43,
    DoubleActingCylinder,
    FlowSource,
    Fluid,
    LineCylinder,
    Orifice,
    Tank,
    Volume,
)
from flexlib.components.mechanics import multibody as mb
from flexlib.components.mechanics import rotational as rot
from flexlib.components.mechanics.translational import Fixed, Force, Mass
from tests.robustness.test_analysis_and_inputs import PushedOscillator


# -- declarations ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("kwargs", "match"), [
    ({"min": "0"}, r"Parameter min='0' is a string"),
    ({"min": math.nan}, r"Parameter min=nan is NaN"),
    ({"max": [1.0, 2.0]}, r"Parameter max=\[1\.0, 2\.0\] is not a single number"),
    ({"min": 2.0, "max": 1.0}, r"bounds min=2 and max=1 admit no value"),
    ({"gt": 0.0, "lt": 0.0}, r"bounds gt=0 and lt=0 admit no value"),
], ids=["min-string", "min-nan", "max-array", "min-above-max", "empty-open-interval"])
def test_parameter_bounds_are_checked_where_declared(kwargs, match):
    with pytest.raises(ModelError, match=match):
        fl.Parameter(1.0, **kwargs)


@pytest.mark.parametrize("shape", ["12", 2.5, True, (2, "3")])
def test_declaration_shape_must_be_ints(shape):
    with pytest.raises(ModelError, match=r"^shape .*: give \(\) for a scalar"):
        fl.Parameter(1.0, shape=shape)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"unit": 5}, r"unit must be a string, got int 5"),
    ({"doc": None}, r"doc must be a string, got NoneType"),
    ({"fixed": "True"}, r"fixed must be True or False, got 'True'"),
    ({"fixed": 2}, r"fixed must be True or False, got 2"),
    ({"error_test": "no"}, r"error_test must be True or False, got 'no'"),
    ({"intermediate": "no"}, r"intermediate must be True or False, got 'no'"),
    ({"derivative": 5}, r"derivative must be a function derivative\(node\)"),
    ({"start": [1.0, 2.0]}, r"start value \[1\.0, 2\.0\] has 2 elements; give one number \(the variable is a scalar\)"),
    ({"start": [1.0, 2.0], "shape": 3}, r"has 2 elements; give one number or 3 \(shape \(3,\)\)"),
], ids=["unit", "doc", "fixed-str", "fixed-2", "error_test", "intermediate", "derivative", "start-scalar",
        "start-vector"])
def test_variable_declaration_arguments(kwargs, match):
    with pytest.raises(ModelError, match=match):
        Variable(**kwargs)


def test_potential_overdetermined_flag_is_checked():
    with pytest.raises(ModelError, match=r"overdetermined must be True or False, got 'no'"):
        fl.Potential(overdetermined="no")


def test_vector_start_and_state_select_member_are_accepted():
    class Vec(fl.Model):
        x = Variable(start=[1.0, 2.0, 3.0], shape=3, state_select=fl.StateSelect.prefer)

    node = Vec()
    assert node.start_of("x")[0].tolist() == [1.0, 2.0, 3.0]
    assert node.state_select_of("x") is fl.StateSelect.prefer


@pytest.mark.parametrize("value", [10**400, [10**400], -(10**400)])
def test_int_beyond_the_float_range_is_named(value):
    with pytest.raises(ParameterError, match=r"^Mass: m: parameter value \[?-?10{70}.* is not numeric \(int too "
                                             r"large to convert to float\)"):
        Mass(m=value)


# -- expressions -------------------------------------------------------------------------------------------------
X = ca.SX.sym("x")


@pytest.mark.parametrize(("call", "match"), [
    (lambda: eq("a", 1.0), r"eq\(\): left side: 'a' is a string"),
    (lambda: eq(X, "b", label="law"), r"eq\('law'\): right side: 'b' is a string"),
    (lambda: eq(None), r"eq\(\): left side: got None"),
    (lambda: eq({"a": 1.0}, 0.0), r"left side: \{'a': 1\.0\} is of type dict"),
    (lambda: eq([X, "b"], 0.0), r"left side: 'b' is a string"),
    (lambda: eq(1.0, 2.0, label=5), r"eq\(\): label must be a string, got int 5"),
    (lambda: der("x"), r"der\(\): 'x' is a string"),
    (lambda: der(None), r"der\(\): got None"),
    (lambda: fl.if_else("x>0", 1.0, 2.0), r"if_else\(\): condition: 'x>0' is a string"),
    (lambda: fl.no_event(X > 0, "a", 1.0), r"no_event\(\): if_true: 'a' is a string"),
    (lambda: fl.assert_("x>0", "too large"), r"assert_\(\): condition: 'x>0' is a string"),
    (lambda: fl.assert_(X > 0, 42), r"assert_\(\): message must be a string, got int 42"),
], ids=["eq-str", "eq-rhs-str", "eq-None", "eq-dict", "eq-list-entry", "eq-label", "der-str", "der-None",
        "if_else-str", "no_event-branch", "assert-str", "assert-message"])
def test_non_expressions_are_refused_naming_the_function_and_side(call, match):
    with pytest.raises(ModelError, match=match):
        call()


def test_lists_mixing_symbols_and_numbers_are_expressions():
    """``eq([x, 0.0], [1.0, y])`` made every entry the constant NaN (numpy's float() of a symbol); a Python bool is
    still a condition."""
    y = ca.SX.sym("y")
    f = ca.Function("f", [X, y], [eq([X, 0.0], [1.0, y]).residual, eq([[X, 0.0], [1.0, y]], 0.0).residual])
    column, matrix = (np.asarray(v).ravel().tolist() for v in f(2.0, 3.0))
    assert column == [1.0, -3.0]
    assert matrix == [2.0, 1.0, 0.0, 3.0]  # rows [x, 0], [1, y], column-major
    assert float(fl.if_else(True, 1.0, 2.0)) == 1.0


# -- what equations() returns ------------------------------------------------------------------------------------
def leaf_model(equations, initial=None):
    class EquationsLeaf(fl.Model):
        x = Variable(start=1.0, fixed=True)

        def equations(self):
            return equations(self)

        def initial_equations(self):
            return [] if initial is None else initial(self)

    class Top(fl.Model):
        def __init__(self):
            super().__init__()
            self.leaf = EquationsLeaf()

    return Top()


@pytest.mark.parametrize(("equations", "initial", "match"), [
    (lambda s: eq(der(s.x), -s.x), None, r"leaf\.equations\(\) returned one equation, not a list"),
    (lambda s: "x' = -x", None, r"leaf\.equations\(\) returned str \"x' = -x\""),
    (lambda s: [der(s.x) + s.x], None, r"leaf\.equations\(\) returned SX\(.*\) in its list; write each equation"),
    (lambda s: [eq(der(s.x), -s.x)], lambda s: eq(s.x, 1.0), r"leaf\.initial_equations\(\) returned one equation"),
    (lambda s: [eq(der(s.x), -s.x)], lambda s: [s.x - 1.0], r"leaf\.initial_equations\(\) returned SX"),
], ids=["one-equation", "string", "expression", "initial-one", "initial-expression"])
def test_what_equations_return_is_checked(equations, initial, match):
    with pytest.raises(ModelError, match=match):
        flatten(leaf_model(equations, initial))


def test_foreign_symbol_in_an_initial_equation_is_named():
    model = leaf_model(lambda s: [eq(der(s.x), -s.x)], lambda s: [eq(s.x, ca.SX.sym("z0"))])
    with pytest.raises(ModelError, match=r"^leaf: initial equation '\(leaf\.x-z0\) = 0' uses symbol z0, which is "
                                         r"not a flexlib variable"):
        flatten(model)


def test_variable_of_a_component_outside_the_model_is_named():
    stray = Mass(m=1.0)
    model = leaf_model(lambda s: [eq(der(s.x), stray.v)])
    with pytest.raises(ModelError, match=r"^leaf: equation .* uses v of Mass \(unnamed\), which is not part"):
        flatten(model)


# -- building a model --------------------------------------------------------------------------------------------
def test_positional_parameter_names_the_class_and_its_parameters():
    with pytest.raises(ParameterError, match=r"^Mass: got positional argument 1\.0; give parameters by name.*"
                                             r"\(parameters: L, m\)"):
        Mass(1.0)


def test_init_and_guess_of_the_same_variable_are_refused():
    with pytest.raises(ModelError, match=r"^Mass: 's' given in both init .* and guess"):
        Mass(m=1.0, init={"s": 0.0}, guess={"s": 1.0})


class Named(fl.Model):
    def __init__(self, name: str) -> None:
        super().__init__()
        self.wall = Fixed()
        setattr(self, name, Mass(m=1.0))
        self.connect(self.wall.flange, getattr(self, name).flange_a)


@pytest.mark.parametrize("name", ["a.b", "x y", "1abc"])
def test_sub_component_names_must_be_identifiers(name):
    with pytest.raises(ModelError, match=rf"a sub-component name must be a Python identifier .* got '{name}'"):
        Named(name)


def test_component_under_an_underscore_name_is_explained_at_connect():
    with pytest.raises(ConnectError, match=r"cannot connect flange_a: it is not inside this model: it belongs to a "
                                           r"Mass .*attribute whose name starts with '_'"):
        Named("_hidden")


class Inner(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.gain = fl.components.control.Gain(k=1.0)


def test_connecting_a_sibling_from_inside_a_sub_model_is_explained():
    class TwoInners(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.a, self.b = Inner(), Inner()
            self.a.connect(self.a.gain.y, self.b.gain.u)

    with pytest.raises(ConnectError, match=r"^a: cannot connect b\.gain\.u: .*it is outside a; connect it in the "
                                           r"model that contains both"):
        TwoInners()


# -- options assigned after construction -------------------------------------------------------------------------
@pytest.mark.parametrize(("make", "name", "value", "error", "match"), [
    (lambda: Limiter(u_max=1.0, u_min=-1.0), "strict", "False", ParameterError, r"Limiter: strict must be True"),
    (FirstOrder, "init_type", "bogus", ModelError, r"FirstOrder: init_type='bogus' is not one of"),
    (mb.WorldForce, "resolve_in_frame", "frame_a", ModelError, r"WorldForce: resolve_in_frame = 'frame_a' is not"),
    (lambda: Volume(V=1e-3), "fluid", "oil", ParameterError, r"Volume: fluid must be a Fluid record, got 'oil'"),
    (lambda: Volume(V=1e-3), "chamber_form", "volume", ModelError, r"Volume: chamber_form must be one of"),
    (lambda: Trapezoid(nperiod=1, period=1.0), "nperiod", -1, ModelError, r"Trapezoid: nperiod must be an integer"),
    (mb.Body, "w_fixed", "no", ParameterError, r"Body: w_fixed must be True or False, got 'no'"),
], ids=["strict", "init_type", "resolve_in_frame", "fluid", "chamber_form", "nperiod", "w_fixed"])
def test_option_assigned_later_is_checked_like_the_constructor(make, name, value, error, match):
    node = make()
    with pytest.raises(error, match=match):
        setattr(node, name, value)


@pytest.mark.parametrize(("make", "name", "value"), [
    (LimPID, "controller_type", "PI"),
    (LimPID, "use_feed_forward", True),
    (rot.Torque, "use_support", True),
    (Force, "use_support", True),
    (FlowSource, "use_input", True),
    (DirectionalValve43, "centre", "tandem"),
    (mb.Revolute, "use_axis_flange", True),
], ids=["controller_type", "use_feed_forward", "rot-use_support", "trans-use_support", "use_input", "centre",
        "use_axis_flange"])
def test_structural_option_cannot_change_after_construction(make, name, value):
    node = make()
    cls = type(node).__name__
    with pytest.raises(ModelError, match=rf"^{cls}: {name} = .* decided the structure of this {cls} when it was built"
                                         rf".*Build it as {cls}\({name}={value!r}, \.\.\.\)"):
        setattr(node, name, value)


def test_option_read_by_the_equations_can_still_change():
    lim = Limiter(u_max=1.0, u_min=-1.0)
    lim.strict = True
    assert lim.strict is True
    pid = LimPID()
    pid.controller_type = "PID"  # the same value: nothing changes
    assert pid.with_D


# -- component arguments -----------------------------------------------------------------------------------------
@pytest.mark.parametrize(("make", "match"), [
    (lambda: mb.Body(m=1.0, orientation_fixed="False"), r"Body: orientation_fixed must be True or False"),
    (lambda: mb.FreeMotion(w_fixed=None), r"FreeMotion: w_fixed must be True or False, got None"),
    (lambda: mb.Revolute(use_axis_flange="no"), r"Revolute: use_axis_flange must be True or False, got 'no'"),
    (lambda: mb.Revolute(use_friction=2), r"Revolute: use_friction must be True or False, got 2"),
    (lambda: mb.Prismatic(use_axis_flange="yes"), r"Prismatic: use_axis_flange must be True or False"),
    (lambda: mb.BodyShape(r=[1, 0, 0], r_CM=[0.5, 0, 0], m=1.0, w_fixed="False"),
     r"BodyShape: Body: w_fixed must be True or False"),
], ids=["Body", "FreeMotion", "Revolute-axis", "Revolute-friction", "Prismatic", "BodyShape"])
def test_multibody_flags_are_not_read_with_bool(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


@pytest.mark.parametrize(("make", "match"), [
    (lambda: mb.BodyBox(r=[1, 0, 0], density="7800"), r"BodyBox: density = '7800' is not a number \(a string"),
    (lambda: mb.BodyBox(r=[1, 0, 0], width=True), r"BodyBox: width = True is not a number \(a bool"),
    (lambda: mb.BodyBox(r=[1, 0, 0], inner_width="0.01"), r"BodyBox: inner_width = '0\.01' is not a number"),
    (lambda: mb.BodyBox(r=[1, 0, 0], width_direction=None), r"BodyBox: width_direction = is None"),
    (lambda: mb.BodyBox(r=[1, 0, 0], length_direction={"x": 1}), r"BodyBox: length_direction .* is of type dict"),
    (lambda: mb.BodyCylinder(r=[1, 0, 0], diameter="0.1"), r"BodyCylinder: diameter = '0\.1' is not a number"),
    (lambda: mb.Universal(n_a=["1", "0", "0"]), r"Universal: n_a = \['1', '0', '0'\] is an array of strings"),
    (lambda: mb.Cylindrical(n={"x": 1}), r"Cylindrical: n = \{'x': 1\} is of type dict"),
], ids=["density-str", "width-bool", "inner_width-str", "width_direction-None", "length_direction-dict",
        "diameter-str", "Universal-strs", "Cylindrical-dict"])
def test_shape_body_and_joint_arguments_are_numbers(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


@pytest.mark.parametrize(("t", "y", "match"), [
    ({0: 1, 1: 2}, [0.0, 1.0], r"TimeTable: t \{0: 1, 1: 2\} is of type dict"),
    (["0", "1"], [0.0, 1.0], r"TimeTable: t \['0', '1'\] is an array of strings"),
    ([0.0, 1.0], [True, False], r"TimeTable: y \[True, False\] is an array of bools"),
    ([0.0, 1.0, 2.0], [0.0, math.nan, 1.0], r"TimeTable: t and y must be finite, but y\[1\] = nan"),
], ids=["dict", "strings", "bools", "nan"])
def test_time_table_points(t, y, match):
    with pytest.raises(ParameterError, match=match):
        TimeTable(t=t, y=y)


@pytest.mark.parametrize("nperiod", ["1.0", None, math.nan, math.inf, True, [1, 2]])
def test_trapezoid_period_count(nperiod):
    shown = re.escape(repr(nperiod))
    with pytest.raises(ModelError, match=rf"Trapezoid: nperiod must be an integer >= 0, got {shown}"):
        Trapezoid(nperiod=nperiod)


def test_trapezoid_whole_float_and_numpy_counts_are_accepted():
    assert Trapezoid(nperiod=2.0).nperiod == 2
    assert Trapezoid(nperiod=np.int64(3)).nperiod == 3


@pytest.mark.parametrize("centre", [["closed"], {"closed": 1}])
def test_valve_centre_that_is_not_a_string(centre):
    with pytest.raises(ModelError, match=r"DirectionalValve43: centre must be one of \['closed', 'float', 'open', "
                                         r"'tandem'\], got"):
        DirectionalValve43(centre=centre)


def test_zero_gravity_direction_is_refused():
    with pytest.raises(ParameterError, match=r"^World: gravity direction n = \[0\.0, 0\.0, 0\.0\] has zero length"):
        mb.World(n=[0.0, 0.0, 0.0])


def test_zero_gear_ratio_is_refused():
    with pytest.raises(ParameterError, match=r"^IdealGear: ratio = 0: the transmission ratio .* must be != 0"):
        rot.IdealGear(ratio=0.0)


def test_misspelt_fluid_field_has_did_you_mean():
    with pytest.raises(ParameterError, match=r"^Fluid: unknown field 'betta'; did you mean beta\? \(fields: name, "):
        Fluid(betta=1.0e9)


class Circuit(fl.Model):
    """source → volume → orifice → tank, the orifice given no fluid (the default HLP46)."""

    def __init__(self, fluid: Fluid) -> None:
        super().__init__()
        self.src = FlowSource(q=1e-5, fluid=fluid)
        self.vol = Volume(V=1e-3, p_start=2e5, fluid=fluid)
        self.orifice = Orifice(A=1e-6)
        self.tank = Tank(fluid=fluid)
        self.connect(self.src.port, self.vol.port)
        self.connect(self.vol.port, self.orifice.port_a)
        self.connect(self.orifice.port_b, self.tank.port)


def test_two_fluids_in_one_circuit_are_refused():
    water = Fluid(name="water", rho_ref=1000.0, beta=2.2e9, nu=1e-6)
    with pytest.raises(ConnectError, match=r"ports src\.port, vol\.port, orifice\.port_a are connected but their "
                                           r"components use different fluids: 'water' \(src, vol\); 'HLP46' "
                                           r"\(orifice\)"):
        flatten(Circuit(water))


def test_one_fluid_per_circuit_flattens():
    from flexlib.components.hydraulics import HLP46

    assert flatten(Circuit(HLP46)).variables


def test_line_cylinder_start_values_reach_the_cylinder():
    cyl = LineCylinder(d_bore=0.1, d_rod=0.05, stroke=1.0, L0=1.0, init={"p_A": 2e6}, guess={"p_B": 1e6})
    assert cyl.cylinder.start_of("p_A")[0] == 2e6 and cyl.cylinder.start_of("p_A")[1] is True
    with pytest.raises(ModelError, match=r"DoubleActingCylinder \(unnamed\): unknown variable 'xx'; did you mean x"):
        LineCylinder(init={"xx": 0.1})


def test_cylinder_chamber_form_later_is_checked():
    cyl = DoubleActingCylinder()
    with pytest.raises(ModelError, match=r"DoubleActingCylinder: chamber_form must be one of"):
        cyl.chamber_form = None


# -- linear analysis ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def osc() -> fl.Simulation:
    return fl.Simulation(PushedOscillator())  # wall – spring – mass, one mode at 1 Hz


def test_sensitivity_keeps_a_column_per_input(osc):
    lin = fl.linearize(osc, inputs=["src.k"], outputs=["mass.s"])
    C, D = lin.sensitivity(["mass.s", "push.f"])
    assert D.shape == (2, 1)  # it had no column
    assert np.allclose(C[0], lin.C[0]) and D[1, 0] == pytest.approx(1.0)  # push.f = src.k


@pytest.mark.parametrize("k", [99, "0", -5, True])
def test_mode_index_out_of_range(osc, k):
    modes = fl.modal_analysis(osc)
    with pytest.raises(LinearizationError, match=r"Modes\.dominant: mode index k = .* is not an integer in 0 … 0 "
                                                 r"\(1 modes\)"):
        modes.dominant(k)


def test_table_vibration_only_is_a_flag(osc):
    with pytest.raises(LinearizationError, match=r"Modes\.table: vibration_only must be True or False, got 'no'"):
        fl.modal_analysis(osc).table(vibration_only="no")


def test_capitalised_rigid_lock_suggests_rigid(osc):
    with pytest.raises(LinearizationError, match=r"cannot lock 'Rigid': .*did you mean lock='rigid'"):
        fl.modal_analysis(osc, lock="Rigid")


def test_times_with_poses_are_refused(osc):
    with pytest.raises(LinearizationError, match=r"modal_sweep: times=\[\.\.\.\] go with at=result"):
        fl.modal_sweep(osc, poses=[{}], times=[0.0, 1.0])
