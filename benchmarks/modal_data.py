"""Modal data for flexible bodies: accuracy against closed forms and the cost of producing it.

Accuracy of the beam mesher + Craig–Bampton reduction against Euler–Bernoulli closed forms, the MPF table of the
seed-001 beam beside the paper's Table 2, geometric stiffening against published values, and the CPU cost of
producing, writing, reading and hashing modal data for a 500-node body with 5…40 modes. Prints tables; asserts
nothing.

Run: ``python benchmarks/modal_data.py`` (about 20 s).
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np
import scipy.linalg as la

from flexlib.fe import (
    ModalData,
    Section,
    beam_mesh,
    box,
    craig_bampton,
    modal_data_from_fe,
    modal_participation,
    rectangle,
)


def bending_y(md: ModalData) -> np.ndarray:
    t = md.translational_modes
    parts = np.einsum("mna,mna->ma", t, t)
    return (parts[:, 1] > 0.9 * parts.sum(axis=1)) & (parts[:, 1] > 1e-9 * parts[:, 1].max())


def row(label: str, errors: np.ndarray) -> tuple:
    print(f"{label:<44}" + "".join(f"{x:10.4f} " for x in 100 * errors))
    return (label, *(100 * errors))


def accuracy() -> list[tuple]:
    E, rho, L, sec = 2.1e11, 7850.0, 2.0, rectangle(0.02, 0.03)
    scale = math.sqrt(E * sec.Iz / (rho * sec.A * L**4))
    print("Mesher + improved Craig–Bampton vs Euler–Bernoulli closed form, first three x-y bending modes")
    print(f"{'case':<44} {'err 1 [%]':>10} {'err 2 [%]':>10} {'err 3 [%]':>10}")
    rows = []
    for mass, n_el in (("consistent", 32), ("lumped", 32), ("lumped", 64)):
        fe = beam_mesh((0, 0, 0), (L, 0, 0), n_el, sec, E=E, rho=rho, mass=mass)
        md = modal_data_from_fe(fe, [0, n_el], 12)
        got = 2 * math.pi * md.frequencies[bending_y(md)][:3]
        ref = np.array([4.7300, 7.8532, 10.9956]) ** 2 * scale
        rows.append(row(f"free-free, {mass}, {n_el} el., 12 modes", got / ref - 1))
        fc = fe.constrained([0])
        cb = craig_bampton(fc.M, fc.K, fc.dofs([n_el]), 12)
        t = cb.modes[fc.dof_map[:, 1][fc.dof_map[:, 1] >= 0]]
        mask = np.sum(t**2, axis=0) > 0.9 * np.sum(cb.modes[np.concatenate(
            [fc.dof_map[:, a][fc.dof_map[:, a] >= 0] for a in range(3)])] ** 2, axis=0)
        got = cb.omega[mask][:3]
        ref = np.array([1.8751, 4.6941, 7.8548]) ** 2 * scale
        rows.append(row(f"clamped, {mass}, {n_el} el., 12 modes", got / ref - 1))
    # seed 001 pinned-free through the linearised floating frame (see tests/.../test_craig_bampton.py)
    s = Section(A=1e-4, Iy=1e-10, Iz=1e-10, J=2e-10, name="seed 001")
    fe = beam_mesh((0, 0, 0), (1.5, 0, 0), 32, s, E=2e11, rho=8000.0)
    md = modal_data_from_fe(fe, [0, 32], 10)
    inv, m = md.invariants, md.n_modes
    Mf = np.zeros((6 + m, 6 + m))
    c = inv["I2"]
    I2x = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
    Mf[:3, :3], Mf[:3, 3:6], Mf[3:6, :3] = float(inv["I1"]) * np.eye(3), -I2x, I2x
    Mf[:3, 6:], Mf[6:, :3], Mf[3:6, 3:6] = inv["I3"], inv["I3"].T, inv["I7"]
    Mf[3:6, 6:], Mf[6:, 3:6], Mf[6:, 6:] = inv["I4"], inv["I4"].T, inv["I6"]
    Kf = np.zeros_like(Mf)
    Kf[6:, 6:] = md.generalized_stiffness
    N = la.null_space(np.hstack([np.eye(3), np.zeros((3, 3)), md.translational_modes[:, 0, :].T]))
    w = np.sqrt(np.clip(la.eigh(N.T @ Kf @ N, N.T @ Mf @ N, eigvals_only=True), 0, None))
    got = np.unique(np.round(w[w > 1.0], 3))[:3]
    ref = np.array([3.9266, 7.0686, 10.2102]) ** 2 * math.sqrt(2e11 * 1e-10 / (8000 * 1e-4 * 1.5**4))
    rows.append(row("seed-001 pinned-free, 32 el., 10 modes", got / ref - 1))
    return rows


def mpf_table() -> list[tuple]:
    s = Section(A=1e-4, Iy=4e-10, Iz=1e-10, J=2e-10, name="seed 001")
    fe = beam_mesh((0, 0, 0), (1.5, 0, 0), 64, s, E=2e11, rho=8000.0)
    b = np.concatenate([fe.dofs([0]), fe.dofs([64], ["ux", "uy", "uz"])])
    cb = craig_bampton(fe.M, fe.K, b, 30, orthogonalize=False)
    field = np.zeros(fe.n_dofs)
    field[fe.dof_map[:, 1]] = fe.nodes[:, 0]
    field[fe.dof_map[:, 5]] = 1.0
    table = modal_participation(cb.basis[:, b.size:], cb.fixed_interface_omega**2, fe.M @ field,
                                frequencies=cb.fixed_interface_omega / (2 * math.pi))
    rows = [r for r in table.rows if r.share > 1e-6][:7]
    paper = [100, 3.46, 0.77, 0.17, 0.06, 0.02, 0.01]
    print("\nSeed-001 beam, clamped-pinned (fixed-interface) bending modes, 64 elements, load rho A alpha x")
    print(f"{'mode':>4} {'f [Hz]':>9} {'MPF [%]':>9} {'paper Table 2':>14}")
    for k, (r, p) in enumerate(zip(rows, paper)):
        print(f"{k + 1:>4} {r.frequency:9.3f} {r.share:9.3f} {p:14.2f}")
    return [(k + 1, r.frequency, r.share, p) for k, (r, p) in enumerate(zip(rows, paper))]


def stiffening() -> tuple[float, float]:
    E, rho, L, b, h = 2.1e11, 7850.0, 2.0, 0.02, 0.03
    fe = beam_mesh((0, 0, 0), (L, 0, 0), 32, rectangle(b, h), E=E, rho=rho).constrained([0])
    md = modal_data_from_fe(fe, [32], 10, free=False, geometric_stiffening=True, support_nodes=[0])
    K, M = md.generalized_stiffness, md.generalized_mass
    w0 = la.eigh(K, M, eigvals_only=True)[0]
    G = md.geometric_stiffness["omega_zz"]
    k1 = (la.eigh(K + 1e-4 * w0 * G, M, eigvals_only=True)[0] - w0) / (1e-4 * w0)
    G = md.geometric_stiffness["F32_ux"]
    lam = la.eigh(K, G + 1e-12 * np.abs(G).max() * np.eye(md.n_modes), eigvals_only=True)
    pcr = lam[lam > 0].min() / (math.pi**2 * E * h * b**3 / 12 / (4 * L**2))
    print("\nGeometric stiffening, cantilever 32 el., 10 modes: Southwell K1 = "
          f"{k1:.5f} (published 1.1933); buckling load / (pi^2 E I / 4 L^2) = {pcr:.7f}")
    return k1, pcr


def timing() -> list[tuple]:
    print("\n500-node Timoshenko box beam (499 elements, 3000 DOFs), interface at both ends; CPU seconds")
    print(f"{'modes':>5} {'n kept':>6} {'mesh':>7} {'reduce+inv':>10} {'write':>7} {'read':>7} {'hash':>7} {'MB':>6}")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in (5, 10, 20, 40):
            t0 = time.process_time()
            fe = beam_mesh((0, 0, 0), (5.0, 0, 0), 499, box(0.2, 0.3, 0.01), E=2.1e11, rho=7850.0,
                           theory="timoshenko")
            t1 = time.process_time()
            md = modal_data_from_fe(fe, [0, 499], n)
            t2 = time.process_time()
            path = md.write(Path(tmp) / f"m{n}.h5")
            t3 = time.process_time()
            back = ModalData.read(path)
            t4 = time.process_time()
            back.content_hash()
            t5 = time.process_time()
            print(f"{n:>5} {md.n_modes:>6} {t1 - t0:7.3f} {t2 - t1:10.3f} {t3 - t2:7.3f} {t4 - t3:7.3f} "
                  f"{t5 - t4:7.4f} {path.stat().st_size / 1e6:6.2f}")
            rows.append((n, md.n_modes, t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4, path.stat().st_size))
    return rows


if __name__ == "__main__":
    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    errors, mpf, (k1, pcr), cost = accuracy(), mpf_table(), stiffening(), timing()
    twenty = next(r for r in cost if r[0] == 20)
    report.write_results(__file__, [
        ("free-free, consistent, 32 el.: frequency errors 1–3", " / ".join(f"{e:.3f}" for e in errors[0][1:]), "%"),
        ("seed-001 pinned-free", " / ".join(f"{e:.3f}" for e in errors[-1][1:]), "%"),
        ("Southwell K1", k1, ""), ("500 nodes, 20 modes: reduce", twenty[3], "s"), ("read", twenty[5], "s")],
        tables=[report.table("Mesher + improved Craig–Bampton vs Euler–Bernoulli closed form, x-y bending",
                             ["case", "error 1 [%]", "error 2 [%]", "error 3 [%]"], errors),
                report.table("Seed-001 beam, fixed-interface bending modes, 64 elements, load rho A alpha x",
                             ["mode", "f [Hz]", "MPF [%]", "paper Table 2 [%]"], mpf),
                report.table("500-node Timoshenko box beam (3000 DOFs), process CPU",
                             ["modes asked", "modes kept", "mesh [s]", "reduce + invariants [s]", "write [s]",
                              "read [s]", "hash [s]", "file [B]"], cost)],
        notes=[f"Geometric stiffening, cantilever: Southwell K1 = {k1:.5f} (published 1.1933); buckling load / "
               f"(pi^2 E I / 4 L^2) = {pcr:.7f}"])
