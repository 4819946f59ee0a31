"""Write a benchmark's figures to ``benchmarks/results/<script>.json``.

Every script in ``benchmarks/`` ends by calling :func:`write_results` with its headline figures (a few named
values with units, shown on the generated page ``benchmarks/README.md``) and the tables it printed (kept in the
JSON only). The file also records when, where and how the figures were measured: the UTC date, the command line,
and the machine (CPU model, cores, load average, Python, CasADi, NumPy and scikit-sundae versions), so that a
figure is never read apart from its conditions. ``python benchmarks/render.py`` turns the JSON files into the page.

Scripts are run as ``python benchmarks/<script>.py`` from the repository root, which puts ``benchmarks/`` on
``sys.path``: they import this module as a sibling (``import report``), at the end where the results are written.

A figure is ``(name, value, unit)``: ``value`` a number (or a short string such as ``"failed"``), ``unit`` an SI
unit or ``""`` for counts and ratios. A ratio is always against a peer or a floor timed in the same run.
"""

from __future__ import annotations

import contextlib
import datetime
import io
import json
import math
import os
import platform
import shlex
import sys
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from importlib import metadata
from pathlib import Path
from typing import Any

RESULTS_DIR = Path(__file__).resolve().parent / "results"

Figure = tuple[str, Any, str]


def table(title: str, columns: Sequence[str], rows: Iterable[Sequence[Any]]) -> dict[str, Any]:
    """One printed table as a JSON record.

    Parameters
    ----------
    title : str
        What the table shows, with its conditions (tolerances, simulated time).
    columns : sequence of str
        Column headers, units in brackets (``"run [s]"``).
    rows : iterable of sequences
        The rows, one value per column (numbers, or strings as printed).

    Returns
    -------
    dict
        ``{"title", "columns", "rows"}``.
    """
    return {"title": title, "columns": list(columns), "rows": [[_plain(v) for v in row] for row in rows]}


@contextlib.contextmanager
def printed() -> Iterator[io.StringIO]:
    """Copy everything printed to standard output inside the block into a buffer (still printed as well).

    Yields
    ------
    io.StringIO
        The copy; read it with ``getvalue()`` after the block, e.g. for :func:`markdown_tables`.
    """

    class Tee(io.StringIO):
        def write(self, text: str) -> int:
            stdout.write(text)
            return super().write(text)

        def flush(self) -> None:
            stdout.flush()

    stdout, copy = sys.stdout, Tee()
    sys.stdout = copy
    try:
        yield copy
    finally:
        sys.stdout = stdout


def markdown_tables(text: str) -> list[dict[str, Any]]:
    """The Markdown tables in printed text, as :func:`table` records.

    Parameters
    ----------
    text : str
        Printed output; a table is a run of lines starting with ``|`` whose second line is the ``|---|`` rule.
        Its title is the last non-empty line printed before it.

    Returns
    -------
    list of dict
        One record per table, cells as printed (strings).
    """
    found, title, lines = [], "", text.splitlines()
    k = 0
    while k < len(lines):
        line = lines[k].strip()
        if line.startswith("|") and k + 1 < len(lines) and lines[k + 1].strip().startswith("|---"):
            end = k + 2
            while end < len(lines) and lines[end].strip().startswith("|"):
                end += 1
            split = [[c.strip() for c in row.strip().strip("|").split("|")] for row in lines[k:end]]
            found.append(table(title, split[0], split[2:]))
            k = end
            continue
        if line:
            title = line.lstrip("# ")
        k += 1
    return found


def machine() -> dict[str, Any]:
    """Facts about the machine and software that set the figures.

    Returns
    -------
    dict
        CPU model, logical cores, 1-minute load average when the figures were written, operating system, and
        the versions of Python, CasADi, NumPy and scikit-sundae.
    """
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    facts: dict[str, Any] = {"cpu": cpu, "cores": os.cpu_count(), "os": platform.platform(),
                             "python": platform.python_version()}
    try:
        facts["load_average_1min"] = round(os.getloadavg()[0], 2)
    except OSError:
        pass
    for dist in ("casadi", "numpy", "scikit-sundae"):
        try:
            facts[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            facts[dist] = None
    return facts


def write_results(script: str, figures: Sequence[Figure], tables: Sequence[dict[str, Any]] = (),
                  notes: Sequence[str] = (), source: str = "run") -> Path:
    """Write one script's results to ``benchmarks/results/<script>.json``, atomically.

    Parameters
    ----------
    script : str
        The script's path (``__file__``) or file name; its stem names the JSON file.
    figures : sequence of (name, value, unit)
        The headline figures shown on the generated page, in the order given.
    tables : sequence of dict
        The printed tables (:func:`table`), kept in the JSON file.
    notes : sequence of str
        Short remarks needed to read the figures (conditions, what a ratio compares).
    source : str
        ``"run"`` for figures measured by this call's process; otherwise where they were copied from.

    Returns
    -------
    pathlib.Path
        The file written. A temporary file in the same directory is renamed over it (``os.replace``), so a
        reader never sees a half-written file.
    """
    name = Path(script).stem
    record = {
        "script": f"{name}.py",
        "command": "python " + " ".join(shlex.quote(a) for a in [f"benchmarks/{name}.py", *sys.argv[1:]]),
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "source": source,
        "machine": machine(),
        "figures": [{"name": n, "value": _plain(v), "unit": u} for n, v, u in figures],
        "notes": list(notes),
        "tables": list(tables),
    }
    return dump(record, RESULTS_DIR / f"{name}.json")


def dump(record: dict[str, Any], path: Path) -> Path:
    """Write ``record`` as indented JSON to ``path`` through a temporary file and ``os.replace``.

    Parameters
    ----------
    record : dict
        JSON-serialisable data.
    path : pathlib.Path
        Destination; its directory is created when missing.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=".json", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            json.dump(record, f, indent=1, ensure_ascii=False)
            f.write("\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    root = Path(__file__).resolve().parent.parent
    print(f"results written to {path.relative_to(root) if path.is_relative_to(root) else path}")
    return path


def _plain(value: Any) -> Any:
    """A JSON value: numpy scalars as Python numbers, floats to four significant digits, non-finite as strings."""
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        try:
            value = value.item()
        except (TypeError, ValueError):
            return str(value)
    if isinstance(value, float):
        return float(f"{value:.4g}") if math.isfinite(value) else str(value)
    if isinstance(value, (bool, int, float, str)) or value is None:
        return value
    return str(value)
