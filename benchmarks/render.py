"""Generate ``benchmarks/README.md`` from the figures in ``benchmarks/results/*.json``.

The page is the current figures and nothing else: a hand-written header (how to run, how to read a ratio), then
per group of benchmarks one table with, per script, the command that produced the figures, what the script
measures (the first line of its module docstring), its headline figures with units, and when and how they were
obtained. The design history behind the figures lives in ``docs/decisions/``; the full printed tables stay in the
JSON files. ``tests/test_benchmarks_page.py`` checks that the committed page is what this script generates.

Run: ``python benchmarks/render.py`` (writes the page), ``--check`` (exit status 1 when the page is stale),
``--rerun`` (first runs again every script whose figures came from a run, with the command recorded in its file).
"""

from __future__ import annotations

import ast
import json
import shlex
import subprocess
import sys
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
PAGE = HERE / "README.md"
NOT_BENCHMARKS = {"report.py", "render.py"}

GROUPS: list[tuple[str, list[str]]] = [
    ("Integrators and the run loop", ["chain", "pendulum", "ida_overhead", "native_default", "native_ida",
                                      "casadi_idas", "linear_solvers", "engine_speed", "event_zero_guard", "friction",
                                      "fixed_step", "evaluator_timing", "work_precision"]),
    ("Building a model", ["cached_build", "cold_chain", "build_scale", "flatten_checks", "zero_geometry",
                          "explicit_elimination", "minimal_dae"]),
    ("Multibody and hydraulics", ["multibody", "headline", "boom_proxy", "hydraulic_servo", "hydraulic_chamber",
                                  "linear_analysis"]),
    ("Flexible bodies", ["modal_data", "flexible_beam", "pinned_free_beam", "flexible_body"]),
    ("Machines", ["pump_truck", "pump_truck_flows", "pump_truck_reference", "pump_truck_friction", "robots",
                  "result_files", "study", "sensitivities"]),
]

HEADER = """\
# Benchmarks

Scripts that time flexlib and print tables; nothing is asserted. Each writes its figures to
`benchmarks/results/<script>.json` (figures with units, the printed tables, date, command line, CPU, cores,
load, Python and CasADi versions) through `benchmarks/report.py`. This page is generated from those files by
`python benchmarks/render.py`; do not edit it by hand. Why the engine is built the way these figures show,
with the before/after measurements, is in `docs/decisions/` (101 and up).

Run from the repository root in the project's virtualenv: the command in a row's first column re-measures that
row (then `python benchmarks/render.py` rewrites this page); `python benchmarks/render.py --rerun` runs every
row measured by a run (the quick variants, ~10 minutes in all) and rewrites the page. Rows marked "copied" take
minutes to an hour each; run their command by hand. Every script sets `OMP_NUM_THREADS=1` and uses a fresh
temporary `FLEXLIB_CACHE_DIR`, so a cold build is cold.

How to read the figures: the reference machine is a 2-core VM shared with other jobs, where the same run can
vary by ±30–50 %. Absolute times are indicative; a **ratio** (×, "/ floor", "/ peer") is always against a
floor (the same model with a feature off, a bare loop) or a peer (CasADi's IDAS, Exudyn, a hand-written DAE)
timed in the same process, interleaved where it matters, and is the figure to compare across runs. CPU times
are process CPU (steadier than wall time under load). "copied" marks figures transcribed from the previous
hand-written page for scripts that take too long to re-run on a shared machine (`source` in the JSON).
"""


def summary(script: Path) -> str:
    """The first line of a script's module docstring (what it measures), without a ``Benchmark:`` prefix.

    Parameters
    ----------
    script : pathlib.Path
        A benchmark script.

    Returns
    -------
    str
        One line; empty when the script has no docstring.
    """
    doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8"))) or ""
    first = " ".join(doc.split("\n\n", 1)[0].split())
    for prefix in ("Benchmark:", "Check:"):
        if first.startswith(prefix):
            first = first[len(prefix):].strip()
    first = first.replace("``", "`")  # reStructuredText literals as Markdown code
    return first[:1].upper() + first[1:]


def number(value: Any) -> str:
    """A figure's value as printed on the page: integers as they are, floats to three significant digits."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    if isinstance(value, int):
        return f"{value:,}".replace(",", " ") if abs(value) >= 10000 else str(value)
    if value == 0 or 1e-3 <= abs(value) < 1e4:
        text = f"{value:.3g}"
        return f"{float(text):.0f}" if abs(value) >= 100 else text
    return f"{value:.2g}".replace("e-0", "e-").replace("e+0", "e")


def figures(record: dict[str, Any]) -> str:
    """The headline figures of one results file as one table cell."""
    parts = []
    for f in record["figures"]:
        unit = f" {f['unit']}" if f["unit"] else ""
        parts.append(f"{f['name']} {number(f['value'])}{unit}")
    return "; ".join(parts).replace("|", "\\|")


def measured(record: dict[str, Any]) -> str:
    """When the figures were measured, and ``copied`` when they were transcribed rather than run."""
    day = record["date"][:10]
    return day if record["source"] == "run" else f"{day}, copied"


def scripts() -> list[Path]:
    """Every benchmark script (``benchmarks/*.py`` except this page's own helpers and ``_*.py``), sorted by name."""
    return sorted(p for p in HERE.glob("*.py") if p.name not in NOT_BENCHMARKS and not p.name.startswith("_"))


def render() -> str:
    """The page's text from the results files.

    Returns
    -------
    str
        Markdown; a script without a results file is listed with "no results yet".
    """
    by_name = {p.stem: p for p in scripts()}
    grouped = [name for _, names in GROUPS for name in names]
    groups = [*GROUPS, ("Other", [n for n in by_name if n not in grouped])]
    lines = [HEADER]
    machines: set[str] = set()
    for title, names in groups:
        names = [n for n in names if n in by_name]
        if not names:
            continue
        lines += [f"## {title}", "", "| run | measures | current figures | measured |", "|---|---|---|---|"]
        for name in names:
            path = RESULTS / f"{name}.json"
            if not path.exists():
                lines.append(f"| `python benchmarks/{name}.py` | {summary(by_name[name])} | no results yet | |")
                continue
            record = json.loads(path.read_text(encoding="utf-8"))
            m = record["machine"]
            if "cpu" in m:
                machines.add(f"{m['cpu']}, {m['cores']} cores, Python {m['python']}, CasADi {m['casadi']}")
            lines.append(f"| `{record['command']}` | {summary(by_name[name])} | {figures(record)} | "
                         f"{measured(record)} |")
        lines.append("")
    lines.append("Machines of the runs above: " + "; ".join(sorted(machines)) + ".")
    return "\n".join(lines) + "\n"


def rerun() -> None:
    """Run again, one after the other, every script whose results file was measured by a run, with its command."""
    for path in sorted(RESULTS.glob("*.json")):
        record = json.loads(path.read_text(encoding="utf-8"))
        if record["source"] != "run":
            continue
        print(f"$ {record['command']}", flush=True)
        subprocess.run([sys.executable, *shlex.split(record["command"])[1:]], cwd=HERE.parent, check=False)


def main() -> int:
    """Write the page, or with ``--check`` report whether it is current; ``--rerun`` measures again first."""
    if "--rerun" in sys.argv[1:]:
        rerun()
    text = render()
    if "--check" in sys.argv[1:]:
        current = PAGE.read_text(encoding="utf-8") == text
        print("benchmarks/README.md is current" if current else "benchmarks/README.md is stale: run render.py")
        return 0 if current else 1
    PAGE.write_text(text, encoding="utf-8")
    print(f"wrote {PAGE.relative_to(HERE.parent)} ({text.count(chr(10))} lines)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
