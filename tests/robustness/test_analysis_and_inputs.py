"""Bad requests to linear analysis and raw inputs to the engine: each gives a named error (or a well-defined answer).

Linear analysis (``fl.linearize``, ``fl.modal_analysis``, ``fl.modal_sweep``, ``LinearSystem.frequency_response``):
list arguments given as one string, repeated names, unknown names (with the closest ones), inputs that are not
parameters, operating points and frequencies that are not finite numbers, a frequency at a pole. Parameters,
``init``/``guess`` start values and ``Fluid`` records given as strings, bools, None, complex numbers, arrays of the
wrong shape; a parameter given as a start value; components connected to nothing (``fl.ModelWarning``).
Each test asserts the error class and that the message names the culprit. References for the values checked:
the receptance of a mass on a spring ``1/(k − m ω²)`` and the pole of a first-order lag ``−1/T``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexlib as fl
from flexlib.compile.flatten import flatten
from flexlib.components.control import Constant, FirstOrder, Gain, TransferFunction
from flexlib.components.hydraulics import FixedDisplacementPump, Orifice, PressureSource, Tank, Volume
from flexlib.components.hydraulics.fluid import Fluid
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World
from flexlib.components.mechanics.translational import Damper, Fixed, Force, Mass, Spring

K, M = 4.0 * math.pi**2, 1.0  # spring-mass: natural frequency 1 Hz


class PushedOscillator(fl.Model):
    """wall – spring – mass (– damper), pushed by a constant force src.k."""

    def __init__(self, d: float = 0.0, extra: str = "") -> None:
        super().__init__()
        self.wall = Fixed()
        self.spring = Spring(c=K)
        self.mass = Mass(m=M, init={"s": 0.0, "v": 0.0})
        self.src = Constant(k=0.0)
        self.push = Force()
        self.connect(self.wall.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.mass.flange_a)
        self.connect(self.src.y, self.push.f)
        self.connect(self.push.flange, self.mass.flange_b)
        if d:
            self.damper = Damper(d=d)
            self.connect(self.wall.flange, self.damper.flange_a)
            self.connect(self.damper.flange_b, self.mass.flange_a)
        if extra == "fixed":
            self.ground = Fixed()
        elif extra == "free mass":
            self.drifting = Mass(m=1.0, init={"s": 0.0, "v": 1.0})
        elif extra == "world":
            self.world = World()
        elif extra == "tank":
            self.tank = Tank()


class FreeMass(fl.Model):
    """A mass pushed by a force and held by nothing: a double integrator (a pole at 0)."""

    def __init__(self) -> None:
        super().__init__()
        self.mass = Mass(m=M, init={"s": 0.0, "v": 0.0})
        self.src = Constant(k=0.0)
        self.push = Force()
        self.connect(self.src.y, self.push.f)
        self.connect(self.push.flange, self.mass.flange_b)


class HingePendulum(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        self.world = World()
        self.hinge = Revolute(init={"phi": 0.3, "w": 0.0})
        self.rod = FixedTranslation(r=[1.0, 0.0, 0.0])
        self.body = Body(m=1.0)
        self.connect(self.world.frame_b, self.hinge.frame_a)
        self.connect(self.hinge.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.body.frame_a)


class StaticGain(fl.Model):
    """No states: a constant through a gain of 3."""

    def __init__(self) -> None:
        super().__init__()
        self.src = Constant(k=1.0)
        self.gain = Gain(k=3.0)
        self.connect(self.src.y, self.gain.u)


class Unstable(fl.Model):
    """A first-order lag with T = -0.5 s: one real pole at +2 1/s."""

    def __init__(self) -> None:
        super().__init__()
        self.src = Constant(k=0.0)
        self.lag = FirstOrder(k=1.0, T=-0.5)
        self.connect(self.src.y, self.lag.u)


@pytest.fixture(scope="module")
def osc() -> fl.Simulation:
    return fl.Simulation(PushedOscillator(d=1.0))


@pytest.fixture(scope="module")
def lin(osc: fl.Simulation) -> fl.analysis.LinearSystem:
    return fl.linearize(osc, inputs=["src.k"], outputs=["mass.s"])


@pytest.fixture(scope="module")
def pendulum() -> fl.Simulation:
    return fl.Simulation(HingePendulum())


# -- linear analysis: list arguments ----------------------------------------------------------------------------
def test_duplicate_lock_is_refused_naming_the_joint(pendulum):
    with pytest.raises(fl.LinearizationError, match=r"lock names 'hinge' more than once"):
        fl.modal_analysis(pendulum, lock=["hinge", "hinge"])


def test_single_joint_name_as_lock_is_one_joint(pendulum):
    """lock="hinge" is lock=["hinge"]: the only joint held, no mode left (a one-DOF pendulum)."""
    one, listed = fl.modal_analysis(pendulum, lock="hinge"), fl.modal_analysis(pendulum, lock=["hinge"])
    assert one.locked == listed.locked == ["hinge"]
    assert one.eigenvalues.size == listed.eigenvalues.size == 0


def test_unknown_lock_joint_has_did_you_mean(pendulum):
    with pytest.raises(fl.LinearizationError, match=r"cannot lock 'hing'.*did you mean hinge\?"):
        fl.modal_analysis(pendulum, lock=["hing"])


def test_single_string_inputs_and_outputs_are_one_name_each(osc):
    """inputs="src.k" is one input, not the letters of the string; the static gain is 1/k [m/N]."""
    lin = fl.linearize(osc, inputs="src.k", outputs="mass.s")
    assert lin.inputs == ["src.k"] and lin.outputs == ["mass.s"]
    np.testing.assert_allclose(lin.frequency_response(0.0, "src.k", "mass.s"), [1.0 / K], rtol=1e-12)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"inputs": ["src.k", "src.k"]}, r"inputs names 'src\.k' more than once"),
    ({"inputs": [3]}, r"inputs: entry 3 \(int\) is not a name"),
    ({"outputs": {"mass.s": 1}}, r"outputs must be a name or a list of names \(str\), got dict"),
    ({"inputs": ["src.kk"]}, r"input 'src\.kk' is not a parameter of PushedOscillator; did you mean src\.k\?"),
    ({"outputs": ["mass.ss"]}, r"output 'mass\.ss' is not a variable of PushedOscillator; did you mean mass\.s"),
    ({"inputs": ["push.f"]}, r"input 'push\.f' is a variable of PushedOscillator, not a parameter"),
], ids=["repeated-input", "non-string-input", "dict-outputs", "unknown-input", "unknown-output",
        "signal-input-as-input"])
def test_bad_input_and_output_names(osc, kwargs, match):
    with pytest.raises(fl.LinearizationError, match=match):
        fl.linearize(osc, **kwargs)


# -- linear analysis: operating point ---------------------------------------------------------------------------
@pytest.mark.parametrize(("kwargs", "error", "match"), [
    ({"starts": {"mass.ss": 0.1}}, fl.LinearizationError,
     r"starts: 'mass\.ss' is not a variable of PushedOscillator; did you mean mass\.s"),
    ({"starts": {"mass.m": 2.0}}, fl.LinearizationError,
     r"starts: 'mass\.m' is a parameter of PushedOscillator, not a variable; give it in params=\{'mass\.m'"),
    ({"starts": {"mass.s": "0.1"}}, fl.LinearizationError, r"starts: mass\.s = '0\.1' is a string, not a number"),
    ({"starts": ["mass.s"]}, fl.LinearizationError, r"starts must be a dict \{name: value\}, got list"),
    ({"t": math.nan}, fl.LinearizationError, r"t \[s\] = nan is not finite"),
    ({"t": "1"}, fl.LinearizationError, r"t \[s\] = '1' is a string"),
    ({"steady_state": "False"}, fl.LinearizationError, r"steady_state must be True or False, got 'False'"),
    ({"params": {"mass.mm": 2.0}}, fl.ParameterError, r"unknown parameter 'mass\.mm'.*did you mean mass\.m"),
    ({"params": [("mass.m", 2.0)]}, fl.LinearizationError, r"params must be a dict"),
], ids=["unknown-start", "parameter-as-start", "string-start", "starts-list", "t-nan", "t-string",
        "steady-state-string", "unknown-param", "params-list"])
def test_bad_operating_point_arguments(osc, kwargs, error, match):
    with pytest.raises(error, match=match):
        fl.linearize(osc, **kwargs)


def test_time_outside_the_result_is_named(osc):
    res = osc.run(0.2, dt_out=0.1, progress=False)
    with pytest.raises(fl.LinearizationError, match=r"t = 5 s is outside the result \(0\.0 \.\.\. 0\.2 s\)"):
        fl.linearize(osc, at=res, t=5.0)


def test_a_sub_component_or_a_non_model_is_refused():
    model = PushedOscillator()
    with pytest.raises(fl.LinearizationError, match=r"mass is a sub-component of PushedOscillator"):
        fl.linearize(model.mass)
    with pytest.raises(fl.LinearizationError, match=r"expected a flexlib Simulation or model \(Component\), got int"):
        fl.modal_analysis(3)


# -- linear analysis: frequency response --------------------------------------------------------------------------
@pytest.mark.parametrize(("f", "match"), [
    ([1.0, -1.0], r"f\[1\] = -1\.0 Hz is negative"),
    ([math.nan], r"f\[0\] = nan Hz is not finite"),
    ([[1.0, 2.0]], r"f has shape \(1, 2\); give a 1-D sequence"),
    ("10", r"f = '10' is a string, not a number"),
    ([1.0, True], r"f = \[1\.0, True\] is a sequence with a bool entry"),
], ids=["negative", "nan", "2-d", "string", "bool-entry"])
def test_bad_frequencies_are_refused(lin, f, match):
    with pytest.raises(fl.LinearizationError, match=match):
        lin.frequency_response(f)


def test_empty_frequency_list_gives_an_empty_response(lin):
    assert lin.frequency_response([]).shape == (0, 1, 1)


def test_unknown_output_of_frequency_response_has_did_you_mean(lin):
    with pytest.raises(fl.LinearizationError, match=r"'mass\.ss' is not an output .*did you mean mass\.s\?"):
        lin.frequency_response([1.0], "src.k", "mass.ss")


def test_frequency_at_a_rigid_body_pole_is_named():
    """A free mass has a double pole at 0: f = 0 is refused naming the pole; above it H = −1/(m ω²)."""
    lin = fl.linearize(FreeMass(), inputs="src.k", outputs="mass.s")
    with pytest.raises(fl.LinearizationError, match=r"f = 0 Hz is at a pole of the system.*free rigid-body mode"):
        lin.frequency_response([0.0, 1.0])
    np.testing.assert_allclose(lin.frequency_response([2.0], "src.k", "mass.s"), [-1.0 / (M * (4 * np.pi) ** 2)],
                               rtol=1e-12)


def test_frequency_at_an_undamped_mode_is_named():
    """Undamped spring-mass at exactly 1 Hz: refused naming the mode; at 0.5 Hz the receptance 1/(k − m ω²)."""
    lin = fl.linearize(PushedOscillator(), inputs="src.k", outputs="mass.s")
    with pytest.raises(fl.LinearizationError, match=r"f = 1 Hz is at a pole .*an undamped mode of 1 Hz"):
        lin.frequency_response([0.5, 1.0])
    w = 2 * np.pi * 0.5
    np.testing.assert_allclose(lin.frequency_response(0.5, "src.k", "mass.s"), [1.0 / (K - M * w**2)], rtol=1e-10)


def test_model_without_states_has_the_static_gain():
    """A constant through a gain of 3: no states, A is 0×0 and H(f) = D = 3 at any frequency; no modes."""
    sim = fl.Simulation(StaticGain())
    lin = fl.linearize(sim, inputs="src.k", outputs="gain.y")
    assert lin.A.shape == (0, 0)
    np.testing.assert_allclose(lin.frequency_response([0.0, 10.0], "src.k", "gain.y"), [3.0, 3.0], rtol=1e-14)
    assert fl.modal_analysis(sim).eigenvalues.size == 0


def test_unstable_system_reports_negative_damping():
    """FirstOrder with T = −0.5 s: the pole +2 1/s is listed with damping ratio −1 (MATLAB's damp), not hidden."""
    modes = fl.modal_analysis(Unstable())
    np.testing.assert_allclose(modes.eigenvalues, [2.0], rtol=1e-12)
    np.testing.assert_allclose(modes.damping, [-1.0], rtol=1e-12)
    with pytest.raises(fl.LinearizationError, match=r"Modes\.table: n must be None or an integer >= 0, got -1"):
        modes.table(-1)


# -- linear analysis: modal sweep -------------------------------------------------------------------------------
@pytest.mark.parametrize(("kwargs", "match"), [
    ({"n_modes": 0}, r"n_modes must be an integer >= 1, got 0"),
    ({"n_modes": 1.5}, r"n_modes must be an integer >= 1, got 1\.5"),
    ({"n_modes": True}, r"n_modes must be an integer >= 1, got True"),
    ({"f_min": -1.0}, r"f_min = -1\.0 Hz is negative"),
    ({"max_damping": math.nan}, r"max_damping \[1\] = nan is not finite"),
    ({"poses": {"mass.s": 0.1}}, r"poses must be a list of dicts"),
    ({"poses": [{"mass.q": 0.1}]}, r"poses\[0\]: starts: 'mass\.q' is not a variable of PushedOscillator"),
    ({"lock": ["spring"]}, r"cannot lock 'spring': not a Revolute or Prismatic joint"),
], ids=["n_modes-0", "n_modes-float", "n_modes-bool", "f_min-negative", "max_damping-nan", "poses-dict",
        "pose-unknown", "lock-not-a-joint"])
def test_bad_modal_sweep_arguments(osc, kwargs, match):
    args = {"poses": [{}], **kwargs}
    with pytest.raises(fl.LinearizationError, match=match):
        fl.modal_sweep(osc, **args)


def test_modal_sweep_times_must_be_finite(osc):
    res = osc.run(0.2, dt_out=0.1, progress=False)
    with pytest.raises(fl.LinearizationError, match=r"times\[1\] = nan s is not finite"):
        fl.modal_sweep(osc, at=res, times=[0.1, math.nan])


# -- parameters given as non-numbers ------------------------------------------------------------------------------
#: (constructor call, message) of parameters given as non-numbers: each is refused naming the parameter.
NON_NUMBERS = [
    (lambda: Mass(m="2"), r"Mass: m: parameter value '2' is a string, not a number; give a real number \[kg\]"),
    (lambda: Mass(m=True), r"Mass: m: parameter value True is a bool, not a number"),
    (lambda: Spring(c=1 + 0j), r"Spring: c: parameter value \(1\+0j\) is complex, not a real number"),
    (lambda: Mass(m=None), r"Mass: m: parameter value is None"),
    (lambda: Mass(m=[1.0]), r"Mass: m: parameter has shape \(\) \(a scalar\), got value of shape \(1,\): \[1\.0\]"),
    (lambda: FixedTranslation(r=np.ones((2, 2))), r"FixedTranslation: r: parameter has shape \(3,\), got value "
                                                  r"of shape \(2, 2\)"),
    (lambda: FixedTranslation(r=["1", "0", "0"]), r"FixedTranslation: r: parameter value \['1', '0', '0'\] is an "
                                                   r"array of strings"),
    (lambda: Body(m=1.0, r_CM=[0.1, None, 0.0]), r"Body: r_CM: parameter value .* entry None \(None, not a number\)"),
    (lambda: Gain(k="2"), r"Gain: k: parameter value '2' is a string"),
    (lambda: TransferFunction(b=[1.0], a="1 1"), r"TransferFunction: a '1 1' is a string"),
    (lambda: Mass(s=0.5), r"Mass \(unnamed\): unknown parameter 's': s is a variable \[m\]; give its start value "
                          r"with init=\{'s': \.\.\.\}"),
]
NON_NUMBER_IDS = ["string", "bool", "complex", "none", "list-for-scalar", "wrong-shape-array", "array-of-strings",
                  "none-in-array", "control-string", "tf-string", "variable-as-parameter"]


def test_string_parameter_assigned_later_names_the_instance_path():
    model = PushedOscillator()
    with pytest.raises(fl.ParameterError, match=r"^mass\.m: parameter value '3' is a string"):
        model.mass.m = "3"


# -- start values (init / guess) --------------------------------------------------------------------------------
@pytest.mark.parametrize(("make", "match"), [
    (lambda: Mass(init={"s": "zero"}), r"Mass: s: start value 'zero' is a string, not a number; give a real "
                                       r"number \[m\]"),
    (lambda: Mass(guess={"v": True}), r"Mass: v: start value True is a bool"),
    (lambda: Mass(init={"s": None}), r"Mass: s: start value is None"),
    (lambda: Mass(init={"s": [0.0, 1.0]}), r"Mass: s: start value \[0\.0, 1\.0\] has 2 elements, the variable is a "
                                           r"scalar"),
    (lambda: Mass(init={"m": 2.0}), r"Mass \(unnamed\): unknown variable 'm': m is a parameter \[kg\], not a "
                                    r"variable; set its value as Mass\(m=\.\.\.\), or per run with params="),
    (lambda: Mass(init={"vv": 0.0}), r"Mass \(unnamed\): unknown variable 'vv'; did you mean v\?"),
    (lambda: Mass(init={1: 0.0}), r"Mass: init key 1 \(int\) is not a variable name"),
    (lambda: Mass(init=[("s", 0.0)]), r"Mass: init must be a dict \{variable name: start value\}, got list"),
    (lambda: Mass(init={"flange_c.s": 0.0}), r"Mass: init key 'flange_c\.s': Mass has no sub-component or "
                                             r"connector 'flange_c'; did you mean flange_a, flange_b\?"),
    (lambda: Mass(state_select={"m": "always"}), r"unknown variable 'm': m is a parameter .* \(in state_select\)"),
    (lambda: fl.Variable(start="0"), r"Variable start value '0' is a string"),
    (lambda: fl.Variable(fixed="False"), r"fixed must be True or False, got 'False'"),
], ids=["string", "bool-guess", "none", "too-many-elements", "parameter-as-start", "did-you-mean", "non-string-key",
        "not-a-dict", "unknown-connector", "parameter-state-select", "declared-string-start", "declared-string-fixed"])
def test_bad_start_values_are_refused(make, match):
    with pytest.raises(fl.ModelError, match=match):
        make()


def test_start_value_on_a_connector_by_dotted_name():
    """init={"flange_a.s": 0.5} sets the start of the connector variable, as Modelica's flange_a(s(start=0.5))."""
    mass = Mass(init={"flange_a.s": 0.5})
    start, fixed = mass.flange_a.start_of("s")
    assert float(start) == 0.5 and fixed is True


def test_string_start_set_later_names_the_instance_path():
    model = PushedOscillator()
    with pytest.raises(fl.ModelError, match=r"^mass\.v: start value '1' is a string"):
        model.mass.set_start("v", "1")


# -- the fluid record and hydraulic components -------------------------------------------------------------------
@pytest.mark.parametrize(("make", "match"), [
    *NON_NUMBERS,
    (lambda: Fluid(beta="1.6e9"), r"Fluid 'HLP46': beta must be a real number \[Pa\], got '1\.6e9' \(a string"),
    (lambda: Fluid(beta=math.inf), r"Fluid 'HLP46': beta must be finite, got inf \[Pa\]"),
    (lambda: Fluid(beta=True), r"Fluid 'HLP46': beta must be a real number \[Pa\], got True \(a bool"),
    (lambda: Fluid(rho_ref=np.array([870.0, 880.0])), r"Fluid 'HLP46': rho_ref must be a real number \[kg/m3\], "
                                                     r"got array"),
    (lambda: Fluid(x_air=1.0), r"Fluid 'HLP46': x_air must be in \[0, 1\), got 1\.0"),
    (lambda: Fluid(name=46), r"Fluid: name must be a string, got 46"),
    (lambda: Volume(V=1e-3, p_start=-1e5), r"Volume: p_start = -100000\.0 Pa is negative; pressures are absolute"),
    (lambda: Volume(V=1e-3, p_start="1e5"), r"Volume: p_start = '1e5' is a string"),
    (lambda: Orifice(A=-1e-6), r"Orifice: A = -1e-06 \[m2\] is below its minimum"),
    (lambda: FixedDisplacementPump(D=1e-6, use_flange="False"), r"FixedDisplacementPump: use_flange must be True "
                                                                r"or False, got 'False'"),
    (lambda: PressureSource(use_input="no"), r"PressureSource: use_input must be True or False, got 'no'"),
], ids=[*NON_NUMBER_IDS, "beta-string", "beta-inf", "beta-bool", "rho-array", "x_air-one", "name-int",
        "p_start-negative", "p_start-string", "orifice-negative-area", "flag-string", "flag-word"])
def test_non_numbers_and_bad_fluid_and_hydraulic_inputs_are_refused(make, match):
    with pytest.raises(fl.ParameterError, match=match):
        make()


def test_fluid_numbers_are_stored_as_floats():
    """A numpy scalar or an int is accepted and stored as a float (the record enters the equations as constants)."""
    fluid = Fluid(beta=np.float32(1.5e9), rho_ref=900)
    assert type(fluid.beta) is float and type(fluid.rho_ref) is float and fluid.rho_ref == 900.0


# -- components connected to nothing ----------------------------------------------------------------------------
@pytest.mark.parametrize(("extra", "culprit"), [
    ("fixed", r"ground \(Fixed\) is connected to nothing: none of its connectors \(flange\) is connected"),
    ("world", r"world \(World\) is connected to nothing"),
    ("tank", r"tank \(Tank\) is connected to nothing"),
], ids=["fixed", "unused-world", "tank"])
def test_component_connected_to_nothing_warns(extra, culprit):
    with pytest.warns(fl.ModelWarning, match=culprit):
        flatten(PushedOscillator(extra=extra))


class SpringMass(fl.Model):
    """wall – spring – mass, the mass's flange_b left open (zero force, Modelica's rule for an open flow)."""

    def __init__(self) -> None:
        super().__init__()
        self.wall, self.spring, self.mass = Fixed(), Spring(c=K), Mass(m=M, init={"s": 0.1, "v": 0.0})
        self.connect(self.wall.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.mass.flange_a)


@pytest.mark.parametrize("make", [SpringMass, lambda: PushedOscillator(extra="free mass")],
                         ids=["open-flange", "free-mass"])
def test_open_connectors_and_free_moving_components_do_not_warn(make):
    """An open flange on a connected component (the mass's flange_b) and a mass left to move freely (its own
    dynamics) are legitimate models: no warning (warnings are errors in this suite)."""
    flat = flatten(make())
    assert any(v.name == "mass.s" for v in flat.variables)


def test_world_used_by_a_free_body_does_not_warn():
    """A World whose frame is unconnected still gives the free body its gravity: it is used, no warning."""

    class Falling(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.world = World()
            self.body = Body(m=1.0, I=np.eye(3), init={"r_0": [0.0, 0.0, 0.0], "v_0": [0.0, 0.0, 0.0]})

    flat = flatten(Falling())
    assert any(v.name == "body.r_0[1]" for v in flat.variables)
