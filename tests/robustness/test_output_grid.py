"""Every run ends with a row at exactly ``t_end`` (issue 26: ``run(0.3, dt_out=0.05)`` ended at 0.25 and
``run(0.7, dt_out=0.1)`` at 0.6, on every backend and through the CLI, because the grid's last point
0.7000000000000001 lay past ``t_end`` and was removed).

The property is checked on the output grid over many (t_end, dt_out) pairs — ratios that are not exact in
floating point, ``t_end < dt_out``, ``dt_out`` not dividing ``t_end``, a shifted ``t_start`` — and on runs of
each backend, whose last row must be ``t_end`` and hold the state there (reference: x = cos t)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from click.testing import CliRunner

import flexlib as fl
from flexlib.cli import cli
from flexlib.models.reference.mass_spring_damper import Oscillator
from flexlib.solve.run_options import _output_grid

T_ENDS = [0.3, 0.7, 0.05, 1.0, 2.9, 3.3, 10.0, 12.34, 1e-3, 0.1 + 0.2, 7.0 / 3.0, 100.0]
DT_OUTS = [0.05, 0.1, 0.3, 0.2, 1.0 / 3.0, 0.01, 0.07, 1e-3, 5.0, 0.15]
T_STARTS = [0.0, 0.1, -1.3, 1e3]


@pytest.mark.parametrize("t0", T_STARTS)
def test_grid_ends_at_t_end_and_keeps_its_spacing(t0):
    for span, dt in itertools.product(T_ENDS, DT_OUTS):
        t1 = t0 + span
        grid = _output_grid(t0, t1, dt, None)
        assert grid[0] == t0 and grid[-1] == t1, (t0, t1, dt)
        steps = np.diff(grid)
        assert np.all(steps > 0), (t0, t1, dt)
        # every step is dt but the last, which is at most dt (plus round-off) and never a sliver of round-off
        assert np.allclose(steps[:-1], dt, rtol=1e-9, atol=1e-9 * max(1.0, abs(t1))), (t0, t1, dt)
        assert steps[-1] <= dt * (1 + 1e-9) + 1e-12 * max(1.0, abs(t1)), (t0, t1, dt)
        assert steps[-1] > 1e-6 * dt, (t0, t1, dt)
        # as many points as whole dt fit (t1 counted once)
        assert len(grid) == int(np.ceil(round(span / dt, 9))) + 1, (t0, t1, dt)



@pytest.fixture(scope="module")
def sim():
    return fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


@pytest.mark.parametrize("solver", ["ida", "ida-sksundae", "casadi-idas"])
@pytest.mark.parametrize(("t_end", "dt_out"), [(0.3, 0.05), (0.7, 0.1), (0.05, 0.1), (1.0, 0.3), (2.9, 0.1)])
def test_run_ends_with_a_row_at_t_end(sim, solver, t_end, dt_out):
    res = sim.run(t_end, dt_out=dt_out, solver=solver, rtol=1e-8, atol=1e-10)
    assert res.t[-1] == t_end
    assert len(res.t) == int(np.ceil(round(t_end / dt_out, 9))) + 1
    assert res["x"][-1] == pytest.approx(np.cos(t_end), abs=1e-6)


def test_cli_run_ends_at_t_end(tmp_path):
    out = tmp_path / "chain.h5"
    res = CliRunner().invoke(cli, ["run", "n-mass-chain", "-s", "short", "--t-end", "0.7", "--dt-out", "0.1",
                                   "--out", str(out), "--no-progress"], env={"COLUMNS": "200"},
                             catch_exceptions=False)
    assert res.exit_code == 0, res.output
    saved = fl.load_result(out)
    assert saved.t[-1] == 0.7 and len(saved.t) == 8
