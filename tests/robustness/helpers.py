"""Helpers shared by the robustness tests (not tests): running the CLI to a refusal, hand-edited copies of files."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import h5py
from click.testing import CliRunner

from flexlib.cli import cli


def cli_error(*args: str, code: int | None = 1, columns: int = 200) -> str:
    """Run the CLI with ``args`` in a terminal ``columns`` wide; it must fail (with exit code ``code``, or any
    non-zero one for ``None``) with one ``Error:`` line and no traceback. Return that line."""
    res = CliRunner().invoke(cli, list(args), env={"COLUMNS": str(columns)})
    assert res.exit_code != 0, res.output
    if code is not None:
        assert res.exit_code == code, res.output
    assert not isinstance(res.exception, Exception) or isinstance(res.exception, SystemExit), res.exception
    assert "Traceback" not in res.output
    errors = [line for line in res.output.splitlines() if line.startswith("Error:")]
    assert len(errors) == 1, res.output
    return errors[0]


def edited_h5(good: Path, tmp_path: Path, edit: Callable[[h5py.File], object], name: str = "edited.h5") -> Path:
    """A copy ``tmp_path / name`` of the HDF5 file ``good`` with ``edit(file)`` applied (a hand edit)."""
    path = tmp_path / name
    path.write_bytes(good.read_bytes())
    with h5py.File(path, "r+") as f:
        edit(f)
    return path

