"""The study commands: ``flexlib sweep`` (a study of a registered model on Dask, :mod:`flexlib.study`) and ``flexlib
study show`` (its table and figures). :mod:`flexlib.cli` adds them to its command group."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import click
import numpy as np
from rich.table import Table

from flexlib.cli_support import friendly, new_console, once_option, say

__all__ = ["study_group", "sweep_cmd"]

#: ``--reduce KIND:SIGNAL`` kinds and their reductions' class names (:mod:`flexlib.study.reductions`)
REDUCE_KINDS = {"peak": "Peak", "max": "Maximum", "min": "Minimum", "final": "Final"}
_RANGE = re.compile(r"^(?P<name>[^=]+)=(?P<lo>[^:]+):(?P<hi>[^:]+):(?P<n>\d+)$")


def parse_axis(text: str) -> tuple[str, list[float], tuple[float, float]]:
    """``NAME=LOW:HIGH:N`` (N values from LOW to HIGH) or ``NAME=V1,V2,...``: the name, its values and bounds."""
    m = _RANGE.match(text)
    try:
        if m:
            lo, hi, n = float(m["lo"]), float(m["hi"]), int(m["n"])
            if n < 1 or not (math.isfinite(lo) and math.isfinite(hi)):
                raise ValueError
            values = list(np.linspace(lo, hi, n)) if n > 1 else [lo]
            return m["name"].strip(), [float(v) for v in values], (lo, hi)
        name, _, rest = text.partition("=")
        values = [float(v) for v in rest.split(",")]
        if not name.strip() or not values or not all(math.isfinite(v) for v in values):
            raise ValueError
        return name.strip(), values, (min(values), max(values))
    except ValueError:
        raise click.ClickException(
            f"--param {text!r}: give NAME=LOW:HIGH:N (N values, SI units) or NAME=V1,V2,...") from None


def parse_reduction(text: str) -> tuple[str, Any]:
    """``KIND:SIGNAL`` (peak, max, min, final): the column name and the reduction."""
    import flexlib.study as study

    kind, _, signal = text.partition(":")
    if kind not in REDUCE_KINDS or not signal:
        raise click.ClickException(f"--reduce {text!r}: give KIND:SIGNAL with KIND one of {', '.join(REDUCE_KINDS)}")
    return f"{kind}({signal})", getattr(study, REDUCE_KINDS[kind])(signal)


@click.command("sweep")
@click.argument("model")
@once_option("-s", "--scenario", help="Scenario (default: the model's).")
@click.option("-p", "--param", "params", multiple=True, metavar="NAME=LOW:HIGH:N",
              help="A parameter axis: N values from LOW to HIGH, or NAME=V1,V2,... (SI units; repeatable: a grid).")
@once_option("--lhs", type=click.IntRange(min=1), metavar="N",
             help="N Latin-hypercube samples in the box of the --param bounds instead of the grid.")
@once_option("--seed", type=int, help="Seed of the samples (default 0).")
@click.option("-r", "--reduce", "reduce_opts", multiple=True, metavar="KIND:SIGNAL", required=True,
              help="What each run is judged by: peak|max|min|final of a signal (repeatable).")
@once_option("--pose", metavar="DEG,DEG,...",
             help="Start the scenario from this pose instead of its own (its data's pose: the pump truck's slew and "
                  "joint angles [deg]).")
@once_option("--workers", type=click.IntRange(min=1), help="Worker processes of the local cluster (default 2).")
@once_option("--scheduler", help="A running Dask scheduler (tcp://host:8786) instead of a local cluster.")
@once_option("-o", "--out", required=True, type=click.Path(dir_okay=False),
             help="The table (Parquet); a sweep started again with it runs only the missing rows.")
@click.option("--no-progress", is_flag=True, help="No progress bar.")
@friendly
def sweep_cmd(model: str, scenario: str | None, params: tuple[str, ...], lhs: int | None, seed: int | None,
              reduce_opts: tuple[str, ...], pose: str | None, workers: int | None, scheduler: str | None, out: str,
              no_progress: bool) -> None:
    """Run MODEL's scenario over parameter values on Dask and write the table of reductions (docs/studies.md)."""
    from flexlib import registry
    from flexlib.errors import RunArgumentError
    from flexlib.study import grid, latin_hypercube, run_study, start_pose

    if not params:
        raise click.ClickException("give at least one --param NAME=LOW:HIGH:N")
    axes = [parse_axis(p) for p in params]
    names = [a[0] for a in axes]
    if len(set(names)) != len(names):
        raise click.ClickException("a parameter is given twice in --param")
    if lhs is not None:
        variants = latin_hypercube({n: b for n, _, b in axes}, lhs, seed=seed or 0)
    else:
        variants = grid(**{n: v for n, v, _ in axes})
    reductions = dict(parse_reduction(r) for r in reduce_opts)
    scen: str | registry.Scenario | None = scenario
    if pose is not None:
        try:
            angles = [float(v) for v in pose.split(",")]
        except ValueError:
            raise click.ClickException(f"--pose {pose!r}: give the angles as DEG,DEG,... (numbers)") from None
        try:
            scen = start_pose(model, scenario, angles)
        except RunArgumentError as err:
            raise click.ClickException(f"--pose: {err}") from None
    table = run_study(model, variants, reductions, scenario=scen, workers=workers or 2, scheduler=scheduler,
                      out=out, progress=not no_progress)
    failed = len(table.failed)
    say("Wrote", f"{out}: {len(table.rows)} runs, {failed} failed" + (f" (first: {table.failed[0]['error']})"
                                                                     if failed else ""))


@click.group("study")
def study_group() -> None:
    """Read study tables (flexlib sweep)."""


@study_group.command("show")
@click.argument("file", type=click.Path(exists=True, dir_okay=False))
@click.option("--top", type=click.IntRange(min=1), default=20, show_default=True, help="Rows shown.")
@once_option("--plot", "plot_file", type=click.Path(dir_okay=False),
             help="Write a figure: each reduction against the parameter (one parameter), a heat map of the first "
                  "reduction (two), or its scatter against each parameter (more).")
@friendly
def study_show_cmd(file: str, top: int, plot_file: str | None) -> None:
    """Print a study's table: inputs, reductions, status; optionally a figure."""
    from flexlib.study.run import read_table

    rows, meta = read_table(file)
    if not rows or not meta:
        raise click.ClickException(f"{file}: not a study table written by flexlib sweep / run_study (or empty)")
    params, reductions = meta["params"], meta["reductions"]
    table = Table(title=f"{Path(file).name}: {meta['model']}, {len(rows)} runs, "
                        f"{sum(r['status'] != 'success' for r in rows)} failed")
    for col in [*params, *reductions, "status", "run_time"]:
        table.add_column(col, justify="right" if col != "status" else "left")
    for r in rows[:top]:
        table.add_row(*[f"{r[c]:.4g}" if isinstance(r[c], float) else str(r[c]) for c in
                        [*params, *reductions, "status", "run_time"]])
    new_console().print(table)
    if plot_file is not None:
        _plot(rows, params, reductions, Path(plot_file))
        say("Wrote", plot_file)


def _plot(rows: list[dict], params: list[str], reductions: list[str], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [r for r in rows if r["status"] == "success"]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    first = reductions[0]
    if len(params) == 1:
        order = sorted(ok, key=lambda r: r[params[0]])
        for red in reductions:
            ax.plot([r[params[0]] for r in order], [r[red] for r in order], "o-", label=red)
        ax.set_xlabel(params[0])
        ax.legend()
    elif len(params) == 2:
        sc = ax.scatter([r[params[0]] for r in ok], [r[params[1]] for r in ok], c=[r[first] for r in ok], s=120,
                        marker="s", cmap="viridis")
        fig.colorbar(sc, ax=ax, label=first)
        ax.set_xlabel(params[0])
        ax.set_ylabel(params[1])
    else:
        for p in params:
            ax.plot([r[p] for r in ok], [r[first] for r in ok], "o", label=p)
        ax.set_xlabel("parameter value")
        ax.set_ylabel(first)
        ax.legend()
    ax.set_title(f"{len(ok)} runs")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
