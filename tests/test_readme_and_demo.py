"""The README's examples and the demo run as written (keeps the front door true)."""

from pathlib import Path

import matplotlib
import numpy as np
import pytest

from tests.doc_blocks import python_blocks

ROOT = Path(__file__).resolve().parent.parent
matplotlib.use("Agg")


def test_readme_examples_run(tmp_path, monkeypatch):
    """Each python block of the README runs on its own, in a fresh namespace (a reader copies one block, not the
    tour: issue 29), and its result is the one the text says."""
    monkeypatch.chdir(tmp_path)
    blocks = python_blocks("README.md")
    assert len(blocks) >= 6
    spaces = []
    for k, block in enumerate(blocks):
        namespace: dict = {}
        exec(compile(block, f"README.md, python block {k + 1}", "exec"), namespace)
        spaces.append(namespace)
    assert (tmp_path / "oscillator.h5").exists()
    assert spaces[1]["sim"].report.index == 3  # the Cartesian pendulum
    lift = next(ns["res"] for ns in spaces if "Lift" in ns)  # the piston extends at Q / A_piston (0.5 %)
    area = 3.141592653589793 / 4 * 0.063**2
    assert abs(lift["cylinder.v"][-1] - lift["flow.q"][-1] / area) <= 5e-3 * lift["cylinder.v"][-1]
    arm = next(ns["arm_res"] for ns in spaces if "arm_res" in ns)  # released horizontally: swung down, deflected
    assert arm["arm.frame_b.r_0"][-1, 1] < -0.5 and abs(arm["arm.q"][-1]).max() > 1e-6


def test_demo_runs(tmp_path, capsys):
    from flexlib.models.examples import demo

    demo.main(["--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert "DAE index" in out and "same compiled model" in out
    assert (tmp_path / "demo.h5").exists() and (tmp_path / "demo.png").exists()


@pytest.mark.parametrize("cmd", ["python -m flexlib.models.examples.demo", 'pip install -q -e ".[test]"',
                                 "flexlib run pump-truck --scenario expand-fold --out pump_truck_output/expand_fold.h5 "
                                 "--plots pump_truck_output"])
def test_readme_commands_present(cmd):
    assert cmd in (ROOT / "README.md").read_text()


def test_readme_main_job_runs_as_written(tmp_path, monkeypatch):
    """The README's main command (after its install part) in a fresh directory: the pump truck's full expand-fold
    cycle; it leaves the result file and the five figures, every joint reaches the working pose (1°) and comes back
    to the transport fold (1°)."""
    import shlex

    import matplotlib.image as mpimg
    from click.testing import CliRunner

    import flexlib as fl
    from flexlib.cli import cli

    text = (ROOT / "README.md").read_text()
    line = next(ln for ln in text.splitlines() if "flexlib run pump-truck" in ln)
    args = shlex.split(line.split("&& flexlib ", 1)[1])
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(cli, [*args, "--no-progress"], env={"COLUMNS": "200"}, catch_exceptions=False)
    assert res.exit_code == 0, res.output
    out = tmp_path / "pump_truck_output"
    from flexlib.models.pump_truck.model import TRANSPORT_POSE_DEG, WORKING_POSE_DEG

    result = fl.load_result(out / "expand_fold.h5")
    assert result.success and result.t[-1] == pytest.approx(560.524, abs=0.01)
    from flexlib.registry import get_model

    t_work = get_model("pump-truck").scenario("expand").data["targets"]["t"][-1]  # then a 2 s pause before folding
    i_work = int(np.searchsorted(result.t, t_work + 1.0))
    for n in range(1, 6):
        phi = np.degrees(result[f"joint{n}.phi"])
        assert phi[i_work] == pytest.approx(WORKING_POSE_DEG[n], abs=1.0), f"joint{n} working pose"
        assert phi[-1] == pytest.approx(TRANSPORT_POSE_DEG[n], abs=1.0), f"joint{n} back in the transport fold"
    for name in ("flows", "pressures", "hinge_forces", "section_lengths", "tip_path"):
        assert mpimg.imread(out / f"{name}.png").shape[0] > 200
