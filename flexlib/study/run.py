"""Running a study on Dask (``dask.distributed``): the variants as tasks, the reductions back, the table in Parquet.

Each task runs one variant in a worker process. A worker keeps the simulation of each (model, scenario) it has built
(:data:`_SIMULATIONS`), so it builds once — from the disk cache when an earlier process built the same model, which
the cache's atomic writes make safe with concurrent workers — and then only runs (``run(params=...)``, no recompile).
A run that fails is a row with ``status = "failed"`` and its error; the study goes on. The table is written to
``out`` (Parquet, through a temporary file renamed over it) as rows arrive; started again with the same ``out``, a
study runs only the variants that have no row there yet.
"""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from flexlib.errors import RunArgumentError

__all__ = ["META_KEY", "WORKER_PRELOAD", "StudyResult", "local_cluster", "read_table", "run_study"]

#: Per worker process: the simulation and scenario of each (model, scenario) it ran, built once.
_SIMULATIONS: dict[tuple[str, str | None, str], tuple[Any, Any]] = {}
#: Rows written to ``out`` at least this often [s] while a study runs.
SAVE_EVERY = 5.0
#: Key of the table's schema metadata: the study's model, scenario, options, parameter and reduction columns (JSON)
META_KEY = "flexlib.study"


@dataclass
class StudyResult:
    """The table of a study: one row per variant (``rows``: dicts), in the variants' order."""

    rows: list[dict[str, Any]]
    path: Path | None

    def column(self, name: str) -> list[Any]:
        """The column ``name`` (a parameter, a reduction, ``status``, ``error``, ``run_time``)."""
        if self.rows and name not in self.rows[0]:
            raise KeyError(f"study table has no column {name!r} (columns: {', '.join(self.rows[0])})")
        return [r[name] for r in self.rows]

    @property
    def failed(self) -> list[dict[str, Any]]:
        """The rows of the runs that failed."""
        return [r for r in self.rows if r["status"] != "success"]

    def to_pandas(self) -> Any:
        """The table as a pandas DataFrame (pandas needed)."""
        import pandas as pd

        return pd.DataFrame(self.rows)


def variant_key(params: Mapping[str, float]) -> str:
    """The identity of a variant in the table (its parameter values as sorted JSON): what a restarted study skips."""
    return json.dumps({k: float(params[k]) for k in sorted(params)}, sort_keys=True)


def _scenario_key(scenario: Any) -> str | None:
    """A scenario's identity in a worker's cache: its name, or a record's whole content (two records of one name
    with other start poses are other machines' starts)."""
    if scenario is None or isinstance(scenario, str):
        return scenario
    return json.dumps(scenario.to_dict(), sort_keys=True, default=str)


def _simulation(model: str, scenario: Any, options: str) -> tuple[Any, Any]:
    key = (model, _scenario_key(scenario), options)
    found = _SIMULATIONS.get(key)
    if found is None:
        from dataclasses import replace

        from flexlib import registry
        from flexlib.solve.simulation import Simulation

        scen = scenario if isinstance(scenario, registry.Scenario) else registry.get_scenario(model, scenario)
        extra = json.loads(options)
        if extra:
            scen = replace(scen, options={**scen.options, **extra})
        instance, scen = registry.scenario_model(model, scen)
        found = _SIMULATIONS[key] = (Simulation(instance), scen)
    return found


def run_variant(model: str, scenario: Any, options: str, t_end: float | None, params: dict[str, float],
                reductions: Mapping[str, Callable[[Any], float]]) -> dict[str, Any]:
    """One variant in a worker: its row (parameters, reductions, status, error, the run's CPU time and the build's in
    this worker (0 once built) [s], the run's wall time [s], the worker's pid, the task's start and end [s since the
    epoch: the benchmark's overhead per run])."""
    row: dict[str, Any] = {"variant": variant_key(params), **params}
    t_start = time.time()
    c0 = time.process_time()
    build, run_wall = 0.0, math.nan
    try:
        built = (model, _scenario_key(scenario), options) not in _SIMULATIONS
        sim, scen = _simulation(model, scenario, options)
        build = time.process_time() - c0 if built else 0.0
        run = dict(scen.run)
        w0 = time.perf_counter()
        res = sim.run(scen.t_end if t_end is None else t_end, params={**dict(scen.params), **params}, progress=False,
                      **run)
        run_wall = time.perf_counter() - w0
        for name, reduce in reductions.items():
            row[name] = float(reduce(res))
        row["status"], row["error"] = "success", ""
    except Exception as err:  # a failed run is a row, whatever failed: the study goes on
        for name in reductions:
            row.setdefault(name, math.nan)
        row["status"], row["error"] = "failed", f"{type(err).__name__}: {str(err).splitlines()[0] if str(err) else ''}"
    row["run_time"] = time.process_time() - c0 - build
    row["build_time"] = build
    row["run_wall"] = run_wall
    row["worker"] = os.getpid()
    row["t_start"], row["t_end"] = t_start, time.time()
    return row


def read_table(path: str | os.PathLike) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """A study table written by :func:`run_study`: its rows and its description (model, scenario, options, the
    parameter and reduction columns)."""
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    raw = (table.schema.metadata or {}).get(META_KEY.encode())
    return table.to_pylist(), json.loads(raw) if raw else {}


def _write(path: Path, done: dict[str, dict[str, Any]], meta: dict[str, Any]) -> None:
    """The rows so far to ``path``, in the variants' order (rows of an earlier study on the same file after them)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    order = {k: n for n, k in enumerate(meta["order"])}
    rows = sorted(done.values(), key=lambda r: order.get(r["variant"], len(order)))
    meta = {k: v for k, v in meta.items() if k != "order"}
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".part", dir=path.parent)
    os.close(fd)
    try:
        table = pa.Table.from_pylist(rows)
        pq.write_table(table.replace_schema_metadata({META_KEY: json.dumps(meta)}), tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


#: The Dask preload module of a study's workers (:mod:`flexlib.study.worker`)
WORKER_PRELOAD = "flexlib.study.worker"


def local_cluster(workers: int = 2) -> Any:
    """A Dask ``LocalCluster`` on this machine as a study uses it: ``workers`` processes of one thread each, every one
    made ready for flexlib runs as it starts (:mod:`flexlib.study.worker`); no dashboard. Start one and pass its
    ``scheduler_address`` to several studies to start the workers once."""
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                        preload=[WORKER_PRELOAD])


def _client(workers: int, scheduler: str | None) -> tuple[Any, Any]:
    from distributed import Client

    if scheduler is not None:
        return Client(scheduler), None
    cluster = local_cluster(workers)
    return Client(cluster), cluster


def run_study(model: str, variants: Sequence[Mapping[str, float]], reductions: Mapping[str, Callable[[Any], float]],
              *, scenario: str | None = None, options: Mapping[str, Any] | None = None, t_end: float | None = None,
              workers: int = 2, scheduler: str | None = None, out: str | os.PathLike | None = None,
              progress: bool | None = None) -> StudyResult:
    """Run ``variants`` of a registered model's scenario on Dask and keep ``reductions`` of each run.

    Parameters
    ----------
    model : str
        A registered model (``flexlib list``); workers import it by name.
    variants : sequence of dict
        Parameter values of each run [SI units] (:func:`~flexlib.study.grid`, :func:`~flexlib.study.latin_hypercube`,
        :func:`~flexlib.study.monte_carlo`, or your own list).
    reductions : dict
        ``{column name: reduction}``: what each run is judged by (:class:`~flexlib.study.Peak`, ... or a function
        of a Result importable by the workers).
    scenario : str or Scenario, optional
        The scenario (default: the model's), or a :class:`~flexlib.registry.Scenario` record of the model's (another
        start pose, :func:`~flexlib.study.start_pose`; other commands: ``dataclasses.replace(scenario, data=...)``).
    options : dict, optional
        Model options on top of the scenario's (``{"flexible": True}``).
    t_end : float, optional
        End time of every run [s] (default: the scenario's).
    workers : int
        Worker processes of the local cluster (default 2: one per core of this machine).
    scheduler : str, optional
        Address of a running Dask scheduler (``"tcp://host:8786"``): the study runs there instead.
    out : str or path-like, optional
        The table's Parquet file, written as rows arrive; a study started again with it runs only the missing rows.
    progress : bool, optional
        A progress bar (default: on a terminal).

    Returns
    -------
    StudyResult
        One row per variant, in their order.
    """
    from flexlib import registry

    if isinstance(scenario, registry.Scenario):  # a record of the user's (another start pose): checked here
        registry.get_model(model).checked(scenario)
    else:
        registry.get_scenario(model, scenario)  # the names checked here, before any worker starts
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise RunArgumentError(f"run_study: workers = {workers!r} must be a positive integer")
    if not reductions:
        raise RunArgumentError("run_study: give at least one reduction (a column of the table)")
    todo_params = [dict(v) for v in variants]
    keys = [variant_key(v) for v in todo_params]
    path = Path(out) if out is not None else None
    done: dict[str, dict[str, Any]] = {}
    if path is not None and path.exists():
        done = {r["variant"]: r for r in read_table(path)[0]}
    todo = [(k, v) for k, v in zip(keys, todo_params, strict=True) if k not in done]
    name = scenario.name if isinstance(scenario, registry.Scenario) else scenario
    meta = {"model": model, "scenario": name, "options": dict(options or {}), "t_end": t_end,
            "params": sorted({k for v in todo_params for k in v}), "reductions": list(reductions), "order": keys}
    if todo:
        _run(meta, scenario, todo, reductions, workers, scheduler, path, done, progress)
    rows = [done[k] for k in keys]
    return StudyResult(rows, path)


def _run(meta: dict[str, Any], scenario: Any, todo: list, reductions: Mapping, workers: int, scheduler: str | None,
         path: Path | None, done: dict, progress: bool | None) -> None:
    """The variants ``todo`` as Dask tasks of the study ``meta`` (model, options, t_end) on ``scenario`` (a name or a
    record); rows into ``done`` and, as they arrive, into ``path``."""
    from distributed import as_completed
    from tqdm import tqdm

    client, cluster = _client(workers, scheduler)
    saved = time.monotonic()
    try:
        options = json.dumps(meta["options"], sort_keys=True)
        futures = [client.submit(run_variant, meta["model"], scenario, options, meta["t_end"], params,
                                 dict(reductions), pure=False) for _, params in todo]
        bar = tqdm(total=len(futures), desc=f"study {meta['model']}", leave=False,
                   disable=progress is False or (progress is None and not sys.stderr.isatty()))
        for fut in as_completed(futures):
            row = fut.result()
            done[row["variant"]] = row
            bar.update(1)
            if path is not None and time.monotonic() - saved > SAVE_EVERY:
                _write(path, done, meta)
                saved = time.monotonic()
        bar.close()
    finally:
        if path is not None:
            _write(path, done, meta)
        client.close()
        if cluster is not None:
            cluster.close()
