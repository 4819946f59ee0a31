"""Structurally constant unknowns eliminated after tearing (flexlib/compile/constants.py).

Models: the planar four-bar of the catalogue (flexlib.models.reference.four_bar: crank A, coupler B, rocker C,
ground D) and a planar 7-body, 3-loop mechanism of ordinary 3D components (three four-bars in
series: each rocker drives the next four-bar as its crank). References: a hand-written minimal dummy-derivative
DAE of each mechanism in absolute link angles (CasADi SX, written below): states θ1, ω1; algebraic the other
angles, their rates (dummy derivatives) and accelerations, and the loop multipliers; rows θ1' = ω1, the
Lagrange equations M(q)q'' + h = Gᵀλ + Q, the loop constraints g(q) = 0 and their first and second derivatives.
The closed-form four-bar position analysis (Norton §4.5) is in flexlib.models.reference.closed_form.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Fixed, FixedTranslation, Revolute, World
from flexlib.models.reference import closed_form as ref
from flexlib.models.reference.four_bar import A, B, C, D, FourBar, link_body
from flexlib.units import g_n


@pytest.fixture(autouse=True)
def _zero_geometry(monkeypatch):
    """The planar reduction relies on zero frame parameters; it is the default (opt-out:
    ``FLEXLIB_ZERO_GEOMETRY=0`` or ``assume_zero_geometry=False``): test the default."""
    monkeypatch.delenv("FLEXLIB_ZERO_GEOMETRY", raising=False)

M_CRANK, M_COUPLER, M_ROCKER = 1.0, 2.0, 1.5  # kg


def chain_angles(theta1: float) -> list[float]:
    """Absolute angles θ1…θ7 of the three-loop chain (each loop: the open four-bar solution for its input)."""
    out = [theta1]
    for _ in range(3):
        th_c, th_r = (float(x) for x in ref.fourbar_angles(A, B, C, D, out[-1], "open"))
        out += [th_c, th_r]
    return out


class PlanarChain(fl.Model):
    """Seven links, ten revolutes, three loops, one degree of freedom, in the vertical x–y plane (gravity −y).

    Loop k (k = 1, 2, 3): input link about the pivot at ((k−1)·D, 0) — the crank for k = 1, the previous rocker
    (a point at distance A along it) for k > 1 — coupler B, rocker C about (k·D, 0); closed at the coupler–rocker
    revolute.
    """

    def __init__(self, theta1: float = 0.3, w1: float = 2.0) -> None:
        super().__init__()
        th = chain_angles(theta1)
        self.world = World()
        self.rev_in = Revolute(init={"phi": th[0], "w": w1})
        self.crank = FixedTranslation(r=[A, 0, 0])
        self.crank_mass = link_body(M_CRANK, A)
        self.connect(self.world.frame_b, self.rev_in.frame_a)
        self.connect(self.rev_in.frame_b, self.crank.frame_a)
        self.connect(self.crank.frame_b, self.crank_mass.frame_a)
        driver, angle = self.crank.frame_b, th[0]
        for k in range(1, 4):
            th_c, th_r = th[2 * k - 1], th[2 * k]
            ground = Fixed(r=[k * D, 0, 0])
            couple = Revolute(guess={"phi": th_c - angle})
            coupler = FixedTranslation(r=[B, 0, 0])
            coupler_mass = link_body(M_COUPLER, B)
            pivot = Revolute(guess={"phi": th_r})
            rocker = FixedTranslation(r=[C, 0, 0])
            rocker_mass = link_body(M_ROCKER, C)
            close = Revolute(guess={"phi": th_r - th_c})
            for name, comp in [("ground", ground), ("couple", couple), ("coupler", coupler),
                               ("coupler_mass", coupler_mass), ("pivot", pivot), ("rocker", rocker),
                               ("rocker_mass", rocker_mass), ("close", close)]:
                setattr(self, f"{name}{k}", comp)
            self.connect(driver, couple.frame_a)
            self.connect(couple.frame_b, coupler.frame_a)
            self.connect(coupler.frame_b, coupler_mass.frame_a, close.frame_a)
            self.connect(ground.frame_b, pivot.frame_a)
            self.connect(pivot.frame_b, rocker.frame_a)
            self.connect(rocker.frame_b, rocker_mass.frame_a)
            self.connect(close.frame_b, rocker.frame_b)
            if k < 3:  # the next loop's input: a point at distance A along this rocker
                arm = FixedTranslation(r=[A, 0, 0])
                setattr(self, f"arm{k}", arm)
                self.connect(pivot.frame_b, arm.frame_a)
                driver = arm.frame_b
            angle = th_r


# --- hand-written minimal dummy-derivative DAEs ----------------------------------------------------------------

def _e(th: ca.SX) -> ca.SX:
    return ca.vertcat(ca.cos(th), ca.sin(th))


def hand_dae(loops: int) -> tuple[ca.Function, int]:
    """Residual ``res(y, yp, p)`` of the minimal DAE of a chain of ``loops`` four-bars, and its size.

    Links (absolute angles): crank θ1, then per loop k coupler θ(2k), rocker θ(2k+1). ``p = [A, B, C, D, m_crank,
    m_coupler, m_rocker, g]``; each link's centre of mass is its midpoint, its inertia about the centre m L²/12.
    """
    a, b, c, d, m1, m2, m3, g = (ca.SX.sym(n) for n in ("A", "B", "C", "D", "m1", "m2", "m3", "g"))
    p = ca.vertcat(a, b, c, d, m1, m2, m3, g)
    nq = 1 + 2 * loops
    q, dq, ddq = ca.SX.sym("q", nq), ca.SX.sym("dq", nq), ca.SX.sym("ddq", nq)
    lam = ca.SX.sym("lam", 2 * loops)
    bodies = [(m1, a, a / 2 * _e(q[0]))]  # (mass, length, CM position)
    cons = []
    base, driver_angle = ca.SX.zeros(2), q[0]
    for k in range(loops):
        th_c, th_r = q[1 + 2 * k], q[2 + 2 * k]
        tip = base + a * _e(driver_angle)
        pivot = ca.vertcat((k + 1) * d, 0)
        bodies += [(m2, b, tip + b / 2 * _e(th_c)), (m3, c, pivot + c / 2 * _e(th_r))]
        cons.append(tip + b * _e(th_c) - pivot - c * _e(th_r))
        base, driver_angle = pivot, th_r
    gq = ca.vertcat(*cons)
    G = ca.jacobian(gq, q)
    gdot = ca.mtimes(G, dq)
    gddot = ca.jtimes(gdot, q, dq) + ca.mtimes(G, ddq)
    eom = -ca.mtimes(G.T, lam)
    for k, (m, L, r) in enumerate(bodies):
        J = ca.jacobian(r, q)
        acc = ca.jtimes(ca.mtimes(J, dq), q, dq) + ca.mtimes(J, ddq)
        eom += ca.mtimes(J.T, m * (acc + ca.vertcat(0, g)))
        eom[k] += m * L**2 / 12 * ddq[k]
    # dummy derivatives: θ1, ω1 states; y = [θ1, ω1, θ2.., ω2.., α2.., λ]
    n_alg = nq - 1
    y = ca.SX.sym("y", 2 + 3 * n_alg + 2 * loops)
    yp = ca.SX.sym("yp", y.numel())
    th = ca.vertcat(y[0], y[2:2 + n_alg])
    om = ca.vertcat(y[1], y[2 + n_alg:2 + 2 * n_alg])
    al = ca.vertcat(yp[1], y[2 + 2 * n_alg:2 + 3 * n_alg])
    lm = y[2 + 3 * n_alg:]
    rows = ca.vertcat(yp[0] - y[1], eom, gq, gdot, gddot)
    F = ca.substitute([rows], [ca.vertcat(q, dq, ddq, lam)], [ca.vertcat(th, om, al, lm)])[0]
    return ca.Function("hand_res", [y, yp, p], [F]), y.numel()


def _counts(sim: fl.Simulation) -> tuple[int, int, int, int]:
    m = sim.compiled
    return m.n, int(m.differential.sum()), m.sx_function("res").n_instructions(), m.sx_function("jac").n_instructions()


def test_hand_written_fourbar_dae_reproduces_the_motion():
    """The hand-written four-bar DAE (the size reference) is the same mechanism: integrated with CasADi IDAS
    from the closed-form start, its rocker angle after 0.3 s equals flexlib's to 1e-6 rad, and it satisfies
    the closed-form position analysis θ4(θ2) to 1e-6 rad."""
    res_fn, n = hand_dae(1)
    assert n == 10
    th2, w2 = 0.3, 6.0
    th3, th4 = (float(x) for x in ref.fourbar_angles(A, B, C, D, th2, "open"))
    w3, w4 = (float(x) for x in ref.fourbar_velocities(A, B, C, th2, th3, th4, w2))
    pv = [A, B, C, D, M_CRANK, M_COUPLER, M_ROCKER, 0.0]
    x, z = ca.SX.sym("x", 2), ca.SX.sym("z", 9)  # z: θ3, θ4, ω3, ω4, α3, α4, λ1, λ2, α2
    y = ca.vertcat(x, z[:8])
    yp = ca.vertcat(x[1], z[8], ca.SX.zeros(8))
    F = res_fn(y, yp, pv)
    dae = {"x": x, "z": z, "ode": ca.vertcat(x[1], z[8]), "alg": F[1:]}
    integ = ca.integrator("I", "idas", dae, 0.0, [0.3], {"abstol": 1e-12, "reltol": 1e-10})
    out = integ(x0=[th2, w2], z0=[th3, th4, w3, w4, 0, 0, 0, 0, 0])
    th2_end, th4_end = float(out["xf"][0]), float(out["zf"][1])
    np.testing.assert_allclose(th4_end, ref.fourbar_angles(A, B, C, D, th2_end, "open")[1], atol=1e-6)
    res = fl.Simulation(FourBar(th2, w2=w2), use_cache=False).run(0.3, dt_out=0.3, rtol=1e-9, atol=1e-11,
                                                                progress=False)
    np.testing.assert_allclose(res["rev1.phi"][-1], th2_end, atol=1e-6)
    np.testing.assert_allclose(res["rev4.phi"][-1], th4_end, atol=1e-6)


def test_fourbar_size_against_the_hand_written_dae():
    """Four-bar: without this stage 125 unknowns, 4056 residual and 12001 Jacobian operations (measured on this
    branch's parent); now at most 52 unknowns and 1300 residual operations (measured 51 and 1243), 2 states.
    The hand-written minimal DAE has 10 unknowns and 230 operations (ratios printed for the report)."""
    sim = fl.Simulation(FourBar(), use_cache=False)
    n, n_states, n_res, n_jac = _counts(sim)
    hand, n_hand = hand_dae(1)
    print(f"four-bar: {n} unknowns, {n_states} states, res {n_res}, jac {n_jac}; hand-written {n_hand} "
          f"unknowns, res {hand.n_instructions()}")
    assert n_states == 2
    assert n <= 52
    assert n_res <= 1300


def test_planar_chain_size_and_motion():
    """7-body, 3-loop planar chain: at most 135 unknowns and 3600 residual operations (measured 133 and 3491;
    without this stage 323, 11321 and 34620 Jacobian operations), 2 states, 9 redundant rows dropped; over
    0.5 s every loop stays closed (closed-form four-bar angles of each loop from its input angle, 1e-7 rad)."""
    sim = fl.Simulation(PlanarChain(), use_cache=False)
    n, n_states, n_res, n_jac = _counts(sim)
    hand, n_hand = hand_dae(3)
    print(f"7-body chain: {n} unknowns, {n_states} states, res {n_res}, jac {n_jac}; hand-written {n_hand} "
          f"unknowns, res {hand.n_instructions()}")
    assert n_states == 2 and len(sim.report.redundant) == 9
    assert n <= 135 and n_res <= 3600
    res = sim.run(0.5, dt_out=0.05, rtol=1e-8, atol=1e-10, progress=False)
    th_in = res["rev_in.phi"]
    for k in range(1, 4):
        th_c = th_in + res[f"couple{k}.phi"] if k == 1 else res[f"pivot{k - 1}.phi"] + res[f"couple{k}.phi"]
        th_r = res[f"pivot{k}.phi"]
        ref_c, ref_r = ref.fourbar_angles(A, B, C, D, th_in, "open")
        np.testing.assert_allclose(th_c, ref_c, atol=1e-7)
        np.testing.assert_allclose(th_r, ref_r, atol=1e-7)
        th_in = th_r


def test_eliminated_variables_are_reported():
    """Eliminated unknowns stay in the results: the out-of-plane cut forces and torques are exactly 0 (and marked
    statically indeterminate), the
    fixed pivot's frame sits at its parameter ``ground4.r`` exactly, the out-of-plane angular velocities are
    exactly 0; with ``run(params=...)`` moving the pivot, the reported position follows (1e-15 m) and the
    loop closes at the new pivot (1e-9 m)."""
    sim = fl.Simulation(FourBar(), use_cache=False)
    assert sim.compiled.n < 60
    names = set(sim.compiled.y_names)
    for name in ["rev1.frame_a.f[2]", "rev3.frame_b.t[0]", "rev3.frame_b.t[1]", "crank_mass.z_a[0]"]:
        assert name not in names
    res = sim.run(0.2, dt_out=0.02, rtol=1e-8, atol=1e-10, progress=False)
    with pytest.warns(fl.IndeterminateReactionWarning):  # the zeroed out-of-plane reactions are indeterminate
        assert np.all(res["rev1.frame_a.f"][:, 2] == 0.0)
        assert np.all(res["rev3.frame_b.t"][:, :2] == 0.0)
    assert np.all(res["coupler_mass.frame_a.t"][:, :2] == 0.0)
    assert np.all(res["rev2.frame_b.w"][:, :2] == 0.0)
    assert np.all(res["rocker_mass.v_0"][:, 2] == 0.0)
    assert np.all(res["rev4.frame_b.r_0"] == [D, 0.0, 0.0])
    assert np.abs(res["rev1.frame_a.f"][:, :2]).max() > 1.0  # the in-plane reaction is not eliminated
    res2 = sim.run(0.2, dt_out=0.02, rtol=1e-8, atol=1e-10, params={"ground4.r": [D + 0.02, 0.0, 0.0]},
                   progress=False)
    np.testing.assert_allclose(res2["rev4.frame_b.r_0"], np.tile([D + 0.02, 0.0, 0.0], (len(res2.t), 1)),
                               rtol=0, atol=1e-15)
    np.testing.assert_allclose(res2["rocker.frame_b.r_0"], res2["coupler.frame_b.r_0"], rtol=0, atol=1e-9)
    assert np.abs(res2["rev4.phi"] - res["rev4.phi"]).max() > 1e-3  # a different mechanism, not a replay


def test_assumed_parameters_are_recorded_and_a_cached_build_follows_them():
    """The build records which zero frame parameters it relied on (joint axes, rod and centre-of-mass
    offsets, products of inertia — not the gravity magnitude, which a row never needed); a second model of
    the same structure with a tilted rocker axis does not reuse the planar cache entry: it is rebuilt."""
    sim = fl.Simulation(FourBar(g=0.0))
    assumed = sim.compiled.assumed
    assert assumed["rev4.n[0]"] == "= 0" and assumed["rev4.n[1]"] == "= 0" and assumed["rev4.n[2]"] == "> 0"
    assert "world.g" not in assumed
    model = FourBar(g=0.0)
    model.rev4.n = [0.0, 0.3, 1.0]
    from flexlib.errors import StructuralSingularityError

    with pytest.raises((StructuralSingularityError, fl.InitializationError)):
        fl.Simulation(model).run(0.1, progress=False)  # rebuilt: a non-planar loop of four revolutes locks


class HeldArm(fl.Model):
    """An arm (point mass m at L on a rod) on a revolute whose drive flange is held at the angle ``lock.phi0``."""

    def __init__(self, phi0: float = 0.5, m: float = 2.0, L: float = 0.8) -> None:
        super().__init__()
        from flexlib.components.mechanics import rotational

        self.world = World()
        self.hinge = Revolute(use_axis_flange=True)
        self.rod = FixedTranslation(r=[L, 0, 0])
        self.bob = Body(m=m, I=np.diag([1e-4, 1e-4, 1e-4]))
        self.lock = rotational.Fixed(phi0=phi0)
        self.housing = rotational.Fixed()
        self.connect(self.world.frame_b, self.hinge.frame_a)
        self.connect(self.hinge.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.bob.frame_a)
        self.connect(self.lock.flange, self.hinge.axis)
        self.connect(self.housing.flange, self.hinge.support)


def test_parameter_expression_follows_run_params():
    """Build without the zero-geometry assumption (``assume_zero_geometry=False``): the held joint angle is the
    parameter expression ``lock.phi0 − housing.phi0``, its rate and acceleration are 0 — all three leave the DAE
    and are reported exactly; ``run(params={"lock.phi0": 0.9})`` moves the arm, and the holding torque on the lock
    follows statics, |τ| = m g L cos φ0 (1e-9 relative)."""
    m, L, g = 2.0, 0.8, g_n  # the World's default gravity
    sim = fl.Simulation(HeldArm(0.5, m, L), use_cache=False, assume_zero_geometry=False)
    assert sim.compiled.assumed == {}
    assert not {"hinge.phi", "hinge.w", "hinge.a"} & set(sim.compiled.y_names)
    for phi0 in (0.5, 0.9):
        res = sim.run(0.2, dt_out=0.1, params={"lock.phi0": phi0}, progress=False)
        assert np.all(res["hinge.phi"] == phi0) and np.all(res["hinge.w"] == 0.0) and np.all(res["hinge.a"] == 0.0)
        np.testing.assert_allclose(np.abs(res["lock.flange.tau"]), m * g * L * np.cos(phi0), rtol=1e-9)


# The size table of docs/engine.md: [FLEXLIB_ZERO_GEOMETRY=0] python tests/test_engine_constants.py
if __name__ == "__main__":
    for label, make, loops in [("four-bar", FourBar, 1), ("7-body 3-loop chain", PlanarChain, 3)]:
        n, n_states, n_res, n_jac = _counts(fl.Simulation(make(), use_cache=False))
        hand, n_hand = hand_dae(loops)
        print(f"{label}: {n} unknowns, {n_states} states, residual {n_res}, Jacobian {n_jac} operations; "
              f"hand-written: {n_hand} unknowns, residual {hand.n_instructions()} operations")
