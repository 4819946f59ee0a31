"""Golden results of the pump-truck boom: regression references for its flows, pressures and hinge forces.

A golden is a small result file (``tests/models/goldens/<scenario>[-flexible].h5``, the HDF5 layout of
``docs/results.md``) holding the signals the boom is judged by, sampled on a decimated grid:

* per cylinder ``n``: the port flows ``axis{n}.cylinder.cylinder.q_A``, ``q_B`` [m3/s] and the chamber pressures
  ``p_A``, ``p_B`` [Pa];
* per joint ``n``: the hinge force on section ``n`` in its frame, components ``joint{n}.frame_b.f[0]``, ``f[1]`` and
  magnitude ``joint{n}.F_hinge`` [N] (the magnitude is derived here; the components come from the run);
* the joint angles ``joint{n}.phi`` [rad] (and ``turret.slew.phi`` if the model slews);
* per joint loop the tracking error ``loop{n}.pid.control_error`` [m] (reference minus measured cylinder length):
  what the controller's tuning moves first (a PI gain × 1.25 on joint 2 changes its error by 0.36 mm, 13 % of its
  range in expand-fold, while the feed-forward keeps flows, pressures and angles within their tolerances).

Its metadata record the scenario, the model options and run settings, the flexlib version and git commit and the
command that made it. :func:`compare` interpolates a new result onto the golden's grid and checks every signal
against ``atol + rtol·range``, with the range of the golden signal over the run:

=========  ===========  ======  =====================================================================
signal     atol         rtol    why
=========  ===========  ======  =====================================================================
pressure   1 bar        1 %     a run at rtol 1e-5 reproduces to about 1e-4 of the range; 1 % leaves
flow       1e-6 m3/s    1 %     room for other BLAS/compilers and event times shifted by a step, and
force      1 kN         1 %     still fails for a 2 % change of a cylinder bore or a valve rating
angle      1e-4 rad     1 %     (``tests/models/test_pump_truck_goldens.py`` checks that it does)
error      1e-4 m       1 %     a tenth of a millimetre, 3 % of the loops' largest error (2.9 mm)
=========  ===========  ======  =====================================================================

Each golden sample may be matched anywhere within ±``TIME_SHIFT`` (a quarter) of the sampling interval of its time:
the short correction bursts of a joint holding its pose move by a few steps with round-off.

Some samples the run does not determine at all: a joint holding its pose drifts slowly (leakage) until its controller
makes a short correction burst, and when the burst starts depends on round-off (changing ``rtol`` by one part in 10¹²
moves it, as do another host's libm and BLAS; ``docs/decisions/025-goldens-hold-round-off-spread.md``). A golden sample
that falls on such a burst, or on the flow spike right after a valve switch, differs between two correct runs by up to
the tolerance or more. So each golden also holds, per sample, the **measured round-off spread** of its scenario:
:func:`make_golden` runs the scenario again with its tolerances changed by one part in 10¹² (``TWINS``) and records, per
sample, ``SPREAD_FACTOR`` times the largest deviation of a twin from the golden run (measured as the comparison measures
it). :func:`compare` allows that spread on top of the tolerance. Where the run is determined — nearly everywhere:
pressures, forces and angles throughout, flows outside the bursts — the spread is at round-off level and the tolerance
is the table's.

A failure names each failing signal, the time of its largest excess, golden and new values, the difference and
the tolerance, and (with ``plot_dir``) writes an overlay PNG of the failing signals there.

Regenerate deliberately (after a change that is meant to move the results; say why in the commit)::

    python -m flexlib.models.pump_truck.goldens --regenerate                 # every golden
    python -m flexlib.models.pump_truck.goldens --regenerate --scenario hold # one
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.errors import ResultFileError
from flexlib.registry import get_model, run_scenario
from flexlib.results.compare import tube

__all__ = ["GOLDENS", "GOLDEN_DIR", "Mismatch", "compare", "deviation_ratios", "golden_path", "golden_signals",
           "make_golden", "report"]

#: Where the golden files live (in the repository's tests).
GOLDEN_DIR = Path(__file__).resolve().parents[2] / "tests" / "models" / "goldens"
#: The goldens kept: (scenario, flexible, sampling interval [s]).
GOLDENS = (("hold", False, 0.25), ("expand-fold", False, 1.0), ("hold", True, 0.25), ("expand-fold", True, 1.0))
#: Timing jitter the comparison tolerates, as a fraction of the golden's sampling interval: a golden sample is
#: matched by the result anywhere within ±TIME_SHIFT·dt of its time. A joint holding its pose makes short
#: correction bursts (cylinder 4: 0.8 L/min for a fraction of a second during the unfolding) whose timing moves by a
#: few steps with round-off (compiled C against CasADi's virtual machine): sampled on the 1 s grid, one burst was
#: in one run and not in the other.
TIME_SHIFT = 0.25
#: Tolerances per kind of signal: (atol in SI units, rtol of the golden signal's range).
TOLERANCES = {"pressure": (1e5, 0.01), "flow": (1e-6, 0.01), "force": (1e3, 0.01), "angle": (1e-4, 0.01),
              "error": (1e-4, 0.01)}
#: Round-off twins of a golden run: factors on the scenario's own ``rtol`` / ``atol``. One part in 10¹² changes IDA's
#: error weights, and so its step sequence, at round-off level and nothing else (the pump truck's flexible expand-fold:
#: 195 373 steps, a twin 194 288).
TWINS = ({"rtol": 1.0 + 1e-12}, {"rtol": 1.0 - 1e-12}, {"atol": 1.0 + 1e-12})
#: The spread recorded is this many times the largest deviation of a twin (a few twins underestimate the range
#: that round-off can reach: another host's value of cylinder 5's flow right after the valve switch at 700 s of the
#: flexible expand-fold lay 2.9 times farther from the golden than this host's twins).
SPREAD_FACTOR = 3.0
#: Name of the column holding the measured spread of golden signal ``name``.
SPREAD = "spread({})"


def _kind(name: str) -> str:
    if ".p_" in name:
        return "pressure"
    if ".q_" in name:
        return "flow"
    if ".f[" in name or name.endswith("F_hinge"):
        return "force"
    if name.endswith(".control_error"):
        return "error"
    return "angle"


def golden_signals(result: fl.Result) -> list[str]:
    """The golden's signals present in ``result`` (the derived hinge-force magnitudes excluded)."""
    names = [f"axis{n}.cylinder.cylinder.{v}" for n in range(1, 6) for v in ("q_A", "q_B", "p_A", "p_B")]
    names += [f"joint{n}.frame_b.f[{i}]" for n in range(1, 6) for i in (0, 1)]
    names += [f"joint{n}.phi" for n in range(1, 6)] + ["turret.slew.phi"]
    names += [f"loop{n}.pid.control_error" for n in range(1, 6)]
    return [n for n in names if n in result.names]


def golden_path(scenario: str, flexible: bool = False, directory: Path | None = None, prefix: str = "") -> Path:
    """File of the golden of ``scenario`` (rigid or flexible; ``prefix`` names another machine's, ``"boom32-"``)."""
    return (directory or GOLDEN_DIR) / f"{prefix}{scenario}{'-flexible' if flexible else ''}.h5"


def _sampled(result: fl.Result, grid: np.ndarray) -> tuple[list[str], np.ndarray, list[str]]:
    """The golden signals of ``result`` on ``grid`` (right values at events), with the hinge-force magnitudes."""
    names = golden_signals(result)
    cols = [np.asarray(result.value(n, grid), dtype=float) for n in names]
    units = [result.unit(n) for n in names]
    for n in range(1, 6):
        fx, fy = f"joint{n}.frame_b.f[0]", f"joint{n}.frame_b.f[1]"
        if fx in names and fy in names:
            cols.append(np.hypot(cols[names.index(fx)], cols[names.index(fy)]))
            names.append(f"joint{n}.F_hinge")
            units.append("N")
    return names, np.column_stack(cols), units


def _commit() -> str:
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=Path(__file__).parent, capture_output=True,
                             text=True, timeout=10, check=False)
        return out.stdout.strip() or "unknown"
    except OSError:
        return "unknown"


def make_golden(scenario: str, flexible: bool = False, dt: float = 1.0, directory: Path | None = None,
                twins: tuple[dict[str, float], ...] = TWINS, model: str = "pump-truck", prefix: str = "",
                command: str | None = None) -> Path:
    """Run ``scenario`` of the registered ``model`` (default ``pump-truck``) and write its golden (atomically), with
    the measured round-off spread of every sample (see the module docstring).

    Parameters
    ----------
    scenario : str
        Registered scenario name.
    flexible : bool
        Flexible sections instead of rigid ones.
    dt : float
        Sampling interval of the golden [s], > 0.
    directory : Path, optional
        Where to write (default :data:`GOLDEN_DIR`).
    twins : tuple of dict
        Round-off twins run to measure the spread (default :data:`TWINS`; empty: none recorded).
    model, prefix : str
        The registered model run, and the prefix of its golden files (:func:`golden_path`).
    command : str, optional
        The command that regenerates it, recorded (default: this module's for ``pump-truck``).
    """
    if not dt > 0:
        raise ValueError(f"make_golden: dt must be > 0 [s], got {dt!r}")
    entry = get_model(model)
    sc = entry.scenario(scenario)
    options = {**sc.options, "flexible": bool(flexible)} if flexible else dict(sc.options)
    from dataclasses import replace

    scen = replace(sc, options=options)
    res = run_scenario(model, scen, progress=False).result
    if not res.success:
        raise fl.SolverError(f"golden {scenario}: the run failed at t = {res.t[-1]:g} s: {res.message}")
    grid = np.arange(res.t[0], res.t[-1] + 1e-9, dt)
    names, values, units = _sampled(res, grid)
    spread = np.zeros_like(values)
    for factors in twins:  # the same scenario, only round-off changed: what the run does not determine
        run = {k: float(dict(sc.run)[k]) * f for k, f in factors.items()}
        twin = run_scenario(model, scen, progress=False, **run).result
        if not twin.success:
            raise fl.SolverError(f"golden {scenario}: the round-off twin {factors} failed at t = {twin.t[-1]:g} s: "
                                 f"{twin.message}")
        dev = _deviations(twin, grid, names, values)
        spread = np.maximum(spread, np.column_stack([dev[n] for n in names]))
    spread *= SPREAD_FACTOR
    if twins:
        names, units = names + [SPREAD.format(n) for n in names], units + units
        values = np.hstack([values, spread])
    cmd = command or f"python -m flexlib.models.pump_truck.goldens --regenerate --scenario {scenario}" + (
        " --flexible" if flexible else "")
    meta = {"golden_scenario": scenario, "golden_options": json.dumps(options, sort_keys=True),
            "golden_run": json.dumps(dict(sc.run), sort_keys=True), "golden_dt": repr(float(dt)),
            "golden_flexlib": getattr(fl, "__version__", "unknown"), "golden_commit": _commit(),
            "golden_command": cmd, "golden_twins": json.dumps(list(twins)), "golden_spread_factor": repr(SPREAD_FACTOR)}
    kinds = ["golden spread" if n.startswith("spread(") else "golden" for n in names]
    golden = fl.Result(model=res.model, t=grid, names=names, values=values, units=units, docs=[""] * len(names),
                       kinds=kinds, parameters={}, stats={}, metadata=meta)
    path = golden_path(scenario, flexible, directory, prefix)
    path.parent.mkdir(parents=True, exist_ok=True)
    golden.save(path)
    return path


@dataclass(frozen=True)
class Mismatch:
    """One signal outside its tolerance: where its excess over the tolerance is largest."""

    name: str
    t: float
    golden: float
    new: float
    tolerance: float
    unit: str
    spread: float = 0.0  #: of ``tolerance``, the golden's measured round-off spread at ``t``

    def line(self) -> str:
        d = self.new - self.golden
        extra = f", of which {self.spread:.4g} {self.unit} round-off spread" if self.spread else ""
        return (f"{self.name}: at t = {self.t:.3f} s golden {self.golden:.6g} {self.unit}, now {self.new:.6g} "
                f"{self.unit}, off by {d:+.4g} {self.unit} (tolerance ±{self.tolerance:.4g} {self.unit}{extra}, "
                f"{abs(d) / self.tolerance:.1f}× it)")


def _sampler(result: fl.Result, name: str) -> Any:
    """``times -> values`` of golden signal ``name`` in ``result`` (right values at events; times clipped to the
    result's span; a hinge-force magnitude from its components), or None if ``result`` lacks it."""
    def clip(t: np.ndarray) -> np.ndarray:
        return np.clip(t, result.t[0], result.t[-1])

    if name.endswith(".F_hinge"):
        fx, fy = (f"{name[:-len('.F_hinge')]}.frame_b.f[{i}]" for i in (0, 1))
        if fx in result.names and fy in result.names:
            return lambda t: np.hypot(result.value(fx, clip(t)), result.value(fy, clip(t)))
        return None
    return (lambda t: np.asarray(result.value(name, clip(t)), dtype=float)) if name in result.names else None


def _shift(grid: np.ndarray) -> float:
    """The time shift a golden sample may be matched within: ``TIME_SHIFT`` of the grid interval [s]."""
    return TIME_SHIFT * float(np.median(np.diff(grid))) if grid.size > 1 else 0.0


def _deviations(result: fl.Result, grid: np.ndarray, names: list[str], values: np.ndarray) -> dict[str, np.ndarray]:
    """Per golden signal and sample: the smallest ``|result - golden|`` over the result sampled at the golden's time and
    at shifts up to ``±TIME_SHIFT`` of the grid interval (:func:`flexlib.results.compare.tube`, the comparison of
    ``flexlib compare``; NaN where ``result`` has no such signal)."""
    out = {}
    for k, name in enumerate(names):
        sample = _sampler(result, name)
        out[name] = (np.full(len(grid), np.nan) if sample is None
                     else tube(grid, values[:, k], sample, 1.0, _shift(grid))[0])
    return out


def compare(result: fl.Result, golden: fl.Result | str | Path, plot_dir: Path | None = None,
            t_end: float | None = None) -> list[Mismatch]:
    """Signals of ``result`` outside the golden's tolerances (empty: the result matches).

    ``t_end`` [s]: compare the golden's samples up to this time only (a run stopped on purpose before the scenario's
    end, e.g. a check of its first motions), each signal against its tolerance over the whole golden; default the
    golden's end.

    ``result`` is sampled on the golden's grid (right values at events) and at shifts up to ``±TIME_SHIFT`` of the
    grid interval; each golden sample is compared with the closest of these values, against the tolerance of its kind
    plus the golden's measured round-off spread at that sample (see the module docstring). A golden signal missing
    from the result is a mismatch at t = golden start with a NaN value. With ``plot_dir``, an overlay of the failing
    signals is written to ``plot_dir/golden-<scenario>.png``.
    """
    golden, grid, checks = _checks(result, golden, t_end)
    new: dict[str, np.ndarray] = {}
    out: list[Mismatch] = []
    for c in checks:
        if c.new is None:
            out.append(Mismatch(c.name, float(grid[0]), float(c.golden[0]), float("nan"), c.tol, c.unit))
            continue
        new[c.name] = c.new
        i = int(np.argmax(c.ratio))
        if c.ratio[i] > 1 or not np.all(np.isfinite(c.new)):
            out.append(Mismatch(c.name, float(grid[i]), float(c.golden[i]), float(c.new[i]),
                                c.tol + float(c.spread[i]), c.unit, float(c.spread[i])))
    if out and plot_dir is not None:
        _plot(golden, grid, new, out, Path(plot_dir))
    return out


def deviation_ratios(result: fl.Result, golden: fl.Result | str | Path, t_end: float | None = None
                     ) -> dict[str, float]:
    """Per golden signal, the largest deviation of ``result`` from the golden in units of the signal's tolerance
    (``≤ 1``: :func:`compare` passes it; ``inf`` for a signal the result lacks or that is not finite), measured as
    :func:`compare` measures (the same sampling, time shift and round-off spread; arguments as there). For
    accuracy reports: how far another solver (``benchmarks/fixed_step.py``) is from the golden IDA runs."""
    _, _, checks = _checks(result, golden, t_end)
    return {c.name: (float(np.max(c.ratio)) if c.new is not None and np.all(np.isfinite(c.new)) else float("inf"))
            for c in checks}


@dataclass(frozen=True)
class _Check:
    """One golden signal against a result: the golden samples, the result's, and the ratio of their deviation to the
    tolerance (tolerance + spread) per sample."""

    name: str
    golden: np.ndarray
    new: np.ndarray | None
    ratio: np.ndarray
    tol: float
    spread: np.ndarray
    unit: str


def _checks(result: fl.Result, golden: fl.Result | str | Path, t_end: float | None
            ) -> tuple[fl.Result, np.ndarray, list[_Check]]:
    """The golden (loaded), its grid up to ``t_end`` and every signal's :class:`_Check` (see :func:`compare`)."""
    if not isinstance(golden, fl.Result):
        path = Path(golden)
        if not path.exists():
            raise ResultFileError(f"golden file {path} does not exist; make it with "
                                  f"'python -m flexlib.models.pump_truck.goldens --regenerate'")
        golden = fl.load_result(path)
    grid = golden.t
    if t_end is not None and not grid[0] < float(t_end) <= grid[-1]:
        raise ValueError(f"t_end = {t_end!r} s must lie in the golden's span ({grid[0]:g}, {grid[-1]:g}] s")
    end = grid[-1] if t_end is None else float(t_end)
    if result.t[-1] < end - 1e-9 or result.t[0] > grid[0] + 1e-9:
        raise ValueError(f"the result spans {result.t[0]:g} … {result.t[-1]:g} s, the golden "
                         f"{grid[0]:g} … {end:g} s: run the golden's scenario to its end")
    window = grid <= end + 1e-9
    grid = grid[window]
    signals = [k for k, n in enumerate(golden.names) if not n.startswith("spread(")]
    names = [golden.names[k] for k in signals]
    values = golden.values[:, signals]
    checks = []
    for k, name in enumerate(names):
        atol, rtol = TOLERANCES[_kind(name)]
        tol = atol + rtol * float(np.ptp(values[:, k]))  # the signal's tolerance over the whole golden
        g = values[window, k]
        spread_name = SPREAD.format(name)
        spread = golden[spread_name][window] if spread_name in golden.names else np.zeros_like(g)
        unit = golden.units[golden.names.index(name)]
        sample = _sampler(result, name)
        if sample is None:
            checks.append(_Check(name, g, None, np.full(len(g), np.inf), tol, spread, unit))
            continue
        _, ratio = tube(grid, g, sample, tol + spread, _shift(grid))  # the tube of flexlib compare
        checks.append(_Check(name, g, sample(grid), ratio, tol, spread, unit))
    return golden, grid, checks


def _plot(golden: fl.Result, grid: np.ndarray, new: dict[str, np.ndarray], bad: list[Mismatch],
          directory: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = bad[:8]
    fig, axes = plt.subplots(len(shown), 1, figsize=(9, 2.4 * len(shown)), sharex=True, squeeze=False)
    for ax, m in zip(axes[:, 0], shown, strict=True):
        ax.plot(golden.t, golden[m.name], "k-", lw=1.5, label="golden")
        if m.name in new:
            ax.plot(grid, new[m.name], "r--", lw=1.2, label="now")
        ax.axvline(m.t, color="0.6", lw=0.8)
        ax.set_ylabel(f"{m.name}\n[{m.unit}]", fontsize=8)
        ax.legend(fontsize=7, loc="best")
    axes[-1, 0].set_xlabel("time [s]")
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"golden-{golden.metadata.get('golden_scenario', 'run')}.png"
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def report(mismatches: list[Mismatch], golden: str | Path, plot_dir: Path | None = None) -> str:
    """A readable failure report: one line per failing signal, then how to look and how to regenerate."""
    lines = [f"{len(mismatches)} signal(s) differ from the golden {golden}:"]
    lines += ["  " + m.line() for m in mismatches]
    if plot_dir is not None:
        lines.append(f"overlay plot: {Path(plot_dir) / 'golden-*.png'}")
    lines.append("if the change is meant to move the results: python -m flexlib.models.pump_truck.goldens --regenerate")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Regenerate the pump-truck goldens (tests/models/goldens).")
    parser.add_argument("--regenerate", action="store_true", help="run the scenarios and overwrite the goldens")
    parser.add_argument("--scenario", help="only this scenario")
    parser.add_argument("--flexible", action="store_true", help="the flexible variant")
    args = parser.parse_args(argv)
    if not args.regenerate:
        parser.print_help()
        return 0
    todo = [(s, f, dt) for s, f, dt in GOLDENS if (args.scenario in (None, s)) and (not args.flexible or f)]
    if args.scenario and not todo:
        todo = [(args.scenario, args.flexible, 1.0)]
    for scenario, flexible, dt in todo:
        path = make_golden(scenario, flexible, dt)
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
