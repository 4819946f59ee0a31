"""Stage 8 — linear analysis: the index-reduced DAE linearised at an operating point, exactly.

The compiled DAE ``F(t, y, y', p) = 0`` is index 1; its differential unknowns ``x`` are the states of the
dummy-derivative selection (independent coordinates of the constraint manifold: joint angles and rates,
modal coordinates, chamber masses, controller states) and the rest ``z`` are algebraic. At a consistent point
``(y₀, y₀', p₀)`` its first-order expansion reads::

    F_x' δx' + F_z δz = −F_x δx − F_u δu

and the matrix ``[F_x'  F_z]`` is regular exactly when the DAE is index 1 there with this state selection
(it is the Newton matrix of the consistent-rates problem). Solving it once for all columns gives::

    δx' = A δx + B δu,        δz = Z_x δx + Z_u δu

so ``A`` is the state matrix *on the constraint manifold* — what Modelica tools' ``linearize`` and Simulink's
``linmod`` return — and every variable of the model follows by the chain rule: an output ``o = h(t, y, y', p)``
gives ``δo = C δx + D δu`` through ``δy`` and ``δy'`` (algebraic rates ``δz' = Z_x δx'``, the input held).
The Jacobians are CasADi's algorithmic derivatives of the compiled functions (the model's C library where it
has one): ``F_y = jac(c_j = 0)`` and ``F_y' = (jac(c_j) − jac(0))/c_j`` (``jac`` is affine in ``c_j``; with
``c_j = 2²⁰`` the cancellation error is ``eps·|F_y|/c_j``), ``F_u`` and the output Jacobians from the SX
functions. No finite differences.

Inputs ``u`` are named scalar parameters: a source's value (``"force_src.k"``), a joint's constant drive torque
(``"joint1.tau_drive"``), a valve command held by a ``Constant``. Outputs are any variable of the model by name.

References
----------
- S. E. Mattsson, G. Söderlind, "Index reduction in differential-algebraic equations using dummy
  derivatives", *SIAM J. Sci. Comput.* 14(3), 1993 (the state selection that makes ``x`` a chart of the
  constraint manifold).
- K. E. Brenan, S. L. Campbell, L. R. Petzold, *Numerical Solution of Initial-Value Problems in DAEs*,
  SIAM 1996, §2.2 (semi-explicit index-1 form and its linearisation).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from flexlib.core.component import Component
from flexlib.core.values import as_bool, not_a_number, not_a_scalar
from flexlib.errors import LinearizationError
from flexlib.results.result import Result

__all__ = ["LinearSystem", "OperatingPoint", "linearize", "operating_point", "result_parameters", "result_point"]

#: ``c_j`` at which the iteration matrix is evaluated to separate ``∂F/∂y'`` from ``∂F/∂y`` (see the module doc)
CJ = float(2**20)


@dataclass
class OperatingPoint:
    """A consistent point of a compiled model: time [s], unknowns ``y`` and rates ``yp``, parameters and
    relation values ``p`` (the compiled model's order), and where it came from."""

    t: float
    y: np.ndarray
    yp: np.ndarray
    p: np.ndarray
    source: str


def as_simulation(model: Any) -> Any:
    """``model`` as a :class:`~flexlib.Simulation` (a top-level model is built; a sub-component is refused)."""
    from flexlib.solve.simulation import Simulation

    if isinstance(model, Simulation):
        return model
    if isinstance(model, Component):
        if model._parent is not None:
            raise LinearizationError(f"{model.path} is a sub-component of {type(model.root).__name__}; linearise the "
                                     "top-level model")
        return Simulation(model)
    raise LinearizationError(f"expected a flexlib Simulation or model (Component), got {type(model).__name__} "
                             f"{model!r:.60}")


def names_argument(value: Any, what: str) -> list[str]:
    """A list-of-names argument (``inputs``, ``outputs``, ``lock``) as a list of distinct strings.

    A single string is one name (``inputs="src.k"`` is ``inputs=["src.k"]``), not a sequence of letters. Anything
    else must be an iterable of strings without repeats; the error names the argument and the offending entry.
    """
    if value is None:
        return []
    if isinstance(value, str):
        return [value]
    if isinstance(value, (bytes, Mapping)) or not hasattr(value, "__iter__"):
        raise LinearizationError(f"{what} must be a name or a list of names (str), got {type(value).__name__} "
                                 f"{value!r:.80}")
    names = list(value)
    for name in names:
        if not isinstance(name, str):
            raise LinearizationError(f"{what}: entry {name!r} ({type(name).__name__}) is not a name; names are "
                                     "strings such as 'src.k'")
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise LinearizationError(f"{what} names {', '.join(repr(n) for n in repeated)} more than once; give each "
                                 "once")
    return names


def real_argument(value: Any, what: str, *, allow_inf: bool = False) -> float:
    """A real-number argument (a time, a frequency bound), refusing strings, bools, NaN (and inf unless allowed)."""
    why = not_a_scalar(value)
    if why is not None:
        raise LinearizationError(f"{what} = {value!r:.80} is {why}")
    v = float(value)
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise LinearizationError(f"{what} = {value!r} is not finite")
    return v


def flag_argument(value: Any, what: str) -> bool:
    """An on/off argument: True or False only (:func:`~flexlib.core.values.as_bool`)."""
    return as_bool(value, what, LinearizationError, ints=False)


def mapping_argument(value: Any, what: str) -> dict[str, Any]:
    """A ``{name: value}`` argument (``params``, a pose) as a dict with str keys (``None``: empty)."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise LinearizationError(f"{what} must be a dict {{name: value}}, got {type(value).__name__} {value!r:.80}")
    for key in value:
        if not isinstance(key, str):
            raise LinearizationError(f"{what}: key {key!r} ({type(key).__name__}) is not a name; keys are strings "
                                     "such as 'joint1.phi'")
    return dict(value)


def operating_point(sim: Any, *, at: Result | None = None, t: float | None = None,
                    params: dict[str, Any] | None = None, steady_state: bool = False,
                    starts: dict[str, float] | None = None) -> OperatingPoint:
    """A consistent operating point of ``sim``'s compiled model.

    Parameters
    ----------
    sim : Simulation
        The simulation whose model is linearised.
    at : Result, optional
        Take the states of this result at time ``t`` [s] (linear interpolation between output rows) and make
        the algebraic unknowns and rates consistent with them (the model's event relations are evaluated at
        the point). Without it: the model's own initial point at ``t`` (default 0 s).
    t : float, optional
        Time [s] of the point.
    params : dict, optional
        Parameter overrides (on top of the result's parameters when ``at`` is given).
    steady_state : bool
        Without ``at``: initialise with ``der(x) = 0`` for every state without an initial condition of its own
        (a static equilibrium, as ``run(steady_state=True)``).
    starts : dict, optional
        Without ``at``: start values ``{"joint1.phi": 0.3}`` used as initial conditions (fixed) instead of the
        model's, e.g. the pose of a static equilibrium.
    """
    m = sim.compiled
    if at is not None and not isinstance(at, Result):
        raise LinearizationError(f"at must be a flexlib Result (of a run of this model), got {type(at).__name__}")
    t = None if t is None else real_argument(t, "t [s]")
    steady_state = flag_argument(steady_state, "steady_state")
    starts, params = mapping_argument(starts, "starts"), mapping_argument(params, "params")
    if at is None:
        t0 = 0.0 if t is None else t
        values, st = sim.model.values()
        for name, value in starts.items():
            if name not in st:
                if name in values or name in m.param_names:
                    raise LinearizationError(f"starts: {name!r} is a parameter of {m.name}, not a variable; give "
                                             f"it in params={{{name!r}: ...}}")
                close = difflib.get_close_matches(name, list(st), n=3)
                hint = f"; did you mean {', '.join(close)}?" if close else ""
                raise LinearizationError(f"starts: {name!r} is not a variable of {m.name}{hint}")
            why = not_a_number(value)
            if why is None and np.ndim(value) != 0:
                why = f"an array of shape {np.shape(value)}; give each element by name (e.g. 'body.r_0[1]')"
            if why is not None:
                raise LinearizationError(f"starts: {name} = {value!r:.80} is {why}")
            st[name] = (float(value), True)
        pvec = sim.parameter_vector(params, values)
        p = np.concatenate([pvec, np.zeros(m.n_relations)])
        y, yp = sim._initialize(t0, p, st, steady_state)
        what = "steady state" if steady_state else "initial point"
        return OperatingPoint(t0, y, yp, p, f"{what} at t = {t0:g} s")
    if t is None:
        raise LinearizationError("at=result needs the time t [s] of the operating point")
    if starts:
        raise LinearizationError("starts apply to the model's own initial point, not to at=result")
    if steady_state:
        raise LinearizationError("steady_state applies to the model's own initial point, not to at=result")
    return result_point(sim, at, t, result_parameters(sim, at, params))


def result_parameters(sim: Any, at: Result, params: dict[str, Any] | None = None) -> np.ndarray:
    """The parameter vector of a result's run (its recorded parameters, then ``params``), checked."""
    index = set(sim.compiled.param_names)
    merged = {k: v for k, (v, _unit) in at.parameters.items() if k in index}
    merged.update(params or {})
    return sim.parameter_vector(merged)


def result_point(sim: Any, at: Result, t: float, pvec: np.ndarray) -> OperatingPoint:
    """The operating point at time ``t`` [s] of result ``at``, parameters ``pvec`` (:func:`operating_point`)."""
    m = sim.compiled
    if not len(at.t) or not at.t[0] - 1e-12 <= t <= at.t[-1] + 1e-12:
        raise LinearizationError(f"t = {t:g} s is outside the result ({at.t[0] if len(at.t) else 'no rows'} ... "
                                 f"{at.t[-1] if len(at.t) else ''} s)")
    diff = np.asarray(m.differential, dtype=bool)
    missing = [n for n, d in zip(m.y_names, diff, strict=True) if d and n not in at]
    if missing:
        raise LinearizationError(f"the result lacks {len(missing)} states of {m.name} ({', '.join(missing[:5])}"
                                 f"{' …' if len(missing) > 5 else ''}): it comes from another model")
    # states from the result (interpolated between its rows, right values at events); algebraic unknowns it does
    # not store (dummy derivatives der(x)) start from the result's slope of x; all algebraics are then solved
    row = at.row(t)
    y = np.array([row[at._col(n)] if n in at else _slope(at, n, t) for n in m.y_names])
    p = np.concatenate([pvec, np.zeros(m.n_relations)])
    if m.n_relations:
        z = np.asarray(m.function("ind")(t, y, np.zeros(m.n), p), dtype=float).ravel()
        p[m.n_params:] = [float(rel.value(zk)) for rel, zk in zip(m.relations, z, strict=True)]
    # algebraic unknowns and state derivatives consistent with the states held (the rates of the algebraic
    # unknowns, which IDA's predictor would want after a restart, do not enter the linearisation)
    y, yp = sim.initializer._reinit(t, y, np.zeros(m.n), p, 1e-10)
    return OperatingPoint(t, y, yp, p, f"result {at.model!r} at t = {t:g} s")


def _slope(at: Result, name: str, t: float) -> float:
    """Guess for ``der(x)`` at ``t`` from the result's rows of ``x`` (0 if the result lacks ``x``)."""
    base = name[4:-1] if name.startswith("der(") and name.endswith(")") else None
    if base is None or base not in at or len(at.t) < 2:
        return 0.0
    k = int(np.clip(np.searchsorted(at.t, t), 1, len(at.t) - 1))
    dt = at.t[k] - at.t[k - 1]
    return float((at[base][k] - at[base][k - 1]) / dt) if dt > 0 else 0.0


@dataclass
class LinearSystem:
    """``δx' = A δx + B δu``, ``δo = C δx + D δu`` of a model at an operating point (module docstring).

    Attributes
    ----------
    A, B, C, D : ndarray
        State-space matrices (SI units of the states, inputs and outputs).
    states, inputs, outputs : list of str
        Names of the states (the compiled model's selection), input parameters and output variables.
    point : OperatingPoint
        Where the model was linearised.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: list[str]
    inputs: list[str]
    outputs: list[str]
    point: OperatingPoint
    _lin: Any = field(repr=False, default=None)

    @property
    def nominal(self) -> np.ndarray:
        """Nominal magnitudes of the states (the model's ``nominal`` attributes) [SI units]."""
        m = self._lin.m
        return np.asarray(m.nominal, dtype=float)[self._lin.diff]

    def sensitivity(self, names: list[str] | str) -> tuple[np.ndarray, np.ndarray]:
        """``(C_n, D_n)``: the rows of ``C`` and ``D`` for other variables ``names`` at the same point (``D_n`` has a
        column per input of this system; it had none)."""
        return self._lin.outputs(self.point, names_argument(names, "names"), self.inputs)

    def frequency_response(self, f: Any, input: str | None = None, output: str | None = None) -> np.ndarray:
        """``H(j2πf) = C (j2πf I − A)⁻¹ B + D`` at frequencies ``f`` [Hz].

        Parameters
        ----------
        f : float or array_like
            One frequency or a 1-D sequence of them [Hz], each finite and >= 0 (``f = 0``: the static gain). An
            empty sequence gives an empty response.
        input, output : str, optional
            One input and one output of this system (default: all of them).

        Returns
        -------
        ndarray of complex
            ``(len(f), n_outputs, n_inputs)``, or ``(len(f),)`` for one ``input`` and ``output``.

        Raises
        ------
        LinearizationError
            A frequency that is not a finite number >= 0, a 2-D array, an unknown input or output name, or a
            frequency at a pole of the system: ``j2πf`` an eigenvalue of ``A`` (``f = 0`` with a free rigid-body
            mode or an integrator; the natural frequency of an undamped mode), where ``j2πf I − A`` is singular
            and the response unbounded. The message names the frequency and the eigenvalue; leave that frequency
            out (a grid that starts above 0 Hz for a free mechanism).
        """
        freqs = self._frequencies(f)
        cols = [self._where(self.inputs, input, "input")] if input is not None else list(range(len(self.inputs)))
        rows = [self._where(self.outputs, output, "output")] if output is not None else list(range(len(self.outputs)))
        B, C, D = self.B[:, cols], self.C[rows], self.D[np.ix_(rows, cols)]
        n = self.A.shape[0]
        H = np.empty((len(freqs), len(rows), len(cols)), dtype=complex)
        for k, fk in enumerate(freqs):
            try:
                X = np.linalg.solve(2j * np.pi * fk * np.eye(n) - self.A, B)
            except np.linalg.LinAlgError:
                X = None
            if X is None or not np.all(np.isfinite(X)):
                raise LinearizationError(self._at_pole(float(fk))) from None
            H[k] = C @ X + D
        return H[:, 0, 0] if input is not None and output is not None else H

    @staticmethod
    def _frequencies(f: Any) -> np.ndarray:
        """``f`` [Hz] as a 1-D float array, checked (:meth:`frequency_response`)."""
        why = not_a_number(f)
        if why is not None:
            raise LinearizationError(f"frequency_response: f = {f!r:.80} is {why}; give frequencies in Hz (a number "
                                     "or a 1-D sequence of numbers >= 0)")
        freqs = np.atleast_1d(np.asarray(f, dtype=float))
        if freqs.ndim != 1:
            raise LinearizationError(f"frequency_response: f has shape {freqs.shape}; give a 1-D sequence of "
                                     "frequencies [Hz] (flatten a grid first)")
        bad = np.flatnonzero(~np.isfinite(freqs) | (freqs < 0.0))
        if bad.size:
            k = int(bad[0])
            raise LinearizationError(f"frequency_response: f[{k}] = {float(freqs[k])!r} Hz is "
                                     f"{'negative' if freqs[k] < 0 else 'not finite'}; frequencies are finite and "
                                     f">= 0 Hz ({bad.size} such entr{'y' if bad.size == 1 else 'ies'})")
        return freqs

    def _at_pole(self, fk: float) -> str:
        """Message for a frequency where ``j2πf I − A`` is singular: names the eigenvalue of ``A`` there."""
        s = 2j * np.pi * fk
        lam = np.linalg.eigvals(self.A) if self.A.size else np.zeros(0, complex)
        near = lam[np.argmin(np.abs(lam - s))] if lam.size else s
        if abs(near) <= 1e-9 * max(1.0, np.abs(lam).max(initial=0.0)):
            what = "λ = 0: a free rigid-body mode or an integrator"
        else:
            what = f"λ = {near.real + 0.0:.6g}{near.imag:+.6g}j: an undamped mode of {abs(near) / (2 * np.pi):.6g} Hz"
        return (f"frequency_response: f = {fk:g} Hz is at a pole of the system: j2πf is an eigenvalue of A "
                f"({what}), where the response is unbounded; leave that frequency out")

    @staticmethod
    def _where(names: list[str], name: Any, what: str) -> int:
        if not isinstance(name, str) or name not in names:
            close = difflib.get_close_matches(name, names, n=3) if isinstance(name, str) else []
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            raise LinearizationError(f"{name!r} is not an {what} of this linear system ({', '.join(names) or 'none'})"
                                     f"{hint}")
        return names.index(name)


class Linearizer:
    """Linearises one simulation's compiled model at any number of points (Jacobian functions built once)."""

    def __init__(self, sim: Any) -> None:
        self.sim = sim
        m = sim.compiled
        self.m = m
        self.diff = np.flatnonzero(np.asarray(m.differential, dtype=bool))
        self.alg = np.flatnonzero(~np.asarray(m.differential, dtype=bool))
        self.pattern = sps.csc_matrix((np.zeros(len(m.jac_row)), np.asarray(m.jac_row), np.asarray(m.jac_colind)),
                                      shape=(m.n, m.n))
        self._pindex = {n: k for k, n in enumerate(m.param_names)}
        self._out_names = [v.name for v in m.variables]
        self._out_index = {n: k for k, n in enumerate(self._out_names)}
        self._fu: dict[tuple, ca.Function] = {}
        self._fo: dict[tuple, ca.Function] = {}
        self._sym: tuple | None = None
        self._cache: dict[int, tuple] = {}

    # -- symbolic pieces ------------------------------------------------------------------------
    def _symbols(self) -> tuple:
        """``(t, y, yp, p)`` symbols and the residual and every output as expressions of them, built once."""
        if self._sym is None:
            m = self.m
            n_p = m.sx_function("res").size1_in(3)
            t, y, yp, p = ca.SX.sym("t"), ca.SX.sym("y", m.n), ca.SX.sym("yp", m.n), ca.SX.sym("p", n_p)
            self._sym = (t, y, yp, p, m.sx_function("res")(t, y, yp, p), m.sx_function("out")(t, y, yp, p))
        return self._sym

    def input_indices(self, inputs: list[str]) -> list[int]:
        out = []
        for name in inputs:
            k = self._pindex.get(name)
            if k is None:
                if name in self._out_index:
                    raise LinearizationError(
                        f"input {name!r} is a variable of {self.m.name}, not a parameter: inputs are scalar "
                        "parameters (a source's value such as 'src.k', a joint's tau_drive/f_drive); to drive a "
                        "signal input, name the parameter of the source connected to it")
                close = difflib.get_close_matches(name, self.m.param_names, n=3)
                hint = f"; did you mean {', '.join(close)}?" if close else ""
                raise LinearizationError(f"input {name!r} is not a parameter of {self.m.name}{hint} (inputs are "
                                         "scalar parameters: a source's value, a joint's tau_drive/f_drive)")
            if name in getattr(self.m, "assumed", {}):
                raise LinearizationError(
                    f"input {name!r} was assumed zero when the model was built (planar geometry; see "
                    "docs/engine.md, 'Constant unknowns'): build with assume_zero_geometry=False to use it as input")
            out.append(k)
        return out

    def _input_function(self, idx: tuple[int, ...]) -> ca.Function:
        f = self._fu.get(idx)
        if f is None:
            t, y, yp, p, F, _ = self._symbols()
            u = ca.vertcat(*[p[k] for k in idx]) if idx else ca.SX(0, 1)
            f = ca.Function("F_u", [t, y, yp, p], [ca.jacobian(F, u)])
            self._fu[idx] = f
        return f

    def _output_function(self, names: tuple[str, ...], idx: tuple[int, ...]) -> ca.Function:
        key = (names, idx)
        f = self._fo.get(key)
        if f is None:
            t, y, yp, p, _, every = self._symbols()
            rows = []
            for name in names:
                k = self._out_index.get(name)
                if k is None:
                    close = difflib.get_close_matches(name, self._out_names, n=3)
                    hint = f"; did you mean {', '.join(close)}?" if close else ""
                    raise LinearizationError(f"output {name!r} is not a variable of {self.m.name}{hint}")
                rows.append(k)
            out = ca.vertcat(*[every[k] for k in rows]) if rows else ca.SX(0, 1)
            u = ca.vertcat(*[p[k] for k in idx]) if idx else ca.SX(0, 1)
            f = ca.Function("O", [t, y, yp, p], [ca.jacobian(out, y), ca.jacobian(out, yp), ca.jacobian(out, u)])
            self._fo[key] = f
        return f

    # -- numeric --------------------------------------------------------------------------------
    def _solve(self, point: OperatingPoint, idx: tuple[int, ...]) -> tuple:
        """``(A, B, Yx, Yu, YPx, YPu)``: state matrices and the sensitivities of every unknown and rate."""
        key = id(point)
        hit = self._cache.get(key)
        if hit is not None and hit[0] is point and hit[1] == idx:
            return hit[2]
        m, t, y, yp, p = self.m, point.t, point.y, point.yp, point.p
        jac = m.function("jac")
        J0, Jc = self.pattern.copy(), self.pattern.copy()
        J0.data = np.asarray(jac(t, y, yp, p, 0.0).nonzeros(), dtype=float)
        Jc.data = np.asarray(jac(t, y, yp, p, CJ).nonzeros(), dtype=float)
        Fy, Fyp = J0, (Jc - J0) / CJ
        ns, n = len(self.diff), m.n
        if n and len(self.alg) and abs(Fyp[:, self.alg]).max() > 0.0:
            raise LinearizationError(f"{m.name}: the residual depends on rates of algebraic unknowns (not an "
                                     "index-1 DAE in IDA's form)")
        M = sps.hstack([Fyp[:, self.diff], Fy[:, self.alg]], format="csc")
        Fu = np.asarray(self._input_function(idx)(t, y, yp, p), dtype=float).reshape(n, len(idx))
        rhs = -np.hstack([Fy[:, self.diff].toarray(), Fu])
        try:
            sol = spla.splu(M).solve(rhs) if n else np.zeros((0, ns + len(idx)))
        except RuntimeError as exc:
            raise LinearizationError(
                f"{m.name} at {point.source}: the DAE is not index 1 there with its state selection "
                f"({', '.join(m.y_names[i] for i in self.diff[:6])}{' …' if ns > 6 else ''}): {exc}") from None
        if not np.all(np.isfinite(sol)) or np.abs(M @ sol - rhs).max(initial=0.0) > 1e-6 * max(
                1.0, np.abs(rhs).max(initial=0.0)) * max(1.0, np.abs(sol).max(initial=0.0)):
            raise LinearizationError(f"{m.name} at {point.source}: the index-1 matrix [F_x', F_z] is numerically "
                                     "singular (a singular configuration, or a state selection that does not hold "
                                     "here)")
        A, B = sol[:ns, :ns], sol[:ns, ns:]
        Zx, Zu = sol[ns:, :ns], sol[ns:, ns:]
        Yx, Yu = np.zeros((n, ns)), np.zeros((n, len(idx)))
        Yx[self.diff] = np.eye(ns)
        Yx[self.alg], Yu[self.alg] = Zx, Zu
        YPx, YPu = np.zeros((n, ns)), np.zeros((n, len(idx)))
        YPx[self.diff], YPu[self.diff] = A, B
        YPx[self.alg], YPu[self.alg] = Zx @ A, Zx @ B
        out = (A, B, Yx, Yu, YPx, YPu)
        self._cache = {key: (point, idx, out)}
        return out

    def outputs(self, point: OperatingPoint, names: list[str], inputs: list[str] | None = None
                ) -> tuple[np.ndarray, np.ndarray]:
        idx = tuple(self.input_indices(list(inputs or [])))
        _, _, Yx, Yu, YPx, YPu = self._solve(point, idx)
        Oy, Oyp, Ou = (np.asarray(x, dtype=float) for x in
                       self._output_function(tuple(names), idx)(point.t, point.y, point.yp, point.p))
        Oy, Oyp = Oy.reshape(len(names), -1), Oyp.reshape(len(names), -1)
        C = Oy @ Yx + Oyp @ YPx
        D = Oy @ Yu + Oyp @ YPu + Ou.reshape(len(names), len(idx))
        return C, D

    def linearize(self, point: OperatingPoint, inputs: list[str], outputs: list[str]) -> LinearSystem:
        idx = tuple(self.input_indices(inputs))
        A, B, *_ = self._solve(point, idx)
        C, D = self.outputs(point, outputs, inputs) if outputs else (np.zeros((0, len(self.diff))),
                                                                      np.zeros((0, len(idx))))
        states = [self.m.y_names[i] for i in self.diff]
        return LinearSystem(A, B, C, D, states, list(inputs), list(outputs), point, self)


def linearize(model: Any, *, inputs: list[str] | tuple[str, ...] | str = (),
              outputs: list[str] | tuple[str, ...] | str = (),
              at: Result | None = None, t: float | None = None, params: dict[str, Any] | None = None,
              steady_state: bool = False, starts: dict[str, float] | None = None) -> LinearSystem:
    """Linearise a model at an operating point (module docstring).

    Parameters
    ----------
    model : Simulation or Component
        The model (a Component is built first).
    inputs : list of str or str
        Names of scalar parameters taken as inputs ``u`` (a single string is one name), each once.
    outputs : list of str or str
        Names of variables taken as outputs (a single string is one name), each once.
    at, t, params, steady_state, starts
        The operating point, as :func:`operating_point`: the model's initial point (``steady_state=True``: a
        static equilibrium; ``starts``: a pose), or the state of a result ``at`` at time ``t`` [s].

    Returns
    -------
    LinearSystem

    Raises
    ------
    LinearizationError
        An unknown input or output name (with the closest names), a name given twice, an input that is not a
        parameter, a bad operating-point argument (``t`` not a finite number, ``starts`` naming an unknown variable
        or a parameter, or a non-numeric start value), or a DAE that is not index 1 at the point.
    ParameterError
        ``params`` naming an unknown parameter or giving a value its declaration refuses.

    Examples
    --------
    >>> lin = linearize(model, inputs=["force.k"], outputs=["mass.s"], steady_state=True)  # doctest: +SKIP
    >>> lin.frequency_response([1.0, 10.0], "force.k", "mass.s")                           # doctest: +SKIP
    """
    inputs, outputs = names_argument(inputs, "inputs"), names_argument(outputs, "outputs")
    sim = as_simulation(model)
    point = operating_point(sim, at=at, t=t, params=params, steady_state=steady_state, starts=starts)
    return Linearizer(sim).linearize(point, inputs, outputs)
