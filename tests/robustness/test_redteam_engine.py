"""The run layer tried as a new user would (issue 26, second pass): a model class for an instance, ``codegen="no"``,
``use_cache="False"``, ``params`` naming a variable or a component, an ``experiment`` written as a dict, output
times as text or stopping before ``t_end``, tolerances below what double precision resolves, ``result_file`` naming
a user's notes, a CSV name, a device or a directory, on/off environment switches spelt ``false`` or ``no``, and
``$FLEXLIB_CACHE_DIR`` set to ``~/...`` or to nothing. Each gives a flexlib error naming the culprit before any work,
or now behaves as documented; and every run, also one that fails or is interrupted, ends with a row at ``t_end``
(or where it stopped)."""

from __future__ import annotations

import os
import re

import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, assert_, der, eq, if_else, time
from flexlib.compile import cache
from flexlib.compile.constants import zero_geometry
from flexlib.compile.environment import env_switch
from flexlib.compile.explicit import explicit_mode
from flexlib.models.reference.blow_up import BlowUp
from flexlib.solve import trajectory
from flexlib.solve.backends import base
from flexlib.solve.native import native_available

SOLVERS = ["ida", "ida-native", "ida-sksundae", "casadi-idas"]


class Osc(fl.Model):
    """x'' = -k x, x(0) = 1: x = cos(sqrt(k) t)."""

    k = Parameter(1.0, unit="N/m")
    x = Variable(unit="m")
    v = Variable(unit="m/s")

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), -self.k * self.x)]


class Holder(fl.Model):
    def __init__(self):
        super().__init__()
        self.osc = Osc(init={"x": 1.0, "v": 0.0})


class Step(fl.Model):
    """w' = +1 before t1, -1 after (a time event at t1): w = t, then 2 t1 - t."""

    t1 = Parameter(0.5, unit="s")
    w = Variable()

    def equations(self):
        return [eq(der(self.w), if_else(time < self.t1, 1.0, -1.0))]


class AssertBelowOne(fl.Model):
    x = Variable()

    def equations(self):
        assert_(self.x < 1.0, "x stays below 1")
        return [eq(der(self.x), 1.0)]


@pytest.fixture(scope="module")
def sim():
    return fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), use_cache=False)


@pytest.fixture(scope="module")
def nested():
    return fl.Simulation(Holder(), use_cache=False)


@pytest.fixture(scope="module")
def step():
    return fl.Simulation(Step(init={"w": 0.0}), use_cache=False)


# -- the model and the build options ----------------------------------------------------------------------------


@pytest.mark.parametrize(("make", "pattern"), [
    (lambda m: fl.Simulation(m), r"Simulation\(\): model = {}"),
    (lambda m: fl.build(m, use_cache=False), r"build\(\): model = {}"),
    (lambda m: fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), use_cache=False).with_model(m),
     r"Simulation.with_model\(\): model = {}"),
], ids=["Simulation", "build", "with_model"])
@pytest.mark.parametrize(("given", "shown"), [
    (Osc, r"Osc is a model class, not a model instance; give an instance such as Osc\(\)"),
    ("Osc", r"'Osc' \(a str\) is not a flexlib model instance"),
    (None, r"None \(a NoneType\) is not a flexlib model instance"),
], ids=["class", "name", "None"])
def test_something_else_than_a_model_instance(make, pattern, given, shown):
    """A model class (forgotten parentheses), a name or None: ModelTypeError (a TypeError, as before) naming it."""
    with pytest.raises(fl.errors.ModelTypeError, match=pattern.format(shown)) as err:
        make(given)
    assert isinstance(err.value, TypeError) and isinstance(err.value, fl.ModelError)


@pytest.mark.parametrize(("option", "value"), [
    ("codegen", "no"),  # compiled C: "no" is true
    ("codegen", "AUTO"),  # compiled C always
    ("codegen", None),
    ("codegen", 1),
    ("use_cache", "False"),  # used the cache
    ("assume_zero_geometry", "no"),  # assumed the zero geometry
])
def test_build_option_of_the_wrong_kind(option, value):
    with pytest.raises(fl.RunArgumentError, match=rf"Simulation\(\): {option} = {value!r} is invalid: must be True"):
        fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), **{option: value})
    with pytest.raises(fl.RunArgumentError, match=rf"build\(\): {option} = {value!r} is invalid"):
        fl.build(Osc(init={"x": 1.0, "v": 0.0}), **{option: value})


def test_numpy_bools_are_build_options():
    sim = fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), codegen=np.False_, use_cache=np.False_,
                        assume_zero_geometry=np.True_)
    assert sim.compiled.library is None and sim.build.key is None


# -- parameters ----------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("params", "pattern"), [
    ([("k", 2.0)], r"parameter_vector\(\): params = \[\('k', 2\.0\)\] is invalid: must be a dict.*list"),
    ("k=2", r"parameter_vector\(\): params = 'k=2' is invalid: must be a dict.*str"),
    ({1: 2.0}, r"parameter_vector\(\): params = \{1: 2\.0\} is invalid: keys must be parameter names"),
])
def test_parameter_vector_checks_params(sim, params, pattern):
    """``sim.parameter_vector`` is public: it gave AttributeError ('list' object has no attribute 'items')."""
    with pytest.raises(fl.RunArgumentError, match=pattern):
        sim.parameter_vector(params)


def test_parameter_vector_checks_values(sim):
    with pytest.raises(fl.RunArgumentError, match=r"parameter_vector\(\): values = \[1, 2\].*dict.*list"):
        sim.parameter_vector(values=[1, 2])


@pytest.mark.parametrize("name", ["osc..k", ".osc.k", "osc.k."])
def test_empty_path_parts_name_no_parameter(nested, sim, name):
    """``params={".k": 2}`` found ``k`` through the empty path and then failed with KeyError: '.k'."""
    with pytest.raises(fl.ParameterError, match=rf"unknown parameter '{re.escape(name)}' in model Holder; the name has "
                                                r"an empty part \(a stray '\.'\): did you mean 'osc\.k'\?"):
        nested.run(1.0, params={name: 2.0})
    with pytest.raises(fl.ParameterError, match=r"unknown parameter '\.k' in model Osc; .*did you mean 'k'"):
        sim.run(1.0, params={".k": 2.0})


@pytest.mark.parametrize(("name", "pattern"), [
    ("osc.x", r"'osc\.x' is a variable, not a parameter: its start value is set with init=\{'x': \.\.\.\}"),
    ("osc", r"'osc' is a component, not a parameter: name one of its parameters such as osc\.k"),
    ("osc.k[0]", r"'osc\.k' is a scalar parameter: give 'osc\.k' without an index"),
])
def test_unknown_parameter_says_what_the_name_is(nested, name, pattern):
    """Before: "unknown parameter 'osc.x'; did you mean osc.k?" — as if the variable were a typo of the parameter."""
    with pytest.raises(fl.ParameterError, match=rf"unknown parameter '{re.escape(name)}' in model Holder; {pattern}"):
        nested.run(1.0, params={name: 2.0})


# -- the experiment record -------------------------------------------------------------------------------------


@pytest.mark.parametrize(("value", "what"), [
    ({"t_end": 2.0}, r"\{'t_end': 2\.0\} is a dict"),
    (2.0, r"2\.0 is a float"),
    (fl.Experiment, r"<class .*Experiment'> is the class itself, not an instance"),
], ids=["dict", "number", "class"])
def test_experiment_that_is_not_an_experiment(value, what):
    """A dict or a number gave AttributeError: 'dict' object has no attribute 'dt_out'."""

    class Timed(Osc):
        experiment = value

    sim = fl.Simulation(Timed(init={"x": 1.0, "v": 0.0}), use_cache=False)
    pattern = rf"Timed\.experiment = {what}; write experiment = flexlib\.Experiment\(t_end="
    with pytest.raises(fl.ModelError, match=pattern):
        sim.run()
    with pytest.raises(fl.ModelError, match=pattern):
        sim.initialize()


@pytest.mark.parametrize(("field", "meant"), [
    ("stop_time", "t_end"), ("StopTime", "t_end"), ("Interval", "dt_out"), ("Tolerance", "rtol"), ("t_ned", "t_end"),
])
def test_experiment_field_under_another_name(field, meant):
    """Modelica's annotation names and typos: Python's "unexpected keyword argument" without the fields."""
    pattern = rf"Experiment\(\): unknown field '{field}' \(did you mean {meant}\?\); the fields are t_end, dt_out"
    with pytest.raises(fl.RunArgumentError, match=pattern):
        fl.Experiment(**{field: 1.0})
    assert fl.Experiment(2.0, 0.5) == fl.Experiment(t_end=2.0, dt_out=0.5)


def test_values_taken_from_the_experiment_are_named_as_such():
    """``max_order`` and ``t_start`` from the experiment were not named as its values."""

    class Late(Osc):
        experiment = fl.Experiment(t_start=5.0, t_end=10.0, max_order=7)

    sim = fl.Simulation(Late(init={"x": 1.0, "v": 0.0}), use_cache=False)
    with pytest.raises(fl.RunArgumentError, match=r"max_order = 7 is invalid.*\(the value comes from Late\.experiment"):
        sim.run()
    with pytest.raises(fl.RunArgumentError,
                       match=r"t_end = 3\.0 is invalid: t_end \(3\) must be greater than t_start \(5\) \(t_start = "
                             r"5\.0 s comes from Late\.experiment\)"):
        sim.run(3.0, max_order=2)


# -- initialize() --------------------------------------------------------------------------------------------------


def test_initialize_names_itself_and_its_arguments(sim):
    """Its argument errors said ``run():``; ``t_start=1e300`` was refused as a bad ``t_end`` (1e300 + 1 == 1e300)."""
    with pytest.raises(fl.RunArgumentError, match=r"^initialize\(\): t_start = '0' is invalid"):
        sim.initialize(t_start="0")
    with pytest.raises(fl.RunArgumentError, match=r"^initialize\(\): params = \[1\] is invalid"):
        sim.initialize(params=[1])
    res = sim.initialize(t_start=1e300)
    assert res.t.tolist() == [1e300] and res["x"][0] == 1.0


class Clock(fl.Model):
    x = Variable()

    def equations(self):
        return [eq(der(self.x), 1.0)]

    def initial_equations(self):
        return [eq(time, 1.0, label="started at one")]


def test_initial_equation_of_time_alone():
    """An initial equation without unknowns that does not hold at the start: "initial condition (model): (time-1) = 0
    #0 = 0 contradicts the model, which fixes it to -1"."""
    sim = fl.Simulation(Clock(init={"x": 0.0}), use_cache=False)
    with pytest.raises(fl.InitializationError, match=r"^initial equation \(model\): started at one involves no unknown "
                                                     r"\(only time and parameters\) and does not hold at the start "
                                                     r"t = 0 s: its residual there is -1$"):
        sim.initialize()
    assert sim.run(2.0, t_start=1.0).t[-1] == 2.0  # it holds when the run starts at 1 s


# -- output times -------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("times", "pattern"), [
    (["0.1", "0.2"], r"output_times = \['0\.1', '0\.2'\].*as numbers, not text"),  # was converted
    ("0.5", r"output_times = '0\.5'.*as numbers, not text"),
    ([False, True], r"output_times = \[False, True\].*not True/False"),  # was [0, 1]
    (np.array([0.1 + 1j]), r"output_times = <array of shape \(1,\)>.*real numbers \[s\] \(got complex128"),  # 0.1
    (0.5, r"output_times = 0\.5.*got a single number; give \[0\.5\]"),
    ({0.1, 0.2}, r"output_times = \{0\.1, 0\.2\}.*a list or an array\), got a set"),
    ((t for t in [0.1]), r"output_times = <generator.*got a generator"),
], ids=["text", "one-string", "bools", "complex", "number", "set", "generator"])
def test_output_times_of_the_wrong_kind(no_work, times, pattern):
    with pytest.raises(fl.RunArgumentError, match=pattern):
        no_work.run(1.0, output_times=times)


@pytest.mark.parametrize("solver", SOLVERS)
def test_output_times_before_t_end_still_end_at_t_end(sim, solver):
    """``run(1.0, output_times=[0.5])`` integrated to 1 s and returned rows at 0 and 0.5 s only."""
    res = sim.run(1.0, output_times=[0.25, 0.5], solver=solver, rtol=1e-8, atol=1e-10, progress=False)
    assert res.t.tolist() == [0.0, 0.25, 0.5, 1.0]
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-6)


def test_output_times_at_the_edges(sim):
    """Only the start given: the start and t_end; a last time within round-off of t_end is t_end (no sliver row);
    a shifted start."""
    assert sim.run(1.0, output_times=[0.0]).t.tolist() == [0.0, 1.0]
    assert sim.run(1.0, output_times=[0.5, 1.0 - 1e-13]).t.tolist() == [0.0, 0.5, 1.0]
    assert sim.run(2.0, t_start=0.5, output_times=[0.75, 1.0]).t.tolist() == [0.5, 0.75, 1.0, 2.0]


@pytest.mark.parametrize("solver", SOLVERS)
def test_output_times_with_a_time_event_on_them_and_at_t_end(step, solver):
    """The time event at 0.5 s on an output time and at t_end itself: both sides of the event are kept, the run ends
    at t_end with the value after it (w = t up to 0.5 s, then 1 - t)."""
    res = step.run(1.0, output_times=[0.25, 0.5], solver=solver, progress=False)
    assert res.t.tolist()[:2] == [0.0, 0.25] and res.t[-1] == 1.0 and set(res.t[2:-1]) == {0.5}
    assert abs(res["w"][-1]) < 1e-12 and res.events == [(0.5, "time event: Step: time < t1")]
    res = step.run(0.5, output_times=[0.25], solver=solver, progress=False)
    assert res.t[-1] == 0.5 and res["w"][-1] == pytest.approx(0.5, abs=1e-12)


# -- tolerances ---------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("kwargs", "pattern"), [
    (dict(rtol=1e-17), r"rtol = 1e-17 is invalid: is below the machine epsilon 2\.22e-16"),  # ran, claimed 1e-17
    (dict(rtol=1e-20), r"rtol = 1e-20 is invalid: is below the machine epsilon"),
    (dict(atol=1e-300), r"atol = 1e-300 is invalid: must be at least 1e-50"),  # IDA_ILL_INPUT at t = 0
    (dict(atol=1e-100), r"atol = 1e-100 is invalid: must be at least 1e-50"),  # step size underflow at 1e-40 s
])
def test_tolerances_double_precision_cannot_meet(no_work, kwargs, pattern):
    with pytest.raises(fl.RunArgumentError, match=pattern):
        no_work.run(1.0, **kwargs)


def test_smallest_tolerances_still_run(sim):
    res = sim.run(1.0, rtol=3e-16, atol=1e-50, dt_out=0.5, max_steps=100_000)
    assert res.success and res.t[-1] == 1.0


# -- result files -------------------------------------------------------------------------------------------------


def test_result_file_does_not_replace_a_users_file(no_work, tmp_path):
    """A text file, a source file: replaced by the HDF5 result without a word."""
    for name, text in (("notes.txt", "my notes"), ("model.py", "print('hi')")):
        path = tmp_path / name
        path.write_text(text)
        with pytest.raises(fl.RunArgumentError,
                           match=rf"result_file = .*{name}' is invalid: .*{name} exists and is not an HDF5 file but "
                                 r"text.*not a flexlib result file; it is not replaced"):
            no_work.run(1.0, result_file=path.as_posix())
        assert path.read_text() == text


def test_result_file_does_not_replace_a_device_or_pipe(no_work, tmp_path):
    """The atomic write replaces the file at the path: ``result_file="/dev/null"`` run as root put a regular file in
    place of the system's /dev/null. A named pipe stands in for the device here."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    pattern = r"result_file = .* is invalid: .*pipe exists and is a named pipe; a result file replaces the file at"
    with pytest.raises(fl.RunArgumentError, match=pattern):
        no_work.run(1.0, result_file=fifo)
    assert fifo.is_fifo()


@pytest.mark.parametrize(("name", "pattern"), [
    ("out.csv", r"a result file is HDF5 \(read back with flexlib\.load_result\), not \.csv; give a name ending in "
                r"\.h5 such as .*out\.h5"),
    ("results/", r"ends with a path separator, so it names a directory"),  # wrote a file named 'results'
    ("a\x00b.h5", r"contains a NUL character"),  # the run went to the end, then the save failed
    ("z" * 300 + ".h5", r"cannot be used as a file name: File name too long"),  # OSError from Path.is_dir
], ids=["csv", "trailing-slash", "nul", "too-long"])
def test_result_file_names_that_cannot_be_what_was_meant(no_work, tmp_path, name, pattern):
    with pytest.raises(fl.RunArgumentError, match=rf"^run\(\): result_file = .* is invalid: {pattern}"):
        no_work.run(1.0, result_file=os.path.join(tmp_path, name))


def test_result_file_replaces_an_earlier_result_and_takes_any_other_name(sim, tmp_path):
    path = tmp_path / "run.h5"
    sim.run(0.5, result_file=path)
    sim.run(0.7, result_file=path)
    assert fl.load_result(path).t[-1] == 0.7
    sim.run(0.5, result_file=tmp_path / "run_001")  # no extension: written (HDF5)
    assert fl.load_result(tmp_path / "run_001").t[-1] == 0.5


# -- failed and interrupted runs end where they stopped ----------------------------------------------------------


@pytest.mark.parametrize("solver", ["ida", "ida-native", "ida-sksundae"])
def test_failed_run_on_a_grid_ends_at_the_failure_time(solver):
    """With ``dt_out=0.1`` the blow-up's rows ended at 0.9 s while IDA failed at 0.99998 s: the last accepted point
    is now the last row, at the time the message names (every step recorded: unchanged)."""
    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.SolverError) as err:
        sim.run(2.0, dt_out=0.1, solver=solver, progress=False)
    res = err.value.result
    assert res.status == "failed" and 0.99 < res.t[-1] < 1.0 and res.t[-2] == pytest.approx(0.9)
    assert f"at t = {res.t[-1]:.10g} s" in str(err.value) and np.isfinite(res["x"][-1])
    np.testing.assert_allclose(res["x"][:-1], 1.0 / (1.0 - res.t[:-1]), rtol=1e-3)


def test_failed_casadi_run_ends_at_its_last_accepted_point():
    """CasADi's IDAS reports no steps: the rows end where the failing call began, the first time the message names."""
    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"between t = ") as err:
        sim.run(2.0, dt_out=0.1, solver="casadi-idas", progress=False)
    start = float(str(err.value).split("between t = ")[1].split(" s")[0])
    assert err.value.result.t[-1] == pytest.approx(start, abs=1e-12)


@pytest.mark.parametrize("solver", ["ida-native", "ida-sksundae"])
def test_interrupted_run_on_a_grid_ends_where_it_stopped(monkeypatch, solver):
    """Ctrl-C during the steps of a run on a 1 s grid: the rows end at the solver's point, the time the message
    names, after the last grid row (they ended at the last grid row before it)."""
    sim = fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), use_cache=False)
    calls = {"n": 0}

    def interrupt(self, t):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt

    monkeypatch.setattr(trajectory.Progress, "update", interrupt)
    if solver == "ida-native":
        from flexlib.solve.backends import ida_c

        monkeypatch.setattr(ida_c, "CHUNK_STEPS", 40)
    with pytest.raises(fl.SimulationInterrupted) as err:
        sim.run(1e4, dt_out=1.0, solver=solver, progress=False)
    res = err.value.result
    assert res.status == "interrupted" and res.t[-2] < res.t[-1] < res.t[-2] + 1.0
    np.testing.assert_array_equal(res.t[:-1], np.arange(len(res.t) - 1))
    assert f"at t = {res.t[-1]:.10g} s" in str(err.value)
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-3)


@pytest.mark.parametrize("solver", SOLVERS)
def test_assertion_turning_false_ends_the_rows_at_that_time(solver):
    """x = t against the assertion x < 1: the run fails at 1 s on every backend, its rows ending there."""
    sim = fl.Simulation(AssertBelowOne(init={"x": 0.0}), use_cache=False)
    with pytest.raises(fl.SolverError,
                       match=r"assertion failed at t = 1 s:\n  AssertBelowOne: x < 1: x stays below 1") as err:
        sim.run(2.0, dt_out=0.3, solver=solver, progress=False)
    assert err.value.result.t[-1] == pytest.approx(1.0, abs=1e-9)


# -- environment switches and the cache directory ---------------------------------------------------------------


@pytest.mark.parametrize(("value", "expected"), [
    ("1", True), ("true", True), ("Yes", True), (" ON ", True), ("0", False), ("false", False), ("No", False),
    ("off", False), ("", None), ("all", "all"),
])
def test_environment_switch_words(monkeypatch, value, expected):
    monkeypatch.setenv("FLEXLIB_X", value)
    default = object()
    assert env_switch("FLEXLIB_X", default, ("all",)) == (default if expected is None else expected)


def test_environment_switches_spelt_as_words(monkeypatch):
    """Only the exact text ``0`` was read: ``FLEXLIB_NATIVE=false`` kept the C driver, ``FLEXLIB_ZERO_GEOMETRY=no``
    the planar reduction, ``FLEXLIB_ERROR_TEST_ALL=yes`` left the error test as it was."""
    monkeypatch.setenv("FLEXLIB_NATIVE", "false")
    assert not native_available()
    monkeypatch.setenv("FLEXLIB_ZERO_GEOMETRY", "no")
    assert zero_geometry() is False
    monkeypatch.setenv("FLEXLIB_EXPLICIT", "Off")
    assert explicit_mode() == "off"

    class Model:
        nominal = np.ones(2)
        derivative_level = np.array([False, True])

    monkeypatch.setenv("FLEXLIB_ERROR_TEST_ALL", "yes")
    assert base.absolute_tolerances(Model, 1e-8).tolist() == [1e-8, 1e-8]
    monkeypatch.setenv("FLEXLIB_ERROR_TEST_ALL", "off")
    assert base.absolute_tolerances(Model, 1e-8).tolist() == [1e-8, 1e20]


@pytest.mark.parametrize("name", ["FLEXLIB_NATIVE", "FLEXLIB_EXPLICIT", "FLEXLIB_ZERO_GEOMETRY"])
def test_environment_switch_with_another_word(monkeypatch, name):
    """``FLEXLIB_EXPLICIT=maybe`` left the stage on without a word."""
    monkeypatch.setenv(name, "maybe")
    with pytest.raises(fl.RunArgumentError, match=rf"environment variable {name} = 'maybe' is invalid: expected one "
                                                  r"of 1, true, yes, on, 0, false, no, off"):
        fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}), use_cache=False).run(0.1, solver="ida")


def test_cache_directory_forms(monkeypatch, tmp_path):
    """``~`` made a directory named '~' in the working directory, an empty value put the cache there; ``$VAR`` is
    expanded, a relative path is made absolute (a later chdir does not move it)."""
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", "~/cache")
    assert cache.cache_dir() == tmp_path / "home" / "cache"
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", "")
    assert cache.cache_dir() == tmp_path / "home" / ".cache" / "flexlib"
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", "$HOME/c2")
    assert cache.cache_dir() == tmp_path / "home" / "c2"
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", "rel")
    assert cache.cache_dir() == tmp_path / "rel"
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", "~/cache")
    sim = fl.Simulation(Osc(init={"x": 1.0, "v": 0.0}))
    assert sim.build.key is not None and list((tmp_path / "home" / "cache").glob("Osc-*"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["home"]
