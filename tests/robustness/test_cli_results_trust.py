"""Trusting what the command line says about results (issue 26): a finished run is never lost to a failed save,
``--out`` never replaces a file that is not a result, ``compare`` never passes a comparison that does not cover
both runs (NaN in one, a run that failed half-way, different models, different units), ``--from`` and ``--plot``
name the file, and ``show`` and the Result API say what is wrong instead of a silent or vague answer.

One short run of the 3-mass chain (0.2 s, 5 rows) per module; every other file is made from it."""

from __future__ import annotations

import dataclasses
import errno
import json
import os
import re
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

import flexlib as fl
from flexlib import registry
from flexlib.cli import cli
from flexlib.errors import EmptyResultError, ResultKeyError, ResultSaveWarning, RunArgumentError
from flexlib.registry import Scenario
from flexlib.results import hdf5
from flexlib.results.compare import compare, compare_results

ENV = {"COLUMNS": "200"}
RUN = ("run", "n-mass-chain", "-s", "short", "--t-end", "0.2", "--no-progress")


def invoke(*args: str):
    res = CliRunner().invoke(cli, list(args), env=ENV)
    assert "Traceback" not in res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    return res


def fails(*args: str, code: int = 1) -> str:
    """Run the CLI, check it failed with ``code`` and one ``Error:`` line; return that line."""
    res = invoke(*args)
    assert res.exit_code == code, res.output
    errors = [line for line in res.output.splitlines() if line.startswith("Error:")]
    assert len(errors) == 1, res.output
    return errors[0]


def lines(output: str, prefix: str) -> list[str]:
    return [line for line in output.splitlines() if line.startswith(prefix)]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The chain run (A) and results made from it: NaN from its second row, cut after its second row (a run
    that failed half-way), another model, different units, a subset of the variables, shifted in time, without
    rows, with a damaged run record."""
    d = tmp_path_factory.mktemp("trust")
    a = d / "a.h5"
    res = CliRunner().invoke(cli, [*RUN, "-o", str(a)], env=ENV)
    assert res.exit_code == 0, res.output
    r = fl.load_result(a)
    assert len(r.t) == 5
    out = {"a": a, "dir": d}

    def save(name, res):
        out[name] = d / f"{name}.h5"
        res.save(out[name])

    v = r.values.copy()
    v[1:, :] = np.nan
    save("nan", dataclasses.replace(r, values=v))
    save("half", dataclasses.replace(r, t=r.t[:2], values=r.values[:2], status="failed",
                                     message="the integrator failed at t = 0.06 s"))
    save("other", dataclasses.replace(r, model="OtherModel", names=[f"other.{n}" for n in r.names]))
    units = list(r.units)
    units[r.names.index("mass0.s")] = "mm"
    save("units", dataclasses.replace(r, units=units))
    keep = [k for k, n in enumerate(r.names) if not n.startswith("mass2.")]
    save("fewer", dataclasses.replace(r, names=[r.names[k] for k in keep], values=r.values[:, keep],
                                      units=[r.units[k] for k in keep], docs=[r.docs[k] for k in keep],
                                      kinds=[r.kinds[k] for k in keep]))
    save("late", dataclasses.replace(r, t=r.t + 10.0))
    save("empty", dataclasses.replace(r, t=r.t[:0], values=r.values[:0], status="failed",
                                      message="assertion failed at t = 0"))
    out["csv"] = d / "data.csv"
    out["csv"].write_text("t,x\n0,1\n0.1,2\n")
    return out


@pytest.fixture(scope="module")
def chain(files):
    return fl.load_result(files["a"])


def with_record(files, tmp_path, name, change):
    """A copy of A whose run record (meta_run) is changed by ``change(dict)``."""
    path = tmp_path / f"{name}.h5"
    shutil.copy(files["a"], path)
    with h5py.File(path, "a") as f:
        rec = json.loads(f.attrs["meta_run"])
        change(rec)
        f.attrs["meta_run"] = json.dumps(rec)
    return path


# == issue items ===================================================================================================
# -- a finished run is never lost to a failed save ------------------------------------------------------------------
def break_directory_after_the_run(monkeypatch, outdir):
    """The directory of --out (checked before the build) is replaced by a file while the model runs."""
    real = fl.Simulation.run

    def run_then_break(self, *args, **kwargs):
        res = real(self, *args, **kwargs)
        shutil.rmtree(outdir)
        outdir.write_text("a file where the directory was")
        return res

    monkeypatch.setattr(fl.Simulation, "run", run_then_break)


def test_run_scenario_keeps_the_result_when_the_save_fails(tmp_path, monkeypatch):
    outdir = tmp_path / "out"
    outdir.mkdir()
    break_directory_after_the_run(monkeypatch, outdir)
    with pytest.warns(ResultSaveWarning, match=r"out/run\.h5: cannot create its directory .*kept in memory"):
        done = registry.run_scenario("n-mass-chain", "short", t_end=0.2, progress=False,
                                     result_file=outdir / "run.h5")
    res = done.result
    assert res.success and res.t[-1] == 0.2 and registry.run_settings(res).model == "n-mass-chain"


def test_cli_out_save_failure_writes_a_fallback_file(files, chain, tmp_path, monkeypatch):
    outdir = tmp_path / "out"
    outdir.mkdir()
    monkeypatch.chdir(tmp_path)
    break_directory_after_the_run(monkeypatch, outdir)
    res = invoke(*RUN, "-o", str(outdir / "run.h5"))
    assert res.exit_code == 1 and "summary signals" in res.output  # the summary is printed all the same
    line = lines(res.output, "Error:")[0]
    assert f"cannot write the result to {outdir / 'run.h5'}" in line and "written to" in line
    fallback = Path(line.rpartition("written to ")[2].split(" instead")[0])
    assert fallback.parent == tmp_path and fallback.name.startswith("run.unsaved-")
    back = fl.load_result(fallback)
    np.testing.assert_array_equal(back.values, chain.values)
    assert registry.run_settings(back).model == "n-mass-chain"


def test_cli_failed_run_whose_save_fails_names_the_fallback(tmp_path, monkeypatch):
    scen = tmp_path / "five-steps.json"
    scen.write_text(json.dumps({"name": "five-steps", "t_end": 1.0, "options": {"n": 3}, "run": {"max_steps": 5}}))
    outdir = tmp_path / "out"
    outdir.mkdir()
    monkeypatch.chdir(tmp_path)
    real = registry.run_scenario

    def run_then_break(*args, **kwargs):
        try:
            return real(*args, **kwargs)
        finally:
            shutil.rmtree(outdir)
            outdir.write_text("x")

    monkeypatch.setattr(registry, "run_scenario", run_then_break)
    line = fails("run", "n-mass-chain", "-s", str(scen), "-o", str(outdir / "p.h5"), "--no-progress")
    assert "maximum number of steps (5)" in line and f"cannot write the result to {outdir / 'p.h5'}" in line
    fallback = Path(line.rpartition("written to ")[2].split(" instead")[0])
    assert fl.load_result(fallback).status == "failed"


def test_cli_says_when_no_file_at_all_could_be_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

    def no_space(result, tmp, *args):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(hdf5, "_write", no_space)
    res = invoke(*RUN, "-o", str(tmp_path / "run.h5"))
    assert res.exit_code == 1 and "summary signals" in res.output
    line = lines(res.output, "Error:")[0]
    assert "run.h5: No space left on device" in line and "the result is lost" in line and str(tmp_path) in line
    assert list(tmp_path.iterdir()) == []


# -- --out does not replace what is not a result --------------------------------------------------------------------
@pytest.mark.parametrize(("name", "content", "what"), [
    ("data.csv", b"t,x\n0,1\n", "not an HDF5 file but CSV text"),
    ("data.h5", b"t,x\n0,1\n", "CSV text"),
    ("notes.h5", b"", "an empty file"),
    ("cut.h5", b"\x89HDF\r\n\x1a\n" + bytes(100), "a truncated or damaged HDF5 file"),
])
def test_out_refuses_to_replace_a_file_that_is_not_a_result(tmp_path, name, content, what):
    target = tmp_path / name
    target.write_bytes(content)
    line = fails(*RUN, "-o", str(target))
    assert str(target) in line and what in line and "--force" in line and "not replaced" in line
    assert target.read_bytes() == content


def test_out_refuses_another_programs_hdf5_file_and_force_replaces_it(tmp_path):
    target = tmp_path / "measured.h5"
    with h5py.File(target, "w") as f:
        f["pressure"] = np.arange(3.0)
    line = fails(*RUN, "-o", str(target))
    assert "HDF5 file that is not a flexlib result" in line and "--force" in line
    assert list(h5py.File(target, "r")) == ["pressure"]
    assert invoke(*RUN, "-o", str(target), "--force").exit_code == 0
    assert fl.load_result(target).success


# -- compare: what it does not cover fails --fail-above and is said without it ----------------------------------------
def test_compare_nan_in_b_fails_and_warns(files):
    line = fails("compare", str(files["a"]), str(files["nan"]), "--fail-above", "1e-3")
    assert "37 signals NaN or inf in B" in line and str(files["nan"]) in line and "from t = 0.05 s" in line
    assert "wall.flange.s" in line
    res = invoke("compare", str(files["a"]), str(files["nan"]))
    assert res.exit_code == 0
    warning = lines(res.output, "Warning:")
    assert len(warning) == 1 and "NaN or inf in B" in warning[0] and "up to 4 of 5 compared points" in warning[0]


def test_compare_run_that_failed_half_way_fails_and_warns(files):
    line = fails("compare", str(files["a"]), str(files["half"]), "--fail-above", "1e-3")
    assert "only the common time span 0 … 0.05 s is compared" in line and "covers 0 … 0.2 s" in line
    assert "is failed: the integrator failed at t = 0.06 s" in line
    res = invoke("compare", str(files["a"]), str(files["half"]))
    assert res.exit_code == 0 and "common time span" in lines(res.output, "Warning:")[0]


def test_compare_different_models_fails_and_warns(files):
    line = fails("compare", str(files["a"]), str(files["other"]), "--fail-above", "1e-3")
    assert "0 signals compared" in line and "NMassChain" in line and "OtherModel" in line
    assert "37 variables only in A" in line and "wall.flange.s" in line and "other.wall.flange.s" in line
    res = invoke("compare", str(files["a"]), str(files["other"]))
    assert res.exit_code == 0 and "no variable in common" in lines(res.output, "Warning:")[0]


# -- vague messages ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("change", "culprit"), [
    (lambda r: r.update(model="no-such-model"), r"the model recorded in the file: unknown model 'no-such-model'"),
    (lambda r: r["scenario"].update(bogus=1), r"the scenario recorded in the file: .*unknown field 'bogus'"),
    (lambda r: r["scenario"]["options"].update(n="three"), r"the scenario recorded in the file: .*'n'.*'three'"),
    (lambda r: r.update(params={"mass0.m": "heavy"}), r"parameter override 'mass0.m' .* 'heavy', not a finite"),
    (lambda r: r.update(run={"rtoll": 1e-6}), r"the run option 'rtoll' recorded in the file is unknown"),
    (lambda r: r.update(run={"t_end": "soon"}), r"t_end.*'soon'.*\(repeating the run recorded in .*\.h5\)"),
])
def test_from_a_damaged_run_record_names_the_file(files, tmp_path, change, culprit):
    path = with_record(files, tmp_path, "record", change)
    line = fails("run", "--from", str(path), "--no-progress")
    assert str(path) in line
    assert re.search(culprit, line), line


def test_plot_with_a_format_matplotlib_cannot_write_is_refused_first(files, tmp_path):
    """Checked before the files are read: the missing file is not the error, the extension is."""
    line = fails("compare", str(tmp_path / "gone.h5"), str(files["a"]), "--plot", str(tmp_path / "diff.h5"))
    assert "--plot" in line and ".h5, not an image format" in line and ".png" in line and ".pdf" in line
    line = fails("compare", str(files["a"]), str(files["a"]), "--plot", str(tmp_path / "diff"))
    assert "has no extension" in line


# == further cases ==================================================================================================
# -- show ----------------------------------------------------------------------------------------------------------
def test_show_csv_names_the_file(files):
    line = fails("show", str(files["csv"]))
    assert str(files["csv"]) in line and "CSV text" in line


def test_show_truncated_result_names_the_file(files, tmp_path):
    cut = tmp_path / "cut.h5"
    cut.write_bytes(files["a"].read_bytes()[:3000])
    line = fails("show", str(cut))
    assert str(cut) in line and "truncated or damaged HDF5 file" in line


def test_show_a_directory_names_it(tmp_path):
    line = fails("show", str(tmp_path), code=2)
    assert str(tmp_path) in line and "is a directory" in line


def test_show_result_without_rows_says_so(files):
    res = invoke("show", str(files["empty"]))
    assert res.exit_code == 0 and "no rows" in res.output
    warning = lines(res.output, "Warning:")
    assert len(warning) == 1 and "did not succeed (failed), it has no rows: assertion failed at t = 0" in warning[0]


def test_show_result_with_nan_says_which_and_when(files):
    res = invoke("show", str(files["nan"]))
    assert res.exit_code == 0
    warning = lines(res.output, "Warning:")
    assert len(warning) == 1 and "37 variables are NaN or inf, from t = 0.05 s" in warning[0]


def test_show_damaged_run_record_shows_the_rest_and_names_the_file(files, tmp_path):
    bad = tmp_path / "bad.h5"
    shutil.copy(files["a"], bad)
    with h5py.File(bad, "a") as f:
        f.attrs["meta_run"] = "{not json"
    res = invoke("show", str(bad))
    assert res.exit_code == 0 and "NMassChain" in res.output and "damaged" in res.output
    warning = lines(res.output, "Warning:")
    assert len(warning) == 1 and str(bad) in warning[0] and "run settings (meta_run) are damaged" in warning[0]


def test_show_result_without_run_record(files, chain, tmp_path):
    plain = tmp_path / "plain.h5"
    r = dataclasses.replace(chain, metadata={k: v for k, v in chain.metadata.items() if k != "run"})
    r.save(plain)
    res = invoke("show", str(plain))
    assert res.exit_code == 0 and "none recorded" in res.output and not lines(res.output, "Warning:")


def test_show_lists_the_signals_asked_for(files):
    """Min and max ignore NaN (counted in their own column); the final value of mass0.s in the NaN file is NaN."""
    res = invoke("show", str(files["nan"]), "--signals", "mass0.s,spring?.f")
    assert res.exit_code == 0 and "4 variables (SI units)" in res.output
    row = next(line for line in res.output.splitlines() if "│ mass0.s " in line)
    assert [c.strip() for c in row.split("│")[1:7]] == ["mass0.s", "m", "1", "1", "nan", "4"]


@pytest.mark.parametrize(("pattern", "culprit"), [
    ("zz*", "'zz*' matches no variable of"), ("time", "the time is the axis of every signal"),
    ("mass0", "'mass0' is a component; its variables are"), (",", "no variable name or pattern given"),
])
def test_show_signals_that_name_nothing(files, pattern, culprit):
    line = fails("show", str(files["a"]), "--signals", pattern)
    assert "--signals" in line and culprit in line


# -- compare: signals --------------------------------------------------------------------------------------------
def test_compare_signal_missing_in_b_names_b(files):
    line = fails("compare", str(files["a"]), str(files["fewer"]), "--signals", "mass2.s")
    assert f"'mass2.s' is not in B ({files['fewer']})" in line and "did you mean" in line


def test_compare_pattern_that_matches_nothing_names_it(files):
    line = fails("compare", str(files["a"]), str(files["fewer"]), "--signals", "mass2.*")
    assert "'mass2.*' matches 6 variables of A" in line and "none of B" in line
    line = fails("compare", str(files["a"]), str(files["a"]), "--signals", "pump*")
    assert "'pump*' matches no variable of A" in line


def test_compare_pattern_matching_more_in_one_file_warns(files):
    res = invoke("compare", str(files["a"]), str(files["fewer"]), "--signals", "mass*.s")
    assert res.exit_code == 0 and "6 signals compared" in res.output
    warning = lines(res.output, "Warning:")
    assert warning == [f"Warning: signal pattern 'mass*.s' matches 3 variables only in A ({files['a']}) (not "
                       "compared): mass2.s, mass2.flange_a.s, mass2.flange_b.s"]
    line = fails("compare", str(files["a"]), str(files["fewer"]), "--signals", "mass*.s", "--fail-above", "1")
    assert "matches 3 variables only in A" in line


def test_compare_pattern_selects_the_matching_signals(files, chain):
    res = invoke("compare", str(files["a"]), str(files["a"]), "--signals", "mass?.s", "--fail-above", "0")
    assert res.exit_code == 0 and "3 signals compared" in res.output
    rows = compare_results(chain, chain, ["mass?.s", "mass0.s"])
    assert [r["name"] for r in rows] == ["mass0.s", "mass1.s", "mass2.s"]  # each once


def test_compare_empty_signals_option(files):
    line = fails("compare", str(files["a"]), str(files["a"]), "--signals", " , ")
    assert "--signals" in line and "no variable name given" in line


def test_compare_time_is_not_a_signal(files):
    line = fails("compare", str(files["a"]), str(files["a"]), "--signals", "mass0.s,time")
    assert "--signals: signal 'time': the time is the axis of every signal" in line


def test_compare_signals_as_one_string(chain):
    assert [r["name"] for r in compare_results(chain, chain, "mass0.s")] == ["mass0.s"]


# -- compare: files and spans ----------------------------------------------------------------------------------------
def test_compare_the_same_file_twice_notes_it(files):
    res = invoke("compare", str(files["a"]), str(files["a"]), "--fail-above", "0")
    assert res.exit_code == 0
    assert "same file" in lines(res.output, "Note:")[0] and not lines(res.output, "Warning:")


def test_compare_without_common_time_span_gives_both(files, chain):
    line = fails("compare", str(files["a"]), str(files["late"]))
    assert "no common time span" in line and "covers 0 … 0.2 s" in line and "10 … 10.2 s" in line
    with pytest.raises(RunArgumentError, match=r"no common time span \(A covers 0 … 0\.2 s, B 10 … 10\.2 s\)"):
        compare(chain, fl.load_result(files["late"]))


def test_compare_different_units_are_not_compared(files):
    line = fails("compare", str(files["a"]), str(files["units"]), "--fail-above", "1")
    assert "1 signal with different units" in line and "mass0.s (m / mm)" in line
    res = invoke("compare", str(files["a"]), str(files["units"]))
    assert res.exit_code == 0 and "36 signals compared" in res.output and "mass0.s (m / mm)" in res.output


def test_compare_result_without_rows_names_it(files, chain):
    line = fails("compare", str(files["a"]), str(files["empty"]))
    assert f"B ({files['empty']}) has no rows" in line and "failed: assertion failed at t = 0" in line
    with pytest.raises(EmptyResultError, match=r"A has no rows"):
        compare(fl.load_result(files["empty"]), chain)


def test_compare_variables_in_one_file_only(files):
    line = fails("compare", str(files["a"]), str(files["fewer"]), "--fail-above", "1")
    assert "6 only in A" in line and "mass2.s" in line and "--signals" in line
    res = invoke("compare", str(files["a"]), str(files["fewer"]), "--signals", "mass0.s,mass1.v", "--fail-above", "0")
    assert res.exit_code == 0, res.output  # a chosen set in both: nothing missing


def test_compare_a_directory_or_a_missing_file(files, tmp_path):
    line = fails("compare", str(tmp_path), str(files["a"]), code=2)
    assert str(tmp_path) in line and "is a directory" in line
    line = fails("compare", str(tmp_path / "gone.h5"), str(files["a"]))
    assert str(tmp_path / "gone.h5") in line and "no such file" in line


def test_compare_top_zero_is_refused(files):
    line = fails("compare", str(files["a"]), str(files["a"]), "--top", "0", code=2)
    assert "--top" in line and "0" in line


# -- compare: values -----------------------------------------------------------------------------------------------
def test_compare_constant_and_zero_signals(chain):
    """wall.flange.s is 0 throughout: relative difference 0 (not NaN); a constant 0 against a constant 1 is a
    relative difference of 1 at the first point."""
    zero = compare_results(chain, chain, ["wall.flange.s"])[0]
    assert zero["abs"] == 0.0 and zero["rel"] == 0.0
    v = chain.values.copy()
    v[:, chain.names.index("wall.flange.s")] = 1.0
    one = compare_results(chain, dataclasses.replace(chain, values=v), ["wall.flange.s"])[0]
    assert one["abs"] == 1.0 and one["rel"] == 1.0 and one["t"] == 0.0


def test_compare_nan_at_the_same_points_in_both_is_a_note(chain):
    v = chain.values.copy()
    v[3:, chain.names.index("mass0.v")] = np.nan
    both = dataclasses.replace(chain, values=v)
    cmp = compare(both, both)
    assert cmp.problems == [] and any("1 signal NaN or inf at the same points in both results" in note
                                      for note in cmp.notes)
    row = next(r for r in cmp.rows if r["name"] == "mass0.v")
    assert row["rel"] == 0.0 and row["nonfinite_a"] == 2


def test_compare_inf_in_a_is_named_with_its_time(chain):
    v = chain.values.copy()
    v[4, chain.names.index("mass1.v")] = np.inf
    cmp = compare(dataclasses.replace(chain, values=v), chain)
    assert cmp.worst["name"] == "mass1.v" and cmp.worst["rel"] == np.inf and cmp.worst["t"] == 0.2
    assert "1 signal NaN or inf in A where B is finite, from t = 0.2 s: mass1.v (up to 1 of 5" in cmp.problems[0]


# -- run: --from, --out, --plots -----------------------------------------------------------------------------------
def test_from_a_file_that_is_not_a_result(files):
    line = fails("run", "--from", str(files["csv"]), "--no-progress")
    assert str(files["csv"]) in line and "not an HDF5 file" in line


def test_from_a_record_that_is_not_an_object(files, tmp_path):
    path = tmp_path / "list.h5"
    shutil.copy(files["a"], path)
    with h5py.File(path, "a") as f:
        f.attrs["meta_run"] = "[1, 2]"
    line = fails("run", "--from", str(path), "--no-progress")
    assert str(path) in line and "run settings (meta_run) are damaged" in line


def test_out_with_a_trailing_separator_is_a_directory(tmp_path):
    target = str(tmp_path / "results") + os.sep
    line = fails(*RUN, "-o", target)
    assert "names a directory" in line and "run.h5" in line
    assert not (tmp_path / "results").exists()


def test_out_without_h5_extension_needs_force(tmp_path):
    target = tmp_path / "run.csv"
    line = fails(*RUN, "-o", str(target))
    assert "HDF5" in line and str(tmp_path / "run.h5") in line and "--force" in line and not target.exists()
    line = fails(*RUN, "-o", str(tmp_path / "run1"))
    assert str(tmp_path / "run1.h5") in line


def test_out_replaces_an_existing_result_file(files, tmp_path):
    target = tmp_path / "old.h5"
    shutil.copy(files["late"], target)
    assert invoke(*RUN, "-o", str(target)).exit_code == 0
    assert fl.load_result(target).t[0] == 0.0  # the new run, not the shifted one


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux /proc")
def test_out_in_a_place_that_cannot_be_written(tmp_path):
    line = fails(*RUN, "-o", "/proc/flexlib-run.h5")
    assert "--out" in line and "/proc" in line


def test_plots_into_a_file_path(files):
    line = fails(*RUN, "--plots", str(files["csv"]), code=2)
    assert "--plots" in line and str(files["csv"]) in line


def test_plots_without_a_hook_is_refused_before_the_run(tmp_path, monkeypatch):
    def no_run(*args, **kwargs):
        raise AssertionError("the model ran")

    monkeypatch.setattr(registry, "run_scenario", no_run)
    line = fails(*RUN, "--plots", str(tmp_path / "figs"), "-o", str(tmp_path / "run.h5"))
    assert "model 'n-mass-chain' has no figures" in line and not (tmp_path / "run.h5").exists()


@pytest.fixture
def plotted(monkeypatch):
    """A registered chain whose plots hook fails (a bug in the model's figure code)."""
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    from flexlib.models.n_mass_chain import NMassChain

    def plots(model, result, directory):
        return [result["no.such.signal"]]

    registry.register_model("plotted-chain", lambda s: NMassChain(n=2), doc="figures",
                            scenarios=[Scenario("a", t_end=0.1)], plots=plots)


def test_plots_under_a_file_is_refused_before_the_run(plotted, files):
    line = fails("run", "plotted-chain", "--plots", str(files["csv"] / "figs"), "--no-progress")
    assert "--plots" in line and "cannot create the directory" in line and str(files["csv"]) in line


def test_plots_hook_that_fails_names_the_model(plotted, tmp_path):
    line = fails("run", "plotted-chain", "--plots", str(tmp_path / "figs"), "-o", str(tmp_path / "r.h5"),
                 "--no-progress")
    assert "model 'plotted-chain': its figures (plots hook) failed: ResultKeyError" in line
    assert fl.load_result(tmp_path / "r.h5").success  # the run is kept


# -- Result API --------------------------------------------------------------------------------------------------
def test_component_name_lists_its_variables(chain):
    with pytest.raises(ResultKeyError, match=r"'mass0' is a component; its variables are mass0\.flange_a\.f, "
                                             r".*mass0\.v"):
        chain["mass0"]


def test_wrong_case_suggests_the_name_first(chain):
    with pytest.raises(ResultKeyError, match=r"no variable 'Mass0\.S' .*did you mean 'mass0\.s'\?"):
        chain.value("Mass0.S", 0.1)


def test_value_outside_the_span(chain, files):
    with pytest.raises(RunArgumentError, match=r"value\('mass0\.s', t\): t = 0\.3 s is outside the result of "
                                               r"NMassChain, which covers 0 … 0\.2 s"):
        chain.value("mass0.s", [0.1, 0.3])
    half = fl.load_result(files["half"])
    with pytest.raises(RunArgumentError, match=r"covers 0 … 0\.05 s; the run is failed: the integrator failed"):
        half.value("mass0.s", 0.2)
    with pytest.raises(RunArgumentError, match=r"row\(-1\): t = -1 s is outside"):
        chain.row(-1)
    assert chain.value("mass0.s", 0.2) == chain["mass0.s"][-1]  # the end itself is inside


@pytest.mark.parametrize(("t", "culprit"), [(np.nan, "must be finite, got nan"), ("0.1", r"got '0\.1' \(str\)"),
                                            (True, r"got True \(bool\)"), (None, r"got None")])
def test_value_at_a_time_that_is_not_a_number(chain, t, culprit):
    with pytest.raises(RunArgumentError, match=rf"value\('mass0\.s', t\): .*{culprit}"):
        chain.value("mass0.s", t)


def test_save_to_an_empty_path(chain):
    with pytest.raises(RunArgumentError, match=r"save_result: the path is an empty string"):
        chain.save("")
