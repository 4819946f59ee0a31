"""Bad input to the pinned-free beam reference solver (``benchmarks/references/pinned_free_beam.py``): each case
raises a clear error naming the argument, and the reference file is written atomically."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import numpy as np
import pytest

_PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "references" / "pinned_free_beam.py"
_SPEC = importlib.util.spec_from_file_location("pinned_free_beam", _PATH)
pfb = importlib.util.module_from_spec(_SPEC)
sys.modules.setdefault("pinned_free_beam", pfb)
_SPEC.loader.exec_module(pfb)


@pytest.mark.parametrize(
    ("kwargs", "culprit"),
    [
        ({"n_elements": 3, "dt": 1e-3}, "n_elements must be even"),
        ({"n_elements": 0, "dt": 1e-3}, "n_elements must be even"),
        ({"n_elements": 4.0, "dt": 1e-3}, "n_elements must be an int"),
        ({"n_elements": 4, "dt": 0.0}, "dt must be finite and > 0"),
        ({"n_elements": 4, "dt": float("nan")}, "dt must be finite and > 0"),
        ({"n_elements": 4, "dt": 3e-3}, "t_end=2.0 s is not a positive multiple of dt=0.003"),
        ({"n_elements": 4, "dt": 1e-3, "rho_inf": 1.5}, "rho_inf must lie in [0, 1]"),
        ({"n_elements": 4, "dt": 1e-3, "young": -1.0}, "young must be finite and > 0"),
        ({"n_elements": 4, "dt": 1e-3, "schedule": ((0.1, 1.0),)}, "torque schedule must start at t=0"),
        ({"n_elements": 4, "dt": 1e-3, "schedule": ((0.0, 1.0), (0.5005, -1.0))}, "torque switch at t=0.5005 s"),
        ({"n_elements": 4, "dt": 1e-3, "schedule": ((0.0, float("inf")),)}, "torque value inf at t=0.0 s"),
    ],
)
def test_bad_solver_arguments_name_the_argument(kwargs, culprit):
    with pytest.raises(ValueError, match=re.escape(culprit)):
        pfb.solve(**kwargs)


def test_newton_failure_names_the_time_and_step():
    """No Newton iteration allowed beyond the first: the solver stops at the first step, naming t and dt."""
    with pytest.raises(RuntimeError, match=r"did not converge in 0 iterations at t=0\.001 s .*dt=0\.001, n=4"):
        pfb.solve(4, 1e-3, t_end=0.01, max_iterations=0)


def test_bad_series_arguments_name_the_argument():
    run = pfb.solve(2, 1e-3, t_end=0.02)
    with pytest.raises(ValueError, match=r"sample_dt=0\.0015 is not a multiple of dt=0\.001"):
        run.sampled(sample_dt=0.0015)
    with pytest.raises(ValueError, match="seed_error: z"):
        pfb.seed_error(np.zeros(3), np.ones(4))
    with pytest.raises(ValueError, match="reference z_ref is identically zero"):
        pfb.seed_error(np.ones(3), np.zeros(3))
    with pytest.raises(ValueError, match="window_average: t must be increasing"):
        pfb.window_average(np.array([0.0, 0.0, 1.0]), np.zeros(3), np.array([0.5]))
    with pytest.raises(ValueError, match="window_average: half_width"):
        pfb.window_average(np.array([0.0, 1.0]), np.zeros(2), np.array([0.5]), half_width=0.0)


def test_reference_write_is_atomic(tmp_path):
    """A write that fails half-way leaves the previous file intact and no temporary file behind."""
    target = tmp_path / "ref.npz"
    pfb.write_reference(target, {"t": np.arange(3.0)})

    class Unconvertible:
        def __array__(self, *args, **kwargs):
            raise RuntimeError("cannot convert")

    with pytest.raises(RuntimeError, match="cannot convert"):
        pfb.write_reference(target, {"t": np.arange(5.0), "bad": Unconvertible()})
    with np.load(target) as data:
        np.testing.assert_array_equal(data["t"], np.arange(3.0))
    assert [p.name for p in tmp_path.iterdir()] == ["ref.npz"]
