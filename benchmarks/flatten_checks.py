"""Benchmark: cost of the flatten-time model checks on the N-link pendulum chain.

* the parameter hook (``Node.validate`` → ``Component.check``) on every instance;
* the scan of all equations for NaN/inf constants (``flat_checks.check_finite``, one CasADi function over the
  whole residual);

each timed alone and as a fraction of one ``flatten`` of the same model, in the same run (the floor).

Run: ``python benchmarks/flatten_checks.py`` (``python benchmarks/flatten_checks.py 10 50`` for chosen sizes).
No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import time

from flexlib.compile import flat_checks
from flexlib.compile import flatten as flatten_mod
from flexlib.models.n_link_pendulum import NLinkPendulum


def _best(fn, reps: int = 3) -> float:
    best = float("inf")
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main(sizes: list[int]) -> None:
    print(f"{'N':>4} {'equations':>9} {'flatten [ms]':>12} {'NaN scan [ms]':>13} {'validate [ms]':>13} {'share':>6}")
    rows = []
    for n in sizes:
        model = NLinkPendulum(n)
        flat = flatten_mod.flatten(model)
        nodes = model.walk()
        t_flat = _best(lambda n=n: flatten_mod.flatten(NLinkPendulum(n)), reps=2)
        t_nan = _best(lambda nodes=nodes, flat=flat: flat_checks.check_finite(nodes, flat.equations, flat.initial))
        t_val = _best(lambda nodes=nodes: [node.validate() for node in nodes])
        rows.append((n, len(flat.equations), t_flat, t_nan, t_val, (t_nan + t_val) / t_flat))
        print(f"{n:>4} {len(flat.equations):>9} {t_flat * 1e3:>12.1f} {t_nan * 1e3:>13.1f} {t_val * 1e3:>13.1f} "
              f"{(t_nan + t_val) / t_flat:>6.1%}")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    n, _, t_flat, _, _, share = rows[-1]
    report.write_results(__file__, [(f"N = {n}: flatten", t_flat, "s"), ("checks / flatten", share, "")],
                         tables=[report.table("N-link pendulum: flatten-time checks against one flatten (the floor)",
                                              ["N", "equations", "flatten [s]", "NaN scan [s]", "validate [s]",
                                               "checks / flatten"], rows)])


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [10, 50])
