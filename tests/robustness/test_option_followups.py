"""The pinned-free beam's declared options and ``flexlib list``'s option table (issue 26, follow-ups).

``pinned-free-beam`` declares ``n_modes`` (int >= 0) and ``geometric_stiffening`` (bool) with
``flexlib.registry.ModelOption``: a refused value or an unknown name on the command line, in a JSON scenario or a
Python scenario is one line naming the model, the option, the value and what is accepted, before the factory runs
(no modal data is made); the upper bound of ``n_modes`` (the modal data's in-plane bending modes) stays the
factory's own check. ``flexlib list`` shows every model's options (name, type, default, accepted values) readably
at 80 columns.
"""

from __future__ import annotations

import json
import re

import pytest
from click.testing import CliRunner

from flexlib import registry
from flexlib.cli import cli
from flexlib.errors import ModelError, RunArgumentError
from flexlib.registry import Scenario
from tests.robustness.helpers import cli_error

ENV = {"COLUMNS": "200"}
MODEL = "pinned-free-beam"


def fails(*args: str, columns: int = 200) -> str:
    """Run the CLI; it must fail with exit code 1 and one ``Error:`` line, no traceback; return that line."""
    return cli_error(*args, columns=columns)


@pytest.fixture
def no_build(monkeypatch):
    """The beam's factory replaced by one that fails the test: a refused option must never reach it."""
    entry = registry.get_model(MODEL)

    def factory(scenario: Scenario):
        raise AssertionError(f"the factory ran for {dict(scenario.options)}: the option was not checked first")

    monkeypatch.setattr(entry, "factory", factory)
    return entry


# -------------------------------------------------------------------------------- pinned-free-beam: --option
@pytest.mark.parametrize(("option", "expected"), [
    ("n_modes=-1", "option 'n_modes' of model 'pinned-free-beam' must be an integer >= 0, got -1"),
    ("n_modes=four", "option 'n_modes' of model 'pinned-free-beam' must be an integer >= 0, got 'four'"),
    ("n_modes=4.0", "option 'n_modes' of model 'pinned-free-beam' must be an integer >= 0, got '4.0'"),
    ("geometric_stiffening=maybe", "option 'geometric_stiffening' of model 'pinned-free-beam' must be true or false "
                                   "(true/false/yes/no/1/0, any case), got 'maybe'"),
    ("geometric_stiffening=", "option 'geometric_stiffening' of model 'pinned-free-beam' must be true or false "
                              "(true/false/yes/no/1/0, any case), got ''"),
])
def test_run_refuses_a_bad_option_value_before_the_build(no_build, option, expected):
    line = fails("run", MODEL, "-O", option, "--no-progress", columns=80)  # one line however narrow the terminal
    assert line == f"Error: --option {option}: {expected}"


def test_run_names_a_misspelt_option_with_the_closest_match(no_build):
    line = fails("run", MODEL, "-O", "n_mode=4", "--no-progress")
    assert "--option n_mode=4: model 'pinned-free-beam': unknown model option 'n_mode'; did you mean 'n_modes'?" \
        in line
    assert "n_modes (an integer >= 0); geometric_stiffening (true or false)" in line


@pytest.mark.parametrize(("text", "value"), [("0", 0), ("13", 13), (" 4 ", 4)])
def test_n_modes_text_is_read_as_an_int(text, value):
    assert registry.get_model(MODEL).parse_options({"n_modes": text}) == {"n_modes": value}


@pytest.mark.parametrize(("text", "value"), [("true", True), ("No", False), ("1", True), ("FALSE", False)])
def test_geometric_stiffening_takes_the_bool_words(text, value):
    assert registry.get_model(MODEL).parse_options({"geometric_stiffening": text}) == {"geometric_stiffening": value}


# ---------------------------------------------------------------- pinned-free-beam: JSON and Python scenarios
@pytest.mark.parametrize(("options", "match"), [
    ({"n_modes": "4"}, r"option 'n_modes' must be an integer >= 0, got '4'"),
    ({"n_modes": True}, r"option 'n_modes' must be an integer >= 0, got True"),
    ({"geometric_stiffening": "false"}, r"option 'geometric_stiffening' must be true or false, got 'false'"),
    ({"geometric_stiffening": 1}, r"option 'geometric_stiffening' must be true or false, got 1"),
    ({"flexible": True}, r"unknown model option 'flexible' \(options of pinned-free-beam: n_modes"),
])
def test_a_json_scenario_gets_the_same_checks(tmp_path, no_build, options, match):
    path = tmp_path / "mine.json"
    path.write_text(json.dumps({"name": "mine", "options": options}))
    where = re.escape(f"model 'pinned-free-beam', scenario 'mine' (file {path}): ")
    with pytest.raises(RunArgumentError, match=where + match):
        registry.run_scenario(MODEL, Scenario.from_file(path), progress=False)
    line = fails("run", MODEL, "-s", str(path), "--no-progress")
    assert str(path) in line and ("option 'n_modes'" in line or "option 'geometric_stiffening'" in line
                                  or "unknown model option 'flexible'" in line)


def test_a_python_scenario_with_a_bad_option_is_refused_where_it_is_registered(no_build):
    with pytest.raises(RunArgumentError, match=r"model 'pinned-free-beam', scenario 'mine': option 'n_modes' must be "
                                               r"an integer >= 0, got -2"):
        no_build.checked(Scenario("mine", options={"n_modes": -2}))
    assert "mine" not in no_build.scenarios


def test_the_upper_bound_of_n_modes_is_the_factorys_check():
    """14 passes the declaration (an int >= 0) and is refused by the factory with the data's count, before the
    DAE is built."""
    from flexlib.models.pinned_free_beam import N_BENDING_MODES

    line = fails("run", MODEL, "-O", f"n_modes={N_BENDING_MODES + 1}", "--no-progress")
    assert (f"model 'pinned-free-beam', scenario 'seed': option n_modes must be an int in 0..{N_BENDING_MODES} "
            f"(the modal data has {N_BENDING_MODES})") in line and f"got {N_BENDING_MODES + 1} (int)" in line


@pytest.mark.parametrize("stiffening", [True, False])
def test_the_documented_mode_count_is_the_datas(stiffening):
    """The ``n_modes`` doc (``flexlib list``) names :data:`N_BENDING_MODES`: it must be the data's count."""
    from flexlib.models.pinned_free_beam import N_BENDING_MODES, OPTIONS, beam_modal_data, bending_modes

    assert len(bending_modes(beam_modal_data(geometric_stiffening=stiffening))) == N_BENDING_MODES
    assert f"at most the {N_BENDING_MODES} " in OPTIONS[0].doc


def test_a_direct_factory_call_is_checked_too():
    """The factory called with an unchecked scenario (Python) gets the declaration's check, as ModelError."""
    factory = registry.get_model(MODEL).factory
    with pytest.raises(ModelError, match=r"model 'pinned-free-beam', scenario 'raw': option geometric_stiffening "
                                         r"must be true or false, got 'yes'"):
        factory(Scenario("raw", options={"geometric_stiffening": "yes"}))


# ----------------------------------------------------------------------------------------------- flexlib list
def list_output(columns: int) -> list[str]:
    res = CliRunner().invoke(cli, ["list"], env={"COLUMNS": str(columns)}, catch_exceptions=False)
    assert res.exit_code == 0, res.output
    return res.output.splitlines()


def test_list_shows_every_option_with_type_default_and_accepted_values():
    lines = list_output(250)  # wide: one line per row
    start = next(k for k, line in enumerate(lines) if "model options" in line)
    rows = [[c.strip() for c in line.split("│")[1:-1]] for line in lines[start:] if line.startswith("│")]
    for name, entry in registry.models().items():
        model_row = next(r for r in rows if r[0] == name)
        if not entry.options:
            assert "no options" in model_row[3]
        if entry.data:
            assert "scenario data: " + ", ".join(entry.data) in model_row[3]
        for o in entry.options:
            row = next(r for r in rows if r[0] == o.name and r[3].startswith(o.accepted()))
            assert row[1] == ("any" if o.type is None else o.type.__name__)
            assert o.doc in row[3]
    beam = [r for r in rows if r[0] in ("n_modes", "geometric_stiffening")]
    assert beam[0][:3] == ["n_modes", "int", "4"] and beam[0][3].startswith("an integer >= 0: lowest in-plane")
    assert beam[1][:3] == ["geometric_stiffening", "bool", "true"]
    assert ["filled", "bool", "none"] == next(r for r in rows if r[0] == "filled")[:3]
    assert ["link_plate", "float", "0.006"] == next(r for r in rows if r[0] == "link_plate")[:3]


def test_list_fits_80_columns():
    lines = list_output(80)
    assert max(len(line) for line in lines) <= 80
    text = "\n".join(lines)
    for word in ("geometric_stiffening", "n_modes", "link_plate", "pinned-free-beam", "pump-truck"):
        assert word in text  # no name cut or folded


def test_list_shows_an_untyped_option(monkeypatch):
    """A user's model registering an option by name alone: shown as type ``any``, default ``none``."""
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    registry.register_model("mine", lambda s: None, doc="a user's model", scenarios=[Scenario("only")],
                            options=["gain"])
    lines = list_output(250)
    row = next(line for line in lines if "│   gain " in line)
    assert [c.strip() for c in row.split("│")[1:-1]] == ["gain", "any", "none", "any value: (untyped)"]
