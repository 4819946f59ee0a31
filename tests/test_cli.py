"""The ``flexlib`` command line and the model/scenario registry (issue 11: list, run, compare, show, --from).

Fast: the 3-mass chain (1 s) and the four-bar (0.5 s). References: the result files themselves (the printed
summary must equal the peaks recomputed from the saved result, to the 6 digits printed; a repeated run must
reproduce its file to 1e-12 relative); ``compare`` against differences computed directly on the common grid.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

import flexlib as fl
from flexlib import registry
from flexlib.cli import cli, compare_results
from flexlib.registry import Scenario

ENV = {"COLUMNS": "200"}  # rich tables wide enough that no cell is folded


def invoke(*args: str):
    return CliRunner().invoke(cli, list(args), env=ENV, catch_exceptions=False)


@pytest.fixture(scope="module")
def chain_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "chain.h5"
    res = invoke("run", "n-mass-chain", "--scenario", "short", "--out", str(out), "--param", "mass0.m=1.5",
                 "--no-progress")
    assert res.exit_code == 0, res.output
    return out, res.output


def test_list_shows_every_registered_model_and_scenario():
    res = invoke("list")
    assert res.exit_code == 0, res.output
    for name, entry in registry.models().items():
        assert name in res.output
        for sname, scen in entry.scenarios.items():
            assert sname in res.output and scen.doc in res.output
    assert {"n-mass-chain", "fourbar", "three-loop", "pinned-free-beam", "boom-proxy"} <= set(registry.models())


def test_run_saves_result_with_run_settings_and_prints_summary(chain_file):
    out, output = chain_file
    res = fl.load_result(out)
    assert res.status == "success" and res.t[-1] == pytest.approx(1.0, abs=0.0)
    assert res.parameters["mass0.m"][0] == 1.5  # the override reached the run
    assert "mass3.s" not in res.names and "mass2.s" in res.names  # the scenario's option n = 3
    rec = registry.run_settings(res)
    assert rec.model == "n-mass-chain" and rec.scenario["name"] == "short" and rec.params == {"mass0.m": 1.5}
    for label in ("simulated time [s]", "CPU time, run [s]", "real-time factor", "steps"):
        assert label in output
    assert str(res.stats["steps"]) in output
    # the summary signals' extremes, printed to 4 digits under their component's name, are those of the saved result
    lines = output.splitlines()
    for name in ("mass2.s", "mass2.v", "spring0.f"):
        x, (component, _, leaf) = res[name], name.rpartition(".")
        at = next(k for k, line in enumerate(lines) if line.strip() == component)
        row = next(line.split() for line in lines[at + 1:] if line.split() and line.split()[0] == leaf)
        assert row[2:5] == [f"{x.min():.4g}", f"{x.max():.4g}", f"{res.t[np.argmax(np.abs(x))]:.4g}"]


def test_run_from_file_repeats_the_run(chain_file, tmp_path):
    out, _ = chain_file
    again = tmp_path / "again.h5"
    res = invoke("run", "--from", str(out), "--out", str(again), "--no-progress")
    assert res.exit_code == 0, res.output
    a, b = fl.load_result(out), fl.load_result(again)
    assert a.names == b.names
    np.testing.assert_allclose(b.t, a.t, rtol=0, atol=0)
    np.testing.assert_allclose(b.values, a.values, rtol=1e-12, atol=1e-14)
    assert registry.run_settings(b) == registry.run_settings(a)
    # options given with --from apply on top of the recorded ones
    shorter = tmp_path / "shorter.h5"
    res = invoke("run", "--from", str(out), "--t-end", "0.5", "--param", "mass1.m=2", "--out", str(shorter),
                 "--no-progress")
    assert res.exit_code == 0, res.output
    c = fl.load_result(shorter)
    assert c.t[-1] == 0.5 and c.parameters["mass0.m"][0] == 1.5 and c.parameters["mass1.m"][0] == 2.0
    assert registry.run_settings(c).run == {"t_end": 0.5}


def test_user_scenario_from_json_file_runs_and_is_recorded(tmp_path):
    scen = {"name": "two-masses", "doc": "mine", "t_end": 0.3, "options": {"n": 2}, "params": {"force.F0": 20.0},
            "run": {"dt_out": 0.01, "rtol": 1e-8}}
    path = tmp_path / "mine.json"
    path.write_text(json.dumps(scen))
    out = tmp_path / "mine.h5"
    res = invoke("run", "n-mass-chain", "--scenario", str(path), "--out", str(out), "--no-progress")
    assert res.exit_code == 0, res.output
    r = fl.load_result(out)
    assert "mass1.s" in r.names and "mass2.s" not in r.names
    assert r.parameters["force.F0"][0] == 20.0 and r.stats["rtol"] == 1e-8
    np.testing.assert_allclose(np.diff(r.t), 0.01, rtol=1e-9)
    assert registry.run_settings(r).scenario == Scenario.from_dict(scen).to_dict()
    # the file repeats the user's scenario without the JSON file
    path.unlink()
    again = tmp_path / "again.h5"
    assert invoke("run", "--from", str(out), "--out", str(again), "--no-progress").exit_code == 0
    np.testing.assert_allclose(fl.load_result(again).values, r.values, rtol=1e-12, atol=1e-14)


def test_compare_reports_the_largest_differences(chain_file, tmp_path):
    out, _ = chain_file
    other = tmp_path / "heavier.h5"
    assert invoke("run", "--from", str(out), "--param", "mass0.m=1.8", "--out", str(other),
                  "--no-progress").exit_code == 0
    a, b = fl.load_result(out), fl.load_result(other)
    rows = compare_results(a, b)
    assert len(rows) == len(a.names)
    # same output grid, no events: the differences are those of the stored columns (exactly)
    np.testing.assert_array_equal(a.t, b.t)
    # the tube (flexlib.results.compare): tol = 1e-6 · the unit's largest |x| in both + 1e-3 · the range of A's x;
    # ranked by max |a − b| / tol (no events: no time shift); signals 0 in both are within the noise floor
    unit_scale = {}
    for name in a.names:
        u = a.unit(name)
        unit_scale[u] = max(unit_scale.get(u, 0.0), np.abs(a[name]).max(), np.abs(b[name]).max())
    for r in rows[:5] + rows[-3:]:
        d = np.abs(a[r["name"]] - b[r["name"]])
        scale = max(np.abs(a[r["name"]]).max(), np.abs(b[r["name"]]).max())
        assert r["abs"] == d.max() and r["rel"] == (d.max() / scale if scale else 0.0)
        assert r["t"] == a.t[np.argmax(d)]
        floor = 1e-6 * unit_scale[a.unit(r["name"])] or np.finfo(float).tiny
        assert r["tol"] == pytest.approx(floor + 1e-3 * np.ptp(a[r["name"]]), rel=1e-12)
        assert r["ratio"] == pytest.approx(d.max() / r["tol"], rel=1e-12)
        assert r["noise"] == (scale <= floor)
    ranked = [r for r in rows if not r["noise"]]
    assert [r["ratio"] for r in ranked] == sorted((r["ratio"] for r in ranked), reverse=True)
    assert all(r["noise"] for r in rows[len(ranked):])
    assert "wall.flange.s" in [r["name"] for r in rows[len(ranked):]]  # 0 in both: not ranked
    assert rows[0]["ratio"] > 1.0 and rows[0]["rel"] > 1e-3  # a 20 % heavier first mass changes the motion
    png = tmp_path / "overlay.png"
    res = invoke("compare", str(out), str(other), "--top", "3", "--plot", str(png))
    assert res.exit_code == 0, res.output
    assert rows[0]["name"] in res.output and f"{rows[0]['abs']:.6g}" in res.output
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    res = invoke("compare", str(out), str(other), "--fail-above", "1e-3")
    assert res.exit_code == 1 and rows[0]["name"] in res.output and "exceeds --fail-above" in res.output
    # --json for CI: the ranked rows with their deviation over tolerance, the same exit code
    res = CliRunner().invoke(cli, ["compare", str(out), str(other), "--json", "--top", "3", "--fail-above", "1"])
    report = json.loads(res.output)
    assert res.exit_code == 1 and report["failed"] and report["fail_above"] == 1.0
    assert [r["name"] for r in report["rows"]] == [r["name"] for r in rows if not r["noise"] and
                                                   r["alias_of"] is None][:3]
    assert report["rows"][0]["ratio"] == pytest.approx(rows[0]["ratio"]) and report["problems"] == []
    # a file compared with itself: no difference, --fail-above 0 passes
    res = invoke("compare", str(out), str(out), "--fail-above", "0", "--signals", "mass0.s,mass2.v")
    assert res.exit_code == 0, res.output
    assert [r["abs"] for r in compare_results(a, a, ["mass0.s", "mass2.v"])] == [0.0, 0.0]


def test_compare_on_different_grids_interpolates(tmp_path):
    a_file, b_file = tmp_path / "a.h5", tmp_path / "b.h5"
    assert invoke("run", "n-mass-chain", "-s", "short", "-o", str(a_file), "--no-progress").exit_code == 0
    assert invoke("run", "n-mass-chain", "-s", "short", "--dt-out", "0.02", "--t-end", "0.6", "-o", str(b_file),
                  "--no-progress").exit_code == 0
    a, b = fl.load_result(a_file), fl.load_result(b_file)
    rows = {r["name"]: r for r in compare_results(a, b, ["mass2.s"])}
    # the same trajectory sampled twice: differences are interpolation and tolerance effects only (rtol 1e-6,
    # sampled every 0.02 / 0.05 s), far below the 0.45 m swing of mass2.s
    grid = np.union1d(a.t, b.t)
    grid = grid[grid <= 0.6]
    ref = np.abs(np.interp(grid, a.t, a["mass2.s"]) - np.interp(grid, b.t, b["mass2.s"])).max()
    assert rows["mass2.s"]["abs"] == pytest.approx(ref, rel=1e-12)
    assert rows["mass2.s"]["abs"] < 0.02


def test_show_prints_the_recorded_settings(chain_file):
    out, _ = chain_file
    res = invoke("show", str(out))
    assert res.exit_code == 0, res.output
    for text in ("n-mass-chain", "short", '"mass0.m": 1.5', '{"n": 3}', f"flexlib run --from {out}", "NMassChain"):
        assert text in res.output


def test_fourbar_summary_signals(tmp_path):
    res = invoke("run", "fourbar", "--scenario", "short", "--no-progress", "-o", str(tmp_path / "fb.h5"))
    assert res.exit_code == 0, res.output
    r = fl.load_result(tmp_path / "fb.h5")
    for name in registry.get_model("fourbar").signals(None):
        values, _unit = r.display(name)  # display units: rad/s shown in rpm
        component, _, leaf = name.rpartition(".")
        assert component in res.output and leaf in res.output
        assert f"{values.max():.4g}" in res.output and f"{values.min():.4g}" in res.output


def test_python_m_flexlib_and_script_entry_point():
    proc = subprocess.run([sys.executable, "-m", "flexlib", "list"], capture_output=True, text=True, timeout=120,
                          env={**os.environ, **ENV})
    assert proc.returncode == 0, proc.stderr
    assert "n-mass-chain" in proc.stdout and "boom-proxy" in proc.stdout
    import tomllib
    from pathlib import Path

    project = tomllib.loads((Path(__file__).parents[1] / "pyproject.toml").read_text())["project"]
    assert project["scripts"] == {"flexlib": "flexlib.cli:main"}
    assert any(d.startswith("click") for d in project["dependencies"])
    assert any(d.startswith("rich") for d in project["dependencies"])


def test_registry_api_user_model_and_scenario(monkeypatch):
    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    from flexlib.models.n_mass_chain import NMassChain

    def factory(scenario):
        return NMassChain(n=scenario.options.get("n", 2))

    entry = registry.register_model("my-chain", factory, doc="mine", scenarios=[Scenario("a", t_end=0.2)],
                                    summary_signals=["mass1.s"], options=["n"])
    assert registry.get_model("my-chain") is entry and registry.get_scenario("my-chain").name == "a"
    registry.register_scenario("my-chain", Scenario("b", "four masses", t_end=0.1, options={"n": 4}))
    done = registry.run_scenario("my-chain", "b", progress=False, rtol=1e-7)
    assert "mass3.s" in done.result.names and done.result.t[-1] == 0.1 and done.result.stats["rtol"] == 1e-7
    assert registry.run_settings(done.result).run == {"rtol": 1e-7}
    assert done.cpu_run > 0
    scen = registry.get_scenario("my-chain", "b")
    with pytest.raises(dataclasses.FrozenInstanceError):
        scen.t_end = 1.0  # type: ignore[misc]
    with pytest.raises(TypeError):
        scen.options["n"] = 5  # type: ignore[index]
    assert Scenario.from_dict(scen.to_dict()) == scen


def test_model_option_on_the_command_line_is_recorded(tmp_path):
    out = tmp_path / "two.h5"
    res = invoke("run", "n-mass-chain", "-s", "short", "--option", "n=2", "-o", str(out), "--no-progress")
    assert res.exit_code == 0, res.output
    r = fl.load_result(out)
    assert "mass1.s" in r.names and "mass2.s" not in r.names  # the scenario's n = 3 overridden
    rec = registry.run_settings(r)
    assert rec.scenario["name"] == "short" and rec.scenario["options"] == {"n": 2}
    again = tmp_path / "again.h5"
    assert invoke("run", "--from", str(out), "-o", str(again), "--no-progress").exit_code == 0
    assert fl.load_result(again).names == r.names


def test_run_writes_the_models_figures(monkeypatch, tmp_path):
    """``--plots DIR`` calls the model's registered plots hook with the model and the run's result; the figures
    land in DIR (PNG files a reader opens); a model without the hook is a clear error naming it."""
    import matplotlib.image as mpimg

    monkeypatch.setattr(registry, "_MODELS", dict(registry.models()))
    from flexlib.models.n_mass_chain import NMassChain

    def plots(model, result, directory):
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots()
        result.plot("mass1.s", ax=ax)
        path = directory / "positions.png"
        fig.savefig(path)
        plt.close(fig)
        return [path]

    registry.register_model("plotted-chain", lambda s: NMassChain(n=2), doc="with figures",
                            scenarios=[Scenario("a", t_end=0.2)], plots=plots)
    res = invoke("run", "plotted-chain", "--plots", str(tmp_path / "figs"), "--no-progress")
    assert res.exit_code == 0, res.output
    image = mpimg.imread(tmp_path / "figs" / "positions.png")
    assert image.ndim == 3 and image.shape[0] > 100
    res = CliRunner().invoke(cli, ["run", "n-mass-chain", "-s", "short", "--plots", str(tmp_path / "none"),
                                   "--no-progress"], env=ENV)
    assert res.exit_code != 0 and "model 'n-mass-chain' has no figures" in res.output
    with pytest.raises(fl.FlexlibError, match="plots must be callable"):
        registry.register_model("bad-plots", lambda s: NMassChain(n=2), doc="x", scenarios=[Scenario("a")],
                                plots="figures.png")


def test_version_and_import_do_not_load_the_engine():
    """``import flexlib`` and ``flexlib --version`` load neither CasADi, SUNDIALS nor SciPy (the version took 0.5 s
    on a quiet machine and 2.5–8 s on a loaded one when it imported the whole engine, issue 29); a public name
    imports its module when first used."""
    import subprocess
    import sys

    code = ("import sys\nimport flexlib\nimport flexlib.cli\n"
            "from click.testing import CliRunner\n"
            "out = CliRunner().invoke(flexlib.cli.cli, ['--version']).output\n"
            "heavy = sorted(m for m in ('casadi', 'sksundae', 'scipy', 'h5py', 'matplotlib') if m in sys.modules)\n"
            "print(out.strip(), heavy)\n"
            "print(flexlib.Simulation.__module__, 'casadi' in sys.modules, 'Simulation' in dir(flexlib))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.splitlines()
    assert out[0].endswith(f"version {__import__('flexlib').__version__} []")  # CliRunner names the program 'cli'
    assert out[1] == "flexlib.solve.simulation True True"


def test_run_summary_is_readable_at_80_columns():
    """``flexlib run pump-truck`` at 80 columns (issue 29: 20 rows read ``cylinder1.cyl…``): no line wider than 80
    characters, no name cut short, each component's name once above its variables, four significant digits."""
    res = CliRunner().invoke(cli, ["run", "pump-truck", "--scenario", "hold", "--t-end", "1"],
                             env={"COLUMNS": "80"}, catch_exceptions=False)
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    assert max(len(line) for line in lines) <= 80
    assert "…" not in res.output
    table = lines[next(k for k, line in enumerate(lines) if "summary signals" in line):]
    assert sum(line.strip() == "axis2.cylinder.cylinder" for line in table) == 1
    p_a = next(line.split() for line in table if line.strip().startswith("p_A"))
    assert p_a[1] == "bar" and all(len(x.replace("-", "").replace(".", "")) <= 4 for x in p_a[2:4])


def test_run_outputs_are_stored_as_columns_and_repeated_with_the_run(tmp_path):
    """``flexlib run --outputs`` stores the named variables as columns besides the run's rows (issue 29): the file's
    ``/variables/stored`` lists exactly the matches, every variable still reads back; the choice is recorded with the
    run, so ``--from`` stores the same; a pattern that matches nothing is a warning and the file is written; an empty
    ``--outputs`` is refused."""
    import h5py

    out = tmp_path / "chain.h5"
    res = invoke("run", "n-mass-chain", "-s", "short", "--t-end", "0.2", "--no-progress", "-o", str(out),
                 "--outputs", "mass0.*,spring1.f")
    assert res.exit_code == 0, res.output
    back = fl.load_result(out)
    with h5py.File(out) as f:
        stored = sorted(back.names[k] for k in f["variables/stored"][()])
    assert stored == sorted(n for n in back.names if n.startswith("mass0.") or n == "spring1.f")
    again = tmp_path / "again.h5"
    assert invoke("run", "--from", str(out), "-o", str(again), "--no-progress").exit_code == 0
    with h5py.File(again) as f:
        assert sorted(back.names[k] for k in f["variables/stored"][()]) == stored
    warned = invoke("run", "n-mass-chain", "-s", "short", "--t-end", "0.2", "--no-progress", "-o",
                    str(tmp_path / "w.h5"), "--outputs", "nosuch.*")
    assert warned.exit_code == 0 and "nosuch" in warned.output and (tmp_path / "w.h5").exists()
    empty = CliRunner().invoke(cli, ["run", "n-mass-chain", "-s", "short", "--outputs", " , "], env=ENV)
    assert empty.exit_code != 0 and "--outputs" in empty.output and "no variable name or pattern" in empty.output
