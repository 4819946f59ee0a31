"""Helpers shared by the robustness tests (not tests): running the CLI to a refusal, hand-edited copies of files,
a small model."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import h5py
from click.testing import CliRunner

import flexlib as fl
from flexlib.cli import cli
from flexlib.components.control import Constant
from flexlib.components.hydraulics import Tank
from flexlib.components.mechanics.multibody import World
from flexlib.components.mechanics.translational import Damper, Fixed, Force, Mass, Spring

#: Spring constant [N/m] and mass [kg] of :class:`PushedOscillator`: natural frequency 1 Hz.
K, M = 4.0 * math.pi**2, 1.0


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


class PushedOscillator(fl.Model):
    """wall – spring – mass (– damper), pushed by a constant force src.k."""

    def __init__(self, d: float = 0.0, extra: str = "") -> None:
        super().__init__()
        self.wall = Fixed()
        self.spring = Spring(c=K)
        self.mass = Mass(m=M, init={"s": 0.0, "v": 0.0})
        self.src = Constant(k=0.0)
        self.push = Force()
        self.connect(self.wall.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.mass.flange_a)
        self.connect(self.src.y, self.push.f)
        self.connect(self.push.flange, self.mass.flange_b)
        if d:
            self.damper = Damper(d=d)
            self.connect(self.wall.flange, self.damper.flange_a)
            self.connect(self.damper.flange_b, self.mass.flange_a)
        if extra == "fixed":
            self.ground = Fixed()
        elif extra == "free mass":
            self.drifting = Mass(m=1.0, init={"s": 0.0, "v": 1.0})
        elif extra == "world":
            self.world = World()
        elif extra == "tank":
            self.tank = Tank()
