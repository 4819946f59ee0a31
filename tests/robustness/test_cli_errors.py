"""Bad input to the ``flexlib`` command line and the registry: exit code != 0, one line naming the culprit
(model, scenario, parameter, option, file, module), no traceback; nothing written where a run never started."""

from __future__ import annotations

import json

import h5py
import pytest
from click.testing import CliRunner

import flexlib as fl
from flexlib import registry
from flexlib.cli import cli
from flexlib.errors import RegistryError, RunArgumentError
from flexlib.registry import Scenario
from tests.robustness.helpers import cli_error

ENV = {"COLUMNS": "200"}


def fails(*args: str, code: int | None = None) -> str:
    """Run the CLI, check it failed with one ``Error:`` line and no traceback; return that line."""
    return cli_error(*args, code=code)


@pytest.fixture(scope="module")
def chain_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli-err") / "chain.h5"
    res = CliRunner().invoke(cli, ["run", "n-mass-chain", "-s", "short", "-o", str(out), "--no-progress"], env=ENV)
    assert res.exit_code == 0, res.output
    return out


# -- run: model, scenario, parameters, options ------------------------------------------------------------------
def test_unknown_model_names_it_and_suggests():
    line = fails("run", "nmass-chain", "--no-progress", code=1)
    assert "'nmass-chain'" in line and "did you mean 'n-mass-chain'" in line and "fourbar" in line


def test_unknown_scenario_names_it_the_model_and_the_known_ones():
    line = fails("run", "n-mass-chain", "--scenario", "shrt", "--no-progress", code=1)
    assert "'shrt'" in line and "'n-mass-chain'" in line and "short, sine" in line and "did you mean 'short'" in line


def test_unknown_parameter_names_it(tmp_path):
    out = tmp_path / "never.h5"
    line = fails("run", "n-mass-chain", "-s", "short", "--param", "mass9.m=1", "-o", str(out), "--no-progress")
    assert "'mass9.m'" in line and "did you mean" in line
    assert not out.exists()


@pytest.mark.parametrize(("item", "culprit"), [("mass0.m=abc", "'abc'"), ("mass0.m", "NAME=VALUE"),
                                               ("=2", "NAME=VALUE"), ("mass0.m=nan", "finite")])
def test_malformed_param_names_it(item, culprit):
    line = fails("run", "n-mass-chain", "-s", "short", "--param", item, "--no-progress", code=1)
    assert repr(item) in line and culprit in line


def test_parameter_out_of_bounds_names_it():
    line = fails("run", "n-mass-chain", "-s", "short", "--param", "mass0.m=-1", "--no-progress", code=1)
    assert "mass0.m" in line and "-1" in line


@pytest.mark.parametrize(("option", "value"), [("--t-end", "-1"), ("--t-end", "abc"), ("--rtol", "2"),
                                                ("--atol", "0"), ("--dt-out", "-0.1"), ("--solver", "euler")])
def test_bad_option_value_names_the_option(option, value):
    line = fails("run", "n-mass-chain", "-s", "short", option, value, "--no-progress", code=2)
    assert option in line and value in line


def test_dt_out_too_small_for_the_run_names_it():
    line = fails("run", "n-mass-chain", "-s", "short", "--dt-out", "1e-9", "--no-progress", code=1)
    assert "dt_out" in line


def test_unwritable_out_names_it_before_the_build(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    line = fails("run", "n-mass-chain", "-s", "short", "-o", str(blocker / "r.h5"), "--no-progress", code=1)
    assert "--out" in line and str(blocker) in line
    line = fails("run", "n-mass-chain", "-s", "short", "-o", str(tmp_path), "--no-progress")
    assert str(tmp_path) in line


def test_model_option_the_model_does_not_have_names_it():
    line = fails("run", "n-mass-chain", "-s", "short", "--flexible", "--no-progress", code=1)
    assert "'flexible'" in line and "'n-mass-chain'" in line and "options of n-mass-chain: n" in line
    line = fails("run", "fourbar", "-s", "short", "--option", "n=3", "--no-progress", code=1)
    assert "'fourbar'" in line and "'n'" in line


def test_malformed_model_option_names_it():
    line = fails("run", "n-mass-chain", "-s", "short", "--option", "n", "--no-progress", code=1)
    assert "--option 'n'" in line and "NAME=VALUE" in line


def test_run_without_model_or_from():
    line = fails("run", "--no-progress", code=1)
    assert "MODEL" in line and "--from" in line


def test_failed_run_is_one_line_and_keeps_the_partial_result(tmp_path):
    path = tmp_path / "five-steps.json"
    path.write_text(json.dumps({"name": "five-steps", "t_end": 1.0, "options": {"n": 3}, "run": {"max_steps": 5}}))
    out = tmp_path / "partial.h5"
    line = fails("run", "n-mass-chain", "-s", str(path), "-o", str(out), "--no-progress", code=1)
    assert "maximum number of steps (5)" in line and str(out) in line
    res = fl.load_result(out)
    assert res.status == "failed" and registry.run_settings(res).scenario["name"] == "five-steps"


# -- scenario files ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("content", "culprit"), [
    ("{not json", "not valid JSON"),
    (json.dumps({"name": "x", "tend": 1.0}), "'tend'"),
    (json.dumps({"name": "x", "run": {"rtoll": 1e-6}}), "did you mean 'rtol'"),
    (json.dumps({"name": "x", "t_end": -2}), "t_end"),
    (json.dumps({"name": "x", "params": {"mass0.m": "heavy"}}), "'mass0.m'"),
    (json.dumps({"doc": "no name"}), "'name'"),
    (json.dumps({"name": "x", "options": {"n_masses": 3}}), "unknown model option 'n_masses'"),
])
def test_bad_scenario_file_names_file_and_field(tmp_path, content, culprit):
    path = tmp_path / "mine.json"
    path.write_text(content)
    line = fails("run", "n-mass-chain", "-s", str(path), "--no-progress", code=1)
    assert culprit in line
    if "n_masses" not in culprit:  # found by the model entry, which names the scenario
        assert str(path) in line


def test_missing_scenario_file_names_it(tmp_path):
    line = fails("run", "n-mass-chain", "-s", str(tmp_path / "gone.json"), "--no-progress", code=1)
    assert str(tmp_path / "gone.json") in line


# -- --from --------------------------------------------------------------------------------------------------------
def test_from_a_result_without_run_settings_names_the_file(chain_file, tmp_path):
    plain = tmp_path / "plain.h5"
    res = fl.load_result(chain_file)
    del res.metadata["run"]
    res.save(plain)
    line = fails("run", "--from", str(plain), "--no-progress", code=1)
    assert str(plain) in line and "no run settings" in line


def test_from_with_another_model_or_a_scenario(chain_file):
    line = fails("run", "fourbar", "--from", str(chain_file), "--no-progress", code=1)
    assert "'fourbar'" in line and "'n-mass-chain'" in line
    line = fails("run", "--from", str(chain_file), "--scenario", "sine", "--no-progress", code=1)
    assert "--from" in line and "--scenario" in line


def test_from_a_damaged_run_record_names_the_file(chain_file, tmp_path):
    bad = tmp_path / "bad-record.h5"
    bad.write_bytes(chain_file.read_bytes())
    with h5py.File(bad, "a") as f:
        f.attrs["meta_run"] = "{not json"
    line = fails("run", "--from", str(bad), "--no-progress", code=1)
    assert str(bad) in line and "damaged" in line


# -- compare and show: files ---------------------------------------------------------------------------------------
def test_compare_missing_file_names_it(chain_file, tmp_path):
    line = fails("compare", str(chain_file), str(tmp_path / "gone.h5"), code=1)
    assert str(tmp_path / "gone.h5") in line and "no such file" in line


def test_compare_non_result_files_name_them(chain_file, tmp_path):
    csv = tmp_path / "data.csv"
    csv.write_text("t,x\n0,1\n")
    line = fails("compare", str(csv), str(chain_file), code=1)
    assert str(csv) in line and "CSV" in line
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = [1.0]
    line = fails("compare", str(chain_file), str(other), code=1)
    assert str(other) in line and "not a flexlib result" in line


def test_compare_unknown_signal_names_it(chain_file):
    line = fails("compare", str(chain_file), str(chain_file), "--signals", "mass0.s,mass7.s", code=1)
    assert "'mass7.s'" in line and "--signals" in line


def test_compare_unwritable_plot_names_it(chain_file, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    line = fails("compare", str(chain_file), str(chain_file), "--plot", str(blocker / "p.png"), code=1)
    assert "--plot" in line and str(blocker) in line


def test_show_non_result_names_it(tmp_path):
    empty = tmp_path / "empty.h5"
    empty.write_bytes(b"")
    line = fails("show", str(empty), code=1)
    assert str(empty) in line and "empty" in line


def test_models_option_unknown_module_names_it():
    line = fails("--models", "no_such_models_module", "list", code=1)
    assert "no_such_models_module" in line


# -- registry API --------------------------------------------------------------------------------------------------
def test_registry_bad_registrations(monkeypatch):
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    with pytest.raises(RegistryError, match="'n-mass-chain' is already registered by"):
        registry.register_model("n-mass-chain", lambda s: None, doc="", scenarios=[Scenario("a")])
    with pytest.raises(RegistryError, match=r"register_model\('x'\): give at least one scenario"):
        registry.register_model("x", lambda s: None, doc="", scenarios=[])
    with pytest.raises(RegistryError, match="two scenarios named 'a'"):
        registry.register_model("x", lambda s: None, doc="", scenarios=[Scenario("a"), Scenario("a")])
    with pytest.raises(RegistryError, match=r"default scenario 'c'.*known: a"):
        registry.register_model("x", lambda s: None, doc="", scenarios=[Scenario("a")], default_scenario="c")
    with pytest.raises(RegistryError, match="unknown model 'nope'"):
        registry.register_scenario("nope", Scenario("a"))
    with pytest.raises(RunArgumentError, match="scenario 'a': unknown run option 'tol'"):
        Scenario("a", run={"tol": 1e-6})
    with pytest.raises(RunArgumentError, match="run_scenario: unknown run option 'tol'"):
        registry.run_scenario("n-mass-chain", "short", tol=1e-6)
