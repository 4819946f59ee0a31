"""Build cost of the planar-geometry assumption (``assume_zero_geometry``, flexlib/compile/constants.py).

For long models, per build choice (default: assumed; opt-out: ``assume_zero_geometry=False``) in one process:
unknowns after stage 2, CPU time [s] of the constant elimination alone (``eliminate_constants``) and of the
whole build without cache and without C (``flexlib.build(..., codegen=False)``: flatten, simplify, index
reduction, CasADi functions). Models: ``models/n_link_pendulum.py`` (planar N-link pendulum of 3D components)
and ``models/n_mass_chain.py`` (1D chain, no frame parameters: the assumption has nothing to do).

Run ``python benchmarks/zero_geometry.py [--sizes 20,50] [--chain 1000]`` from the repository root.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import time

import flexlib as fl
from flexlib.compile.constants import eliminate_constants
from flexlib.compile.flatten import flatten
from flexlib.compile.passes.multibody.redundancy import remove_redundant
from flexlib.compile.passes.multibody.tearing import eliminate_frame_kinematics
from flexlib.compile.simplify import simplify
from flexlib.models.n_link_pendulum import NLinkPendulum
from flexlib.models.n_mass_chain import NMassChain


def measure(make, zero: bool) -> tuple[int, int, float, float]:
    """(unknowns before, after the elimination, elimination CPU [s], whole uncached build CPU [s])."""
    flat = flatten(make(), check=False)
    params = {q.sym.element_hash(): q.value for q in flat.parameters}
    torn = eliminate_frame_kinematics(remove_redundant(simplify(flat), params))
    c0 = time.process_time()
    simple = eliminate_constants(torn, params, assume_zero_geometry=zero)
    c_const = time.process_time() - c0
    c0 = time.process_time()
    fl.build(make(), codegen=False, use_cache=False, assume_zero_geometry=zero)
    return len(torn.variables), len(simple.variables), c_const, time.process_time() - c0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="5,20,50", help="N-link pendulum sizes")
    ap.add_argument("--chain", type=int, default=1000, help="mass-chain size (0: skip)")
    args = ap.parse_args()
    cases = [(f"N-link pendulum N = {n}", lambda n=n: NLinkPendulum(n)) for n in map(int, args.sizes.split(","))]
    if args.chain:
        cases.append((f"mass chain N = {args.chain}", lambda: NMassChain(args.chain)))
    print("CPU = process time; one build per cell (machine shared: compare within a row)\n")
    print("| model | build | unknowns after tearing | after constants | constants CPU (s) | whole build CPU (s) |")
    print("|---|---|---|---|---|---|")
    rows = []
    for label, make in cases:
        for zero, what in ((False, "assume_zero_geometry=False"), (True, "default (assumed)")):
            n0, n1, c_const, c_build = measure(make, zero)
            rows.append((label, what, n0, n1, c_const, c_build))
            print(f"| {label} | {what} | {n0} | {n1} | {c_const:.2f} | {c_build:.2f} |", flush=True)

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    figures = []
    for off, on in zip(rows[::2], rows[1::2], strict=True):
        figures += [(f"{on[0]}: unknowns", f"{off[3]} → {on[3]}", ""), ("build", on[5], "s"),
                    ("build / opt-out", on[5] / off[5], "")]
    report.write_results(__file__, figures, tables=[report.table(
        "Planar geometry assumed (default) or not, one uncached build without C per cell (process CPU)",
        ["model", "build", "unknowns after tearing", "after constants", "constants [s]", "whole build [s]"], rows)])


if __name__ == "__main__":
    main()
