"""The ``flexlib`` command line (click + rich): list, run, compare and show registered models and results.

::

    flexlib list                                   # models and scenarios with their docs
    flexlib run n-mass-chain --scenario short --out chain.h5 --param mass0.m=2
    flexlib run --from chain.h5 --rtol 1e-8        # repeat a run from its file (options on top)
    flexlib show chain.h5 --signals 'mass*.s'      # run settings stored in a result file, some variables
    flexlib compare a.h5 b.h5 --plot diff.png      # signals out of their tube around A, and what is not covered

Models and scenarios come from :mod:`flexlib.registry`; ``--models MODULE`` (or ``$FLEXLIB_MODELS``) imports a
user's module that registers more. Every error is one line naming the culprit (model, scenario, parameter,
option, file), with exit code 1 (2 for a malformed option, as click reports it); no traceback.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import tempfile
import warnings
from pathlib import Path
from typing import Any

import click
import numpy as np
from rich import box
from rich.table import Table
from rich.text import Text

from flexlib.cli_results import compare_cmd, show_cmd
from flexlib.cli_study import study_group, sweep_cmd
from flexlib.cli_support import fmt, friendly, new_console, once_option, one_line, say
from flexlib.errors import FlexlibError, IndeterminateReactionWarning, RegistryError, ResultKeyError, SolverError
from flexlib.results.compare import compare_results
from flexlib.solve.solvers import SOLVERS

__all__ = ["cli", "compare_results", "main"]

#: File name endings of a result file ``--out`` writes without ``--force`` (the file is HDF5).
RESULT_SUFFIXES = (".h5", ".hdf5", ".hdf", ".he5")


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--models", "modules", multiple=True, metavar="MODULE",
              help="Import this Python module first (it registers more models); repeatable.")
@click.version_option(package_name="flexlib")
def cli(modules: tuple[str, ...]) -> None:
    """flexlib: acausal multibody, flexible-body and hydraulic models, from the command line."""
    from flexlib.model_modules import import_user_module, module_hint

    for module in modules:
        try:
            import_user_module(module)
        except Exception as err:  # any failure of the user's module: one line naming it

            raise click.ClickException(f"--models {module}: cannot import the module: {one_line(err)}"
                                       f"{module_hint(module)}") from None


# -- list ----------------------------------------------------------------------------------------------------------
@cli.command("list")
@friendly
def list_cmd() -> None:
    """Show the registered models, their scenarios and their options (``run -O NAME=VALUE``)."""
    from flexlib import registry

    entries = registry.models()
    table = Table(title="flexlib models and scenarios", show_lines=False)
    table.add_column("model", style="bold")
    table.add_column("scenario")
    table.add_column("t_end [s]", justify="right")
    table.add_column("description")
    for name, entry in entries.items():
        table.add_row(name, "", "", entry.doc)
        for sname, scen in entry.scenarios.items():
            default = " (default)" if sname == entry.default_scenario else ""
            t_end = fmt(scen.t_end) if scen.t_end is not None else "model"
            table.add_row("", sname + default, t_end, scen.doc)
    console = new_console()
    console.print(table)
    console.print(_options_table(entries))


def _options_table(entries: dict[str, Any]) -> Table:
    """The model options of every model: a row per model (with the ``data`` keys its scenarios may hold), then one
    per option (name, type, default, the accepted values and the doc), a rule after each model."""
    table = Table(title="model options (flexlib run MODEL -O NAME=VALUE)", show_lines=False)
    table.add_column("option")
    table.add_column("type")
    table.add_column("default")
    table.add_column("accepted values: description")
    for name, entry in entries.items():
        notes = [] if entry.options else ["no options"]
        if entry.data:
            notes.append("scenario data: " + ", ".join(entry.data))
        table.add_row(name, "", "", "; ".join(notes), style="bold", end_section=not entry.options)
        for k, o in enumerate(entry.options, 1):
            type_name = "any" if o.type is None else o.type.__name__
            table.add_row(f"  {o.name}", type_name, _option_value(o.default),
                          o.accepted() + (f": {o.doc}" if o.doc else ""), end_section=k == len(entry.options))
    return table


def _option_value(value: Any) -> str:
    """An option's value as the command line writes it (``true``, ``none``, ``4``, ``0.006``, ``mpf``)."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, (int, str)):
        return str(value)
    return json.dumps(value, default=str)


# -- run -----------------------------------------------------------------------------------------------------------
#: ``a=1,b=2``: several NAME=VALUE in one --param / --option (each takes one).
_SEVERAL = re.compile(r",\s*[A-Za-z_][\w.\[\]]*\s*=")


def _name_value(item: str, option: str, example: str, repeat: str) -> tuple[str, str]:
    """``NAME=VALUE`` of one ``--param``/``--option`` as ``(name, value text)``; one pair per option."""
    name, sep, value = item.partition("=")
    name, value = name.strip(), value.strip()
    if not sep or not name:
        raise click.ClickException(f"{option} {item!r}: expected NAME=VALUE (for example {example})")
    if _SEVERAL.search(value):
        raise click.ClickException(f"{option} {item!r}: one NAME=VALUE per {option} (repeat it: {repeat} "
                                   f"{name}=... {repeat} ...)")
    return name, value


def _parse_params(items: tuple[str, ...]) -> dict[str, float]:
    """``NAME=VALUE`` parameter overrides by name, each a finite number."""
    out: dict[str, float] = {}
    for item in items:
        name, value = _name_value(item, "--param", "mass0.m=2.0", "--param")
        try:
            number = float(value)
        except ValueError:
            raise click.ClickException(f"--param {item!r}: the value {value!r} of {name} is not a number") from None
        if not math.isfinite(number):
            raise click.ClickException(f"--param {item!r}: the value of {name} must be finite")
        if name in out and out[name] != number:
            raise click.ClickException(f"--param {name} is given twice ({out[name]:g} and {number:g}); give it once")
        out[name] = number
    return out


def _parse_options(items: tuple[str, ...]) -> dict[str, str]:
    """``NAME=VALUE`` texts by name; the registry converts each by the model's declaration of the option."""
    out: dict[str, str] = {}
    for item in items:
        name, value = _name_value(item, "--option", "n=4 or flexible=true", "-O")
        if name in out and out[name] != value:
            raise click.ClickException(f"--option {name} is given twice ({out[name]!r} and {value!r}); give it once")
        out[name] = value
    return out


@cli.command("run")
@click.argument("model", required=False)
@once_option("-s", "--scenario", help="Scenario name, or a JSON file with a scenario (default: the model's).")
@once_option("-o", "--out", type=click.Path(dir_okay=False), help="Write the result (HDF5) to this file.")
@click.option("-p", "--param", "params", multiple=True, metavar="NAME=VALUE",
              help="Parameter override in SI units (repeatable).")
@once_option("--t-end", type=click.FloatRange(min=0.0, min_open=True), help="End time [s].")
@once_option("--rtol", type=click.FloatRange(0.0, 1.0, min_open=True, max_open=True), help="Relative tolerance.")
@once_option("--atol", type=click.FloatRange(min=0.0, min_open=True), help="Absolute tolerance.")
@once_option("--dt-out", type=click.FloatRange(min=0.0, min_open=True), help="Output interval [s].")
@once_option("--solver", type=click.Choice(SOLVERS), help="Solver backend.")
@once_option("--step", type=click.FloatRange(min=0.0, min_open=True),
             help="Step of --solver fixed-step [s] (default 0.001).")
@click.option("--realtime", is_flag=True, help="With --solver fixed-step: keep in step with the wall clock, report "
                                               "overruns.")
@once_option("--max-halvings", type=click.IntRange(0, 8),
             help="With --solver fixed-step: times a step that does not converge may be halved (default 2; 0: the "
                  "bounded cost a hard real-time loop needs).")
@once_option("--from", "from_file", type=click.Path(dir_okay=False),
              help="Repeat the run recorded in this result file (other options apply on top).")
@click.option("-O", "--option", "model_options", multiple=True, metavar="NAME=VALUE",
              help="Model option on top of the scenario's, VALUE converted by the option's declared type "
                   "(bool: true/false/yes/no/1/0; repeatable).")
@once_option("--flexible/--rigid", help="Shorthand for --option flexible=true / false.")
@click.option("--no-progress", is_flag=True, help="No progress bar.")
@once_option("--plots", "plots_dir", type=click.Path(file_okay=False),
              help="Write the model's figures (PNG) of the run into this directory.")
@click.option("--force", is_flag=True,
              help="Let --out replace a file that is not a flexlib result, or write a name without .h5.")
@click.option("--outputs", "outputs", multiple=True, metavar="PATTERN[,PATTERN...]",
              help="Also store these variables as columns in --out (names, array names, patterns with * and ?; "
                   "'all': every variable). Without it the file stores the run's rows and derives every variable "
                   "when read.")
@friendly
def run_cmd(model: str | None, scenario: str | None, out: str | None, params: tuple[str, ...], t_end: float | None,
            rtol: float | None, atol: float | None, dt_out: float | None, solver: str | None, step: float | None,
            realtime: bool, max_halvings: int | None, from_file: str | None, model_options: tuple[str, ...],
            flexible: bool | None,
            no_progress: bool, plots_dir: str | None, force: bool, outputs: tuple[str, ...]) -> None:
    """Run MODEL in a scenario, then print a summary (times, steps, peaks of the model's signals)."""
    from flexlib import registry
    from flexlib.scenario import Scenario

    overrides = _parse_params(params)
    given: dict[str, Any] = {k: v for k, v in (("rtol", rtol), ("atol", atol), ("dt_out", dt_out),
                                               ("solver", solver)) if v is not None}
    fixed = {k: v for k, v in (("h", step), ("realtime", realtime or None), ("max_halvings", max_halvings))
             if v is not None}
    if fixed:
        if solver != "fixed-step":
            flag = {"h": "--step", "realtime": "--realtime", "max_halvings": "--max-halvings"}[next(iter(fixed))]
            raise click.ClickException(f"{flag} is an option of --solver fixed-step; give that too")
        given["solver"] = {"kind": "fixed-step", **fixed}
    stored = [p.strip() for opt in outputs for p in opt.split(",") if p.strip()]
    if outputs and not stored:
        raise click.ClickException(f"--outputs {outputs[0]!r}: no variable name or pattern given")
    if stored:
        given["outputs"] = "all" if stored == ["all"] else stored
    scen: str | Scenario | None = scenario
    if scenario is not None and (scenario.endswith(".json") or os.path.isfile(scenario)):
        scen = Scenario.from_file(scenario)
    if from_file is not None:
        if scenario is not None:
            raise click.ClickException("--from and --scenario: give one (the file records its scenario)")
        record, scen = _recorded_run(from_file)
        if model is not None and model != record.model:
            raise click.ClickException(f"model {model!r} differs from the model {record.model!r} recorded in "
                                       f"{from_file}; omit MODEL with --from")
        model = record.model
        overrides = {**record.params, **overrides}
        t_end = t_end if t_end is not None else record.run.get("t_end")
        given = {**{k: v for k, v in record.run.items() if k != "t_end"}, **given}
    if model is None:
        raise click.ClickException("give a MODEL (see 'flexlib list') or --from FILE")
    entry = registry.get_model(model)
    if isinstance(scen, str) and scen not in entry.scenarios and ("/" in scen or os.sep in scen
                                                                  or Path(scen).suffix):
        raise click.ClickException(f"--scenario {scen}: no such file, and model {model!r} has no scenario of that "
                                   f"name (its scenarios: {', '.join(sorted(entry.scenarios))}; a scenario file "
                                   "is JSON, see docs/cli.md)")
    extra_options = entry.parse_options(_parse_options(model_options))  # by declared type
    if flexible is not None:
        entry.option("flexible", f"--{'flexible' if flexible else 'rigid'}: model {model!r}: ")
        if extra_options.get("flexible", flexible) != flexible:
            raise click.ClickException(f"--{'flexible' if flexible else 'rigid'} and --option "
                                       f"flexible={extra_options['flexible']} contradict each other; give one")
        extra_options["flexible"] = flexible
    if extra_options:  # recorded as part of the scenario, so that --from repeats them
        base = scen if isinstance(scen, Scenario) else registry.get_scenario(model, scen)
        scen = dataclasses.replace(base, options={**base.options, **extra_options})
    if out is not None:
        _check_out(out, force)  # before the build
    if plots_dir is not None:
        _check_plots_dir(entry, plots_dir)
    try:  # the CLI writes the file itself, so that a failed write still leaves the result somewhere
        done = registry.run_scenario(model, scen, params=overrides, t_end=t_end, progress=not no_progress, **given)
    except SolverError as err:
        where = ""
        if out and err.result is not None:
            written, problem = _save(err.result, out, given.get("outputs"))
            where = f"; {problem}" if problem else f"; the result up to the failure is in {written}"
        raise click.ClickException(f"{model}: the run failed: {one_line(err)}{where}") from None
    except (FlexlibError, ValueError, LookupError) as err:
        if from_file is None:
            raise
        raise click.ClickException(f"{one_line(err)} (repeating the run recorded in {from_file})") from None
    written, problem = _save(done.result, out, given.get("outputs")) if out else (None, None)
    _print_summary(done, written)
    if plots_dir is not None:
        _write_plots(done, plots_dir)
    if problem:
        raise click.ClickException(problem)


@cli.command("export-fmu")
@click.argument("model")
@once_option("-s", "--scenario", help="Scenario whose model options, parameters and start time the unit takes "
                                      "(default: the model's).")
@once_option("-o", "--out", required=True, type=click.Path(dir_okay=False), help="The unit to write (.fmu).")
@once_option("--step", type=click.FloatRange(min=0.0, min_open=True), help="The unit's fixed step [s] (default "
                                                                          "0.001).")
@once_option("--max-halvings", type=click.IntRange(0, 8),
             help="Times the unit may halve a step that does not converge (default 2; 0: a bounded cost per step).")
@click.option("-p", "--param", "params", multiple=True, metavar="NAME=VALUE",
              help="Parameter value of the unit's start in SI units (repeatable).")
@click.option("--output", "outputs", multiple=True, metavar="NAME",
              help="A variable the unit outputs (repeatable; default: the model's summary signals, else its "
                   "top-level outputs or states).")
@once_option("--flexible/--rigid", help="Shorthand for the model option flexible=true / false.")
@friendly
def export_fmu_cmd(model: str, scenario: str | None, out: str, step: float | None, max_halvings: int | None,
                   params: tuple[str, ...], outputs: tuple[str, ...], flexible: bool | None) -> None:
    """Export MODEL (in a scenario) as an FMI 2.0 co-simulation unit for Linux x86-64 (docs/fmi.md)."""
    step = 1e-3 if step is None else step
    from flexlib import registry
    from flexlib.fmi import export_fmu
    from flexlib.solve.simulation import Simulation

    overrides = _parse_params(params)
    entry = registry.get_model(model)
    scen = registry.get_scenario(model, scenario)
    if flexible is not None:
        entry.option("flexible", f"--{'flexible' if flexible else 'rigid'}: model {model!r}: ")
        scen = dataclasses.replace(scen, options={**scen.options, "flexible": flexible})
    instance, scen = registry.scenario_model(model, scen)
    sim = Simulation(instance)
    names = {v.name for v in sim.compiled.variables}
    chosen = list(outputs) or [n for n in entry.signals(instance) if n in names] or None
    path = export_fmu(sim, out, h=step, params={**dict(scen.params), **overrides}, outputs=chosen,
                      t_start=scen.run.get("t_start"), name=model.replace("-", "_"),
                      **({"max_halvings": max_halvings} if max_halvings is not None else {}))
    say("Wrote", f"{path} ({path.stat().st_size / 1e6:.1f} MB): {len(chosen or [])} outputs, step {step:g} s")


def _recorded_run(from_file: str) -> tuple[Any, Any]:
    """The run record of ``--from FILE`` and its scenario, checked: every problem of the record names the file."""
    from flexlib import registry
    from flexlib.results.hdf5 import load_result
    from flexlib.scenario import RUN_OPTIONS, Scenario

    record = registry.run_settings(load_result(from_file), from_file)
    try:
        entry = registry.get_model(record.model)
    except RegistryError as err:
        raise click.ClickException(f"{from_file}: the model recorded in the file: {one_line(err)}") from None
    try:
        scen = Scenario.from_dict(record.scenario)
        entry.check_options(scen)
    except (FlexlibError, TypeError, ValueError) as err:
        raise click.ClickException(f"{from_file}: the scenario recorded in the file: {one_line(err)}") from None
    for name, value in record.params.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise click.ClickException(f"{from_file}: the parameter override {name!r} recorded in the file is "
                                       f"{value!r}, not a finite number")
    unknown = [k for k in record.run if k not in (*RUN_OPTIONS, "t_end")]
    if unknown:
        raise click.ClickException(f"{from_file}: the run option {unknown[0]!r} recorded in the file is unknown "
                                   f"(allowed: t_end, {', '.join(RUN_OPTIONS)})")
    return record, scen


def _check_out(out: str, force: bool) -> None:
    """``--out``: a file name that can be written, ending in .h5 (or --force), not an existing file of another kind
    (or --force); checked before the build."""
    from flexlib.results.hdf5 import not_a_result
    from flexlib.solve.run_options import check_result_path

    if out.endswith(("/", os.sep)) or (os.altsep and out.endswith(os.altsep)):
        raise click.ClickException(f"--out {out!r} names a directory; give a file name such as "
                                   f"{os.path.join(out, 'run.h5')}")
    path = check_result_path(out, "--out")
    if force:
        return
    what = not_a_result(path)
    if what is not None:
        raise click.ClickException(f"--out {out}: the file exists and is {what}, not a flexlib result file; it is "
                                   "not replaced (give another name, or --force to replace it)")
    if path.suffix.lower() not in RESULT_SUFFIXES:
        hint = path.with_suffix(".h5") if path.suffix else path.with_name(path.name + ".h5")
        raise click.ClickException(f"--out {out}: a result file is HDF5; give a name ending in "
                                   f"{' or '.join(RESULT_SUFFIXES[:2])} (for example {hint}), or --force to write "
                                   "it under this name")


def _check_plots_dir(entry: Any, directory: str) -> None:
    """``--plots DIR``: the model has figures and DIR can be created; checked before the build."""
    if entry.plots is None:
        raise click.ClickException(f"model {entry.name!r} has no figures (--plots needs a plots hook)")
    path = Path(directory).expanduser()
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise click.ClickException(f"--plots {directory}: cannot create the directory: "
                                   f"{err.strerror or err}") from None
    if not os.access(path, os.W_OK):
        raise click.ClickException(f"--plots {directory}: the directory is not writable")


def _save(result: Any, out: str, outputs: Any = None) -> tuple[str | None, str | None]:
    """Write ``result`` to ``out``; if that fails (directory removed during the run, disk full), to a new file in
    the working directory or else the temporary directory, so that a finished run is never lost.

    Returns
    -------
    (str or None, str or None)
        The file written (None if none could be) and, if it is not ``out``, what went wrong.
    """
    import warnings

    from flexlib.results.hdf5 import keep_outputs

    with warnings.catch_warnings(record=True) as caught:  # a pattern that matches nothing: a Warning line
        warnings.simplefilter("always")
        outputs = keep_outputs(result, outputs, out)
    for w in caught:
        say("Warning", str(w.message))
    try:
        result.save(out, outputs=outputs)
        return out, None
    except Exception as err:  # any failure to write: keep the result elsewhere
        reason = one_line(err)
    stem = Path(out).stem or "result"
    tried = []
    for directory in (Path.cwd(), Path(tempfile.gettempdir())):
        tried.append(str(directory))
        try:
            fd, name = tempfile.mkstemp(dir=directory, prefix=f"{stem}.unsaved-", suffix=".h5")
        except OSError:
            continue
        os.close(fd)
        try:
            result.save(name, outputs=outputs)
        except Exception:
            Path(name).unlink(missing_ok=True)
            continue
        return name, f"{reason}; the result was written to {name} instead"
    return None, f"{reason}; nor could it be written to a new file in {' or '.join(tried)}: the result is lost"


def _write_plots(done: Any, directory: str) -> None:
    """The model's figures of the run, through its registered ``plots`` hook."""
    if done.entry.plots is None:
        raise click.ClickException(f"model {done.entry.name!r} has no figures (--plots needs a plots hook)")
    import matplotlib

    matplotlib.use("Agg")
    path = Path(directory).expanduser()
    path.mkdir(parents=True, exist_ok=True)
    try:
        written = list(done.entry.plots(done.model, done.result, path))
    except Exception as err:  # a model's own figure code: one line naming the model, not its traceback
        raise click.ClickException(f"model {done.entry.name!r}: its figures (plots hook) failed: "
                                   f"{type(err).__name__}: {one_line(err)}") from None
    new_console().print(f"figures: {len(written)} in {path}" + "".join(f"\n  {p}" for p in written))


def _print_summary(done: Any, out: str | None) -> None:
    res = done.result
    t_sim = float(res.t[-1] - res.t[0]) if len(res.t) else 0.0
    console = new_console()
    table = Table(title=f"{done.entry.name} / {done.scenario.name}: {res.status}", show_header=False)
    table.add_column("quantity", style="bold")
    table.add_column("value", justify="right")
    rows = [("simulated time [s]", fmt(t_sim)),
            ("CPU time, build [s]", f"{done.cpu_build:.3f}" + (" (cached)" if res.stats.get("build_cached") else "")),
            ("CPU time, run [s]", f"{done.cpu_run:.3f}"),
            ("real-time factor", f"{t_sim / done.cpu_run:.3g}" if done.cpu_run > 0 else "-"),
            ("steps", str(res.stats.get("steps", "-"))),
            ("residual evaluations", str(res.stats.get("nfev", "-"))),
            ("events", str(len(res.events))),
            ("unknowns / states", f"{res.stats.get('n_unknowns', '-')} / {res.stats.get('n_states', '-')}")]
    if res.stats.get("solver") == "fixed-step":
        rows += [("step h [s]", fmt(res.stats.get("h", float("nan")))),
                 ("step cost, mean / worst [ms]", f"{1e3 * res.stats.get('mean_step_wall', float('nan')):.3f} / "
                                                  f"{1e3 * res.stats.get('worst_step_wall', float('nan')):.3f}"),
                 ("worst step: corrections / matrices / full LU",
                  " / ".join(map(str, res.stats.get("worst_step_work", ("-",) * 3)))),
                 ("halved / unconverged steps", f"{res.stats.get('halved_steps', 0)} / "
                                                f"{res.stats.get('unconverged_steps', 0)}")]
        if res.stats.get("realtime"):
            rows.append(("real-time overruns (worst late [ms])",
                         f"{res.stats['overruns']} ({1e3 * res.stats.get('worst_late', 0.0):.3f})"))
    if out:
        rows.append(("result file", str(out)))
    for row in rows:
        table.add_row(*row)
    console.print(table)
    where = f"model {done.entry.name!r}: summary signals (register_model(..., summary_signals=...))"
    try:
        signals = done.entry.signals(done.model)
    except Exception as err:  # a model's own summary_signals function: a warning naming it; the run is kept
        say("Warning", f"{where}: {type(err).__name__}: {one_line(err)}; no summary table")
        return
    if not signals or not len(res.t):
        return
    missing, groups = [], {}
    res.prefetch(*signals)  # one pass over the rows for all of them
    for name in signals:
        try:
            with warnings.catch_warnings():  # statically indeterminate signals are marked in the table instead
                warnings.simplefilter("ignore", IndeterminateReactionWarning)
                values, unit = res.display(name)
        except ResultKeyError as err:
            missing.append(one_line(err))
            continue
        elems = res.elements(name)  # an array: a row per element (a matrix's in column order, as its names)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IndeterminateReactionWarning)
            columns = [values] if values.ndim == 1 else [res.display(elem)[0] for elem in elems]
        for col, elem in zip(columns, elems, strict=True):
            k = int(np.argmax(np.abs(col)))
            component, _, leaf = elem.rpartition(".")
            leaf += " (indeterminate)" if elem in res.indeterminate else ""
            short = [f"{x:.4g}" for x in (col.min(), col.max(), res.t[k])]  # 80 columns
            groups.setdefault(component, []).append((leaf, unit, *short))
    # grouped by component (its name once, then its variables), no column rules, four significant digits: the
    # table fits 80 columns; a name longer than the screen allows wraps, it is not cut short
    names = [len(c) for c in groups] + [len(r[0]) + 2 for rows in groups.values() for r in rows]
    peaks = Table(title="summary signals", box=box.SIMPLE_HEAD)
    peaks.add_column("signal", overflow="fold", min_width=min(max(names, default=6), 32))
    for col, justify in (("unit", "left"), ("min", "right"), ("max", "right"), ("|x| peaks at t [s]", "right")):
        peaks.add_column(col, justify=justify, no_wrap=True)  # (the peak |x| is the larger of |min| and |max|)
    for component, rows in groups.items():
        if component:
            peaks.add_row(Text(component, style="bold"), "", "", "", "")
        for leaf, *cells in rows:
            peaks.add_row(("  " if component else "") + leaf, *cells)
    console.print(peaks)
    for text in missing:
        say("Warning", f"{where}: {text}; left out of the table")


cli.add_command(compare_cmd)
cli.add_command(show_cmd)
cli.add_command(sweep_cmd)
cli.add_command(study_group)


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``flexlib`` script and ``python -m flexlib``."""
    cli.main(args=argv, prog_name="flexlib")
