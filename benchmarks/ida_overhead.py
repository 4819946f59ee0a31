"""Where the scikit-sundae integrator (``flexlib.solve.backends.sksundae``) spends its time, on the mass chain.

For each N it times, interleaved and repeated (median of ``REPEAT`` rounds), on the same compiled
model, tolerances, initial values and 101-point output grid:

1. ``integrate("ida-sksundae", ...)`` (the run loop over the scikit-sundae adapter);
2. a bare loop of scikit-sundae ``IDA.step(..., "onestep")`` calls with flexlib's callbacks and
   options (the same solver work without flexlib's per-step bookkeeping);
3. the same IDA driven in ``"normal"`` mode, one ``step()`` call per output time;
4. ``IDA.solve(tspan)`` (the whole loop in C, returning only the output times);
5. CasADi's own IDAS on the same residual (``benchmarks/chain.py``'s reference route);

and the cost of one residual / Jacobian callback body (``timeit``, best of 5), times the number
of calls. Differences between the rows give flexlib's per-step Python cost (1 − 2), the cost of
a ``step()`` call in one-step mode (2 − 3), and what is left for IDA, SuperLU_MT and
scikit-sundae's callback wrapping (3 − callback bodies).

Run: ``python benchmarks/ida_overhead.py [N ...]`` (default 10 100). No timing is asserted.
"""

from __future__ import annotations

import os

os.environ["OMP_NUM_THREADS"] = "1"

import sys
import tempfile
import time
import timeit
import warnings

import numpy as np
import sksundae as sun
from chain import casadi_reference

import flexlib as fl
from flexlib.models.n_mass_chain import NMassChain
from flexlib.solve import sundae_callbacks
from flexlib.solve.solvers import integrate

REPEAT, RTOL, ATOL, T_END = 5, 1e-6, 1e-8, 10.0


def measure(n: int) -> dict:
    sim = fl.Simulation(NMassChain(n))
    m = sim.compiled
    p = np.concatenate([sim.parameter_vector(), np.zeros(m.n_relations)])
    _, starts = sim.model.values()
    y0, yp0 = sim._initialize(0.0, p, starts, False)
    grid = np.linspace(0.0, T_END, 101)
    cb = sundae_callbacks.Callbacks(m, p.copy(), np.zeros(0, dtype=int), dense=False)
    opts = dict(rtol=RTOL, atol=ATOL * m.nominal, algebraic_idx=[int(i) for i in np.flatnonzero(~m.differential)],
                linsolver="sparse", sparsity=cb.pattern, jacfn=cb.jacfn, max_num_steps=100000)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        solver = sun.ida.IDA(cb.resfn, **opts)
    counts = {}

    def flexlib_integrate():
        tr = integrate("ida-sksundae", m, sim.initializer, p.copy(), y0, yp0, 0.0, T_END, grid, rtol=RTOL, atol=ATOL)
        counts.update(steps=tr.stats["steps"], nfev=tr.stats["nfev"], njev=tr.stats["njev"])

    def onestep():
        solver.init_step(0.0, y0, yp0)
        t = 0.0
        while t < T_END:
            t = solver.step(T_END, "onestep", tstop=T_END).t

    def normal():
        solver.init_step(0.0, y0, yp0)
        for tq in grid[1:]:
            solver.step(float(tq), "normal", tstop=T_END)

    def in_c():
        solver.solve(grid, y0, yp0)

    ref = {}

    def casadi():
        ref.update(casadi_reference(m, p, y0, yp0, grid, y_only=True))

    routes = {"flexlib ida.integrate": flexlib_integrate, "bare onestep loop": onestep,
              "normal mode, 1 call per output": normal, "IDA.solve(tspan) (loop in C)": in_c}
    times: dict[str, list[float]] = {k: [] for k in routes}
    for _ in range(REPEAT):
        for name, fn in routes.items():
            t0 = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t0)
    casadi()  # best of 3 inside, build excluded
    med = {k: float(np.median(v)) for k, v in times.items()}
    # callback bodies
    r = np.zeros(m.n)
    JJ = np.zeros(len(m.jac_row))
    t_res = min(timeit.repeat(lambda: cb.resfn(0.1, y0, yp0, r), number=2000, repeat=5)) / 2000
    t_jac = min(timeit.repeat(lambda: cb.jacfn(0.1, y0, yp0, r, 10.0, JJ), number=2000, repeat=5)) / 2000
    body = counts["nfev"] * t_res + counts["njev"] * t_jac
    steps = counts["steps"]
    print(f"\nN = {n} masses ({m.n} unknowns, codegen {'yes' if m.library else 'no'}): {steps} steps, "
          f"{counts['nfev']} residual and {counts['njev']} Jacobian calls; median of {REPEAT} (ms)\n")
    print("| route | ms | µs per step |")
    print("|---|---|---|")
    for k, v in med.items():
        print(f"| {k} | {1e3 * v:.1f} | {1e6 * v / steps:.1f} |")
    print(f"| CasADi IDAS, same DAE (best of 3) | {1e3 * ref['run']:.1f} | {1e6 * ref['run'] / ref['steps']:.1f} "
          f"({ref['steps']} steps) |")
    f_, o_, n_ = med["flexlib ida.integrate"], med["bare onestep loop"], med["normal mode, 1 call per output"]
    print(f"\nflexlib per-step bookkeeping (1 − 2): {1e3 * (f_ - o_):.1f} ms; "
          f"one-step step() calls (2 − 3): {1e3 * (o_ - n_):.1f} ms = {1e6 * (o_ - n_) / steps:.1f} µs per step; "
          f"callback bodies: {1e3 * body:.1f} ms ({1e6 * t_res:.1f} µs per residual, "
          f"{1e6 * t_jac:.1f} µs per Jacobian); IDA + SuperLU_MT + scikit-sundae callback wrapping "
          f"(3 − bodies): {1e3 * (n_ - body):.1f} ms")
    return {"N": n, "unknowns": m.n, "steps": steps, **{k: v / steps for k, v in med.items()},
            "CasADi IDAS": ref["run"] / ref["steps"], "bookkeeping": (f_ - o_) / steps,
            "step() call": (o_ - n_) / steps, "callback bodies": body / steps, "IDA + wrapping": (n_ - body) / steps}


if __name__ == "__main__":
    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    os.environ.setdefault("FLEXLIB_CACHE_DIR", tempfile.mkdtemp(prefix="flexlib_bench_"))
    found = [measure(n) for n in [int(a) for a in sys.argv[1:]] or [10, 100]]
    columns = [k for k in found[0] if k not in ("N", "unknowns", "steps")]
    figures = []
    for f in found:
        figures += [(f"N = {f['N']}: flexlib", f["flexlib ida.integrate"], "s/step"),
                    ("bookkeeping", f["bookkeeping"], "s/step"), ("CasADi IDAS", f["CasADi IDAS"], "s/step")]
    report.write_results(__file__, figures, tables=[report.table(
        f"Mass chain, {T_END:g} s, rtol {RTOL:g}: time per IDA step by route and part (median of {REPEAT})",
        ["N", "unknowns", "steps", *(f"{c} [s/step]" for c in columns)],
        [[f[k] for k in ("N", "unknowns", "steps", *columns)] for f in found])])
