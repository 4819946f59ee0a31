"""Benchmark: cold build + first run of the N-mass chain, this tree and optionally a git revision before.

For each N (default 100 and 1000) and each source tree, a fresh Python process (imports and the native driver
warmed on a 5-mass chain first) measures, as **process CPU time** (``time.process_time``: the background gcc
is another process and is not counted; this 2-core machine is shared, so CPU time is steadier than wall time):

* ``build``: ``fl.Simulation(NMassChain(N))`` in a new, empty ``FLEXLIB_CACHE_DIR`` (instantiation included);
* ``run``: the first ``sim.run(10.0, dt_out=0.1, rtol=1e-6, atol=1e-8)`` of that simulation (it starts on
  CasADi's VM while gcc compiles in the background);
* ``cached``: ``fl.Simulation(NMassChain(N))`` again on the filled cache (instantiation included);

best of ``--repeat`` (default 3) for each figure. "before" is the tree of git revision ``--before``, exported
with ``git archive``; "after" is this working tree. Targets: build + run <= 0.5 s at N = 100, <= 10 s at N = 1000;
cached <= 0.1 s at N = 100. No timing is asserted.

Run (from the repository root)::

    python benchmarks/cold_chain.py                  # N = 100, 1000; before (8ee10ca) and after (~3 min)
    python benchmarks/cold_chain.py 100 --no-before  # this tree only
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def load_tree(root: str) -> None:
    """Import the flexlib of the source tree ``root``, with its ``components/`` and ``models/`` as
    ``flexlib.components`` / ``flexlib.models`` (as setup.py installs them)."""
    spec = importlib.util.spec_from_file_location("flexlib", os.path.join(root, "flexlib", "__init__.py"),
                                                  submodule_search_locations=[os.path.join(root, "flexlib"), root])
    assert spec is not None and spec.loader is not None
    sys.modules["flexlib"] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(sys.modules["flexlib"])


def measure(root: str, n: int, repeat: int) -> dict[str, float]:
    """Best-of-``repeat`` process CPU [s] of cold build, first run and cached build of the tree ``root``."""
    os.environ["OMP_NUM_THREADS"] = "1"
    load_tree(root)
    import flexlib as fl
    from flexlib.models.n_mass_chain import NMassChain

    os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="cold_chain_warm_")
    fl.Simulation(NMassChain(5)).run(1.0, dt_out=0.1)  # imports, native driver
    best = {"build": float("inf"), "run": float("inf"), "cached": float("inf"), "total": float("inf")}
    for _ in range(repeat):
        os.environ["FLEXLIB_CACHE_DIR"] = tempfile.mkdtemp(prefix="cold_chain_")
        t0 = time.process_time()
        sim = fl.Simulation(NMassChain(n))
        t1 = time.process_time()
        sim.run(10.0, dt_out=0.1, rtol=1e-6, atol=1e-8)
        t2 = time.process_time()
        fl.Simulation(NMassChain(n))
        t3 = time.process_time()
        for key, value in (("build", t1 - t0), ("run", t2 - t1), ("cached", t3 - t2), ("total", t2 - t0)):
            best[key] = min(best[key], value)
    return best


def export(rev: str) -> str:
    """The source tree of git revision ``rev`` in a temporary directory."""
    out = tempfile.mkdtemp(prefix=f"cold_chain_{rev}_")
    data = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True, capture_output=True).stdout
    with tempfile.TemporaryFile() as fh:
        fh.write(data)
        fh.seek(0)
        with tarfile.open(fileobj=fh) as tar:
            tar.extractall(out, filter="data")
    return out


def run_worker(root: str, n: int, repeat: int) -> dict[str, float]:
    """:func:`measure` in a fresh interpreter (no module state shared between trees)."""
    proc = subprocess.run([sys.executable, __file__, "--worker", root, str(n), "--repeat", str(repeat)],
                          check=True, capture_output=True, text=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sizes", nargs="*", type=int, default=[100, 1000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--before", default="8ee10ca", help="git revision measured as 'before'")
    parser.add_argument("--no-before", action="store_true", help="measure this tree only")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        print(json.dumps(measure(args.worker, args.sizes[0], args.repeat)))
        return
    trees = [("after", str(ROOT))]
    if not args.no_before:
        trees.insert(0, (f"before ({args.before})", export(args.before)))
    print(f"process CPU [s], best of {args.repeat}; 10 s run at rtol 1e-6, atol 1e-8, dt_out 0.1")
    print(f"{'N':>5}  {'tree':<18} {'build cold':>10} {'first run':>10} {'build+run':>10} {'cached':>8}")
    rows = []
    for n in args.sizes:
        for label, root in trees:
            r = run_worker(root, n, args.repeat)
            rows.append((n, label, r["build"], r["run"], r["total"], r["cached"]))
            print(f"{n:>5}  {label:<18} {r['build']:>10.3f} {r['run']:>10.3f} {r['total']:>10.3f} {r['cached']:>8.3f}")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures = []
    for n, _, build, _, total, cached in (r for r in rows if r[1] == "after"):
        figures += [(f"N = {n}: build + first run", total, "s"), ("build", build, "s"), ("cached", cached, "s")]
    report.write_results(__file__, figures, tables=[report.table(
        f"Mass chain, process CPU, best of {args.repeat}; 10 s run at rtol 1e-6, atol 1e-8, dt_out 0.1; 'after' is "
        "this tree", ["N", "tree", "build cold [s]", "first run [s]", "build + run [s]", "cached [s]"], rows)])


if __name__ == "__main__":
    main()
