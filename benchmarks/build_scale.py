"""Benchmark: front-end build time at scale, this tree and optionally another checkout in one run.

For the N-link chain (``models/n_link_pendulum.py``) and the mass chain (``models/n_mass_chain.py``) it measures
the process CPU time of stages 1–3 (flatten, simplify, index reduction: ``pipeline.analyse``) and of stage 5's
function construction (``compile_dae`` without C and without the cache), each in a fresh subprocess, for this
tree and optionally for a second checkout (``--before PATH``, e.g. ``git archive main | tar -x -C /tmp/main``),
alternating the two so that load changes hit both. CPU time, not wall: the machine is shared. The log-log slope
over N is printed per tree. No C compiler runs; no timing is asserted.

Run: ``python benchmarks/build_scale.py [--before PATH] [--link 2 5 10 20 50] [--chain 100 1000]``.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

_CHILD = r"""
import importlib.util, json, os, sys, time
os.environ["OMP_NUM_THREADS"] = "1"
tree = sys.argv[1]
# the tree's flexlib, with its components/ and models/ as flexlib.components / flexlib.models (as setup.py installs)
spec = importlib.util.spec_from_file_location("flexlib", os.path.join(tree, "flexlib", "__init__.py"),
                                              submodule_search_locations=[os.path.join(tree, "flexlib"), tree])
sys.modules["flexlib"] = importlib.util.module_from_spec(spec)
spec.loader.exec_module(sys.modules["flexlib"])
kind, n = sys.argv[2], int(sys.argv[3])
from flexlib.compile import pipeline
from flexlib.compile.codegen import compile_dae
if kind == "link":
    from flexlib.models.n_link_pendulum import NLinkPendulum as M
else:
    from flexlib.models.n_mass_chain import NMassChain as M
root = M(n)
t0 = time.process_time()
flat, simple, dae, _ = pipeline.analyse(root)
t1 = time.process_time()
m = compile_dae(flat, simple, dae, codegen=False, build_dir=None)
t2 = time.process_time()
print(json.dumps({"analyse": t1 - t0, "compile": t2 - t1, "n": m.n, "jac_nnz": len(m.jac_row)}))
"""


def measure(tree: Path, kind: str, n: int) -> dict:
    """CPU seconds of stages 1–3 and of compile_dae for one model, in a fresh interpreter on ``tree``."""
    out = subprocess.run([sys.executable, "-c", _CHILD, str(tree), kind, str(n)], capture_output=True, text=True,
                         cwd=tree, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _sizes(argv: list[str], flag: str, default: list[int]) -> list[int]:
    if flag not in argv:
        return default
    out = []
    for a in argv[argv.index(flag) + 1:]:
        if a.startswith("--"):
            break
        out.append(int(a))
    return out


def main(argv: list[str]) -> None:
    trees = [("this tree", ROOT)]
    if "--before" in argv:
        trees.insert(0, ("before", Path(argv[argv.index("--before") + 1]).resolve()))
    cases = [("link", n) for n in _sizes(argv, "--link", [2, 5, 10, 20, 50])]
    cases += [("chain", n) for n in _sizes(argv, "--chain", [100, 1000])]
    names = " | ".join(f"{label}: stages 1–3 / compile / total (s CPU)" for label, _ in trees)
    print(f"| model | N | unknowns | Jacobian nnz | {names} |")
    print("|---|---|---|---|" + "---|" * len(trees))
    totals: dict[tuple[str, str], list[tuple[int, float]]] = {}
    rows = []
    for kind, n in cases:
        cells, info = [], None
        for label, tree in trees:
            r = measure(tree, kind, n)
            info = r
            total = r["analyse"] + r["compile"]
            totals.setdefault((kind, label), []).append((n, total))
            cells.append(f"{r['analyse']:.2f} / {r['compile']:.2f} / **{total:.2f}**")
        name = "N-link chain" if kind == "link" else "mass chain"
        print(f"| {name} | {n} | {info['n']} | {info['jac_nnz']} | " + " | ".join(cells) + " |", flush=True)
        rows.append((name, n, info["n"], info["jac_nnz"], *cells))
    figures = []
    for (kind, label), pts in totals.items():
        if label == "this tree":
            figures.append((f"{kind} N = {pts[-1][0]}: build", pts[-1][1], "s"))
        if len(pts) >= 3:
            n, t = (np.array(c, dtype=float) for c in zip(*pts, strict=True))
            slope = np.polyfit(np.log(n), np.log(t), 1)[0]
            print(f"\n{kind} ({label}): build CPU ~ N^{slope:.2f} over N = {int(n[0])}…{int(n[-1])}")
            if label == "this tree":
                figures.append(("growth", f"N^{slope:.2f}", ""))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, figures, tables=[report.table(
        "Front-end build CPU per model size (fresh interpreter per cell; no C); cells: stages 1–3 / compile / total "
        "[s]",
        ["model", "N", "unknowns", "Jacobian nnz", *(label for label, _ in trees)], rows)])


if __name__ == "__main__":
    main(sys.argv[1:])
