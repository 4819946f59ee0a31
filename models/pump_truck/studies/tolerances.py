"""Monte Carlo of the pump truck's emergency stop over manufacturing tolerances (issue 33, study b).

Every cylinder bore ±1 %, every boom section's mass ±3 % and every cylinder's seal friction (its Coulomb force
``F_c``) ±30 %, each uniform and independent (``flexlib.study.monte_carlo``, seeded); the rigid boom's
``emergency-stop`` scenario (working pose, filled pipe, joints 1 and 2 lowering, every valve closed at 4 s) run once
per variant on Dask; kept of each run: the peak in-plane hinge force of joints 1–5 (:class:`HingeForce`)
and the peak cap-side pressure of axes 1–3. The table (Parquet, resumable) and a figure of the distributions with the
nominal machine marked; the spread printed as mean, standard deviation and the 5/95 % quantiles.

Run: ``python -m flexlib.models.pump_truck.studies.tolerances [-n 200] [--workers 2] [--out DIR]`` (about 5 minutes on
2 cores for 200 runs).
"""

from __future__ import annotations

import argparse
import functools
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from flexlib.study import Peak, monte_carlo, run_study

SCENARIO = "emergency-stop"
#: relative half-width of each tolerance band (uniform)
BORE, MASS, SEAL = 0.01, 0.03, 0.30
JOINTS, AXES = (1, 2, 3, 4, 5), (1, 2, 3)


@dataclass(frozen=True)
class HingeForce:
    """The peak in-plane hinge force of joint ``k`` [N]: the largest norm of ``joint{k}.frame_b.f[0:2]`` (the
    components across the hinge axis, z; along it the rigid linkage leaves the force statically indeterminate:
    ``result.indeterminate``)."""

    k: int

    def __call__(self, result: Any) -> float:
        f = np.column_stack([result[f"joint{self.k}.frame_b.f[{i}]"] for i in (0, 1)])
        return float(np.max(np.linalg.norm(f, axis=1)))


REDUCTIONS = {**{f"peak_f{k}": HingeForce(k) for k in JOINTS},
              **{f"peak_pA{k}": Peak(f"axis{k}.cylinder.cylinder.p_A") for k in AXES}}


def tolerances() -> dict[str, float]:
    """``{parameter: relative half-width}`` of the study."""
    out = {f"axis{k}.cylinder.cylinder.d_bore": BORE for k in JOINTS}
    out.update({f"section{k}.body.m": MASS for k in JOINTS})
    out.update({f"axis{k}.cylinder.cylinder.F_c": SEAL for k in JOINTS})
    return out


@functools.cache
def _nominal() -> tuple[tuple[str, float], ...]:
    import flexlib as fl
    from flexlib import registry

    instance, scen = registry.scenario_model("pump-truck", SCENARIO)
    sim = fl.Simulation(instance)
    vec = sim.parameter_vector(dict(scen.params))
    names = sim.compiled.param_names
    return tuple((k, float(vec[names.index(k)])) for k in tolerances())


def variants(n: int, seed: int = 1) -> list[dict[str, float]]:
    """The nominal machine followed by ``n`` samples of the tolerance bands around it [SI units]."""
    nominal = dict(_nominal())
    return [nominal, *monte_carlo(nominal, n, relative=tolerances(), seed=seed)]


def run(n: int, workers: int = 2, out: Path | None = None, progress: bool | None = None, seed: int = 1) -> Any:
    """Run the study (the nominal machine and ``n`` samples); its :class:`~flexlib.study.StudyResult`."""
    table = out / "tolerances.parquet" if out is not None else None
    return run_study("pump-truck", variants(n, seed), REDUCTIONS, scenario=SCENARIO, workers=workers, out=table,
                     progress=progress)


def summary(result: Any) -> list[tuple[str, float, float, float, float, float]]:
    """Per reduction: nominal, mean, standard deviation, 5 % and 95 % quantiles of the samples (SI units)."""
    rows = [r for r in result.rows if r["status"] == "success"]
    out = []
    for key in REDUCTIONS:
        x = np.array([r[key] for r in rows[1:]])
        out.append((key, float(rows[0][key]), float(x.mean()), float(x.std(ddof=1)), float(np.quantile(x, 0.05)),
                    float(np.quantile(x, 0.95))))
    return out


def drivers(result: Any, top: int = 3) -> dict[str, tuple[float, list[tuple[str, float]]]]:
    """Per reduction: the share of its variance a linear fit on the parameters' relative deviations explains (R²) and
    the ``top`` parameters by their contribution (|coefficient| × the deviation's standard deviation, as a fraction of
    the reduction's standard deviation)."""
    rows = [r for r in result.rows if r["status"] == "success"]
    names = list(tolerances())
    X = np.array([[r[n] / rows[0][n] - 1.0 for n in names] for r in rows[1:]])
    A = np.column_stack([np.ones(len(X)), X])
    out = {}
    for key in REDUCTIONS:
        y = np.array([r[key] for r in rows[1:]])
        coef = np.linalg.lstsq(A, y, rcond=None)[0]
        share = np.abs(coef[1:]) * X.std(axis=0) / y.std()
        order = np.argsort(-share)[:top]
        out[key] = (float(1.0 - np.var(y - A @ coef) / np.var(y)), [(names[i], float(share[i])) for i in order])
    return out


def figure(result: Any, path: Path) -> None:
    """Histograms of the peak hinge forces [kN] and cap pressures [bar], the nominal machine marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in result.rows if r["status"] == "success"]
    fig, axes = plt.subplots(2, 4, figsize=(13, 6), constrained_layout=True)
    for ax, key in zip(axes.flat, REDUCTIONS, strict=False):
        scale, unit = (1e-3, "kN") if key.startswith("peak_f") else (1e-5, "bar (absolute)")
        x = np.array([r[key] for r in rows[1:]]) * scale
        ax.hist(x, bins=20, color="tab:blue", alpha=0.8)
        ax.axvline(rows[0][key] * scale, color="tab:red", label="nominal")
        what = f"joint {key[-1]} peak hinge force" if key.startswith("peak_f") else f"axis {key[-1]} peak p_A"
        ax.set_title(what, fontsize=10)
        ax.set_xlabel(unit)
        ax.set_ylabel("runs")
        ax.legend(fontsize=8)
    fig.suptitle(f"Emergency stop over manufacturing tolerances: {len(rows) - 1} runs (bores ±1 %, section masses "
                 "±3 %, seal friction ±30 %)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=200, help="samples (besides the nominal machine)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", type=Path, default=Path("."), help="directory of the table and the figure")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    result = run(args.n, args.workers, args.out, seed=args.seed)
    failed = [r for r in result.rows if r["status"] != "success"]
    print(f"{len(result.rows) - 1} samples, {len(failed)} failed")
    print(f"{'reduction':10s} {'nominal':>12s} {'mean':>12s} {'std':>10s} {'5 %':>12s} {'95 %':>12s}")
    for key, nom, mean, std, lo, hi in summary(result):
        print(f"{key:10s} {nom:12.5g} {mean:12.5g} {std:10.3g} {lo:12.5g} {hi:12.5g}")
    for key, (r2, top) in drivers(result).items():
        print(f"{key:10s} linear fit R² {r2:.3f}; " + ", ".join(f"{n} {c:.2f}" for n, c in top))
    figure(result, args.out / "tolerances.png")
    print(f"table {args.out / 'tolerances.parquet'}, figure {args.out / 'tolerances.png'}")


if __name__ == "__main__":
    main()
