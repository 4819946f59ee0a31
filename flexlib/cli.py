"""The ``flexlib`` command line (click + rich): list, run, compare and show registered models and results.

::

    flexlib list                                   # models and scenarios with their docs
    flexlib run n-mass-chain --scenario short --out chain.h5 --param mass0.m=2
    flexlib run --from chain.h5 --rtol 1e-8        # repeat a run from its file (options on top)
    flexlib show chain.h5                          # run settings stored in a result file
    flexlib compare a.h5 b.h5 --plot diff.png      # largest differences of the common signals

Models and scenarios come from :mod:`flexlib.registry`; ``--models MODULE`` (or ``$FLEXLIB_MODELS``) imports a
user's module that registers more. Every error is one line naming the culprit (model, scenario, parameter,
option, file), with exit code 1 (2 for a malformed option, as click reports it); no traceback.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import json
import math
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click
import numpy as np
from rich.console import Console
from rich.table import Table

from flexlib.errors import FlexlibError, SolverError

__all__ = ["cli", "compare_results", "main"]

SOLVERS = ("ida", "ida-native", "ida-sksundae", "casadi-idas")


def _one_line(err: BaseException) -> str:
    return " ".join(str(err).split()) or type(err).__name__


def _friendly(func: Callable[..., Any]) -> Callable[..., Any]:
    """Turn flexlib's errors (and bad values) into a one-line ``Error: ...`` with exit code 1."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except click.ClickException:
            raise
        except (FlexlibError, ValueError, OSError, LookupError) as err:
            raise click.ClickException(_one_line(err)) from None

    return wrapper


def _console() -> Console:
    return Console(highlight=False, markup=False)  # "[s]" in labels is text, not a style


def _fmt(x: float) -> str:
    return f"{x:.6g}"


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--models", "modules", multiple=True, metavar="MODULE",
              help="Import this Python module first (it registers more models); repeatable.")
@click.version_option(package_name="flexlib")
def cli(modules: tuple[str, ...]) -> None:
    """flexlib: acausal multibody, flexible-body and hydraulic models, from the command line."""
    if modules and "" not in sys.path:
        sys.path.insert(0, "")  # a user's module in the working directory
    for module in modules:
        try:
            importlib.import_module(module)
        except Exception as err:  # any failure of the user's module: one line naming it
            raise click.ClickException(f"--models {module}: cannot import the module: {_one_line(err)}") from None


# -- list ----------------------------------------------------------------------------------------------------------
@cli.command("list")
@_friendly
def list_cmd() -> None:
    """Show the registered models and their scenarios."""
    from flexlib import registry

    table = Table(title="flexlib models and scenarios", show_lines=False)
    table.add_column("model", style="bold")
    table.add_column("scenario")
    table.add_column("t_end [s]", justify="right")
    table.add_column("description")
    for name, entry in registry.models().items():
        table.add_row(name, "", "", entry.doc)
        for sname, scen in entry.scenarios.items():
            default = " (default)" if sname == entry.default_scenario else ""
            t_end = _fmt(scen.t_end) if scen.t_end is not None else "model"
            table.add_row("", sname + default, t_end, scen.doc)
    _console().print(table)


# -- run -----------------------------------------------------------------------------------------------------------
def _parse_params(items: tuple[str, ...]) -> dict[str, float]:
    out: dict[str, float] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name, value = name.strip(), value.strip()
        if not sep or not name:
            raise click.ClickException(f"--param {item!r}: expected NAME=VALUE (for example mass0.m=2.0)")
        try:
            number = float(value)
        except ValueError:
            raise click.ClickException(f"--param {item!r}: the value {value!r} of {name} is not a number") from None
        if not math.isfinite(number):
            raise click.ClickException(f"--param {item!r}: the value of {name} must be finite")
        out[name] = number
    return out


def _parse_options(items: tuple[str, ...]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise click.ClickException(f"--option {item!r}: expected NAME=VALUE (for example n=4 or flexible=true)")
        try:
            out[name] = json.loads(value)
        except ValueError:
            out[name] = value.strip()
    return out


@cli.command("run")
@click.argument("model", required=False)
@click.option("-s", "--scenario", help="Scenario name, or a JSON file with a scenario (default: the model's).")
@click.option("-o", "--out", type=click.Path(dir_okay=False), help="Write the result (HDF5) to this file.")
@click.option("-p", "--param", "params", multiple=True, metavar="NAME=VALUE",
              help="Parameter override in SI units (repeatable).")
@click.option("--t-end", type=click.FloatRange(min=0.0, min_open=True), help="End time [s].")
@click.option("--rtol", type=click.FloatRange(0.0, 1.0, min_open=True, max_open=True), help="Relative tolerance.")
@click.option("--atol", type=click.FloatRange(min=0.0, min_open=True), help="Absolute tolerance.")
@click.option("--dt-out", type=click.FloatRange(min=0.0, min_open=True), help="Output interval [s].")
@click.option("--solver", type=click.Choice(SOLVERS), help="Solver backend.")
@click.option("--from", "from_file", type=click.Path(dir_okay=False),
              help="Repeat the run recorded in this result file (other options apply on top).")
@click.option("-O", "--option", "model_options", multiple=True, metavar="NAME=VALUE",
              help="Model option on top of the scenario's (VALUE read as JSON, else text; repeatable).")
@click.option("--flexible/--rigid", default=None, help="Shorthand for --option flexible=true / false.")
@click.option("--no-progress", is_flag=True, help="No progress bar.")
@click.option("--plots", "plots_dir", type=click.Path(file_okay=False),
              help="Write the model's figures (PNG) of the run into this directory.")
@_friendly
def run_cmd(model: str | None, scenario: str | None, out: str | None, params: tuple[str, ...], t_end: float | None,
            rtol: float | None, atol: float | None, dt_out: float | None, solver: str | None, from_file: str | None,
            model_options: tuple[str, ...], flexible: bool | None, no_progress: bool,
            plots_dir: str | None) -> None:
    """Run MODEL in a scenario, then print a summary (times, steps, peaks of the model's signals)."""
    from flexlib import registry
    from flexlib.registry import Scenario

    overrides = _parse_params(params)
    given = {k: v for k, v in (("rtol", rtol), ("atol", atol), ("dt_out", dt_out), ("solver", solver))
             if v is not None}
    scen: str | Scenario | None = scenario
    if scenario is not None and (scenario.endswith(".json") or os.path.isfile(scenario)):
        scen = Scenario.from_file(scenario)
    if from_file is not None:
        from flexlib.results.hdf5 import load_result

        if scenario is not None:
            raise click.ClickException("--from and --scenario: give one (the file records its scenario)")
        record = registry.run_settings(load_result(from_file), from_file)
        if model is not None and model != record.model:
            raise click.ClickException(f"model {model!r} differs from the model {record.model!r} recorded in "
                                       f"{from_file}; omit MODEL with --from")
        model = record.model
        scen = Scenario.from_dict(record.scenario)
        overrides = {**record.params, **overrides}
        t_end = t_end if t_end is not None else record.run.get("t_end")
        given = {**{k: v for k, v in record.run.items() if k != "t_end"}, **given}
    if model is None:
        raise click.ClickException("give a MODEL (see 'flexlib list') or --from FILE")
    extra_options = _parse_options(model_options)
    if flexible is not None:
        extra_options["flexible"] = flexible
    if extra_options:  # recorded as part of the scenario, so that --from repeats them
        base = scen if isinstance(scen, Scenario) else registry.get_scenario(model, scen)
        scen = dataclasses.replace(base, options={**base.options, **extra_options})
    if out is not None:
        from flexlib.solve.run_options import check_result_path

        check_result_path(out, "--out")  # before the build
    try:
        done = registry.run_scenario(model, scen, params=overrides, t_end=t_end, progress=not no_progress,
                                     result_file=out, **given)
    except SolverError as err:
        where = f"; the result up to the failure is in {out}" if out and err.result is not None else ""
        raise click.ClickException(f"{model}: the run failed: {_one_line(err)}{where}") from None
    _print_summary(done, out)
    if plots_dir is not None:
        _write_plots(done, plots_dir)


def _write_plots(done: Any, directory: str) -> None:
    """The model's figures of the run, through its registered ``plots`` hook."""
    if done.entry.plots is None:
        raise click.ClickException(f"model {done.entry.name!r} has no figures (--plots needs a plots hook)")
    import matplotlib

    matplotlib.use("Agg")
    path = Path(directory)
    path.mkdir(parents=True, exist_ok=True)
    written = done.entry.plots(done.model, done.result, path)
    _console().print(f"figures: {len(written)} in {path}" + "".join(f"\n  {p}" for p in written))


def _print_summary(done: Any, out: str | None) -> None:
    res = done.result
    t_sim = float(res.t[-1] - res.t[0]) if len(res.t) else 0.0
    console = _console()
    table = Table(title=f"{done.entry.name} / {done.scenario.name}: {res.status}", show_header=False)
    table.add_column("quantity", style="bold")
    table.add_column("value", justify="right")
    rows = [("simulated time [s]", _fmt(t_sim)),
            ("CPU time, build [s]", f"{done.cpu_build:.3f}" + (" (cached)" if res.stats.get("build_cached") else "")),
            ("CPU time, run [s]", f"{done.cpu_run:.3f}"),
            ("real-time factor", f"{t_sim / done.cpu_run:.3g}" if done.cpu_run > 0 else "-"),
            ("steps", str(res.stats.get("steps", "-"))),
            ("residual evaluations", str(res.stats.get("nfev", "-"))),
            ("events", str(len(res.events))),
            ("unknowns / states", f"{res.stats.get('n_unknowns', '-')} / {res.stats.get('n_states', '-')}")]
    if out:
        rows.append(("result file", str(out)))
    for row in rows:
        table.add_row(*row)
    console.print(table)
    signals = done.entry.signals(done.model)
    if not signals or not len(res.t):
        return
    peaks = Table(title="summary signals")
    for col, justify in (("signal", "left"), ("unit", "left"), ("min", "right"), ("max", "right"),
                         ("peak |x|", "right"), ("at t [s]", "right")):
        peaks.add_column(col, justify=justify)
    for name in signals:
        values, unit = res.display(name)
        k = int(np.argmax(np.abs(values)))
        peaks.add_row(name, unit, _fmt(values.min()), _fmt(values.max()), _fmt(abs(values[k])), _fmt(res.t[k]))
    console.print(peaks)


# -- compare -------------------------------------------------------------------------------------------------------
def _right_values(res: Any) -> tuple[np.ndarray, np.ndarray]:
    """Time points and rows with the right value kept at events (as :meth:`Result.value`)."""
    t = res.t
    keep = np.ones(len(t), dtype=bool)
    keep[:-1] = t[1:] != t[:-1]
    return t[keep], res.values[keep]


def compare_results(a: Any, b: Any, signals: list[str] | None = None) -> list[dict[str, Any]]:
    """Largest differences between two results on a common time grid.

    Both results are interpolated linearly (right values at events) on the union of their time points inside
    the common time span.

    Parameters
    ----------
    a, b : Result
        The results.
    signals : list of str, optional
        Variables to compare (array variables expand to their elements); default: every variable in both.

    Returns
    -------
    list of dict
        One per signal, largest relative difference first: ``name``, ``unit``, ``abs`` (max ``|a − b|``, SI),
        ``rel`` (that over the larger of ``max |a|`` and ``max |b|``; 0 if both are 0), ``t`` [s] where it
        occurs, ``a`` and ``b`` there.

    Raises
    ------
    ResultKeyError
        A requested signal is not in one of the results (names it, with close matches).
    ValueError
        The results have no common time span.
    """
    from flexlib.errors import ResultKeyError

    common = set(b.names)
    if signals:
        names: list[str] = []
        for s in signals:
            for res in (a, b):
                if s not in res.names and not any(n.startswith(s + "[") for n in res.names):
                    try:
                        res[s]
                    except ResultKeyError as err:
                        raise ResultKeyError(f"{err} (signal asked for with --signals)") from None
            names += [s] if s in a.names else [n for n in a.names if n.startswith(s + "[") and n in common]
    else:
        names = [n for n in a.names if n in common]
    if not len(a.t) or not len(b.t):
        raise ValueError("cannot compare: a result has no rows")
    t0, t1 = max(a.t[0], b.t[0]), min(a.t[-1], b.t[-1])
    if t1 < t0:
        raise ValueError(f"cannot compare: no common time span ({a.t[0]:g} … {a.t[-1]:g} s and "
                         f"{b.t[0]:g} … {b.t[-1]:g} s)")
    ta, va = _right_values(a)
    tb, vb = _right_values(b)
    grid = np.union1d(ta, tb)
    grid = grid[(grid >= t0) & (grid <= t1)]
    ia, ib = {n: k for k, n in enumerate(a.names)}, {n: k for k, n in enumerate(b.names)}
    rows = []
    for n in names:
        xa = np.interp(grid, ta, va[:, ia[n]])
        xb = np.interp(grid, tb, vb[:, ib[n]])
        d = np.abs(xa - xb)
        k = int(np.argmax(d))
        scale = max(float(np.max(np.abs(xa))), float(np.max(np.abs(xb))))
        rel = float(d[k]) / scale if scale else 0.0
        rows.append({"name": n, "unit": a.units[ia[n]], "abs": float(d[k]), "rel": rel, "t": float(grid[k]),
                     "a": float(xa[k]), "b": float(xb[k])})
    rows.sort(key=lambda r: (-r["rel"], -r["abs"]))
    return rows


@cli.command("compare")
@click.argument("file_a", type=click.Path(dir_okay=False))
@click.argument("file_b", type=click.Path(dir_okay=False))
@click.option("--signals", "signal_opts", multiple=True, metavar="NAME[,NAME...]",
              help="Compare only these variables (repeatable or comma-separated).")
@click.option("--top", type=click.IntRange(min=1), default=15, show_default=True, help="Rows shown.")
@click.option("--plot", "plot_file", type=click.Path(dir_okay=False),
              help="Write an overlay plot (PNG) of the signals (default: the 4 that differ most).")
@click.option("--fail-above", type=click.FloatRange(min=0.0), metavar="REL",
              help="Exit with code 1 if the largest relative difference exceeds REL.")
@_friendly
def compare_cmd(file_a: str, file_b: str, signal_opts: tuple[str, ...], top: int, plot_file: str | None,
                fail_above: float | None) -> None:
    """Overlay two result files and print their largest differences."""
    from flexlib.results.hdf5 import load_result
    from flexlib.solve.run_options import check_result_path

    signals = [s.strip() for opt in signal_opts for s in opt.split(",") if s.strip()]
    if plot_file is not None:
        check_result_path(plot_file, "--plot")
    a, b = load_result(file_a), load_result(file_b)
    rows = compare_results(a, b, signals or None)
    console = _console()
    only_a = len(set(a.names) - set(b.names))
    only_b = len(set(b.names) - set(a.names))
    console.print(f"A = {file_a} ({a.model}, {a.status}), B = {file_b} ({b.model}, {b.status}): "
                  f"{len(rows)} signals compared, {only_a} only in A, {only_b} only in B")
    table = Table(title="largest differences (SI units)")
    for col, justify in (("signal", "left"), ("unit", "left"), ("max |A−B|", "right"), ("relative", "right"),
                         ("at t [s]", "right"), ("A", "right"), ("B", "right")):
        table.add_column(col, justify=justify)
    for r in rows[:top]:
        table.add_row(r["name"], r["unit"], _fmt(r["abs"]), f"{r['rel']:.3g}", _fmt(r["t"]), _fmt(r["a"]),
                      _fmt(r["b"]))
    console.print(table)
    if plot_file is not None:
        _plot_overlay(a, b, signals or [r["name"] for r in rows[:4]], plot_file, file_a, file_b)
        console.print(f"plot written to {plot_file}")
    worst = rows[0]["rel"] if rows else 0.0
    if fail_above is not None and worst > fail_above:
        raise click.ClickException(f"the largest relative difference {worst:.3g} ({rows[0]['name']} at "
                                   f"t = {rows[0]['t']:g} s) exceeds --fail-above {fail_above:g}")


def _plot_overlay(a: Any, b: Any, names: list[str], path: str, label_a: str, label_b: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = names or []
    fig, axes = plt.subplots(max(len(names), 1), 1, figsize=(8, 2.6 * max(len(names), 1)), sharex=True,
                             squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        ya, unit = a.display(name)
        yb, _ = b.display(name)
        ax.plot(a.t, ya, label=f"A: {Path(label_a).name}")
        ax.plot(b.t, yb, "--", label=f"B: {Path(label_b).name}")
        ax.set_ylabel(f"{name}\n[{unit}]", fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    axes[-1, 0].set_xlabel("time [s]")
    fig.tight_layout()
    try:
        fig.savefig(path, dpi=100)
    finally:
        plt.close(fig)


# -- show ----------------------------------------------------------------------------------------------------------
@cli.command("show")
@click.argument("file", type=click.Path(dir_okay=False))
@_friendly
def show_cmd(file: str) -> None:
    """Show the run settings and solver statistics stored in a result file."""
    from flexlib.results.hdf5 import load_result

    res = load_result(file)
    table = Table(title=file, show_header=False)
    table.add_column("key", style="bold")
    table.add_column("value")
    table.add_row("model class", res.model)
    table.add_row("status", res.status + (f" ({_one_line(Exception(res.message))})" if res.message else ""))
    table.add_row("time", f"{res.t[0]:g} … {res.t[-1]:g} s, {len(res.t)} points" if len(res.t) else "no rows")
    table.add_row("variables / parameters", f"{len(res.names)} / {len(res.parameters)}")
    for key in ("steps", "rtol", "atol", "n_unknowns", "n_states"):
        if key in res.stats:
            table.add_row(key, str(res.stats[key]))
    for key in ("created", "flexlib", "casadi", "scikit-sundae"):
        if key in res.metadata:
            table.add_row(key, res.metadata[key])
    raw = res.metadata.get("run")
    if raw is None:
        table.add_row("run settings", "none recorded (not written by 'flexlib run')")
    else:
        from flexlib.registry import run_settings

        rec = run_settings(res, file)
        scen = rec.scenario
        table.add_row("registered model", rec.model)
        table.add_row("scenario", f"{scen.get('name')}: {scen.get('doc', '')}")
        for key in ("t_end", "params", "run", "options", "data"):
            value = scen.get(key)
            if value not in (None, {}):
                table.add_row(f"scenario {key}", json.dumps(value))
        if rec.params:
            table.add_row("parameter overrides", json.dumps(rec.params))
        if rec.run:
            table.add_row("run options given", json.dumps(rec.run))
        table.add_row("repeat with", f"flexlib run --from {file}")
    _console().print(table)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``flexlib`` script and ``python -m flexlib``."""
    cli.main(args=argv, prog_name="flexlib")
