"""A new user's mistakes with the command line, the registry and results (issue 26, red-team pass): an empty or
mistyped scenario name, a hand-edited JSON scenario (a key twice, a bad run option, ``t_end`` under ``run``), a
model option given as a parameter and the reverse, ``--fail-above nan``, hand-edited result files, damaged run
records, a user's model whose factory or summary signals fail, the wrong type where a name, a Result, a path or a
list is expected, and malformed registrations. Each is one error naming the culprit (or, for a finished run, a
warning and the result kept), never a raw traceback or a silent wrong answer.

No model is built except two tiny user models (one state); the run-option checks are shown to come before the
build by a ``Simulation`` that fails the test if it is made."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

import flexlib as fl
from flexlib import Variable, der, eq, registry
from flexlib.cli import cli
from flexlib.errors import ModelError, RegistryError, ResultFileError, ResultKeyError, RunArgumentError
from flexlib.registry import ModelOption, RunRecord, Scenario
from flexlib.results.compare import compare, select
from flexlib.results.hdf5 import load_result
from flexlib.results.result import Result
from flexlib.solve.simulation import Simulation

ENV = {"COLUMNS": "200"}
CHAIN = ("run", "n-mass-chain", "--no-progress")


def invoke(*args: str):
    res = CliRunner().invoke(cli, list(args), env=ENV)
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    assert "Traceback" not in res.output
    return res


def fails(*args: str) -> str:
    """Run the CLI; it must fail with exit code 1 and one ``Error:`` line; return that line."""
    res = invoke(*args)
    assert res.exit_code == 1, res.output
    errors = [line for line in res.output.splitlines() if line.startswith("Error:")]
    assert len(errors) == 1, res.output
    return errors[0]


@pytest.fixture
def no_build(monkeypatch):
    """A ``Simulation`` that fails the test if it is made: the checks must come before the build."""
    def refuse(self, *args, **kwargs):
        raise AssertionError("the model was built: the value was not checked first")

    monkeypatch.setattr(Simulation, "__init__", refuse)


@pytest.fixture
def own_models(monkeypatch):
    """A private copy of the registry, so that a test's registrations do not leak."""
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))


def made(**kwargs) -> Result:
    """A result made by hand (no run): 3 rows, a scalar and an array variable, a recorded run of n-mass-chain."""
    t = np.array([0.0, 0.05, 0.1])
    record = RunRecord("n-mass-chain", Scenario("short", t_end=1.0, options={"n": 3}).to_dict(), {}, {})
    fields = {"model": "NMassChain", "t": t, "names": ["mass0.s", "mass0.v", "frame.r[0]", "frame.r[1]"],
              "values": np.column_stack([1.0 + t, np.ones(3), 2 * t, 3 * t]), "units": ["m", "m/s", "m", "m"],
              "docs": [""] * 4, "kinds": ["variable"] * 4, "parameters": {"mass0.m": (1.0, "kg")},
              "stats": {"steps": 3}, "metadata": {"run": record.to_json()}}
    return Result(**{**fields, **kwargs})


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    path = tmp_path_factory.mktemp("redteam") / "made.h5"
    made().save(path)
    return path


def edited(saved, tmp_path, change) -> str:
    """A copy of the saved result with ``change(h5py.File)`` applied (a hand edit)."""
    path = tmp_path / "edited.h5"
    shutil.copy(saved, path)
    with h5py.File(path, "r+") as f:
        change(f)
    return str(path)


def json_file(tmp_path, text: str, name: str = "mine.json") -> str:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return str(path)


# == the command line: scenario names and files =====================================================================
def test_an_empty_scenario_name_is_not_the_default_scenario():
    line = fails(*CHAIN, "-s", "")
    assert "model 'n-mass-chain': a scenario is named by a non-empty str (known: short, sine), got ''" in line


def test_a_mistyped_scenario_file_says_there_is_no_such_file(tmp_path):
    line = fails(*CHAIN, "-s", str(tmp_path / "mine.jsn"))
    assert "mine.jsn: no such file, and model 'n-mass-chain' has no scenario of that name (its scenarios: short, " \
           "sine" in line


def test_a_key_given_twice_in_a_json_scenario_is_refused(tmp_path):
    path = json_file(tmp_path, '{"name": "d", "t_end": 0.1, "t_end": 0.2}')
    assert f"the scenario file {path}: the key 't_end' is given twice in one object" in fails(*CHAIN, "-s", path)


def test_a_json_scenario_with_a_byte_order_mark_is_read(tmp_path, no_build):
    path = json_file(tmp_path, '\ufeff{"name": "bom", "options": {"n": 0}}')  # read: its option is what is refused
    assert f"scenario 'bom' (file {path}): option 'n' must be an integer >= 1, got 0" in fails(*CHAIN, "-s", path)


def test_t_end_under_run_says_where_it_goes(tmp_path):
    path = json_file(tmp_path, json.dumps({"name": "r", "run": {"t_end": 0.1}}))
    assert "unknown run option 't_end'" in (line := fails(*CHAIN, "-s", path))
    assert "the end time is the scenario's own field t_end, beside run" in line


@pytest.mark.parametrize(("run", "culprit"), [
    ({"rtol": "1e-6"}, r"rtol = '1e-6' is invalid: .* \(the value is the scenario's run option rtol\)"),
    ({"solver": "euler"}, r"solver = 'euler' is invalid: must be one of .* the scenario's run option solver\)"),
    ({"steady_state": "false"}, r"steady_state = 'false' is invalid: must be True or False .* run option "
                                r"steady_state\)"),
    ({"t_start": 5.0}, r"t_end \(0\.1\) must be greater than t_start \(5\) \(the value is the scenario's t_end\)"),
])
def test_a_bad_run_option_of_a_json_scenario_names_the_file_before_the_build(tmp_path, no_build, run, culprit):
    path = json_file(tmp_path, json.dumps({"name": "r", "t_end": 0.1, "run": run}))
    line = fails(*CHAIN, "-s", path)
    assert f"model 'n-mass-chain', scenario 'r' (file {path}): run():" in line
    assert re.search(culprit, line), line


def test_a_run_option_given_on_the_command_line_is_not_blamed_on_the_scenario(no_build):
    line = fails(*CHAIN, "-s", "short", "--t-end", "nan")
    assert "t_end = nan is invalid" in line and "scenario" not in line


# == the command line: options and parameters ========================================================================
def test_a_model_option_given_as_a_parameter_says_it_is_an_option(no_build):
    line = fails(*CHAIN, "-s", "short", "-p", "n=4")
    assert "model 'n-mass-chain': 'n' is given as a parameter override, but it is a model option (an integer " \
           ">= 1): give it as an option (--option n=VALUE" in line


def test_a_parameter_given_as_a_model_option_says_it_looks_like_a_parameter():
    line = fails(*CHAIN, "-O", "mass0.m=2")
    assert "unknown model option 'mass0.m'; 'mass0.m' looks like a parameter (component.parameter): give it as a " \
           "parameter override" in line


@pytest.mark.parametrize("flag", ["--flexible", "--rigid"])
def test_flexible_on_a_model_without_the_option_names_the_flag(flag):
    line = fails(*CHAIN, flag)
    assert f"{flag}: model 'n-mass-chain': unknown model option 'flexible' (options of n-mass-chain: n" in line


def test_fail_above_nan_is_refused_not_passed(saved, tmp_path):
    other = tmp_path / "other.h5"
    made(values=made().values * 2.0).save(other)
    assert "--fail-above nan: the threshold must be a number >= 0" in fails("compare", str(saved), str(other),
                                                                             "--fail-above", "nan")


@pytest.mark.parametrize(("args", "culprit"), [
    (("-s", "short", "-s", "sine"), "'--scenario': given 2 times ('short' and 'sine'); give it once"),
    (("--t-end", "1", "--t-end", "2"), "'--t-end': given 2 times (1.0 and 2.0); give it once"),
    (("--flexible", "--rigid"), "'--flexible': given 2 times (True and False); give it once"),
])
def test_an_option_given_twice_with_different_values_is_refused(args, culprit):
    res = invoke(*CHAIN, *args)
    assert res.exit_code == 2 and culprit in res.output, res.output


@pytest.mark.parametrize(("args", "culprit"), [
    (("-p", "mass0.m=2,mass1.m=3"), "--param 'mass0.m=2,mass1.m=3': one NAME=VALUE per --param"),
    (("-O", "n=3,flexible=true"), "--option 'n=3,flexible=true': one NAME=VALUE per --option"),
])
def test_several_assignments_in_one_option_are_refused(args, culprit):
    assert culprit in fails(*CHAIN, *args)


def test_a_models_module_given_as_a_file_says_to_give_its_name(tmp_path):
    line = fails("--models", str(tmp_path / "my_models.py"), "list")
    assert "cannot import the module" in line and "give the module's name, 'my_models', not its file" in line


def test_compare_plot_under_home_or_in_a_new_directory_is_written(saved, tmp_path, monkeypatch):
    monkeypatch.setenv("HOME", str(tmp_path))
    for given, written in (("~/d.png", tmp_path / "d.png"), (str(tmp_path / "new" / "sub" / "d.png"), None)):
        res = invoke("compare", str(saved), str(saved), "--signals", "mass0.s", "--plot", given)
        assert res.exit_code == 0 and f"plot written to {given}" in res.output, res.output
        assert (written or Path(given)).stat().st_size > 0


# == hand-edited result files ========================================================================================
def _rename(f, group: str, k: int, name: str) -> None:
    names = [n.decode() if isinstance(n, bytes) else n for n in f[f"{group}/names"][()]]
    names[k] = name
    del f[f"{group}/names"]
    f[group].create_dataset("names", data=np.array(names, dtype=object), dtype=h5py.string_dtype())


def _set_time(f, t) -> None:
    f["time"][...] = t


def _numbers_as_names(f) -> None:
    n = len(f["variables/names"][()])
    del f["variables/names"]
    f["variables"].create_dataset("names", data=np.arange(n))


@pytest.mark.parametrize(("change", "culprit"), [
    (lambda f: _rename(f, "variables", 1, "mass0.s"), r"/variables/names holds 'mass0\.s' twice"),
    (lambda f: _set_time(f, [0.1, 0.05, 0.0]), r"/time decreases at row 1 \(0\.1 s, then 0\.05 s\)"),
    (lambda f: _set_time(f, [0.0, np.nan, 0.1]), r"/time holds NaN or inf \(first at row 1\)"),
    (lambda f: f.attrs.__setitem__("solver_stats", "[1, 2]"), r"the attribute 'solver_stats' must be a JSON "
                                                              r"object .* got list"),
    (lambda f: f.attrs.__setitem__("solver_stats", "null"), r"the attribute 'solver_stats' must be a JSON "
                                                            r"object .* got NoneType"),
    (_numbers_as_names, r"/variables/names holds int64 values, not text"),
])
def test_a_hand_edited_result_file_names_the_file_and_the_problem(saved, tmp_path, change, culprit):
    path = edited(saved, tmp_path, change)
    with pytest.raises(ResultFileError, match=rf"cannot read the result file .*edited\.h5: {culprit}"):
        load_result(path)


def test_show_of_a_file_whose_solver_stats_are_null_is_one_line(saved, tmp_path):
    path = edited(saved, tmp_path, lambda f: f.attrs.__setitem__("solver_stats", "null"))
    assert "'solver_stats' must be a JSON object" in fails("show", path)


def _record(change):
    def apply(f):
        rec = json.loads(f.attrs["meta_run"])
        change(rec)
        f.attrs["meta_run"] = json.dumps(rec)
    return apply


@pytest.mark.parametrize(("change", "culprit"), [
    (lambda r: r.__setitem__("model", None), "the field 'model' must be a model name (str), got None"),
    (lambda r: r.__setitem__("params", [["mass0.m", 2]]), r"the field 'params' must be a JSON object, got "
                                                          r"[['mass0.m', 2]]"),
    (lambda r: r.__setitem__("run", "rtol=1e-6"), "the field 'run' must be a JSON object, got 'rtol=1e-6'"),
    (lambda r: r.__setitem__("scenario", "short"), "the field 'scenario' must be a JSON object, got 'short'"),
    (lambda r: r.pop("run"), "the field 'run' is missing"),
])
def test_from_a_run_record_with_a_field_of_the_wrong_type_names_the_field(saved, tmp_path, change, culprit):
    path = edited(saved, tmp_path, _record(change))
    assert f"{path}: the run settings (meta_run) are damaged: {culprit}" in fails("run", "--from", path)


# == a user's model: factory and summary signals =====================================================================
class Decay(fl.Model):
    """``x' = -x``, ``x(0) = 1``; ``r = (x, 2x)``: one state and an array variable."""

    x = Variable(unit="m", start=1.0, fixed=True)
    r = Variable(unit="m", shape=2)

    def equations(self):
        return [eq(der(self.x), -self.x), eq(self.r[0], self.x), eq(self.r[1], 2.0 * self.x)]


def _register(name: str, factory, **kwargs) -> None:
    registry.register_model(name, factory, doc="a user's model", scenarios=[Scenario("a", t_end=0.1)], **kwargs)


def _attribute_error(scenario):
    return scenario.nope


def _value_error(scenario):
    return int("x")


@pytest.mark.parametrize(("factory", "culprit"), [
    (_attribute_error, "its factory failed: AttributeError: 'Scenario' object has no attribute 'nope'"),
    (_value_error, "its factory failed: ValueError: invalid literal for int() with base 10: 'x'"),
    (lambda scenario: None, "its factory returned NoneType None, not a flexlib model (a Component)"),
])
def test_a_factory_that_fails_names_the_model(own_models, factory, culprit):
    _register("mine", factory)
    assert f"model 'mine', scenario 'a': {culprit}" in fails("run", "mine", "--no-progress")
    with pytest.raises(ModelError, match="model 'mine', scenario 'a': its factory"):
        registry.run_scenario("mine", progress=False)


def test_a_missing_summary_signal_is_a_warning_and_the_run_is_kept(own_models, tmp_path):
    _register("mine", lambda s: Decay(), summary_signals=["x", "y.z"])
    res = invoke("run", "mine", "--no-progress", "-o", str(tmp_path / "run.h5"))
    assert res.exit_code == 0, res.output
    assert "Warning: model 'mine': summary signals (register_model(..., summary_signals=...)): no variable 'y.z' " \
           "in the result of Decay" in res.output
    assert load_result(tmp_path / "run.h5").success


def test_summary_signals_that_fail_are_a_warning(own_models):
    _register("mine", lambda s: Decay(), summary_signals=lambda model: model.nope)
    res = invoke("run", "mine", "--no-progress")
    assert res.exit_code == 0 and "Warning: model 'mine': summary signals" in res.output
    assert "AttributeError" in res.output and "no summary table" in res.output


def test_an_array_summary_signal_gives_a_row_per_element(own_models):
    _register("mine", lambda s: Decay(), summary_signals=["r"])
    rows = [line for line in invoke("run", "mine", "--no-progress").output.splitlines() if "r[" in line]
    assert [row.split()[0] for row in rows] == ["r[0]", "r[1]"]
    cells = rows[1].split()  # signal, unit, min, max, |x| peaks at t
    assert float(cells[3]) == pytest.approx(2.0) and float(cells[4]) == 0.0  # peak of r[1] = 2·x(0), at t = 0


def test_numpy_arrays_in_scenario_data_are_recorded(own_models):
    _register("mine", lambda s: Decay())
    done = registry.run_scenario("mine", Scenario("np", t_end=0.1, data={"table": np.arange(3.0)}), progress=False)
    assert registry.run_settings(done.result).scenario["data"] == {"table": [0.0, 1.0, 2.0]}


def test_data_that_json_cannot_hold_is_refused_before_the_build(own_models, no_build):
    _register("mine", lambda s: Decay())
    with pytest.raises(RunArgumentError, match=r"scenario 'np': data\['hook'\] cannot be recorded in the result"):
        registry.run_scenario("mine", Scenario("np", t_end=0.1, data={"hook": print}))


# == the registry API ================================================================================================
@pytest.mark.parametrize("name", [None, 123, ["n-mass-chain"], ""])
def test_get_model_with_something_other_than_a_name(name):
    with pytest.raises(RegistryError, match=r"a model is named by a non-empty str \(known: .*n-mass-chain"):
        registry.get_model(name)


def test_run_scenario_with_a_model_instance_says_how_to_run_it():
    from flexlib.models.n_mass_chain import NMassChain

    with pytest.raises(RegistryError, match=r"got <NMassChain .*a model instance runs with flexlib.Simulation"):
        registry.run_scenario(NMassChain(1))


@pytest.mark.parametrize("scenario", [3, ""])
def test_get_scenario_with_something_other_than_a_name(scenario):
    with pytest.raises(RegistryError, match=r"model 'n-mass-chain': a scenario is named by a non-empty str"):
        registry.get_scenario("n-mass-chain", scenario)


@pytest.mark.parametrize(("kwargs", "culprit"), [
    ({"doc": 123}, r"doc must be a str \(one line\), got 123"),
    ({"scenarios": Scenario("a")}, r"scenarios must be a sequence of Scenario records, got Scenario"),
    ({"options": ModelOption("n", int, 1)}, r"options must be a sequence of ModelOption, got ModelOption"),
    ({"data": 5}, r"data must be a sequence of key names \(str\), got int 5"),
    ({"summary_signals": "x"}, r"summary_signals must be a sequence of variable names .* got str 'x'"),
    ({"default_scenario": ""}, r"default_scenario must be the name of one of its scenarios .* got ''"),
])
def test_malformed_registrations(own_models, kwargs, culprit):
    args = {"doc": "d", "scenarios": [Scenario("a")], **kwargs}
    with pytest.raises(RegistryError, match=rf"register_model\('mine'\): {culprit}"):
        registry.register_model("mine", lambda s: Decay(), **args)


@pytest.mark.parametrize(("declare", "culprit"), [
    (lambda: ModelOption("x", int, 1, choices=5), r"choices must be a sequence of the accepted values .* got 5"),
    (lambda: ModelOption("x", str, "a", choices="abc"), r"choices must be a sequence .* got 'abc'"),
    (lambda: ModelOption("x", float, None, allow_none=True, low=5, high=1), r"the bounds low = 5 and high = 1 leave "
                                                                            r"no value accepted"),
    (lambda: ModelOption("x", int, 1, doc=5), r"doc must be a str, got 5"),
    (lambda: ModelOption("x", int, 1, allow_none="no"), r"allow_none must be True or False, got 'no'"),
    (lambda: ModelOption("x", None, 1, check=lambda v: {}[v]), r"the default is refused by the declaration: x: "
                                                               r"the option's check failed on 1: KeyError: 1"),
])
def test_malformed_option_declarations(declare, culprit):
    with pytest.raises(RegistryError, match=rf"ModelOption\('x'\): {culprit}"):
        declare()


@pytest.mark.parametrize(("call", "culprit"), [
    (lambda e: e.parse_options({"n": 3}), r"parse reads the command line's text \(a str\), got 3 \(int\)"),
    (lambda e: e.parse_options(["n=3"]), r"parse_options takes the option texts by name .* got \['n=3'\]"),
    (lambda e: e.check_options("short"), r"check_options takes a Scenario record, got 'short' \(str\)"),
])
def test_model_entry_methods_with_the_wrong_type(call, culprit):
    with pytest.raises(RunArgumentError, match=culprit):
        call(registry.get_model("n-mass-chain"))


def test_a_numpy_number_is_a_number_of_seconds():
    assert Scenario("x", t_end=np.int64(2)).t_end == 2.0 and Scenario("y", t_end=np.float32(0.5)).t_end == 0.5


@pytest.mark.parametrize("path", [12345, None, b"mine.json", ""])
def test_scenario_from_file_with_something_other_than_a_path(path):
    with pytest.raises(RunArgumentError, match=r"Scenario.from_file: the path of a JSON scenario file must be a "
                                               r"non-empty str or os.PathLike"):
        Scenario.from_file(path)


@pytest.mark.parametrize("result", ["run.h5", None])
def test_run_settings_of_a_path_says_to_load_it(result):
    with pytest.raises(RunArgumentError, match=r"run_settings takes a Result \(read a file with "
                                               r"flexlib.load_result\(path\)\)"):
        registry.run_settings(result)


# == the pump truck's modes (declaration checks only: no model is made) =============================================
@pytest.mark.parametrize(("modes", "culprit"), [
    ({"1": [0], "01": [0], "2": [0], "3": [0], "4": [0], "5": [0]}, r"must give section 1 once, got it twice "
                                                                     r"\(keys '1' and '01'\)"),
    ({"1": [], "2": [0], "3": [0], "4": [0], "5": [0]}, r"must give section 1 at least one mode index, got an empty"),
    ({"1": [0], "2": [0], "3": [0], "4": [0], "5": [-1]}, r"of section 5 must be distinct mode indices >= 0, got "
                                                          r"\[-1\]"),
    ({"1": [0, 0], "2": [0], "3": [0], "4": [0], "5": [0]}, r"of section 1 must be distinct mode indices >= 0"),
])
def test_pump_truck_modes_mapping_is_checked_before_the_build(modes, culprit):
    scen = Scenario("m", options={"flexible": True, "modes": modes}, source="m.json")
    with pytest.raises(RunArgumentError, match=rf"model 'pump-truck', scenario 'm' \(file m.json\): option 'modes' "
                                               rf"{culprit}"):
        registry.get_model("pump-truck").check_options(scen)


def test_pump_truck_modes_on_a_rigid_boom_are_refused_not_ignored(no_build):
    line = fails("run", "pump-truck", "-O", "modes=3", "--no-progress")
    assert "model 'pump-truck', scenario 'expand': PumpTruck: modes = 3 selects the modes of the flexible " \
           "sections, but the boom is rigid (flexible=False)" in line


# == results =========================================================================================================
def test_row_of_several_times_is_refused():
    with pytest.raises(RunArgumentError, match=r"row\(t\): t must be one time \[s\] \(a number\), got \[0\.01, "
                                               r"0\.02\]; .*value\(name, times\)"):
        made().row([0.01, 0.02])


@pytest.mark.parametrize("call", [lambda r: r.unit(["mass0.s"]), lambda r: r.display(["mass0.s"]),
                                  lambda r: r.final(["mass0.s"])])
def test_a_list_where_a_name_is_expected(call):
    with pytest.raises(ResultKeyError, match=r"variables are looked up by name \(str\), got \['mass0\.s'\] \(list\)"):
        call(made())


@pytest.mark.parametrize("method", ["summary", "plot"])
def test_summary_and_plot_of_a_list_say_how_to_pass_names(method):
    with pytest.raises(ResultKeyError, match=rf"{method}: give the variable names as separate arguments, "
                                             rf"{method}\('a', 'b'\) or {method}\(\*names\), got the list"):
        getattr(made(), method)(["mass0.s", "mass0.v"])


def test_value_and_final_of_an_array_variable_give_each_element():
    res = made()
    assert res.value("frame.r", 0.05) == pytest.approx([0.1, 0.15])
    assert res.value("frame.r", [0.0, 0.1]) == pytest.approx(np.array([[0.0, 0.0], [0.2, 0.3]]))
    assert res.final("frame.r") == pytest.approx([0.2, 0.3]) and res.final("mass0.s") == pytest.approx(1.1)


def test_contains_with_a_list_is_false():
    assert ["mass0.s"] not in made() and "mass0.s" in made()


@pytest.mark.parametrize(("kwargs", "culprit"), [
    ({"ax": "x"}, r"plot: ax must be a matplotlib Axes \(or None: a new figure\), got 'x' \(str\)"),
    ({"si": "yes"}, r"plot: si must be True \(SI units\) or False \(display units\), got 'yes'"),
    ({"title": 5}, r"plot: title must be a str \(or None: the model's name\), got 5"),
])
def test_plot_arguments_of_the_wrong_type(kwargs, culprit):
    with pytest.raises(RunArgumentError, match=culprit):
        made().plot("mass0.s", **kwargs)


def test_compare_of_paths_says_to_load_them(saved):
    with pytest.raises(RunArgumentError, match=r"compare: a \(A\) must be a Result \(read a result file with "
                                               r"flexlib.load_result\(path\)\), got str"):
        compare(str(saved), made())


@pytest.mark.parametrize(("signals", "culprit"), [
    (5, r"signals must be a variable name or a list of names \(str\), got int 5"),
    ({"mass0.s": 1}, r"signals must be a variable name or a list of names \(str\), got dict"),
    ([], r"signals is empty; give variable names or patterns, or None for every variable"),
])
def test_compare_and_select_with_signals_of_the_wrong_kind(signals, culprit):
    with pytest.raises(RunArgumentError, match=rf"compare: {culprit}"):
        compare(made(), made(), signals)
    with pytest.raises(RunArgumentError, match=rf"select: {culprit}"):
        select(made(), signals)


@pytest.mark.parametrize("labels", [("A",), None, "AB", ("A", 2)])
def test_compare_labels_must_be_two_str(labels):
    with pytest.raises(RunArgumentError, match=r"compare: labels must be two str"):
        compare(made(), made(), labels=labels)
