"""Cost of the exact-zero and noise guard in the compiled state-event function against the plain indicators.

The guard is CasADi's ``if_else`` of ``flexlib.solve.events.off_zero`` (every backend's root functions), timed on
the boom of ``tests/robustness/test_initialization.py`` (4 watched relations) against the same indicators
unguarded, per call of the compiled function; interleaved, three rounds.

Run: ``python benchmarks/event_zero_guard.py``. No timing is asserted.
"""

from __future__ import annotations

import os
import tempfile
import timeit

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("FLEXLIB_CACHE_DIR", tempfile.mkdtemp(prefix="flexlib_bench_"))

import casadi as ca
import numpy as np

import flexlib as fl
from flexlib.models.reference.hydraulic_boom import CylinderBoom
from flexlib.solve.events import off_zero, state_relations


def main() -> None:
    sim = fl.Simulation(CylinderBoom())
    m = sim.compiled
    p = np.concatenate([sim.parameter_vector(), np.zeros(m.n_relations)])
    rel = state_relations(m)
    t, y, yp, pp = ca.SX.sym("t"), ca.SX.sym("y", m.n), ca.SX.sym("yp", m.n), ca.SX.sym("p", len(p))
    z = m.sx_function("ind")(t, y, yp, pp)
    plain = ca.Function("a", [t, y, yp, pp], [ca.vertcat(*[z[int(k)] for k in rel])])
    guard = ca.Function("b", [t, y, yp, pp],
                        [ca.vertcat(*[off_zero(z[int(k)], m.relations[int(k)].strict, pp[m.n_params + int(k)])
                                      for k in rel])])
    keep = []  # the buffers read these arrays: keep them alive
    calls = []
    for f in (plain, guard):
        fb, ev = f.buffer()
        arrays = (np.zeros(1), np.ones(m.n) * 0.37, np.zeros(m.n), p, np.zeros(len(rel)))
        for k, a in enumerate(arrays[:4]):
            fb.set_arg(k, memoryview(a))
        fb.set_res(0, memoryview(arrays[4]))
        keep.append((fb, arrays))
        calls.append(ev)
    n = 200_000
    rounds = []
    for _ in range(3):
        a = timeit.timeit(calls[0], number=n) / n
        b = timeit.timeit(calls[1], number=n) / n
        rounds.append((a, b, b / a))
        print(f"{len(rel)} indicators: plain {a * 1e6:.3f} us, guarded {b * 1e6:.3f} us per call "
              f"(+{(b - a) * 1e6:.3f} us, ratio {b / a:.2f})")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    a, b, ratio = min(rounds, key=lambda r: r[0])
    report.write_results(__file__, [("indicators", len(rel), ""), ("plain", a, "s/call"), ("guarded", b, "s/call"),
                                    ("guarded / plain", ratio, "")], tables=[report.table(
        f"{len(rel)} state-event indicators, {n} calls per round, interleaved",
        ["plain [s/call]", "guarded [s/call]", "guarded / plain"], rounds)])


if __name__ == "__main__":
    main()
