"""Benchmark: where the default run path spends its time, against older routes reproduced in the same process.

Four tables, each timed in one process with ratios against a floor measured in the same run:

Models whose generated C is compiled in the background (``codegen="auto"``) are timed once it is ready.

1. **State-selection monitor** — four-bar 10 s, hydraulic servo 20 s (``benchmarks/hydraulic_servo.py``),
   the triple rocker of ``tests/test_state_selection_speed.py`` 5 s and the Cartesian pendulum over the
   top 10 s (rtol 1e-9). Routes, interleaved: the floor (``dynamic_states=False``, where the model
   can run without switching), *before* (the previous monitor: full pivoted-QR/SVD test on every step
   once two selections were near-ties, reproduced here as ``LegacyMonitor``) and *after* (the current
   :class:`~flexlib.solve.state_selection.StateSelectionMonitor`). The monitor's own time is measured
   by timing every ``needs_switch`` call.
2. **Split of one step** (four-bar, servo; monitor off): model evaluation (callback bodies × calls),
   IDA + SuperLU + scikit-sundae (time inside scikit-sundae's ``step()`` minus the bodies) and
   flexlib's per-step Python (``integrate`` minus the time inside ``step()``), for the current
   ``integrate`` and for ``flexlib/solve/ida.py`` of commit fee99d3 (from git), interleaved.
3. **Result assembly** per row: one DM call of ``out.map(rows)`` (before) against the mapped
   FunctionBuffer of ``Simulation._assemble`` (after).
4. **Cold build + 10 s run of the 100-mass chain** with ``codegen=True`` (waits for gcc, as
   ``"auto"`` did before) and ``codegen="auto"`` (starts on the SX virtual machine, gcc in the
   background), then the same run once the library is ready, and the cached build.

Run: ``python benchmarks/engine_speed.py`` (from the repository root; about 3–5 minutes on a loaded
2-core machine). ``python benchmarks/engine_speed.py 1000`` adds the 1000-mass chain to table 4;
``--only=split,assembly`` (first argument) runs only the named tables.
No timing is asserted.
"""

from __future__ import annotations

import os
from functools import partial

os.environ["OMP_NUM_THREADS"] = "1"  # before numpy / sksundae are imported

import sys
import tempfile
import time
import timeit
import warnings
from pathlib import Path

import numpy as np
import sksundae as sun

import flexlib as fl
from flexlib.compile.dummy_derivatives import pick_columns
from flexlib.solve import state_selection as ss
from flexlib.solve import sundae_callbacks
from flexlib.solve.backends import base, sksundae
from flexlib.solve.simulation import Simulation
from flexlib.solve.solvers import integrate

REPEAT = 3


def _simulation(make) -> fl.Simulation:
    """Build and wait for the generated C (compiled in the background) so that every route is timed on it."""
    sim = fl.Simulation(make())
    m = sim.compiled
    while m.library is None and m.library_pending is not None:
        time.sleep(0.1)
        m.function("res")
    return sim


class LegacyMonitor(ss.StateSelectionMonitor):
    """The monitor before issue 9: full test on every ``every``-th step, on every step once the worst
    quality ratio fell below ``min(1, 2·ratio)`` (always, at the default ratio, for a near-tie)."""

    def __init__(self, rebuild, ratio: float = 0.5, every: int = 8) -> None:
        super().__init__(rebuild, ratio=ratio, every=every)

    def reset(self) -> None:
        self._skip = 0

    def needs_switch(self, model, t, y, yp, p) -> bool:
        if self._skip > 0:
            self._skip -= 1
            return False
        J = self._jlev(model, t, y, yp, p)
        worst = 1.0
        offset = 0
        for n_rows, n_cands, costs, selected in model.levels:
            block = J[offset:offset + n_rows * n_cands].reshape((n_rows, n_cands), order="F")
            offset += n_rows * n_cands
            if n_cands == n_rows:
                continue
            best = pick_columns(block, list(range(n_cands)), costs, n_rows)
            if best is None or sorted(best) == sorted(selected):
                continue
            quality = ss._smallest_sv(block[:, selected]) / max(ss._smallest_sv(block[:, best]), 1e-300)
            if quality < self.ratio:
                return True
            worst = min(worst, quality)
        self._skip = 0 if worst < min(1.0, 2 * self.ratio) else self.every - 1
        return False


class Timed:
    """Wraps a monitor's ``needs_switch`` and accumulates its wall time."""

    def __init__(self, monitor: ss.StateSelectionMonitor) -> None:
        self.monitor, self.seconds = monitor, 0.0
        inner = monitor.needs_switch

        def timed(*args):
            t = time.perf_counter()
            try:
                return inner(*args)
            finally:
                self.seconds += time.perf_counter() - t

        monitor.needs_switch = timed  # type: ignore[method-assign]


def _models():
    from flexlib.models.reference import closed_form as ref
    from flexlib.models.reference.cartesian_pendulum import CartesianPendulum
    from flexlib.models.reference.four_bar import A, B, C, D, FourBar, TripleRocker
    from flexlib.models.reference.hydraulic_servo import HydraulicServo

    th3, th4 = ref.fourbar_angles(A, B, C, D, 0.3, "open")
    return [
        ("four-bar 10 s", lambda: FourBar(0.3, th3, th4, 6.0), dict(t_end=10.0, dt_out=0.01), True),
        ("hydraulic servo 20 s", HydraulicServo, dict(t_end=20.0, dt_out=0.01), True),
        ("triple rocker 5 s", lambda: TripleRocker(1.2, 4.0), dict(t_end=5.0, dt_out=0.01, rtol=1e-7, atol=1e-9),
         False),
        ("Cartesian pendulum over the top 10 s", lambda: CartesianPendulum(init={"x": 0.0, "u": 8.0},
                                                                          guess={"y": -1.0}),
         dict(t_end=10.0, rtol=1e-9, atol=1e-11), False),
    ]


def monitor_table() -> None:
    print("## 1. State-selection monitor (median of runs; run = Simulation.run wall time)\n")
    print("| model | unknowns | steps | floor: dynamic_states=False (s) | before: run (s) | before: monitor share "
          "| before / floor | after: run (s) | after: monitor share | after / floor | after: indicator checks "
          "/ full tests / switches |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, make, kw, has_floor in _models():
        sim = _simulation(make)
        rebuild = sim._monitor().rebuild
        routes = {"after": ss.StateSelectionMonitor(rebuild), "before": LegacyMonitor(rebuild)}
        times = {k: [] for k in ("floor", "before", "after")}
        share = {k: [] for k in routes}
        info: dict = {}
        for rep in range(REPEAT):
            if has_floor:
                t = time.perf_counter()
                sim.run(progress=False, dynamic_states=False, **kw)
                times["floor"].append(time.perf_counter() - t)
            for key, mon in routes.items():
                if key == "before" and rep >= 2:  # slow: two runs are enough
                    continue
                timer = Timed(mon)
                sim._state_monitor = mon
                t = time.perf_counter()
                res = sim.run(progress=False, **kw)
                times[key].append(time.perf_counter() - t)
                share[key].append(timer.seconds / res.stats["wall_integrate"])
                del mon.needs_switch  # drop the timing wrapper
                if key == "after":
                    info = dict(steps=res.stats["steps"], switches=res.stats["state_switches"],
                                counts=dict(mon.counts))
                    mon.counts = {"indicator": 0, "full": 0}
        med = {k: float(np.median(v)) if v else np.nan for k, v in times.items()}
        sh = {k: float(np.median(v)) for k, v in share.items()}
        floor = med["floor"]

        def ratio(x: float, floor: float = floor, has_floor: bool = has_floor) -> str:
            return f"{x / floor:.2f}" if has_floor else "–"

        c = info["counts"]
        print(f"| {name} | {sim.compiled.n} | {info['steps']} | {floor:.2f} | {med['before']:.2f} | "
              f"{100 * sh['before']:.0f} % | {ratio(med['before'])} | {med['after']:.2f} | {100 * sh['after']:.1f} % | "
              f"{ratio(med['after'])} | {c['indicator']} / {c['full']} / "
              f"{info['switches']} |", flush=True)
    print("\n(floor: the same compiled DAE without the monitor — not possible for the triple rocker and the "
          "pendulum, which must switch; monitor share = time inside needs_switch / integration time; the counts "
          "are for one run.)\n")


def _count_calls(run) -> dict[str, int]:
    """Callback calls of one run (``run()``), counted by wrapping the callback methods (not timed)."""
    calls = {"resfn": 0, "jacfn": 0, "_jacfn_dense": 0, "eventsfn": 0}
    saved = {k: getattr(sundae_callbacks.Callbacks, k) for k in calls}

    def wrap(name, fn):  # scikit-sundae checks the callback signatures: no *args
        if name == "eventsfn":
            def counted(self, t, y, yp, out):
                calls[name] += 1
                return fn(self, t, y, yp, out)
        elif name == "resfn":
            def counted(self, t, y, yp, out):
                calls[name] += 1
                return fn(self, t, y, yp, out)
        else:
            def counted(self, t, y, yp, r, cj, JJ):
                calls[name] += 1
                return fn(self, t, y, yp, r, cj, JJ)
        return counted

    try:
        for k, fn in saved.items():
            setattr(sundae_callbacks.Callbacks, k, wrap(k, fn))
        run()
    finally:
        for k, fn in saved.items():
            setattr(sundae_callbacks.Callbacks, k, fn)
    calls["jacfn"] += calls.pop("_jacfn_dense")
    return calls


#: The commit before issue 9's engine work: its ``flexlib/solve/ida.py`` is the "before" integrate loop.
BEFORE_COMMIT = "fee99d3"


def _ida_before():
    """``flexlib/solve/ida.py`` as of :data:`BEFORE_COMMIT` (from git), as a module; None without git."""
    import importlib.util
    import subprocess

    root = Path(__file__).resolve().parent.parent
    proc = subprocess.run(["git", "-C", str(root), "show", f"{BEFORE_COMMIT}:flexlib/solve/ida.py"],
                          capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        return None
    path = Path(tempfile.mkdtemp(prefix="flexlib_bench_")) / "ida_before.py"
    path.write_text(proc.stdout)
    spec = importlib.util.spec_from_file_location("ida_before", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules["ida_before"] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def _split_one(name: str, make, kw: dict, ida_before) -> None:
    """One row of the split table."""
    sim = _simulation(make)
    m = sim.compiled
    p = np.concatenate([sim.parameter_vector(), np.zeros(m.n_relations)])
    _, starts = sim.model.values()
    y0, yp0 = sim._initialize(0.0, p, starts, False)
    grid = np.arange(0.0, kw["t_end"] + 1e-9, kw["dt_out"])
    t_end = kw["t_end"]
    counts: dict = {}
    inside = [0.0]
    step = sun.ida.IDA.step

    def timed_step(self, t, method="normal", tstop=None):  # time inside scikit-sundae's step()
        t0 = time.perf_counter()
        try:
            return step(self, t, method, tstop)
        finally:
            inside[0] += time.perf_counter() - t0

    def run(module) -> tuple[float, float]:
        inside[0] = 0.0
        sun.ida.IDA.step = timed_step
        try:
            t0 = time.perf_counter()
            fn = module.integrate if module is not None else partial(integrate, "ida-sksundae")
            tr = fn(m, sim.initializer, p.copy(), y0, yp0, 0.0, t_end, grid, progress=False)
            total = time.perf_counter() - t0
        finally:
            sun.ida.IDA.step = step
        counts.update(tr.stats)
        return total, inside[0]

    calls = _count_calls(lambda: run(None))
    after, before = [], []
    for _ in range(5):
        after.append(run(None))
        if ida_before is not None:
            before.append(run(ida_before))
    _, cb, _, _ = sksundae.make_solver(m, p.copy(), 1e-6, 1e-8, 0.0)
    r = np.zeros(m.n)
    JJ = np.zeros((m.n, m.n)) if m.n <= base.DENSE_MAX else np.zeros(len(m.jac_row))
    ev = np.zeros(cb.n_events)
    t_res = min(timeit.repeat(lambda: cb.resfn(0.1, y0, yp0, r), number=2000, repeat=5)) / 2000
    t_jac = min(timeit.repeat(lambda: cb.jacfn(0.1, y0, yp0, r, 10.0, JJ), number=500, repeat=5)) / 500
    t_ev = (min(timeit.repeat(lambda: cb.eventsfn(0.1, y0, yp0, ev), number=2000, repeat=5)) / 2000
            if cb.n_events else 0.0)
    steps = counts["steps"]
    body = calls["resfn"] * t_res + calls["jacfn"] * t_jac + calls["eventsfn"] * t_ev
    tot_a, in_a = (float(np.median(v)) for v in zip(*after, strict=True))
    tot_b, in_b = (float(np.median(v)) for v in zip(*before, strict=True)) if before else (np.nan, np.nan)
    us = lambda x: f"{1e6 * x / steps:.1f}"  # noqa: E731
    print(f"| {name} | {steps} | {calls['resfn']} / {calls['jacfn']} / {calls['eventsfn']} | {us(body)} | "
          f"{us(in_a - body)} | {us(tot_b - in_b)} | {us(tot_a - in_a)} | {us(tot_b)} | {us(tot_a)} |", flush=True)


def split_table() -> None:
    print("## 2. Split of the integration time per step (monitor off, generated C; median of 5, µs per step)\n")
    print("| model | steps | res / jac / event calls | model evaluation | IDA + SuperLU + scikit-sundae | "
          "flexlib per-step Python: before | after | integrate: before | after |")
    print("|---|---|---|---|---|---|---|---|---|")
    ida_before = _ida_before()
    for name, make, kw, _ in _models()[:2]:
        _split_one(name, make, kw, ida_before)
    print("\n(model evaluation = calls × the cost of one callback body through its FunctionBuffer (timeit); "
          "IDA + … = time inside scikit-sundae's step() minus the bodies; flexlib per-step Python = ida.integrate "
          "minus the time inside step(); before = flexlib/solve/ida.py of commit " + BEFORE_COMMIT + " on the "
          "same compiled model, interleaved.)\n")


def assembly_table() -> None:
    print("## 3. Result assembly (µs per row, best of 3)\n")
    print("| model | unknowns | variables | rows | before: DM call of out.map(rows) | after: mapped FunctionBuffer "
          "| speed-up |")
    print("|---|---|---|---|---|---|---|")
    for name, make, kw, _ in _models()[:2]:
        sim = _simulation(make)
        m = sim.compiled
        res = sim.run(progress=False, dynamic_states=False, **{**kw, "dt_out": None})
        T = res.t
        Y = np.ascontiguousarray(np.array([res[k] for k in m.y_names]).T)
        YP = np.zeros_like(Y)
        P = np.tile(np.concatenate([sim.parameter_vector(), np.zeros(m.n_relations)]), (len(T), 1))
        out_map = m.function("out").map(len(T))

        def before(out_map=out_map, T=T, Y=Y, YP=YP, P=P):
            return np.asarray(out_map(T[None, :], Y.T, YP.T, P.T)).T

        def after(sim=sim, m=m, T=T, Y=Y, YP=YP, P=P):
            return Simulation._assemble(sim, m, T, Y, YP, P)

        assert np.array_equal(before(), after())
        tb = min(timeit.repeat(before, number=1, repeat=3)) / len(T)
        ta = min(timeit.repeat(after, number=1, repeat=3)) / len(T)
        print(f"| {name} | {m.n} | {len(m.variables)} | {len(T)} | {1e6 * tb:.1f} | {1e6 * ta:.2f} | {tb / ta:.0f}× |",
              flush=True)
    print()


def chain_table(sizes: list[int]) -> None:
    from flexlib.models.n_mass_chain import NMassChain

    print("## 4. Chain of N masses: cold build + 10 s run (rtol 1e-6, 101 outputs), fresh cache each\n")
    print("| N | unknowns | codegen | build (s) | first run (s) | build + first run (s) | C ready after (s) | "
          "run on C (s) | cached build (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n in sizes:
        for mode in (True, "auto"):
            os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
            t0 = time.perf_counter()
            sim = fl.Simulation(NMassChain(n), codegen=mode)
            build = time.perf_counter() - t0
            t = time.perf_counter()
            sim.run(10.0, dt_out=0.1, progress=False)
            first = time.perf_counter() - t
            m = sim.compiled
            while m.library is None and m.library_pending is not None:
                time.sleep(0.05)
                m.function("res")
            ready = time.perf_counter() - t0
            t = time.perf_counter()
            sim.run(10.0, dt_out=0.1, progress=False)
            on_c = time.perf_counter() - t
            t = time.perf_counter()
            fl.Simulation(NMassChain(n), codegen=mode)
            cached = time.perf_counter() - t
            label = "True (waits for gcc)" if mode is True else '"auto" (gcc in background)'
            print(f"| {n} | {m.n} | {label} | {build:.2f} | {first:.2f} | {build + first:.2f} | {ready:.2f} | "
                  f"{on_c:.2f} | {cached:.3f} |", flush=True)
    print()


def main(argv: list[str]) -> None:
    warnings.simplefilter("ignore", UserWarning)
    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="flexlib_bench_")
    tables = {"monitor", "split", "assembly", "chain"}
    if argv and argv[0].startswith("--only="):
        tables = set(argv[0].split("=", 1)[1].split(","))
        argv = argv[1:]
    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    print(f"flexlib engine speed; scikit-sundae {sun.__version__}, OMP_NUM_THREADS=1\n")
    with report.printed() as out:
        if "monitor" in tables:
            monitor_table()
        if "split" in tables:
            split_table()
        if "assembly" in tables:
            assembly_table()
        if "chain" in tables:
            chain_table([100] + [int(a) for a in argv])
    found = report.markdown_tables(out.getvalue())
    figures = []
    for t in found:  # the first row's "after" figures of each table
        cols, first = t["columns"], t["rows"][0]
        for col in cols:
            if col.startswith(("after", "speed-up", "build + first run")) and "/" not in col[:6]:
                figures.append((f"{first[0]}: {col}", first[cols.index(col)], ""))
    report.write_results(__file__, figures[:6], tables=found)


if __name__ == "__main__":
    main(sys.argv[1:])
