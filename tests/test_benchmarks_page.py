"""The benchmarks' page is generated from their results files and cannot go stale.

``benchmarks/README.md`` must be exactly what ``benchmarks/render.py`` makes of ``benchmarks/results/*.json``,
every benchmark script must have a results file with the fields the page and a reader need, and the page stays
under 150 lines. ``benchmarks/report.py`` writes a results file in one piece.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path
from types import ModuleType

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


def _load(name: str) -> ModuleType:
    """A module of ``benchmarks/`` (a directory of scripts, not a package) loaded from its file."""
    spec = importlib.util.spec_from_file_location(f"benchmarks_{name}", BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)  # type: ignore[union-attr]
    return module


render = _load("render")
report = _load("report")


def test_page_is_generated_from_the_results() -> None:
    page = (BENCHMARKS / "README.md").read_text(encoding="utf-8")
    assert page == render.render(), "benchmarks/README.md is stale: run python benchmarks/render.py"


def test_page_is_short() -> None:
    assert len(render.render().splitlines()) < 150


@pytest.mark.parametrize("script", [p.stem for p in render.scripts()])
def test_every_benchmark_has_results(script: str) -> None:
    path = BENCHMARKS / "results" / f"{script}.json"
    assert path.exists(), f"no results for benchmarks/{script}.py: run it (or its quick variant)"
    record = json.loads(path.read_text(encoding="utf-8"))
    assert record["script"] == f"{script}.py"
    assert record["command"].startswith(f"python benchmarks/{script}.py")
    assert record["source"] == "run" or " as of " in record["source"]
    assert record["date"] and record["machine"]
    assert record["figures"], "the page shows a script's headline figures: give at least one"
    for figure in record["figures"]:
        assert set(figure) == {"name", "value", "unit"}
    assert render.summary(BENCHMARKS / f"{script}.py"), "the page takes what a script measures from its docstring"


def test_every_benchmark_is_grouped_on_the_page() -> None:
    grouped = {name for _, names in render.GROUPS for name in names}
    assert {p.stem for p in render.scripts()} <= grouped


def test_results_are_written_whole(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(report, "RESULTS_DIR", tmp_path / "results")
    monkeypatch.setattr(sys, "argv", ["x.py", "--quick"])
    path = report.write_results("/somewhere/example.py", [("run", 0.123456789, "s"), ("steps", 12, "")],
                                tables=[report.table("t", ["a [s]"], [[1.0]])], notes=["n"])
    record = json.loads(path.read_text(encoding="utf-8"))
    assert path == tmp_path / "results" / "example.json"
    assert record["script"] == "example.py" and record["source"] == "run"
    assert record["command"] == "python benchmarks/example.py --quick"
    assert record["figures"] == [{"name": "run", "value": 0.1235, "unit": "s"},
                                 {"name": "steps", "value": 12, "unit": ""}]
    assert record["tables"] == [{"title": "t", "columns": ["a [s]"], "rows": [[1.0]]}]
    assert record["machine"]["cores"] and record["machine"]["python"]
    assert [p.name for p in path.parent.iterdir()] == ["example.json"]  # no temporary file left behind


def test_printed_markdown_tables_are_read_back() -> None:
    text = "## 1. Monitor\n\n| model | run (s) |\n|---|---|\n| four-bar | 0.46 |\nafter\n"
    assert report.markdown_tables(text) == [{"title": "1. Monitor", "columns": ["model", "run (s)"],
                                              "rows": [["four-bar", "0.46"]]}]
