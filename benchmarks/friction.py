"""Stick/slip friction (MSL PartialFriction, events) against a regularised law: run time and what sticking costs.

Two cases, each run with the hybrid element (modes as state events, sticking exact) and with a regularised law
``tau = tau_c · tanh(w / w_reg)`` (no events; a stuck element creeps at the speed where the law gives the holding
torque), interleaved, fastest of three:

* MSL's ``Rotational.Examples.CoupledClutches`` (three clutches, 1.5 s; the regularised clutches at
  ``w_reg = 1e-3`` rad/s): run time, events, and the largest clutch-1 slip speed while the hybrid one is stuck;
* a 1 kg block on a support with 10 N sliding friction (hybrid: 15 N breakaway) pushed by 9 N for 10 s
  (regularised at ``v_reg = 1e-3`` m/s): distance moved.

Run: ``python benchmarks/friction.py``. No timing is asserted.
"""

from __future__ import annotations

import os
import tempfile
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("FLEXLIB_CACHE_DIR", tempfile.mkdtemp(prefix="flexlib_bench_"))

import casadi as ca
import numpy as np

import flexlib as fl
from flexlib import Input, Parameter, eq
from flexlib.components.control import Constant
from flexlib.components.mechanics.rotational.interfaces import PartialCompliantWithRelativeStates
from flexlib.components.mechanics.translational import Force, Mass, SupportFriction
from flexlib.components.mechanics.translational.interfaces import PartialTwoFlanges
from flexlib.models.reference.drive_trains import CoupledClutches

W_REG = 1e-3  # regularisation speed [rad/s] and [m/s]


class TanhClutch(PartialCompliantWithRelativeStates):
    """The peer: a clutch with the regularised law ``tau = cgeo fn mu tanh(w_rel / w_reg)``."""

    mu = Parameter(0.5, unit="1", doc="Friction coefficient")
    cgeo = Parameter(1.0, unit="m", doc="Geometry constant")
    fn_max = Parameter(unit="N", doc="Maximum normal force")
    w_reg = Parameter(W_REG, unit="rad/s", doc="Regularisation speed")
    f_normalized = Input(unit="1", doc="Normalised normal force")

    def __init__(self, peak: float = 1.0, **kw: object) -> None:  # (no breakaway peak in a regularised law)
        super().__init__(**kw)

    def equations(self) -> list:
        fn = self.fn_max * fl.no_event(self.f_normalized > 0, self.f_normalized, 0.0)
        return [*super().equations(),
                eq(self.tau, self.cgeo * fn * self.mu * ca.tanh(self.w_rel / self.w_reg))]


class TanhSupportFriction(PartialTwoFlanges):
    """The peer: support friction ``f = f_c tanh(v / v_reg)`` on a grounded support."""

    f_c = Parameter(unit="N", doc="Coulomb friction force")
    v_reg = Parameter(W_REG, unit="m/s", doc="Regularisation speed")

    def equations(self) -> list:
        fa, fb = self.flange_a, self.flange_b
        v = fl.der(fa.s)
        return [eq(fb.s, fa.s), eq(fa.f + fb.f, self.f_c * ca.tanh(v / self.v_reg))]


class Block(fl.Model):
    """A 1 kg block pushed by 9 N against friction (hybrid: 10 N sliding, 15 N breakaway; regularised: 10 N)."""

    def __init__(self, regularised: bool) -> None:
        super().__init__()
        self.source = Constant(k=9.0)
        self.push = Force()
        self.block = Mass(m=1.0, init={"s": 0.0, "v": 0.0})
        self.friction = (TanhSupportFriction(f_c=10.0) if regularised
                         else SupportFriction(f_pos=[[0.0, 10.0]], peak=1.5))
        self.connect(self.source.y, self.push.f)
        self.connect(self.push.flange, self.block.flange_a)
        self.connect(self.block.flange_b, self.friction.flange_a)


def timed(sim: fl.Simulation, t_end: float, dt: float) -> tuple[float, fl.Result]:
    c0 = time.process_time()
    res = sim.run(t_end, dt_out=dt, rtol=1e-6, progress=False)
    return time.process_time() - c0, res


def main() -> None:
    sims = {"hybrid": fl.Simulation(CoupledClutches()),
            "regularised": fl.Simulation(CoupledClutches(clutch=TanhClutch))}
    best: dict[str, tuple[float, fl.Result]] = {}
    for _ in range(3):
        for name, sim in sims.items():
            cpu, res = timed(sim, 1.5, 0.0005)
            if name not in best or cpu < best[name][0]:
                best[name] = (cpu, res)
    hyb, reg = best["hybrid"][1], best["regularised"][1]
    stuck = hyb["clutch1.locked"] > 0.5
    creep = float(np.max(np.abs(reg.value("clutch1.w_rel", hyb.t[stuck], side="right"))))
    rows = [(name, cpu, res.stats["steps"], res.stats["state_events"]) for name, (cpu, res) in best.items()]
    ratio = best["hybrid"][0] / best["regularised"][0]
    print("CoupledClutches, 1.5 s, rtol 1e-6 (fastest of 3, interleaved):")
    for name, cpu, steps, events in rows:
        print(f"  {name:12s} {cpu * 1e3:8.1f} ms CPU  {steps:6d} steps  {events:3d} state events")
    print(f"  hybrid / regularised: {ratio:.2f}; clutch-1 slip while the hybrid is stuck: regularised "
          f"{creep:.2e} rad/s, hybrid {float(np.max(np.abs(hyb['clutch1.w_rel'][stuck]))):.2e} rad/s")
    blocks = {}
    for regularised in (False, True):
        cpu, res = timed(fl.Simulation(Block(regularised)), 10.0, 0.5)
        blocks["regularised" if regularised else "hybrid"] = (cpu, float(np.max(np.abs(res["block.s"]))))
    print("Block pushed by 9 N for 10 s (sliding friction 10 N):")
    for name, (cpu, moved) in blocks.items():
        print(f"  {name:12s} {cpu * 1e3:8.1f} ms CPU  moved {moved:.3e} m")

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    report.write_results(__file__, [
        ("CoupledClutches hybrid", best["hybrid"][0], "s"), ("regularised", best["regularised"][0], "s"),
        ("hybrid / regularised", ratio, ""), ("regularised slip while stuck", creep, "rad/s"),
        ("block moved, hybrid", blocks["hybrid"][1], "m"), ("block moved, regularised", blocks["regularised"][1], "m"),
    ], tables=[
        report.table("CoupledClutches, 1.5 s, rtol 1e-6, fastest of 3 interleaved",
                     ["law", "CPU [s]", "steps", "state events"], rows),
        report.table("Block pushed by 9 N for 10 s (sliding friction 10 N; hybrid breakaway 15 N)",
                     ["law", "CPU [s]", "moved [m]"], [(k, c, m) for k, (c, m) in blocks.items()]),
    ])


if __name__ == "__main__":
    main()
