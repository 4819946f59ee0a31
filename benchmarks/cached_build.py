"""Benchmark: building a model from the disk cache (``models/n_mass_chain.py``).

For N masses it times, best of 7 in a fresh ``FLEXLIB_CACHE_DIR`` after one cold build:

* the floor: instantiating ``NMassChain(N)`` (pure Python, the same for any cache format);
* the cache key (``flexlib.compile.cache_key.model_key``);
* the cached build (``flexlib.build``: key, file checks against the manifest, JSON + ``.npz`` reading, and
  deserializing and checking the functions every run needs);

and prints the cached build in ms and as a ratio to the floor. Target: cached build <= 0.1 s at N = 100.
Run: ``python benchmarks/cached_build.py [N ...]`` (from the repository root). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import tempfile
import time

import flexlib as fl
from flexlib.compile.cache_key import model_key
from flexlib.models.n_mass_chain import NMassChain


def best_of(fn, repeat: int = 7) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def bench(n: int) -> tuple[float, float, float, float]:
    """Cold build [s], floor, key and cached build [s] for N masses."""
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    t0 = time.perf_counter()
    fl.build(NMassChain(n))
    cold = time.perf_counter() - t0
    models = [NMassChain(n) for _ in range(14)]
    floor = best_of(lambda: NMassChain(n))
    key = best_of(lambda: model_key(models[0], {"codegen": "auto"}))

    def cached() -> None:
        assert fl.build(models.pop()).cached

    return cold, floor, key, best_of(cached)


def main(sizes: list[int]) -> None:
    print(f"{'N':>6} {'cold [s]':>9} {'floor [ms]':>11} {'key [ms]':>9} {'cached [ms]':>12} {'cached/floor':>13}")
    rows = []
    for n in sizes:
        cold, floor, key, t_cached = bench(n)
        rows.append((n, cold, floor, key, t_cached, t_cached / floor))
        print(f"{n:>6} {cold:>9.2f} {1e3 * floor:>11.1f} {1e3 * key:>9.1f} {1e3 * t_cached:>12.1f} "
              f"{t_cached / floor:>13.2f}")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures = []
    for n, cold, _, _, t_cached, ratio in rows:
        figures += [(f"N = {n}: cold", cold, "s"), ("cached", t_cached, "s"), ("cached / floor", ratio, "")]
    report.write_results(__file__, figures, tables=[report.table(
        "Mass chain built from the disk cache (best of 7); floor = instantiating the model",
        ["N", "cold [s]", "floor [s]", "key [s]", "cached [s]", "cached / floor"], rows)])


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [10, 100])
