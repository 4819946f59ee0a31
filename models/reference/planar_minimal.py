"""Hand-written references of the planar mechanisms of :mod:`flexlib.models.planar_mechanisms`.

Two formulations of the same :class:`~flexlib.models.planar_mechanisms.PlanarSpec`, written by hand in
CasADi SX and integrated by SUNDIALS through scikit-sundae, with residual/Jacobian (or right-hand side)
called through CasADi ``FunctionBuffer`` (``docs/casadi_ida.md``, "Wiring a CasADi residual into IDA"):

* :class:`MinimalDAE` — the minimal index-1 dummy-derivative DAE in absolute link angles ``q`` (one per
  moving link). Loops are cut at the cut joints: ``Φ(q) = r_cut,a(q) − r_cut,b(q) = 0`` (2 rows per loop).
  The driver angle ``q_d`` and speed ``ω_d`` are the states; every other angle, speed and acceleration is a
  dummy (algebraic). Unknowns ``y = [q_d, ω_d | q_o, ω_o, α_o, λ]`` (2 + 3·(n−1) + 2·loops; 10 for the
  four-bar, 26 for the 7-body mechanism) and the residual (Mattsson & Söderlind 1993)::

      q_d' − ω_d = 0
      Φ(q) = 0,   Φ_q ω = 0,   Φ_q α + (Φ_q ω)_q ω = 0                         (constraints, 3 levels)
      Σ_i J_iᵀ m_i (a_i − g) + I_i α_i e_i + Φ_qᵀ λ = 0                        (Newton–Euler, projected)

  with ``α_d = ω_d'``, ``r_i(q)`` the centre of mass of link i, ``J_i = ∂r_i/∂q`` and
  ``a_i = J_i α + (J_i ω)_q ω`` (CasADi ``jtimes``). Jacobian ``∂F/∂y + cj ∂F/∂y'`` in SX.
* :class:`MinimalODE` — the minimal-coordinate ODE in the driver angle alone: every other angle from the
  closed-form circle intersection of each loop (Norton §4.5), kinetic energy
  ``T = ½ M(θ) θ'²`` with ``M = Σ m_i |∂r_i/∂θ|² + I_i (∂q_i/∂θ)²`` and Lagrange's equation
  ``M θ'' + ½ M'(θ) θ'² = −∂V/∂θ``, integrated by CVODE (BDF, Newton, dense). At rtol 1e-12 it is the
  tight reference of ``benchmarks/work_precision.py``.

References
----------
S. E. Mattsson, G. Söderlind, "Index reduction in differential-algebraic equations using dummy
derivatives", *SIAM J. Sci. Comput.* 14 (1993) 677–692.
R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill 2012, §4.5.
"""

from __future__ import annotations

import time
from typing import Any

import casadi as ca
import numpy as np
import sksundae as sun

from flexlib.models.planar_mechanisms import PlanarSpec, assemble

__all__ = ["MinimalDAE", "MinimalODE", "size_comparison"]


def _rot(th: ca.SX) -> ca.SX:
    return ca.vertcat(ca.horzcat(ca.cos(th), -ca.sin(th)), ca.horzcat(ca.sin(th), ca.cos(th)))


def _pin(spec: PlanarSpec, q: dict[str, ca.SX], ref: str) -> ca.SX:
    """World position of ``"ground:<pivot>"`` or ``"<link>:<pin>"`` as an SX 2-vector."""
    owner, pin = ref.split(":")
    if owner == "ground":
        return ca.DM(spec.ground[pin])
    lk = spec.link(owner)
    return _pin(spec, q, lk.parent) + ca.mtimes(_rot(q[owner]), ca.DM(lk.pins[pin]))


def _cm(spec: PlanarSpec, q: dict[str, ca.SX], name: str) -> ca.SX:
    lk = spec.link(name)
    return _pin(spec, q, lk.parent) + ca.mtimes(_rot(q[name]), ca.DM(lk.r_cm))


class MinimalDAE:
    """The hand-written minimal dummy-derivative DAE of a planar mechanism (see the module docstring).

    Parameters
    ----------
    spec : PlanarSpec
        The mechanism.

    Attributes
    ----------
    n : int
        Number of unknowns.
    res, jac : casadi.Function
        Residual ``F(t, y, yp)`` and iteration matrix ``∂F/∂y + cj ∂F/∂yp`` (inputs t, y, yp, cj).
    names : list of str
        Names of the unknowns.
    """

    def __init__(self, spec: PlanarSpec) -> None:
        self.spec = spec
        links = [lk.name for lk in spec.links]
        nl, nc = len(links), 2 * len(spec.cuts)
        qv, wv, av = ca.SX.sym("q", nl), ca.SX.sym("w", nl), ca.SX.sym("a", nl)
        lam = ca.SX.sym("lam", nc)
        yp_q, yp_w = ca.SX.sym("qdot_d"), ca.SX.sym("wdot_d")
        q = dict(zip(links, ca.vertsplit(qv), strict=True))
        phi = ca.vertcat(*[_pin(spec, q, a) - _pin(spec, q, b) for a, b in spec.cuts])
        dphi = ca.jtimes(phi, qv, wv)
        ddphi = ca.jtimes(dphi, ca.vertcat(qv, wv), ca.vertcat(wv, av))
        g = ca.DM([0.0, -spec.g])
        eom = ca.mtimes(ca.jacobian(phi, qv).T, lam)
        for k, lk in enumerate(spec.links):
            r = _cm(spec, q, lk.name)
            J = ca.jacobian(r, qv)
            acc = ca.jtimes(ca.jtimes(r, qv, wv), ca.vertcat(qv, wv), ca.vertcat(wv, av))
            e = ca.DM.zeros(nl)
            e[k] = 1.0
            eom += lk.m * ca.mtimes(J.T, acc - g) + lk.I_zz * av[k] * e
        # unknowns: [q_d, w_d | q_o, w_o, a_o, lam]; a_d is yp of w_d
        y = ca.vertcat(qv[0], wv[0], qv[1:], wv[1:], av[1:], lam)
        yp_full = ca.vertcat(yp_q, yp_w, ca.SX.sym("yp_alg", y.numel() - 2))
        F = ca.vertcat(yp_q - wv[0], phi, dphi, ddphi, eom)
        F = ca.substitute(F, av[0], yp_w)
        t, cj = ca.SX.sym("t"), ca.SX.sym("cj")
        self.n = int(y.numel())
        self.names = ([f"q_{links[0]}", f"w_{links[0]}"] + [f"q_{n}" for n in links[1:]] + [f"w_{n}" for n in links[1:]]
                      + [f"a_{n}" for n in links[1:]] + [f"lam{i}" for i in range(nc)])
        self.res = ca.Function("res_min", [t, y, yp_full], [F])
        self.jac = ca.Function("jac_min", [t, y, yp_full, cj],
                               [ca.jacobian(F, y) + cj * ca.jacobian(F, yp_full)])
        self._y, self._yp, self._F = y, yp_full, F
        self.links = links

    def initial_values(self) -> tuple[np.ndarray, np.ndarray]:
        """Consistent ``y0, yp0`` at the spec's start: angles from :func:`assemble`, the rest by Newton on F."""
        spec = self.spec
        th = assemble(spec, spec.theta0)
        nl = len(self.links)
        z = ca.SX.sym("z", self.n - 1)  # q_o, w_o, a_o, lam, a_d
        y = ca.vertcat(spec.theta0, spec.w0, z[: self.n - 2])
        yp = ca.vertcat(spec.w0, z[-1], ca.DM.zeros(self.n - 2))
        G = ca.Function("G", [z], [self.res(0.0, y, yp)[1:]])
        solver = ca.rootfinder("ic", "newton", G, {"abstol": 1e-14})
        z0 = np.zeros(self.n - 1)
        z0[: nl - 1] = [th[n] for n in self.links[1:]]
        z = np.asarray(solver(z0)).ravel()
        y0 = np.concatenate([[spec.theta0, spec.w0], z[: self.n - 2]])
        yp0 = np.zeros(self.n)
        yp0[:2] = spec.w0, z[-1]
        return y0, yp0

    def solve(self, t_out: np.ndarray, rtol: float = 1e-8, atol: float | None = None, error_test: str = "kinematic",
              max_num_steps: int = 10**7) -> dict[str, Any]:
        """Integrate with IDA (dense LU, CasADi Jacobian, FunctionBuffer callbacks).

        Parameters
        ----------
        t_out : array_like
            Output times [s] (more than two).
        rtol, atol : float
            Tolerances (``atol`` default ``rtol/100``, rad and rad/s).
        error_test : str
            ``"kinematic"`` (default): angles and speeds of every link in IDA's local error test, accelerations
            and multipliers out of it (atol 1e10; the same policy as flexlib's derivative-level unknowns);
            ``"all"``: every unknown in the test. Measured on the four-bar (2 s): ``"all"`` is 2–7× more accurate
            at rtol 1e-8…1e-9 but costs 2.5–5× the residual calls, and above rtol 1e-10 its Newton iteration
            struggles (α and λ tested near round-off: 10× the Jacobians, accuracy no longer improves).
        max_num_steps : int
            IDA's step limit between outputs.

        Returns
        -------
        dict
            ``t``, ``q`` (absolute angles per link [rad]), ``y``, ``cpu`` [s] (process time of the solve,
            callbacks included), ``nfev``, ``njev``.
        """
        y0, yp0 = self.initial_values()
        atol = rtol * 1e-2 if atol is None else atol
        if error_test == "kinematic":
            nk = 2 + 2 * (len(self.links) - 1)
            atol = np.r_[np.full(nk, atol), np.full(self.n - nk, 1e10)]
        elif error_test != "all":
            raise ValueError(f"error_test must be 'kinematic' or 'all', not {error_test!r}")
        fr, evr = self.res.buffer()
        fj, evj = self.jac.buffer()
        tb, tj, cjb = np.zeros(1), np.zeros(1), np.zeros(1)
        fr.set_arg(0, memoryview(tb))
        fj.set_arg(0, memoryview(tj))
        fj.set_arg(3, memoryview(cjb))
        sp = self.jac.sparsity_out(0)
        rows = np.asarray(sp.row(), dtype=np.intp)
        cols = np.repeat(np.arange(self.n), np.diff(np.asarray(sp.colind())))
        nz = np.zeros(sp.nnz())

        def resfn(t, y, yp, r):
            tb[0] = t
            fr.set_arg(1, memoryview(y))
            fr.set_arg(2, memoryview(yp))
            fr.set_res(0, memoryview(r))
            evr()

        def jacfn(t, y, yp, r, cj, JJ):
            tj[0], cjb[0] = t, cj
            fj.set_arg(1, memoryview(y))
            fj.set_arg(2, memoryview(yp))
            fj.set_res(0, memoryview(nz))
            evj()
            JJ[:, :] = 0.0
            JJ[rows, cols] = nz

        solver = sun.ida.IDA(resfn, jacfn=jacfn, linsolver="dense", rtol=rtol, atol=atol,
                             algebraic_idx=list(range(2, self.n)), max_num_steps=max_num_steps)
        c0 = time.process_time()
        sol = solver.solve(np.asarray(t_out, dtype=float), y0, yp0)
        cpu = time.process_time() - c0
        if not sol.success:
            raise RuntimeError(f"minimal DAE failed: {sol.message}")
        nl = len(self.links)
        q = {self.links[0]: sol.y[:, 0]}
        for k, name in enumerate(self.links[1:]):
            q[name] = sol.y[:, 2 + k]
        assert len(q) == nl
        return {"t": sol.t, "q": q, "y": sol.y, "cpu": cpu, "nfev": sol.nfev, "njev": sol.njev}


class MinimalODE:
    """Minimal-coordinate ODE in the driver angle (closed-form loop closure, Lagrange), integrated by CVODE.

    Parameters
    ----------
    spec : PlanarSpec
        The mechanism (every loop a four-bar whose coupler starts at a known pin, as :func:`assemble`).
    """

    def __init__(self, spec: PlanarSpec) -> None:
        self.spec = spec
        th = ca.SX.sym("theta")
        q = self.angles(th)
        M = 0.0
        V = 0.0
        for lk in spec.links:
            r = _cm(spec, q, lk.name)
            dr = ca.jacobian(r, th)
            dq = ca.jacobian(q[lk.name], th)
            M += lk.m * ca.dot(dr, dr) + lk.I_zz * dq**2
            V += lk.m * spec.g * r[1]
        w = ca.SX.sym("w")
        acc = (-ca.jacobian(V, th) - 0.5 * ca.jacobian(M, th) * w**2) / M
        x = ca.vertcat(th, w)
        self.rhs = ca.Function("rhs_min", [x], [ca.vertcat(w, acc)])
        self.angle_fun = ca.Function("angles", [th], [ca.vertcat(*[q[lk.name] for lk in spec.links])])
        self.energy = ca.Function("energy", [x], [0.5 * M * w**2 + V])

    def angles(self, th: ca.SX) -> dict[str, ca.SX]:
        """Absolute link angles as closed-form SX expressions of the driver angle (circle intersection)."""
        spec = self.spec
        q: dict[str, ca.SX] = {spec.links[0].name: th}
        for (a_ref, b_ref), sign in zip(spec.cuts, spec.branch, strict=True):
            coupler, rocker = spec.link(a_ref.split(":")[0]), spec.link(b_ref.split(":")[0])
            pin_b, pin_c = coupler.pins[a_ref.split(":")[1]], rocker.pins[b_ref.split(":")[1]]
            P, Op = _pin(spec, q, coupler.parent), _pin(spec, q, rocker.parent)
            b, c = float(np.hypot(*pin_b)), float(np.hypot(*pin_c))
            d = Op - P
            dist = ca.norm_2(d)
            x = (b**2 - c**2 + dist**2) / (2 * dist)
            h = ca.sqrt(b**2 - x**2)
            ex = d / dist
            ey = ca.vertcat(-ex[1], ex[0])
            B = P + x * ex + sign * h * ey
            q[coupler.name] = ca.atan2(B[1] - P[1], B[0] - P[0]) - float(np.arctan2(pin_b[1], pin_b[0]))
            q[rocker.name] = ca.atan2(B[1] - Op[1], B[0] - Op[0]) - float(np.arctan2(pin_c[1], pin_c[0]))
        return q

    def solve(self, t_out: np.ndarray, rtol: float = 1e-12, atol: float | None = None) -> dict[str, Any]:
        """Integrate with CVODE (BDF); returns ``t``, ``q`` (absolute angles per link), ``x``, ``cpu`` [s], ``nfev``."""
        fb, ev = self.rhs.buffer()
        atol = rtol * 1e-2 if atol is None else atol

        def rhsfn(t, x, xdot):
            fb.set_arg(0, memoryview(x))
            fb.set_res(0, memoryview(xdot))
            ev()

        solver = sun.cvode.CVODE(rhsfn, rtol=rtol, atol=atol, max_num_steps=10**7)
        c0 = time.process_time()
        sol = solver.solve(np.asarray(t_out, dtype=float), np.array([self.spec.theta0, self.spec.w0]))
        cpu = time.process_time() - c0
        if not sol.success:
            raise RuntimeError(f"minimal ODE failed: {sol.message}")
        Q = np.asarray(self.angle_fun.map(len(sol.t))(sol.y[:, 0]))
        q = {lk.name: Q[k] for k, lk in enumerate(self.spec.links)}
        return {"t": sol.t, "q": q, "x": sol.y, "cpu": cpu, "nfev": sol.nfev}


def size_comparison(sim: Any, dae: MinimalDAE) -> dict[str, tuple[int, int]]:
    """(component-built, hand-written) unknowns and residual / Jacobian operation counts."""
    comp = sim.compiled
    return {"unknowns": (comp.n, dae.n),
            "residual ops": (comp.sx_function("res").n_instructions(), dae.res.n_instructions()),
            "Jacobian ops": (comp.sx_function("jac").n_instructions(), dae.jac.n_instructions())}
