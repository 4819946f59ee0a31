"""The variants of a study: parameter values on a grid, from a list, or sampled (Latin hypercube, Monte Carlo).

Each variant is a dict ``{parameter name: value}`` [SI units]; a study runs its scenario once per variant with those
values as parameter overrides (``run(params=...)``). Samples are reproducible: the same seed gives the same variants.

References
----------
M. D. McKay, R. J. Beckman, W. J. Conover, "A comparison of three methods for selecting values of input variables in
the analysis of output from a computer code", *Technometrics* 21 (1979) 239–245 (Latin hypercube sampling; scipy's
``scipy.stats.qmc.LatinHypercube``).
"""

from __future__ import annotations

import itertools
import math
import numbers
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from flexlib.errors import RunArgumentError

__all__ = ["grid", "latin_hypercube", "monte_carlo", "start_pose"]


def _finite(name: str, value: Any, who: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise RunArgumentError(f"{who}: {name} = {value!r} must be a finite number (SI units)")
    return float(value)


def grid(**axes: Sequence[float]) -> list[dict[str, float]]:
    """Every combination of the values of each parameter (the first parameter varies slowest).

    ``grid(**{"cbv3.pilot_ratio": [2.5, 3, 4], "loop2.pid.k": [1.0, 1.2]})`` gives six variants.
    """
    if not axes:
        raise RunArgumentError("grid: give at least one parameter with its values")
    for name, values in axes.items():
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence | np.ndarray) or len(values) == 0:
            raise RunArgumentError(f"grid: {name} must have a non-empty sequence of values, got {values!r:.60}")
    names = list(axes)
    checked = [[_finite(n, v, "grid") for v in axes[n]] for n in names]
    return [dict(zip(names, combo, strict=True)) for combo in itertools.product(*checked)]


def _bounds(bounds: Mapping[str, tuple[float, float]], who: str) -> tuple[list[str], np.ndarray, np.ndarray]:
    if not bounds:
        raise RunArgumentError(f"{who}: give at least one parameter with its (low, high) bounds")
    names, lo, hi = [], [], []
    for name, pair in bounds.items():
        if not isinstance(pair, Sequence) or len(pair) != 2:
            raise RunArgumentError(f"{who}: {name} must have (low, high), got {pair!r:.60}")
        a, b = (_finite(name, v, who) for v in pair)
        if not a < b:
            raise RunArgumentError(f"{who}: {name}: low {a} must be below high {b}")
        names.append(name)
        lo.append(a)
        hi.append(b)
    return names, np.array(lo), np.array(hi)


def _count(n: Any, who: str) -> int:
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise RunArgumentError(f"{who}: n = {n!r} must be a positive integer (the number of variants)")
    return int(n)


def latin_hypercube(bounds: Mapping[str, tuple[float, float]], n: int, seed: int = 0) -> list[dict[str, float]]:
    """``n`` variants filling the box ``bounds`` (``{name: (low, high)}``) by Latin hypercube sampling: each
    parameter's range cut into ``n`` equal strata, each stratum sampled once (scipy's ``LatinHypercube``, ``seed``)."""
    from scipy.stats import qmc

    names, lo, hi = _bounds(bounds, "latin_hypercube")
    unit = qmc.LatinHypercube(d=len(names), seed=seed).random(_count(n, "latin_hypercube"))
    values = qmc.scale(unit, lo, hi)
    return [dict(zip(names, map(float, row), strict=True)) for row in values]


def monte_carlo(nominal: Mapping[str, float], n: int, *, relative: Mapping[str, float] | None = None,
                distribution: str = "uniform", seed: int = 0) -> list[dict[str, float]]:
    """``n`` variants around ``nominal`` values: each parameter ``x·(1 + e)`` with ``e`` uniform in ``±relative[x]``
    (``distribution="uniform"``: a manufacturing tolerance band) or normal with standard deviation ``relative[x]``
    (``"normal"``), independently, from numpy's generator seeded with ``seed``.

    ``monte_carlo({"axis2.cylinder.d_piston": 0.2}, 200, relative={"axis2.cylinder.d_piston": 0.01})``: bores ±1 %.
    """
    n = _count(n, "monte_carlo")
    if distribution not in ("uniform", "normal"):
        raise RunArgumentError(f"monte_carlo: distribution = {distribution!r} must be 'uniform' or 'normal'")
    relative = dict(relative or {})
    unknown = [k for k in relative if k not in nominal]
    if unknown:
        raise RunArgumentError(f"monte_carlo: relative[{unknown[0]!r}] names no parameter of nominal")
    names = list(nominal)
    if not names:
        raise RunArgumentError("monte_carlo: give at least one nominal parameter value")
    x0 = np.array([_finite(k, nominal[k], "monte_carlo") for k in names])
    spread = np.array([_finite(f"relative[{k!r}]", relative.get(k, 0.0), "monte_carlo") for k in names])
    if np.any(spread < 0):
        raise RunArgumentError("monte_carlo: relative spreads must be >= 0")
    rng = np.random.default_rng(seed)
    e = (rng.uniform(-1.0, 1.0, (n, len(names))) if distribution == "uniform"
         else rng.standard_normal((n, len(names))))
    values = x0 * (1.0 + e * spread)
    return [dict(zip(names, map(float, row), strict=True)) for row in values]


def start_pose(model: str, scenario: str | None, pose: Sequence[float], name: str | None = None) -> Any:
    """The registered ``scenario`` of ``model`` started from ``pose`` instead of its own (its data's ``"pose"``, e.g.
    the pump truck's slew and joint angles [deg]): a :class:`~flexlib.registry.Scenario` record named ``name``
    (default ``"<scenario>@pose"``) for :func:`~flexlib.study.run_study` — a start pose is not a parameter.
    :class:`RunArgumentError` if the scenario has no start pose in its data."""
    from dataclasses import replace

    from flexlib import registry

    base = registry.get_scenario(model, scenario)
    if "pose" not in base.data:
        raise RunArgumentError(f"the scenario {base.name!r} of {model!r} has no start pose in its data")
    return replace(base, name=name or f"{base.name}@pose", data={**dict(base.data), "pose": [float(a) for a in pose]})
