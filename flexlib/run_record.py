"""The run record: what a scenario run stores in its result to be repeated (``flexlib run --from FILE``).

:func:`flexlib.registry.run_scenario` writes a :class:`RunRecord` (model, full scenario, parameter overrides, run
options) as JSON into the result's metadata (``meta_run`` in the HDF5 file); :func:`run_settings` reads it back.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from flexlib.errors import ResultFileError, RunArgumentError
from flexlib.scenario import Scenario

__all__ = ["RunRecord", "json_value", "record_json", "run_settings"]


@dataclass(frozen=True)
class RunRecord:
    """What :func:`run_scenario` stores in a result (``result.metadata["run"]``, JSON) to repeat the run.

    Attributes
    ----------
    model : str
        Registered model name.
    scenario : dict
        The full scenario (:meth:`Scenario.to_dict`), so that a user's own scenario repeats too.
    params : dict
        Parameter overrides given on top of the scenario's.
    run : dict
        Options given on top of the scenario's (``t_end``, ``rtol``, ...).
    """

    model: str
    scenario: dict[str, Any]
    params: dict[str, float]
    run: dict[str, Any]

    def to_json(self) -> str:
        """The record as JSON (numpy arrays and scalars as lists and numbers); ``TypeError`` for a value JSON
        cannot hold."""
        return json.dumps({"model": self.model, "scenario": self.scenario, "params": self.params, "run": self.run},
                          default=json_value)


def json_value(value: Any) -> Any:
    """``json.dumps(default=...)``: a numpy array as a list, a numpy scalar as a number; ``TypeError`` otherwise."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} {value!r} cannot be written as JSON")


def record_json(record: RunRecord, scen: Scenario) -> str:
    """``record.to_json()``, checked before the build: a scenario value JSON cannot hold (an object, a
    function) is a :class:`RunArgumentError` naming the scenario and the field, not a failure after the run."""
    try:
        return record.to_json()
    except (TypeError, ValueError) as err:
        fields = {"options": scen.options, "data": scen.data, "run": scen.run}
        for key, mapping in fields.items():
            for name, value in mapping.items():
                try:
                    json.dumps(value, default=json_value)
                except (TypeError, ValueError) as sub:
                    raise RunArgumentError(f"{scen.label}: {key}[{name!r}] cannot be recorded in the result (the "
                                           f"run settings are JSON: lists, numbers, str, bool, None and dicts with "
                                           f"str keys): {sub}") from None
        raise RunArgumentError(f"{scen.label}: the run settings cannot be recorded as JSON: {err}") from None


def run_settings(result: Any, source: str = "the result") -> RunRecord:
    """The run settings recorded by :func:`run_scenario` in a result (loaded with ``flexlib.load_result``).

    Raises
    ------
    ResultFileError
        The result holds no run record (it was not written by :func:`run_scenario` / ``flexlib run``) or the
        record is damaged (not JSON, a field missing or of the wrong type, named); names ``source``.
    RunArgumentError
        ``result`` is not a Result (a path: read it with ``flexlib.load_result``).
    """
    metadata = getattr(result, "metadata", None)
    if isinstance(result, (str, bytes, os.PathLike)) or not isinstance(metadata, Mapping):
        raise RunArgumentError(f"run_settings takes a Result (read a file with flexlib.load_result(path)), got "
                               f"{result!r} ({type(result).__name__})")
    raw = metadata.get("run")
    if raw is None:
        raise ResultFileError(f"{source} holds no run settings (it was not written by 'flexlib run' or "
                              "flexlib.registry.run_scenario)")
    damaged = f"{source}: the run settings (meta_run) are damaged"
    try:
        d = json.loads(raw)
    except (ValueError, TypeError) as err:
        raise ResultFileError(f"{damaged}: not JSON ({err})") from None
    if not isinstance(d, dict):
        raise ResultFileError(f"{damaged}: a JSON object with model, scenario, params and run is expected, got "
                              f"{type(d).__name__}")
    missing = [k for k in ("model", "scenario", "params", "run") if k not in d]
    if missing:
        raise ResultFileError(f"{damaged}: the field {missing[0]!r} is missing")
    if not isinstance(d["model"], str):
        raise ResultFileError(f"{damaged}: the field 'model' must be a model name (str), got {d['model']!r}")
    for key in ("scenario", "params", "run"):
        if not isinstance(d[key], dict):
            raise ResultFileError(f"{damaged}: the field {key!r} must be a JSON object, got {d[key]!r}")
    return RunRecord(model=d["model"], scenario=d["scenario"], params=d["params"], run=d["run"])
