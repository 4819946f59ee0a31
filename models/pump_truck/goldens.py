"""Golden results of the pump-truck boom: regression references for its flows, pressures and hinge forces.

A golden is a small result file (``tests/models/goldens/<scenario>[-flexible].h5``, the HDF5 layout of
``docs/results.md``) holding the signals the boom is judged by, sampled on a decimated grid:

* per cylinder ``n``: the port flows ``cylinder{n}.cylinder.q_A``, ``q_B`` [m3/s] and the chamber pressures
  ``p_A``, ``p_B`` [Pa];
* per joint ``n``: the hinge force on section ``n`` in its frame, components ``joint{n}.frame_b.f[0]``, ``f[1]`` and
  magnitude ``joint{n}.F_hinge`` [N] (the magnitude is derived here; the components come from the run);
* the joint angles ``joint{n}.phi`` [rad] (and ``slew.phi`` if the model slews).

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
=========  ===========  ======  =====================================================================

Each golden sample may be matched anywhere within ±``TIME_SHIFT`` (a quarter) of the sampling interval of its time:
the short correction bursts of a joint holding its pose move by a few steps with round-off.

A failure names each failing signal, the time of its largest excess, golden and new values, the difference and
the tolerance, and (with ``plot_dir``) writes an overlay PNG of the failing signals there.

Regenerate deliberately (after a change that is meant to move the results; say why in the commit)::

    python -m models.pump_truck.goldens --regenerate                 # every golden
    python -m models.pump_truck.goldens --regenerate --scenario hold # one
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import flexlib as fl
from flexlib.errors import ResultFileError
from flexlib.registry import get_model, run_scenario

__all__ = ["GOLDENS", "GOLDEN_DIR", "Mismatch", "compare", "golden_path", "golden_signals", "make_golden",
           "report"]

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
TOLERANCES = {"pressure": (1e5, 0.01), "flow": (1e-6, 0.01), "force": (1e3, 0.01), "angle": (1e-4, 0.01)}


def _kind(name: str) -> str:
    if ".p_" in name:
        return "pressure"
    if ".q_" in name:
        return "flow"
    if ".f[" in name or name.endswith("F_hinge"):
        return "force"
    return "angle"


def golden_signals(result: fl.Result) -> list[str]:
    """The golden's signals present in ``result`` (the derived hinge-force magnitudes excluded)."""
    names = [f"cylinder{n}.cylinder.{v}" for n in range(1, 6) for v in ("q_A", "q_B", "p_A", "p_B")]
    names += [f"joint{n}.frame_b.f[{i}]" for n in range(1, 6) for i in (0, 1)]
    names += [f"joint{n}.phi" for n in range(1, 6)] + ["slew.phi"]
    return [n for n in names if n in result.names]


def golden_path(scenario: str, flexible: bool = False, directory: Path | None = None) -> Path:
    """File of the golden of ``scenario`` (rigid or flexible)."""
    return (directory or GOLDEN_DIR) / f"{scenario}{'-flexible' if flexible else ''}.h5"


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


def make_golden(scenario: str, flexible: bool = False, dt: float = 1.0, directory: Path | None = None) -> Path:
    """Run ``scenario`` of the registered ``pump-truck`` model and write its golden (atomically).

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
    """
    if not dt > 0:
        raise ValueError(f"make_golden: dt must be > 0 [s], got {dt!r}")
    entry = get_model("pump-truck")
    sc = entry.scenario(scenario)
    options = {**sc.options, "flexible": bool(flexible)} if flexible else dict(sc.options)
    from dataclasses import replace

    done = run_scenario("pump-truck", replace(sc, options=options), progress=False)
    res = done.result
    if not res.success:
        raise fl.SolverError(f"golden {scenario}: the run failed at t = {res.t[-1]:g} s: {res.message}")
    grid = np.arange(res.t[0], res.t[-1] + 1e-9, dt)
    names, values, units = _sampled(res, grid)
    cmd = f"python -m models.pump_truck.goldens --regenerate --scenario {scenario}" + (" --flexible" if flexible
                                                                                      else "")
    meta = {"golden_scenario": scenario, "golden_options": json.dumps(options, sort_keys=True),
            "golden_run": json.dumps(dict(sc.run), sort_keys=True), "golden_dt": repr(float(dt)),
            "golden_flexlib": getattr(fl, "__version__", "unknown"), "golden_commit": _commit(),
            "golden_command": cmd}
    golden = fl.Result(model=res.model, t=grid, names=names, values=values, units=units, docs=[""] * len(names),
                       kinds=["golden"] * len(names), parameters={}, stats={}, metadata=meta)
    path = golden_path(scenario, flexible, directory)
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

    def line(self) -> str:
        d = self.new - self.golden
        return (f"{self.name}: at t = {self.t:.3f} s golden {self.golden:.6g} {self.unit}, now {self.new:.6g} "
                f"{self.unit}, off by {d:+.4g} {self.unit} (tolerance ±{self.tolerance:.4g} {self.unit}, "
                f"{abs(d) / self.tolerance:.1f}× it)")


def compare(result: fl.Result, golden: fl.Result | str | Path, plot_dir: Path | None = None) -> list[Mismatch]:
    """Signals of ``result`` outside the golden's tolerances (empty: the result matches).

    ``result`` is sampled on the golden's grid (right values at events) and at shifts up to ``±TIME_SHIFT`` of the
    grid interval; each golden sample is compared with the closest of these values. A golden signal missing from the
    result is a mismatch at t = golden start with a NaN value. With ``plot_dir``, an overlay of the failing signals is
    written to ``plot_dir/golden-<scenario>.png``.
    """
    if not isinstance(golden, fl.Result):
        path = Path(golden)
        if not path.exists():
            raise ResultFileError(f"golden file {path} does not exist; make it with "
                                  f"'python -m models.pump_truck.goldens --regenerate'")
        golden = fl.load_result(path)
    grid = golden.t
    if result.t[-1] < grid[-1] - 1e-9 or result.t[0] > grid[0] + 1e-9:
        raise ValueError(f"the result spans {result.t[0]:g} … {result.t[-1]:g} s, the golden "
                         f"{grid[0]:g} … {grid[-1]:g} s: run the golden's scenario to its end")
    names, values, _ = _sampled(result, grid)
    new = dict(zip(names, values.T, strict=True))
    dt = float(np.median(np.diff(grid))) if grid.size > 1 else 0.0
    shifted = []
    for shift in np.linspace(-TIME_SHIFT * dt, TIME_SHIFT * dt, 9):
        times = np.clip(grid + shift, result.t[0], result.t[-1])
        shifted.append(dict(zip(names, _sampled(result, times)[1].T, strict=True)))
    out: list[Mismatch] = []
    for k, name in enumerate(golden.names):
        g = golden.values[:, k]
        atol, rtol = TOLERANCES[_kind(name)]
        tol = atol + rtol * float(np.ptp(g))
        unit = golden.units[k]
        if name not in new:
            out.append(Mismatch(name, float(grid[0]), float(g[0]), float("nan"), tol, unit))
            continue
        excess = np.min([np.abs(s[name] - g) for s in shifted], axis=0) - tol
        i = int(np.argmax(excess))
        if excess[i] > 0 or not np.all(np.isfinite(new[name])):
            out.append(Mismatch(name, float(grid[i]), float(g[i]), float(new[name][i]), tol, unit))
    if out and plot_dir is not None:
        _plot(golden, new, out, Path(plot_dir))
    return out


def _plot(golden: fl.Result, new: dict[str, np.ndarray], bad: list[Mismatch], directory: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = bad[:8]
    fig, axes = plt.subplots(len(shown), 1, figsize=(9, 2.4 * len(shown)), sharex=True, squeeze=False)
    for ax, m in zip(axes[:, 0], shown, strict=True):
        ax.plot(golden.t, golden[m.name], "k-", lw=1.5, label="golden")
        if m.name in new:
            ax.plot(golden.t, new[m.name], "r--", lw=1.2, label="now")
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
    lines.append("if the change is meant to move the results: python -m models.pump_truck.goldens --regenerate")
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
