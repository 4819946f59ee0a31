"""The commands that read result files: ``flexlib compare`` (two results, signal by signal) and ``flexlib show``
(what one result holds). :mod:`flexlib.cli` adds them to its command group."""

from __future__ import annotations

import json
import math
import os
import warnings
from pathlib import Path
from typing import Any

import click
import numpy as np
from rich.table import Table

from flexlib.cli_support import fmt, friendly, new_console, once_option, one_line, say
from flexlib.errors import IndeterminateReactionWarning, ResultKeyError
from flexlib.results.compare import compare

__all__ = ["compare_cmd", "show_cmd"]


# -- compare -------------------------------------------------------------------------------------------------------
@click.command("compare")
@click.argument("file_a", type=click.Path(dir_okay=False))
@click.argument("file_b", type=click.Path(dir_okay=False))
@click.option("--signals", "signal_opts", multiple=True, metavar="NAME[,NAME...]",
              help="Compare only these variables: names, array names or patterns with * and ? (repeatable or "
                   "comma-separated).")
@click.option("--top", type=click.IntRange(min=1), default=15, show_default=True, help="Rows shown.")
@once_option("--plot", "plot_file", type=click.Path(dir_okay=False),
              help="Write an overlay plot of the signals, format by the extension (.png, .pdf, .svg, ...; default "
                   "signals: the 4 farthest out of their tube).")
@once_option("--fail-above", type=click.FloatRange(min=0.0), metavar="X",
              help="Exit with code 1 if a signal leaves its tolerance tube around A by more than X times its "
                   "tolerance (1: any signal outside the tube), or if the comparison does not cover both runs (NaN "
                   "or inf in one, different time spans, variables in one file only, different units or models, 0 "
                   "signals compared).")
@once_option("--rtol", type=click.FloatRange(min=0.0, min_open=True), default=None, metavar="R",
             help="Tube width relative to each signal's range in A (default 1e-3); the absolute floor is 1e-6 of "
                  "the largest magnitude of the signal's unit.")
@click.option("--json", "as_json", is_flag=True, help="Print the comparison as JSON (for CI) instead of tables.")
@friendly
def compare_cmd(file_a: str, file_b: str, signal_opts: tuple[str, ...], top: int, plot_file: str | None,
                fail_above: float | None, rtol: float | None, as_json: bool) -> None:
    """Compare two result files in a tolerance tube around A: the signals that leave it most, ranked by deviation
    over tolerance (signals within their noise floor in both are not ranked), and what the comparison does not
    cover."""
    from flexlib.results.compare import RTOL
    from flexlib.results.hdf5 import load_result

    signals = [s.strip() for opt in signal_opts for s in opt.split(",") if s.strip()]
    if signal_opts and not signals:
        raise click.ClickException(f"--signals {signal_opts[0]!r}: no variable name given")
    if fail_above is not None and math.isnan(fail_above):
        raise click.ClickException("--fail-above nan: the threshold must be a number >= 0 (a multiple of each "
                                   "signal's tolerance, such as 1); no deviation is ever above NaN")
    if plot_file is not None:
        plot_path = _check_plot_file(plot_file)  # before the comparison
    a, b = load_result(file_a), load_result(file_b)
    try:
        cmp = compare(a, b, signals or None, labels=(f"A ({file_a})", f"B ({file_b})"),
                      rtol=RTOL if rtol is None else rtol)
    except ResultKeyError as err:  # only --signals names variables
        raise click.ClickException(f"--signals: {one_line(err)}") from None
    notes = list(cmp.notes)
    if _same_file(file_a, file_b):
        notes.insert(0, f"A and B are the same file ({file_a}): no difference is possible")
    ranked = cmp.ranked
    failure = _failure(cmp, fail_above)
    if as_json:
        click.echo(json.dumps({"a": file_a, "b": file_b, "model_a": a.model, "model_b": b.model,
                               "span": list(cmp.span), "compared": len(cmp.rows), "ranked": len(ranked),
                               "only_a": len(cmp.only_a), "only_b": len(cmp.only_b),
                               "rows": [_json_row(r) for r in ranked[:top]], "problems": cmp.problems, "notes": notes,
                               "fail_above": fail_above, "failed": failure}, indent=1, allow_nan=False))
        if failure:
            raise SystemExit(1)
        return
    console = new_console()
    console.print(f"A = {file_a} ({a.model}, {a.status}), B = {file_b} ({b.model}, {b.status}): "
                  f"{len(cmp.rows)} signals compared over {cmp.span[0]:g} … {cmp.span[1]:g} s ({len(ranked)} ranked, "
                  f"{len(cmp.rows) - len(ranked)} within their noise floor), {len(cmp.only_a)} only in A, "
                  f"{len(cmp.only_b)} only in B")
    if ranked:
        table = Table(title="signals farthest out of their tube around A (SI units)")
        for col, justify in (("signal", "left"), ("unit", "left"), ("× tol", "right"), ("max |A−B|", "right"),
                             ("tol", "right"), ("at t [s]", "right"), ("A", "right"), ("B", "right")):
            table.add_column(col, justify=justify)
        for r in ranked[:top]:
            name = r["name"] + (f" (+{len(r['same'])} same)" if r["same"] else "")  # aliases: one row
            table.add_row(name, r["unit"], f"{r['ratio']:.3g}", fmt(r["abs"]), f"{r['tol']:.3g}", fmt(r["t"]),
                          fmt(r["a"]), fmt(r["b"]))
        console.print(table)
    if plot_file is not None:
        names = [r["name"] for r in cmp.rows][:12] if signals else [r["name"] for r in ranked][:4]
        if names:
            _plot_overlay(a, b, names, plot_path, file_a, file_b)
            more = (f" (the {len(names)} farthest out of their tube of {len(cmp.rows)})"
                    if len(cmp.rows) > len(names) else "")
            console.print(f"plot written to {plot_file}{more}")
        else:
            notes.append(f"no plot written to {plot_file}: no signal compared")
    for note in notes:
        say("Note", note)
    if fail_above is None:
        for problem in cmp.problems:
            say("Warning", problem)
        return
    if failure:
        raise click.ClickException(failure)


def _failure(cmp: Any, fail_above: float | None) -> str:
    """Why ``--fail-above`` fails the comparison ("" if it passes or is not given)."""
    if fail_above is None:
        return ""
    if cmp.problems:
        return f"--fail-above {fail_above:g}: the comparison does not cover both runs: " + "; ".join(cmp.problems)
    worst = cmp.worst
    if worst is not None and worst["ratio"] > fail_above:
        return (f"{worst['name']} leaves its tube by {worst['ratio']:.3g} × its tolerance {worst['tol']:.3g} "
                f"{worst['unit']} (max |A−B| = {worst['abs']:.4g} at t = {worst['t']:g} s), which exceeds "
                f"--fail-above {fail_above:g}")
    return ""


def _json_row(r: dict[str, Any]) -> dict[str, Any]:
    """A row of the comparison for ``--json`` (an infinite deviation as the string "inf")."""
    keys = ("name", "unit", "ratio", "tol", "abs", "rel", "t", "a", "b", "mismatch", "same")
    return {k: (str(r[k]) if isinstance(r[k], float) and not math.isfinite(r[k]) else r[k]) for k in keys}


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _check_plot_file(plot_file: str) -> str:
    """``--plot``: an extension matplotlib writes and a place that can be written; returns the path to write
    (``~`` expanded, as the check did)."""
    from matplotlib.backend_bases import FigureCanvasBase

    from flexlib.solve.run_options import check_result_path

    formats = sorted(FigureCanvasBase.get_supported_filetypes())
    suffix = Path(plot_file).suffix.lower().lstrip(".")
    if suffix not in formats:
        what = "has no extension" if not suffix else f"has the extension .{suffix}, not an image format"
        raise click.ClickException(f"--plot {plot_file} {what}; the extension gives the format, one of "
                                   f"{', '.join('.' + f for f in formats)} (for example diff.png)")
    return str(check_result_path(plot_file, "--plot"))


def _plot_overlay(a: Any, b: Any, names: list[str], path: str, label_a: str, label_b: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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
        Path(path).parent.mkdir(parents=True, exist_ok=True)  # a directory the check found creatable
        fig.savefig(path, dpi=100)
    except OSError as err:  # the place was checked; it can still fail (disk full, removed meanwhile)
        raise click.ClickException(f"--plot {path}: cannot write the plot: {err.strerror or err}") from None
    finally:
        plt.close(fig)


# -- show ----------------------------------------------------------------------------------------------------------
@click.command("show")
@click.argument("file", type=click.Path(dir_okay=False))
@click.option("--signals", "patterns", multiple=True, metavar="PATTERN[,PATTERN...]",
              help="Also list these variables (names, array names or patterns with * and ?) with unit, min, max "
                   "and final value; '*' lists all.")
@friendly
def show_cmd(file: str, patterns: tuple[str, ...]) -> None:
    """Show the run settings and solver statistics stored in a result file."""
    from flexlib.errors import ResultFileError
    from flexlib.results.compare import select
    from flexlib.results.hdf5 import load_result

    res = load_result(file)
    wanted = [p.strip() for opt in patterns for p in opt.split(",") if p.strip()]
    if patterns and not wanted:
        raise click.ClickException(f"--signals {patterns[0]!r}: no variable name or pattern given")
    try:
        listed = select(res, wanted, file) if wanted else []
    except ResultKeyError as err:
        raise click.ClickException(f"--signals: {one_line(err)}") from None
    warnings_: list[str] = []
    table = Table(title=file, show_header=False)
    table.add_column("key", style="bold")
    table.add_column("value")
    table.add_row("model class", res.model)
    table.add_row("status", res.status + (f" ({one_line(Exception(res.message))})" if res.message else ""))
    table.add_row("time", f"{res.t[0]:g} … {res.t[-1]:g} s, {len(res.t)} points" if len(res.t) else "no rows")
    table.add_row("variables / parameters", f"{len(res.names)} / {len(res.parameters)}")
    bad = _nonfinite(res)
    if bad:
        table.add_row("NaN or inf", bad)
        warnings_.append(f"{file}: {bad}")
    if not res.success:
        warnings_.append(f"{file}: the run did not succeed ({res.status}), "
                         + (f"its last row is at t = {res.t[-1]:g} s" if len(res.t) else "it has no rows")
                         + (f": {one_line(Exception(res.message))}" if res.message else ""))
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
        from flexlib.run_record import run_settings

        try:
            rec = run_settings(res, file)
        except ResultFileError as err:
            table.add_row("run settings", "damaged (see the warning below); 'flexlib run --from' cannot repeat it")
            warnings_.append(one_line(err))
        else:
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
    new_console().print(table)
    if listed:
        new_console().print(_signal_table(res, listed))
    for text in warnings_:
        say("Warning", text)


def _signal_table(res: Any, names: list[str]) -> Table:
    """Unit, min, max and final value of ``names`` (SI; NaN and inf ignored in min and max, counted); a statically
    indeterminate variable (``res.indeterminate``) is marked ``(indeterminate)`` instead of warned about."""
    table = Table(title=f"{len(names)} variable{'' if len(names) == 1 else 's'} (SI units)")
    for col, justify in (("variable", "left"), ("unit", "left"), ("min", "right"), ("max", "right"),
                         ("final", "right"), ("NaN/inf", "right"), ("description", "left")):
        table.add_column(col, justify=justify)
    index = {n: k for k, n in enumerate(res.names)}
    for name in names:
        k = index[name]
        with warnings.catch_warnings():  # statically indeterminate: marked in the table instead
            warnings.simplefilter("ignore", IndeterminateReactionWarning)
            x = res[name]
        finite = x[np.isfinite(x)]
        lo, hi = (fmt(finite.min()), fmt(finite.max())) if finite.size else ("-", "-")
        final = fmt(x[-1]) if len(x) else "-"
        shown = f"{name} (indeterminate)" if name in res.indeterminate else name
        table.add_row(shown, res.units[k], lo, hi, final, str(len(x) - finite.size), res.docs[k])
    return table


def _nonfinite(res: Any) -> str:
    """Which variables of a result hold NaN or inf, from when ("" if none). A result file that derives its variables
    when read is checked on what it stores (the unknowns, stored outputs: a derived variable is NaN when they are)."""
    stored = getattr(res.source, "nonfinite", None)
    if stored is not None:
        names, first = stored(res.names)
        if not names:
            return ""
    else:
        if not res.values.size:
            return ""
        finite = np.isfinite(res.values)
        cols = np.flatnonzero(~finite.all(axis=0))
        if not cols.size:
            return ""
        first = int(np.argmax(~finite.all(axis=1)))
        names = [res.names[k] for k in cols]
    shown = ", ".join(names[:5]) + (f", ... ({len(names) - 5} more)" if len(names) > 5 else "")
    return f"{len(names)} variables are NaN or inf, from t = {res.t[first]:g} s: {shown}"
