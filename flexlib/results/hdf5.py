"""Result files (HDF5, self-describing, written atomically). Layout: docs/results.md."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

import h5py
import numpy as np

from flexlib.results.result import Result

__all__ = ["FORMAT", "load_result", "save_result"]

FORMAT = "flexlib-result"
FORMAT_VERSION = 1
_STR = h5py.string_dtype("utf-8")


def save_result(result: Result, path: str | os.PathLike) -> None:
    """Write ``result`` to ``path``: a temporary file in the same directory, then an atomic rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    os.close(fd)
    try:
        with h5py.File(tmp, "w") as f:
            f.attrs["format"] = FORMAT
            f.attrs["format_version"] = FORMAT_VERSION
            f.attrs["model"] = result.model
            f.attrs["status"] = result.status
            f.attrs["message"] = result.message
            f.attrs["index_report"] = result.index_report
            for key, val in result.metadata.items():
                f.attrs[f"meta_{key}"] = str(val)
            ds = f.create_dataset("time", data=result.t)
            ds.attrs["unit"] = "s"
            g = f.create_group("variables")
            g.create_dataset("values", data=result.values, compression="gzip" if result.values.size > 1e5 else None)
            g.create_dataset("names", data=np.array(result.names, dtype=object), dtype=_STR)
            g.create_dataset("units", data=np.array(result.units, dtype=object), dtype=_STR)
            g.create_dataset("docs", data=np.array(result.docs, dtype=object), dtype=_STR)
            g.create_dataset("kinds", data=np.array(result.kinds, dtype=object), dtype=_STR)
            pg = f.create_group("parameters")
            names = list(result.parameters)
            pg.create_dataset("names", data=np.array(names, dtype=object), dtype=_STR)
            pg.create_dataset("values", data=np.array([result.parameters[n][0] for n in names], dtype=float))
            units = np.array([result.parameters[n][1] for n in names], dtype=object)
            pg.create_dataset("units", data=units, dtype=_STR)
            eg = f.create_group("events")
            eg.create_dataset("time", data=np.array([e[0] for e in result.events], dtype=float))
            eg.create_dataset("text", data=np.array([e[1] for e in result.events], dtype=object), dtype=_STR)
            f.attrs["solver_stats"] = json.dumps(result.stats, default=float)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _strings(ds: h5py.Dataset) -> list[str]:
    return [s.decode() if isinstance(s, bytes) else str(s) for s in ds[()]]


def load_result(path: str | os.PathLike) -> Result:
    """Read a result written by :meth:`Result.save`."""
    with h5py.File(path, "r") as f:
        if f.attrs.get("format") != FORMAT:
            raise ValueError(f"{path}: not a flexlib result file")
        g, pg, eg = f["variables"], f["parameters"], f["events"]
        params = {n: (float(v), u) for n, v, u in zip(_strings(pg["names"]), pg["values"][()], _strings(pg["units"]),
                                                     strict=True)}
        meta = {k[5:]: str(v) for k, v in f.attrs.items() if k.startswith("meta_")}
        return Result(
            model=str(f.attrs["model"]), t=f["time"][()], names=_strings(g["names"]), values=g["values"][()],
            units=_strings(g["units"]), docs=_strings(g["docs"]), kinds=_strings(g["kinds"]), parameters=params,
            stats=json.loads(f.attrs["solver_stats"]), status=str(f.attrs["status"]), message=str(f.attrs["message"]),
            events=list(zip(eg["time"][()].tolist(), _strings(eg["text"]), strict=True)),
            index_report=str(f.attrs["index_report"]), metadata=meta,
        )
