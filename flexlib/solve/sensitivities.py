"""Forward sensitivities of a run's outputs with respect to its parameters, through the DAE and its events.

With ``S = ∂y/∂p`` (one column per parameter) the sensitivity DAE of ``F(t, y, y', p) = 0`` is
``F_y S + F_y' S' + F_p = 0`` (Hindmarsh et al. 2005, IDAS, §2.5). It is integrated by CasADi's IDAS: between two
events the relation values are constants of the DAE, and the forward derivative of CasADi's ``idas`` integrator is
the integrator of the DAE augmented by its sensitivity equations (derived by CasADi's automatic differentiation of
the model's symbolic residual), one direction per parameter, seeded with the sensitivities at the segment's start.
The nominal run is flexlib's own (the default solver, its events and consistent points).

At an event the states are continuous, but the event time moves with the parameters: for a state event whose
relation's indicator ``g(t, y, y', p)`` crosses zero at ``τ``, ``dτ/dp = −(g_y S + g_y' S' + g_p) / ġ``
(``ġ = g_t + g_y y' + g_y' y''`` along the trajectory just before it), and the states' sensitivities jump by
``S⁺ = S⁻ + (ẏ⁻ − ẏ⁺) dτ/dp`` (Galán, Feehery, Barton 1999, "Parametric sensitivity functions for hybrid
discrete/continuous systems", Appl. Numer. Math. 31, 1999); for a time event ``a(p) t + b(p) = 0``,
``τ = −b/a`` and its derivative. The algebraic sensitivities after it are solved again from the held event problem's
Jacobian (``F_w S_w = −(F_x S_x + F_p)``), and the next segment's start checks them (``IDACalcIC`` on the augmented
DAE). Above :data:`SMALL` unknowns the DAE, its Jacobian and its forward derivative are generated C
(:func:`_compiled_dae`), in the COLAMD order of the ``casadi-idas`` backend. The start's sensitivities are those of the
consistent start: central differences of the initialisation (the states' start values, the initial equations and a
steady start all enter it; a start costs a fraction of a run).

Not differentiated (refused, naming the event): ``fl.reinit`` (a state set at an event), a change of state
selection during the run (the run is made with ``dynamic_states=False``), a sampled block (FMU).
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import RunArgumentError, SolverError
from flexlib.results.result import Result

__all__ = ["Sensitivities", "forward_sensitivities"]

#: scale of the unknowns kept out of IDA's tests, in nominal values
OUT_OF_TEST = 1e10
#: models up to this many unknowns integrate their sensitivities on CasADi's virtual machine (gcc would cost more)
SMALL = 40
#: relative step of the central differences of the consistent start (their error ~1e-12 of the start's scale)
START_STEP = 1e-6


@dataclass
class Sensitivities:
    """Outputs of a run and their derivatives with respect to parameters, at the run's output times.

    Attributes
    ----------
    t : ndarray (m,)
        Output times [s] (an event's time twice: before and after it).
    params : list of str
        Parameter names (``sim.compiled.param_names``).
    outputs : list of str
        Output variable names.
    values : ndarray (m, n_outputs)
        The outputs (SI units).
    d : ndarray (m, n_outputs, n_params)
        ``d[i, j, k] = ∂ outputs[j] / ∂ params[k]`` at ``t[i]`` (output unit per parameter unit).
    result : Result
        The nominal run.
    stats : dict
        Costs: ``run_cpu`` (the nominal run), ``start_cpu`` (the start's differences), ``sens_cpu`` (the sensitivity
        integration), ``segments``, ``events``.
    """

    t: np.ndarray
    params: list[str]
    outputs: list[str]
    values: np.ndarray
    d: np.ndarray
    result: Result
    stats: dict[str, Any] = field(default_factory=dict)

    def __getitem__(self, key: tuple[str, str]) -> np.ndarray:
        """``sens["cylinder.p_A", "valve.k"]``: the derivative of an output by a parameter over ``t``."""
        if not (isinstance(key, tuple) and len(key) == 2):
            raise KeyError(f"index a Sensitivities by (output, parameter), got {key!r}")
        out, par = key
        if out not in self.outputs:
            raise KeyError(f"no output {out!r} (outputs: {', '.join(self.outputs)})")
        if par not in self.params:
            raise KeyError(f"no parameter {par!r} (parameters: {', '.join(self.params)})")
        return self.d[:, self.outputs.index(out), self.params.index(par)]

    def final(self, output: str) -> dict[str, float]:
        """The derivatives of the output's final value by each parameter."""
        return {p: float(self[output, p][-1]) for p in self.params}

    def peak(self, output: str) -> dict[str, float]:
        """The derivatives of the output's peak magnitude ``max |o(t)|`` over the output times by each parameter:
        ``sign(o(t*)) ∂o/∂p(t*)`` at the time ``t*`` of the peak (differentiable where the peak is unique and
        inside the span, or at an end; the peak's time moving with the parameters adds nothing at first order)."""
        o = self.value(output)
        k = int(np.argmax(np.abs(o)))
        return {p: float(np.sign(o[k]) * self[output, p][k]) for p in self.params}

    def value(self, output: str) -> np.ndarray:
        """The output's values over ``t``."""
        if output not in self.outputs:
            raise KeyError(f"no output {output!r} (outputs: {', '.join(self.outputs)})")
        return self.values[:, self.outputs.index(output)]


class _Dae:
    """The model's DAE as CasADi's IDAS sees it, in normalised time (as :mod:`flexlib.solve.casadi_runner`):
    ``x = [T; y_d]``, ``z = [y'_d; y_a]``, ``dx/dτ = [u; u y'_d]``, ``0 = F(T, y, y', p)``, one integrator per number
    of output intervals (built once per model and options)."""

    def __init__(self, model: CompiledModel) -> None:
        from flexlib.solve.casadi_dae import fill_reducing_order, unknowns_from_xz

        self.model = model
        n = model.n
        # x, z and the rows in the COLAMD order that keeps csparse's LU factors sparse (as the casadi-idas backend)
        x_idx, z_idx, z_w, rows = fill_reducing_order(model, model.sx_function("res"))
        self.x_idx, self.z_idx, self.z_w = x_idx, z_idx, z_w
        nd, nz = len(x_idx), len(z_idx)
        T, tau, u = ca.SX.sym("T"), ca.SX.sym("tau"), ca.SX.sym("u")
        xd, z = ca.SX.sym("xd", nd), ca.SX.sym("z", nz)
        p = ca.SX.sym("p", model.n_params + model.n_relations)
        # the unknowns in units of their nominal values, so that IDA's scalar atol weighs each as the runs' atol·nominal
        # does; the states' derivatives and the derivative-level unknowns (forces, accelerations) in units 1e10 times
        # larger: out of the error and Newton tests, as in the runs (docs/engine.md, "Error-test policy")
        nom = np.asarray(model.nominal, dtype=float)
        level = np.asarray(model.derivative_level, dtype=bool) if len(model.derivative_level) else np.zeros(n, bool)
        scale = np.where(level, OUT_OF_TEST * nom, nom)
        self.x_scale = scale[x_idx]
        self.z_scale = np.where(z_w, OUT_OF_TEST * nom[z_idx], scale[z_idx])
        xs = xd * ca.DM(self.x_scale) if nd else xd
        zs = z * ca.DM(self.z_scale) if nz else z
        y, yp, w = unknowns_from_xz(n, x_idx, z_idx, z_w, xs, zs)
        F = model.sx_function("res")(T, y, yp, p)[[int(r) for r in rows]]
        w = w / ca.DM(self.x_scale) if nd else w  # dx/dτ = u·y'/scale
        self.dae = ca.Function("flexlib_sens_dae", [tau, ca.vertcat(T, xd), z, p, u],
                               [ca.vertcat(u, u * w), F, ca.SX(0, 1), ca.SX(0, 1)], ca.dyn_in(), ca.dyn_out())
        self.compiled: dict[int, ca.Function | None] = {}
        self.integrators: dict[tuple, ca.Function] = {}

    def forward(self, K: int, n_dir: int, rtol: float, atol: float) -> ca.Function:
        """The forward derivative (``n_dir`` directions) of the integrator over ``τ = 1..K``: on the DAE compiled
        as C with its Jacobian and forward derivative (:func:`_compiled_dae`) where gcc is there, else on CasADi's
        virtual machine."""
        key = (K, n_dir, rtol, atol)
        if key not in self.integrators:
            if n_dir not in self.compiled:
                self.compiled[n_dir] = _compiled_dae(self.dae, n_dir) if self.model.n > SMALL else None
            dae = self.compiled[n_dir] or self.dae
            opts = {"reltol": rtol, "abstol": atol, "calc_ic": True,
                    "max_num_steps": 1_000_000, "disable_internal_warnings": True, "show_eval_warnings": False,
                    "linear_solver": "csparse", "second_order_correction": False}
            F = ca.integrator("flexlib_sens", "idas", dae, 0.0, [float(k) for k in range(1, K + 1)], opts)
            self.integrators[key] = F.forward(n_dir)
        return self.integrators[key]


def _compiled_dae(dae: ca.Function, n_dir: int) -> ca.Function | None:
    """``dae`` as generated C with its Jacobian and its forward derivative in ``n_dir`` directions
    (:func:`flexlib.compile.gcc.compile_functions`, gcc at a background compile's level) in
    ``$FLEXLIB_CACHE_DIR/sensitivity/``, once per DAE and number of directions: a manifest named by the digest of both
    records the library and its SHA-256, checked before it is loaded; None without a C compiler or when gcc fails.
    CasADi's forward sensitivities of an integrator then need no second derivatives (``second_order_correction``
    off: the Newton matrix of the augmented system is block diagonal with the DAE's own)."""
    import hashlib
    import json
    import os
    import tempfile
    from pathlib import Path

    from flexlib.compile.cache import cache_dir
    from flexlib.compile.gcc import compile_functions
    from flexlib.compile.integrity import sha256_file
    from flexlib.errors import FlexlibError

    digest = hashlib.sha256(f"{dae.serialize()}|{n_dir}|{ca.__version__}".encode()).hexdigest()[:32]
    where = cache_dir() / "sensitivity"
    manifest = where / f"sens_{digest}.json"
    try:
        known = json.loads(manifest.read_text())
        if Path(known["library"]).is_file() and sha256_file(Path(known["library"])) == known["sha256"]:
            return ca.external("flexlib_sens_dae", known["library"])
    except (OSError, ValueError, KeyError, TypeError):
        pass  # none yet, or unreadable: compiled (again)
    try:
        lib, sha, _ = compile_functions([dae, dae.jacobian(), dae.forward(n_dir)], where, "sens",
                                        background_level=True)
    except FlexlibError:
        return None
    fd, part = tempfile.mkstemp(dir=where, prefix=".manifest-", suffix=".tmp")
    with os.fdopen(fd, "w") as fh:
        json.dump({"library": lib, "sha256": sha}, fh)
    os.replace(part, manifest)
    return ca.external("flexlib_sens_dae", lib)


def _dae(model: CompiledModel) -> _Dae:
    found = model._functions.get("sensitivity_dae")
    if found is None:
        found = _Dae(model)
        model._functions["sensitivity_dae"] = found  # type: ignore[assignment]
    return found  # type: ignore[return-value]


def _partials(model: CompiledModel, name: str) -> ca.Function:
    """``(t, y, yp, p) -> (e, ∂e/∂t, ∂e/∂y, ∂e/∂y', ∂e/∂p)`` of the model's function ``name`` (``res``, ``ind``, or
    ``tev`` of ``p`` alone), built once per model (its expression too)."""
    key = f"sensitivity_{name}"
    if key not in model._functions:
        t, y, yp, p = _symbols(model)
        expr = model.sx_function(name)(p) if name == "tev" else model.sx_function(name)(t, y, yp, p)
        parts = [expr, ca.jacobian(expr, t), ca.jacobian(expr, y), ca.jacobian(expr, yp), ca.jacobian(expr, p)]
        model._functions[key] = ca.Function("flexlib_partials", [t, y, yp, p], parts)
    return model._functions[key]


def _seed(m: CompiledModel, idx: list[int]) -> np.ndarray:
    """The directions: ``∂p/∂p_k`` of each parameter ``idx[k]`` in the residual's parameter vector (parameters, then
    relation values)."""
    seed = np.zeros((m.n_params + m.n_relations, len(idx)))
    seed[idx, np.arange(len(idx))] = 1.0
    return seed


def _symbols(model: CompiledModel) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
    return (ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n),
            ca.SX.sym("p", model.n_params + model.n_relations))


def _dense(x: Any) -> np.ndarray:
    return np.asarray(ca.DM(x), dtype=float)


def forward_sensitivities(sim: Any, t_end: float | None, params: list[str], outputs: list[str], *,
                          values: dict[str, Any] | None = None, rtol: float = 1e-8, atol: float = 1e-10,
                          **run: Any) -> Sensitivities:
    """Forward sensitivities of ``outputs`` with respect to ``params`` over a run (:meth:`Simulation.sensitivities`).

    Parameters
    ----------
    sim : Simulation
        The simulation.
    t_end : float or None
        End time [s] (None: the model's experiment).
    params : list of str
        Run-time parameters (names of ``sim.compiled.param_names``).
    outputs : list of str
        Variables of the result.
    values : dict, optional
        Parameter values of the run (``params=`` of :meth:`Simulation.run`).
    rtol, atol : float
        Tolerances of the nominal run and of the sensitivity integration.
    **run
        Further arguments of :meth:`Simulation.run` (``dt_out``, ``output_times``, ``t_start``, ...).
    """
    from flexlib.solve.options import experiment_of
    from flexlib.solve.run_options import check_run_arguments
    from flexlib.solve.sampling import sampled_blocks
    from flexlib.solve.signals import sigterm_as_interrupt

    m0 = sim.compiled
    params, outputs = _checked_names(m0, params, outputs)
    if sampled_blocks(sim.model):
        raise RunArgumentError(f"sensitivities(): {m0.name} has sampled blocks (an FMU): their steps are not "
                               "differentiated")
    cpu = _time.process_time()
    given = dict(t_start=None, dt_out=None, output_times=None, max_step=0.0, max_steps=5_000_000,
                 steady_state=False, solver="ida", max_order=None, outputs=None)
    unknown = set(run) - set(given)
    if unknown:
        raise RunArgumentError(f"sensitivities(): unknown run arguments {sorted(unknown)}")
    given.update(run)
    opts = check_run_arguments(experiment_of(sim.model), f"{type(sim.model).__name__}.experiment", t_end=t_end,
                               rtol=rtol, atol=atol, params=values, progress=False, dynamic_states=False,
                               result_file=None, **given)
    starts, pvec, p = sim._parameters(opts.params)
    with sigterm_as_interrupt() as stop:
        traj, pvec, t_init = sim._initialize_and_integrate(opts, stop, starts, pvec, p)
        stop.stopping = True
        result = sim._result(traj, pvec, t_init, opts.rtol, opts.atol)
    m = sim.compiled
    run_cpu = _time.process_time() - cpu
    if len(traj.models) > 1:
        raise SolverError(f"{m.name}: the state selection changed during the run; sensitivities follow one")
    idx = [m.param_names.index(name) for name in params]
    cpu = _time.process_time()
    S0, SP0 = _start_sensitivities(sim, opts, params, pvec, idx, traj)
    start_cpu = _time.process_time() - cpu
    cpu = _time.process_time()
    T, Y, YP = np.asarray(traj.t, dtype=float), *traj.stacked()
    REL = np.vstack(traj.rel)
    S, SP, n_seg, n_ev = _integrate(m, sim.initializer, T, Y, YP, REL, pvec, idx, S0, SP0, opts.rtol, opts.atol)
    out_idx = [[v.name for v in m.variables].index(name) for name in outputs]
    values_out, d = _outputs(m, T, Y, YP, REL, pvec, idx, S, SP, out_idx)
    sens_cpu = _time.process_time() - cpu
    stats = {"run_cpu": run_cpu, "start_cpu": start_cpu, "sens_cpu": sens_cpu, "segments": n_seg, "events": n_ev}
    return Sensitivities(T, params, outputs, values_out, d, result, stats)


def _checked_names(m: CompiledModel, params: Any, outputs: Any) -> tuple[list[str], list[str]]:
    import difflib

    def names(value: Any, what: str) -> list[str]:
        if isinstance(value, str):
            value = [value]
        if not isinstance(value, (list, tuple)) or not value or not all(isinstance(v, str) for v in value):
            raise RunArgumentError(f"sensitivities(): {what} must be a non-empty list of names, got {value!r:.80}")
        if len(set(value)) != len(value):
            raise RunArgumentError(f"sensitivities(): {what} name one variable twice: {list(value)}")
        return list(value)

    params, outputs = names(params, "params"), names(outputs, "outputs")
    known = set(m.param_names)
    for name in params:
        if name not in known:
            close = difflib.get_close_matches(name, m.param_names, 3)
            raise RunArgumentError(f"sensitivities(): {name!r} is not a run-time parameter of {m.name}"
                                   + (f" (close: {', '.join(close)})" if close else "")
                                   + "; a parameter fixed at build time (structural) has no sensitivity")
    var_names = [v.name for v in m.variables]
    have = set(var_names)
    for name in outputs:
        if name not in have:
            close = difflib.get_close_matches(name, var_names, 3)
            raise RunArgumentError(f"sensitivities(): no variable {name!r} in {m.name}"
                                   + (f" (close: {', '.join(close)})" if close else ""))
    return params, outputs


def _start_sensitivities(sim: Any, opts: Any, params: list[str], pvec: np.ndarray, idx: list[int],
                         traj: Any) -> tuple[np.ndarray, np.ndarray]:
    """``∂y0/∂p``, ``∂y0'/∂p`` of the consistent start, by central differences of the initialisation (the parameter
    vector perturbed entry by entry: a run's overrides only set its entries, ``ParameterTable.vector``)."""
    m = sim.compiled
    starts, _, _ = sim._parameters(opts.params)
    S0, SP0 = np.zeros((m.n, len(idx))), np.zeros((m.n, len(idx)))
    t0 = float(traj.t[0])
    for k, i in enumerate(idx):
        v = float(pvec[i])
        h = START_STEP * max(abs(v), 1e-3)
        ends = []
        for sign in (1.0, -1.0):
            p = np.concatenate([pvec, np.zeros(m.n_relations)])
            p[i] = v + sign * h
            ends.append(sim._consistent_start(t0, p, starts, opts.steady_state))
        S0[:, k] = (ends[0][0] - ends[1][0]) / (2 * h)
        SP0[:, k] = (ends[0][1] - ends[1][1]) / (2 * h)
    return S0, SP0


def _integrate(m: CompiledModel, init: Any, T: np.ndarray, Y: np.ndarray, YP: np.ndarray, REL: np.ndarray,
               pvec: np.ndarray, idx: list[int], S0: np.ndarray, SP0: np.ndarray, rtol: float,
               atol: float) -> tuple[np.ndarray, np.ndarray, int, int]:
    """``S = ∂y/∂p`` and ``S' = ∂y'/∂p`` at every row (``(rows, n, n_params)``), segment by segment."""
    dae = _dae(m)
    x_idx, z_idx, z_w = dae.x_idx, dae.z_idx, dae.z_w
    nd, nz, n_dir = len(x_idx), len(z_idx), len(idx)
    rows = len(T)
    S, SP = np.zeros((rows, m.n, n_dir)), np.zeros((rows, m.n, n_dir))
    S[0], SP[0] = S0, SP0
    seed_p = _seed(m, idx)
    starts = [0] + [i + 1 for i in range(rows - 1) if T[i + 1] <= T[i]]
    ends = [s - 1 for s in starts[1:]] + [rows - 1]
    n_ev = 0
    for a, b in zip(starts, ends, strict=True):
        P = np.concatenate([pvec, REL[a]])
        if a > 0:  # the event between row a-1 (before) and row a (after)
            n_ev += 1
            S[a], SP[a] = _jump(m, T, Y, YP, REL, pvec, a - 1, a, S[a - 1], SP[a - 1], seed_p)
            S[a], SP[a] = _consistent(m, init, T[a], Y[a], YP[a], P, S[a], SP[a], seed_p)
        if b == a:
            continue
        K = b - a
        F = dae.forward(K, n_dir, rtol, atol)
        xs, zs = dae.x_scale[:, None], dae.z_scale[:, None]
        x0 = np.concatenate([[T[a]], Y[a, x_idx] / dae.x_scale])
        z0 = np.where(z_w, YP[a, z_idx], Y[a, z_idx]) / dae.z_scale
        fx0 = np.vstack([np.zeros((1, n_dir)), S[a][x_idx] / xs])
        fz0 = np.where(z_w[:, None], SP[a][z_idx], S[a][z_idx]) / zs
        try:
            out = F(x0=x0, z0=z0, p=P, u=np.diff(T[a:b + 1])[None, :], fwd_x0=fx0, fwd_z0=fz0,
                    fwd_p=seed_p, fwd_u=np.zeros((1, K * n_dir)))
        except RuntimeError as err:
            raise SolverError(f"{m.name}: the sensitivity integration failed between t = {T[a]:.10g} and "
                              f"{T[b]:.10g} s: {str(err).splitlines()[-1]}") from None
        fx = _dense(out["fwd_xf"]).reshape(nd + 1, n_dir, K)  # columns: direction-major, then output time
        fz = _dense(out["fwd_zf"]).reshape(nz, n_dir, K)
        S[a + 1:b + 1, x_idx, :] = np.transpose(fx[1:] * xs[:, :, None], (2, 0, 1))
        fz = np.transpose(fz * zs[:, :, None], (2, 0, 1))
        S[a + 1:b + 1, z_idx[~z_w], :] = fz[:, ~z_w]
        SP[a + 1:b + 1, z_idx[z_w], :] = fz[:, z_w]
    return S, SP, len(starts), n_ev


def _consistent(m: CompiledModel, init: Any, t: float, y: np.ndarray, yp: np.ndarray, P: np.ndarray,
                S: np.ndarray, SP: np.ndarray, seed_p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The algebraic unknowns' and the states' derivatives' sensitivities consistent with the states' ``S`` at
    ``(t, y, yp)``: ``F_w S_w = −(F_x S_x + F_p)``, ``w`` the unknowns of the event problem with the states held
    (its Jacobian, as the event iteration solves it)."""
    import scipy.sparse.linalg as spla

    diff = np.asarray(m.differential, dtype=bool)
    d_idx, a_idx = np.flatnonzero(diff), np.flatnonzero(~diff)
    J, _ = init.held_jacobian(t, y, yp, P)
    _, _, Fy, _, Fp = (v.sparse() for v in _partials(m, "res")(t, y, yp, P))
    rhs = -(Fy[:, d_idx] @ S[d_idx] + Fp @ seed_p)
    Sw = spla.splu(J.tocsc()).solve(np.asarray(rhs, dtype=float))
    S, SP = S.copy(), SP.copy()
    S[a_idx], SP[d_idx] = Sw[:len(a_idx)], Sw[len(a_idx):]
    return S, SP


def _jump(m: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray, REL: np.ndarray, pvec: np.ndarray,
          before: int, after: int, Sb: np.ndarray, SPb: np.ndarray, seed_p: np.ndarray) -> tuple[np.ndarray,
                                                                                                   np.ndarray]:
    """The sensitivities just after the event between rows ``before`` and ``after``: the states' by the event
    time's derivative, the others as a guess for the consistent start of the next segment."""
    t = float(T[before])
    d_idx = np.flatnonzero(np.asarray(m.differential, dtype=bool))
    moved = d_idx[Y[after, d_idx] != Y[before, d_idx]]
    if moved.size:  # a state set at the event: fl.reinit
        rels = "; ".join(f"{r.owner}: {r.text}" for r in m.relations if r.reinit)
        raise SolverError(f"{m.name}: sensitivities across a reinit() event are not computed (t = {t:.10g} s: "
                          f"{', '.join(m.y_names[int(i)] for i in moved)} set by {rels})")
    switched = np.flatnonzero(REL[before] != REL[after])
    if switched.size == 0:
        return Sb.copy(), SPb.copy()  # a restart without a switch (a sample, a recovery)
    P = np.concatenate([pvec, REL[before]])
    dtau = _event_time_derivative(m, t, Y, YP, T, P, before, switched, Sb, SPb, seed_p)
    Sa, SPa = Sb.copy(), SPb.copy()
    if dtau is not None:
        Sa[d_idx] += np.outer(YP[before, d_idx] - YP[after, d_idx], dtau)
    return Sa, SPa


def _event_time_derivative(m: CompiledModel, t: float, Y: np.ndarray, YP: np.ndarray, T: np.ndarray, P: np.ndarray,
                           row: int, switched: np.ndarray, Sb: np.ndarray, SPb: np.ndarray,
                           seed_p: np.ndarray) -> np.ndarray | None:
    """``dτ/dp`` of the event at row ``row``'s time (None if its time does not move with the parameters)."""
    timed = [int(k) for k in switched if m.relations[int(k)].time_event]
    if timed:  # a·t + b = 0 with a, b of the parameters: τ = −b/a
        ab, _, _, _, dab = (_dense(v) for v in _partials(m, "tev")(t, Y[row], YP[row], P))
        k, n_rel = timed[0], m.n_relations
        a, b = ab.reshape(n_rel, 2)[k]
        da, db = dab[k] @ seed_p, dab[n_rel + k] @ seed_p  # ∂vec(tev)/∂p: the a column, then the b column
        return (b * da - a * db) / (a * a)
    z_all, zt, zy, zyp, zp = (_dense(v) for v in _partials(m, "ind")(t, Y[row], YP[row], P))
    z_all = z_all.ravel()
    k = int(switched[np.argmin(np.abs(z_all[switched]))])  # the relation that crossed: its indicator is at zero
    ypp = (YP[row] - YP[row - 1]) / (T[row] - T[row - 1]) if row > 0 and T[row] > T[row - 1] else np.zeros(m.n)
    rate = float(zt[k, 0] + zy[k] @ YP[row] + zyp[k] @ ypp)
    if rate == 0.0:
        raise SolverError(f"{m.name}: the event at t = {t:.10g} s ({m.relations[k].owner}: {m.relations[k].text}) "
                          "is a tangential crossing: its time has no derivative by the parameters")
    return -(zy[k] @ Sb + zyp[k] @ SPb + zp[k] @ seed_p) / rate


def _outputs(m: CompiledModel, T: np.ndarray, Y: np.ndarray, YP: np.ndarray, REL: np.ndarray, pvec: np.ndarray,
             idx: list[int], S: np.ndarray, SP: np.ndarray, out_idx: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """The outputs and their derivatives ``∂o/∂y S + ∂o/∂y' S' + ∂o/∂p`` at every row."""
    ts, ys, yps, ps = _symbols(m)
    n_dir, n_out, rows = len(idx), len(out_idx), len(T)
    key = f"sensitivity_outputs_{n_dir}_" + ",".join(map(str, out_idx))
    if key not in m._functions:  # the outputs and their directional derivatives, one call over every row
        o = m.sx_function("out")(ts, ys, yps, ps)[out_idx]
        Sy, Syp, Sp = ca.SX.sym("Sy", m.n, n_dir), ca.SX.sym("Syp", m.n, n_dir), ca.SX.sym("Sp", ps.numel(), n_dir)
        d = ca.mtimes(ca.jacobian(o, ca.vertcat(ys, yps, ps)), ca.vertcat(Sy, Syp, Sp))
        m._functions[key] = ca.Function("flexlib_sens_out", [ts, ys, yps, ps, Sy, Syp, Sp], [o, d])
    fn = m._functions[key].map(rows)
    seed_p = _seed(m, idx)
    P = np.vstack([np.repeat(pvec[:, None], rows, axis=1), REL.T])
    o, dd = fn(T[None, :], Y.T, YP.T, P, np.hstack(list(S)), np.hstack(list(SP)), np.tile(seed_p, (1, rows)))
    values = _dense(o).T.reshape(rows, n_out)
    d = _dense(dd).reshape(n_out, rows, n_dir).transpose(1, 0, 2)
    return values, d
