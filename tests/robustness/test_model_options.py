"""Model options, the pump truck's options and design record, JSON scenarios and ``$FLEXLIB_MODELS`` (issue 26).

Every option of a registered model is declared once (``flexlib.registry.ModelOption``: type, default, accepted
values, doc) and checked there — for a registered scenario, a JSON file and the command line's ``--option`` text,
converted by the declared type; a refused value names the model, the scenario (and its file), the option, the
value and what is accepted. No case here builds a pump-truck DAE (model construction and checks only).
"""

from __future__ import annotations

import json
import math
import re
import sys
from dataclasses import replace

import pytest
from click.testing import CliRunner

import flexlib as fl
from flexlib import Parameter, Variable, der, eq, registry
from flexlib.cli import cli
from flexlib.errors import InitializationError, ParameterError, RegistryError, RunArgumentError
from flexlib.models.pump_truck.model import PumpTruck
from flexlib.models.pump_truck.parameters import DirectDrive, EndHose, Pipe, PumpTruckParameters, Steel, Turret
from flexlib.registry import ModelOption, Scenario
from tests.robustness.helpers import cli_error

ENV = {"COLUMNS": "250"}
REC = PumpTruckParameters()


def fails(*args: str, code: int = 1) -> str:
    """Run the CLI; it must fail with one ``Error:`` line, no traceback; return that line."""
    return cli_error(*args, code=code, columns=int(ENV["COLUMNS"]))


def scenario_file(tmp_path, content) -> str:
    path = tmp_path / "mine.json"
    path.write_text(content if isinstance(content, str) else json.dumps(content))
    return str(path)


# -- the pump-truck cases ----------------------------------------------------------------------------------
def test_cli_filled_false_is_read_as_false_and_empties_the_pipe():
    """``--option filled=False`` was the truthy string 'False' (pipe filled): the declared bool type converts it."""
    entry = registry.get_model("pump-truck")
    options = entry.parse_options({"filled": "False", "slewing": "no"})
    assert options == {"filled": False, "slewing": False}
    scen = entry.checked(replace(entry.scenario("hold"), options=options))
    model = entry.factory(scen)  # construction only, no DAE
    assert model.record.pipe.filled is False and not model.slewing and not hasattr(model, "slew")


@pytest.mark.parametrize(("text", "value"), [("true", True), ("FALSE", False), ("Yes", True), ("no", False),
                                              ("1", True), ("0", False)])
def test_cli_bool_words_any_case(text, value):
    assert registry.get_model("pump-truck").parse_options({"flexible": text}) == {"flexible": value}


def test_cli_bool_option_refuses_other_words():
    line = fails("run", "pump-truck", "-s", "hold", "-O", "filled=maybe", "--no-progress")
    assert "filled=maybe" in line and "'pump-truck'" in line and "true/false/yes/no/1/0" in line


@pytest.mark.parametrize("kwargs", [{"slewing": "no"}, {"filled": "False"}, {"flexible": 1}])
def test_pump_truck_bool_arguments_are_not_truthiness(kwargs):
    (name, value), = kwargs.items()
    with pytest.raises(ParameterError, match=rf"PumpTruck: {name} must be true or false.*got {value!r}"):
        PumpTruck(**kwargs)


def test_a_joint_with_both_a_target_and_a_command_is_refused():
    with pytest.raises(ParameterError, match=r"PumpTruck: joint2 is given in both targets and commands; give either "
                                             r"a target \(closed loop\) or a command \(open loop\) per joint"):
        PumpTruck(targets={"t": [0.0, 10.0], "joint2": [176.0, 170.0]},
                  commands={"t": [0.0, 10.0], "joint2": [0.0, 0.5]})


@pytest.mark.parametrize(("field", "value", "match"), [
    ("p_hold_fraction", 80, r"p_hold_fraction must be a finite number in \(0, 1\] \[1\] \(the share of p_system "
                            r"allowed for holding\), got 80"),
    ("p_system", 350, r"p_system must be a finite number in \[1e\+06, 1e\+08\] \[Pa\] \(10 \.\.\. 1000 bar\), "
                      r"got 350"),
    ("g", 0.0, r"g must be a finite number > 0 \[m/s2\], got 0\.0"),
    ("g", True, r"g must be a finite number > 0 \[m/s2\], got True"),
    ("min_transmission_deg", 95.0, r"min_transmission_deg must be a finite number in \(0, 90\) \[deg\], got 95"),
    ("p_system", "35e6", r"p_system must be a finite number .* got '35e6'"),
    ("steel", "S690", r"steel must be a Steel, got str 'S690'"),
    ("sections", REC.sections[:4], r"sections must be 5 SectionSpec records \(root to tip\), got tuple of 4"),
    ("sections", (REC.sections[0], *REC.sections[:3], replace(REC.sections[4], b=250.0)),
     r"sections\[4\]\.b must be a finite number in \(0, 5\.9\) \[m\] \(below the section's length 5\.9 m\), "
     r"got 250\.0"),
])
def test_record_fields_name_field_unit_range_and_value(field, value, match):
    with pytest.raises(ParameterError, match=r"pump-truck record: " + match):
        PumpTruckParameters(**{field: value})


@pytest.mark.parametrize(("make", "match"), [
    (lambda: Steel(E=210.0), r"steel\.E must be a finite number in \[1e\+09, 1e\+12\] \[Pa\], got 210\.0"),
    (lambda: Steel(rho=7.85), r"steel\.rho must be a finite number in \[1000, 25000\] \[kg/m3\], got 7\.85"),
    (lambda: Pipe(inner_diameter=125.0), r"pipe\.inner_diameter must be .* \(0, 1\] \[m\] \(metres, not mm\)"),
    (lambda: Pipe(filled="no"), r"pipe\.filled must be True or False, got 'no'"),
    (lambda: EndHose(mass=-150.0), r"hose\.mass must be a finite number > 0 \[kg\], got -150\.0"),
    (lambda: Turret(J_slew=math.nan), r"turret\.J_slew must be a finite number > 0 \[kg\.m2\], got nan"),
    (lambda: DirectDrive(q_max=80.0), r"joint1\.q_max must be a finite number in \[-3\.14159, 3\.14159\] \[rad\] "
                                      r"\(radians\), got 80\.0"),
    (lambda: DirectDrive(H=(0.45, "a")), r"joint1\.H must be a point \(x, y\) of two finite numbers \[m\]"),
    (lambda: replace(REC.linkages[0], sigma=2), r"linkage\.sigma \(assembly branch\) must be \+1 or -1, got 2"),
    (lambda: replace(REC.linkages[0], r="0.5"), r"linkage\.r must be a finite number > 0 \[m\], got '0\.5'"),
])
def test_record_parts_name_field_unit_range_and_value(make, match):
    with pytest.raises(ParameterError, match=r"pump-truck record: " + match):
        make()


def test_json_pose_as_a_mapping_says_what_pose_must_be():
    scen = Scenario("mine", data={"pose": {"slew": 0.0, "joint1": 10.0}})
    with pytest.raises(ParameterError, match=r"model 'pump-truck', scenario 'mine': PumpTruck: pose must be a "
                                             r"sequence of 6 angles \[deg\] \(slew, q1 \.\.\. q5\), got dict"):
        registry.run_scenario("pump-truck", scen, progress=False)


# -- every registered model's options: typed, range-checked, did-you-mean -----------------------------------------
@pytest.mark.parametrize(("model", "item", "match"), [
    ("n-mass-chain", "n=0", r"--option n=0: option 'n' of model 'n-mass-chain' must be an integer >= 1, got 0"),
    ("n-mass-chain", "n=2.5", r"option 'n' of model 'n-mass-chain' must be an integer >= 1, got '2\.5'"),
    ("n-mass-chain", "n=", r"option 'n' of model 'n-mass-chain' must be an integer >= 1, got ''"),
    ("n-mass-chain", "n=1e3", r"option 'n' of model 'n-mass-chain' must be an integer >= 1, got '1e3'"),
    ("boom-proxy", "linkages=maybe", r"option 'linkages' of model 'boom-proxy' must be true or false"),
    ("pump-truck", "modes=all", r"option 'modes' of model 'pump-truck' must be 'mpf', a count or a mapping"),
    ("pump-truck", "modes=0", r"option 'modes' of model 'pump-truck' must be at least 1 per section, got 0"),
    ("pump-truck", "link_plate=big", r"option 'link_plate' of model 'pump-truck' must be a positive area \[m2\]"),
    ("pump-truck", "link_plate=-1", r"must be a positive area \[m2\] \(a finite number > 0\), got -1\.0"),
])
def test_cli_option_value_refused_by_its_declaration(model, item, match):
    name, _, text = item.partition("=")
    with pytest.raises(RunArgumentError, match=match):
        registry.get_model(model).parse_options({name: text})
    line = fails("run", model, "-O", item, "--no-progress")  # before any build
    assert f"--option {item}" in line


@pytest.mark.parametrize(("model", "name", "hint"), [
    ("n-mass-chain", "nn", "did you mean 'n'?"), ("boom-proxy", "linkage", "did you mean 'linkages'?"),
    ("pump-truck", "flexibel", "did you mean 'flexible'?"), ("pump-truck", "slew", "did you mean 'slewing'?"),
    ("fourbar", "n", "options of fourbar: none"), ("three-loop", "flexible", "options of three-loop: none"),
])
def test_unknown_option_names_it_with_the_closest_match(model, name, hint):
    line = fails("run", model, "-O", f"{name}=1", "--no-progress")
    assert f"unknown model option {name!r}" in line and hint in line


def test_unknown_option_lists_the_accepted_values():
    line = fails("run", "pump-truck", "-O", "fillled=true", "--no-progress")
    assert "filled (true or false or none" in line and "link_plate (a positive area [m2]" in line


@pytest.mark.parametrize(("model", "options", "match"), [
    ("n-mass-chain", {"n": "3"}, r"option 'n' must be an integer >= 1, got '3'"),
    ("n-mass-chain", {"n": True}, r"option 'n' must be an integer >= 1, got True"),
    ("n-mass-chain", {"n": 2.5}, r"option 'n' must be an integer >= 1, got 2\.5"),
    ("boom-proxy", {"linkages": "no"}, r"option 'linkages' must be true or false, got 'no'"),
    ("pump-truck", {"filled": "False"}, r"option 'filled' must be true or false or none .*got 'False'"),
    ("pump-truck", {"modes": {"1": [1]}}, r"option 'modes' must give every section 1-5 \(missing \[2, 3, 4, 5\]"),
])
def test_json_scenario_options_get_the_same_checks(tmp_path, model, options, match):
    path = scenario_file(tmp_path, {"name": "mine", "options": options})
    where = re.escape(f"model '{model}', scenario 'mine' (file {path}): ")
    with pytest.raises(RunArgumentError, match=where + match):
        registry.run_scenario(model, Scenario.from_file(path), progress=False)
    line = fails("run", model, "-s", path, "--no-progress")
    assert path in line and "option" in line


def test_json_null_leaves_the_filled_option_to_the_record():
    entry = registry.get_model("pump-truck")
    scen = entry.checked(Scenario.from_dict({"name": "mine", "options": {"filled": None}}))
    assert scen.options["filled"] is None
    assert entry.parse_options({"filled": "none"}) == {"filled": None}


def test_a_registered_scenario_with_a_bad_option_value_is_refused(monkeypatch):
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    with pytest.raises(RunArgumentError, match=r"model 'n-mass-chain', scenario 'mine': option 'n' must be an "
                                               r"integer >= 1, got -2"):
        registry.register_scenario("n-mass-chain", Scenario("mine", options={"n": -2}))


def test_nmasschain_checks_n_with_the_same_declaration():
    from flexlib.models.n_mass_chain import NMassChain

    with pytest.raises(ParameterError, match=r"NMassChain: n must be an integer >= 1, got 0"):
        NMassChain(0)  # was "list index out of range"
    with pytest.raises(ParameterError, match=r"NMassChain: n must be an integer >= 1, got 2\.7"):
        NMassChain(2.7)  # was silently 2 masses


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"pose": "0,0,0,0,0,0"}, r"pose must be a sequence of 6 angles \[deg\] .* got str '0,0,0,0,0,0'"),
    ({"pose": (0.0, True, 0.0, 0.0, 0.0, 0.0)}, r"pose needs 6 finite angles"),
    ({"targets": {"t": "0 10", "joint2": [176.0, 170.0]}}, r"targets\['t'\] must be finite, strictly increasing "
                                                          r"times \[s\], got '0 10'"),
    ({"targets": {"t": [0.0, 10.0], "jiont2": [176.0, 170.0]}}, r"targets has unknown joint 'jiont2' \(did you "
                                                                 r"mean 'joint2'\?\)"),
    ({"commands": {"t": [0.0, 1.0], "joint1": ["0", "0.5"]}}, r"commands\['joint1'\] needs 2 finite values"),
    ({"modes": 2.5, "flexible": True}, r"modes must be 'mpf', a count or a mapping .* got 2\.5"),
    ({"link_plate": "big"}, r"link_plate must be a positive area \[m2\] \(a finite number > 0\), got 'big'"),
])
def test_pump_truck_arguments_of_the_wrong_type(kwargs, match):
    with pytest.raises(ParameterError, match=r"PumpTruck: " + match):
        PumpTruck(**kwargs)


def test_pump_truck_data_key_misspelt():
    with pytest.raises(RunArgumentError, match=r"model 'pump-truck', scenario 'mine': unknown data 'poses'; did you "
                                               r"mean 'pose'\? \(data of pump-truck: pose, targets, commands\)"):
        registry.run_scenario("pump-truck", Scenario("mine", data={"poses": [0.0] * 6}), progress=False)


def test_data_for_a_model_that_reads_none(tmp_path):
    path = scenario_file(tmp_path, {"name": "mine", "data": {"n": 3}})
    line = fails("run", "n-mass-chain", "-s", path, "--no-progress")
    assert "unknown data 'n'" in line and "n-mass-chain reads no data" in line and path in line


# -- the command line: duplicates, contradictions ------------------------------------------------------------------
@pytest.mark.parametrize(("args", "culprit"), [
    (("-p", "mass0.m=1", "-p", "mass0.m=2"), "--param mass0.m is given twice (1 and 2)"),
    (("-O", "n=2", "-O", "n=3"), "--option n is given twice ('2' and '3')"),
    (("-p", "mass0.m=2", "-p", "mass0.m=2.0"), None),  # the same value twice is no contradiction: runs
])
def test_cli_repeated_values(args, culprit):
    if culprit is None:
        res = CliRunner().invoke(cli, ["run", "n-mass-chain", "-s", "short", "--t-end", "0.01", *args,
                                       "--no-progress"], env=ENV)
        assert res.exit_code == 0, res.output
        return
    assert culprit in fails("run", "n-mass-chain", "-s", "short", *args, "--no-progress")


def test_cli_flexible_flag_contradicting_the_option():
    line = fails("run", "pump-truck", "--flexible", "-O", "flexible=no", "--no-progress")
    assert "--flexible and --option flexible=False contradict each other" in line


# -- JSON scenario files -------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("content", "culprit"), [
    ("", "is not valid JSON"),
    ("[1, 2]", "a scenario must be a mapping (JSON object), got list"),
    ({"name": "mine", "model": "n-mass-chain"}, "unknown field 'model' (fields: name, doc, t_end"),
    ({"doc": "no name"}, "a scenario needs a 'name' (fields: name, doc"),
    ({"name": 5}, "name must be a non-empty str, got 5"),
    ({"name": "mine", "t_end": "1"}, "t_end must be a positive finite number of seconds, got '1'"),
    ({"name": "mine", "params": [1]}, "params must be a mapping (dict), got list"),
    ({"name": "mine", "params": {"mass0.m": math.nan}}, "parameter 'mass0.m' must be a finite number"),
    ({"name": "mine", "run": {"max_steps": "10"}}, "max_steps = '10' is invalid"),
])
def test_bad_scenario_files(tmp_path, content, culprit):
    path = scenario_file(tmp_path, content)
    line = fails("run", "n-mass-chain", "-s", path, "--no-progress")
    assert culprit in line


# -- the registry API ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("kwargs", "match"), [
    ({"scenario": 5}, r"run_scenario: scenario must be a scenario name or a Scenario record, got int"),
    ({"params": [1]}, r"run_scenario: params must be a mapping \(dict\), got list"),
    ({"params": {"mass0.m": "2"}}, r"run_scenario: parameter 'mass0\.m' must be a finite number \(SI units\), "
                                   r"got '2'"),
])
def test_run_scenario_arguments_checked_before_the_build(kwargs, match):
    with pytest.raises(RunArgumentError, match=match):
        registry.run_scenario("n-mass-chain", **{"scenario": "short", **kwargs}, progress=False)


@pytest.mark.parametrize(("declare", "match"), [
    (lambda: ModelOption("n", list), r"ModelOption\('n'\): type must be bool, int, float, str or None"),
    (lambda: ModelOption("n", int, 0, low=1), r"ModelOption\('n'\): the default is refused by the declaration: n "
                                              r"must be an integer >= 1, got 0"),
    (lambda: ModelOption("n-masses", int, 1), r"name must be a Python identifier \(a keyword\), got 'n-masses'"),
    (lambda: ModelOption("kind", str, "a", low=1), r"low/high bound an int or float option"),
    (lambda: ModelOption("kind", str, "c", choices=("a", "b")), r"must be one of 'a', 'b', got 'c'"),
])
def test_malformed_option_declarations(declare, match):
    with pytest.raises(RegistryError, match=match):
        declare()


def test_malformed_option_lists_in_register_model(monkeypatch):
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    with pytest.raises(RegistryError, match=r"register_model\('x'\): two options named 'n'"):
        registry.register_model("x", lambda s: None, doc="", scenarios=[Scenario("a")],
                                options=[ModelOption("n", int, 1), "n"])
    with pytest.raises(RegistryError, match=r"register_model\('x'\): options must be a sequence of ModelOption, "
                                            r"got str"):
        registry.register_model("x", lambda s: None, doc="", scenarios=[Scenario("a")], options="n")


class Scaled(fl.Model):
    """``x' = −x``, ``c·y = x``: the algebraic row's rank follows the parameter ``c``."""

    k = Parameter(1.0, unit="1/s")
    c = Parameter(1.0, unit="1")
    x = Variable(unit="m", start=1.0, fixed=True)
    y = Variable(unit="m")

    def equations(self):
        return [eq(der(self.x), -self.k * self.x), eq(self.c * self.y, self.x, label="scaled")]


def test_initialization_error_after_a_params_override_names_it(monkeypatch):
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    registry.register_model("scaled", lambda s: Scaled(), doc="rank follows c", options=(), data=(),
                            scenarios=[Scenario("a", t_end=0.1, params={"k": 2.0})])
    with pytest.raises(InitializationError) as info:
        registry.run_scenario("scaled", params={"c": 0.0}, progress=False)
    msg = str(info.value)
    assert "(model): y" in msg  # the engine's own diagnosis is kept
    assert "parameter overrides (scenario 'a': k = 2.0; given: c = 0.0)" in msg and "rank" in msg


# -- $FLEXLIB_MODELS -----------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("source", "match"), [
    ("def f(:\n    pass\n", r"SyntaxError: invalid syntax \(.*user_models_26\.py:1\)"),
    ("import math\nx = 1 / 0\n", r"ZeroDivisionError: division by zero \(.*user_models_26\.py:2\)"),
    (None, r"ModuleNotFoundError: No module named 'user_models_26'"),
])
def test_env_module_that_fails_to_import_is_one_clear_line(monkeypatch, tmp_path, source, match):
    if source is not None:
        (tmp_path / "user_models_26.py").write_text(source)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(sys, "path", list(sys.path))
    monkeypatch.setenv("FLEXLIB_MODELS", "user_models_26")
    monkeypatch.setattr(registry, "_loaded", False)
    with pytest.raises(RegistryError, match=r"\$FLEXLIB_MODELS: cannot import the model module 'user_models_26': "
                                            + match):
        registry.models()
    line = fails("list")
    assert "'user_models_26'" in line
