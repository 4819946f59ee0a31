"""Stage 4 — initialisation: consistent ``y(t0)``, ``y'(t0)`` from start values and ``fixed`` flags.

The initialisation problem (:class:`~flexlib.solve.init.problem.InitProblem`) has the unknowns ``y`` and the
derivatives of the states, and the equations ``F(t0, y, y', p) = 0`` plus one equation per initial condition (a fixed
start value, or ``der(x) = 0`` for every state without one in steady-state mode). It must be square and structurally
regular; otherwise the error names the over-specified conditions or the states left free. It is solved by a damped
Newton method on the sparse CasADi Jacobian, falling back to trust-region least squares
(:mod:`flexlib.solve.init.newton`).

The same machinery re-initialises after an event (:mod:`flexlib.solve.init.reinit`): states keep their values,
algebraic variables and derivatives are recomputed; the relation values of the start are found with the start
(:mod:`flexlib.solve.init.relations`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sps

from flexlib.compile.codegen import CompiledModel, compile_dae
from flexlib.errors import InitializationError, ParameterError
from flexlib.solve.init import relations
from flexlib.solve.init.newton import solve
from flexlib.solve.init.problem import InitProblem
from flexlib.solve.init.reinit import algebraic_rates, held_arguments, held_functions, reinit_point

__all__ = ["Initializer"]


class Initializer:
    """Consistent initial values for one compiled model (functions built lazily, reused)."""

    def __init__(self, model: CompiledModel, structure: Any = None) -> None:
        self.model = model
        #: callable giving the model's index-reduction structure (``Build.structure``): a failure of a model with
        #: explicit algebraics eliminated is diagnosed on the DAE that keeps them (see :meth:`initial`)
        self._structure = structure
        self.diff = np.flatnonzero(model.differential)
        self.problem = InitProblem(model)
        self._reinit_fns: tuple[Any, Any] | None = None
        self._last_jac: Any = None  # the Jacobian at the point the last solve accepted (None: not evaluated)

    def initial(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                steady_state: bool = False, tol: float = 1e-10, diagnose: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Consistent initial values at ``t0``.

        Parameters
        ----------
        t0 : float
            Initial time [s].
        p : ndarray
            Parameter vector (parameters, then relation values).
        starts : dict
            ``{name: (start, fixed)}`` for every scalar variable (from the model instance).
        steady_state : bool
            Add ``der(x) = 0`` for every state that has no initial condition of its own.

        A failure of a model whose explicit algebraics were eliminated (``report.explicit``) is diagnosed
        again on the DAE that keeps them, so the message names the equations and variables as written
        (``x + y = 1`` and ``2x + 2y = 3`` both, not their combination).
        """
        try:
            return self._initial(t0, p, starts, steady_state, tol, diagnose)
        except InitializationError:
            full = self._full_model() if diagnose else None
            if full is None:
                raise
            Initializer(full).initial(t0, p, starts, steady_state, tol, diagnose)
            raise  # the full DAE initialises: the reduced model's own message stands

    def _full_model(self) -> CompiledModel | None:
        """The model compiled without the explicit-algebraics stage (None if it has none or no structure)."""
        if not self.model.report.explicit or self._structure is None:
            return None
        structure = self._structure()
        dummies, levels = structure.select()
        dae = structure.assemble(dummies, levels, explicit=False)
        return compile_dae(structure.simple.flat, structure.simple, dae, codegen=False)

    def _initial(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                 steady_state: bool = False, tol: float = 1e-10, diagnose: bool = True
                 ) -> tuple[np.ndarray, np.ndarray]:
        m = self.model
        self._check_finite(p, starts)
        cond_vals = np.array([starts.get(name, (val, True))[0] for name, val in m.conditions])
        active = []
        cond_fn = m.function("cond")
        y_guess = self.guess(starts)
        for k, (name, _) in enumerate(m.conditions):
            if m.cond_depends[k]:
                active.append(k)
                continue
            have = float(np.asarray(cond_fn(t0, y_guess, np.zeros(m.n), p)).ravel()[k])
            if abs(have - cond_vals[k]) > 1e-9 * max(1.0, abs(have)):
                if ": " in name and " #" in name:  # an initial equation of time and parameters only
                    raise InitializationError(
                        f"initial equation {name.rsplit(' #', 1)[0]} involves no unknown (only time and parameters) "
                        f"and does not hold at the start t = {t0:g} s: its residual there is {have:g}")
                raise InitializationError(
                    f"initial condition {name} = {cond_vals[k]:g} contradicts the model, which fixes it to {have:g}")
        steady: list[int] = []
        held: list[int] = []
        par = np.concatenate([[t0], p, cond_vals[active]])
        w0 = np.concatenate([y_guess, np.zeros(len(self.diff))])
        if steady_state and len(self.diff):
            # der(x) = 0 for every state; those of states held by an initial condition come first (the start
            # value says where the equilibrium is sought, and free states take the values that make it one);
            # a state held by a fixed start value must then be at rest (checked below), one held by a
            # component's initial equation may start away from equilibrium (a partial steady state)
            held, by_start = self.problem.held_states(tuple(active))
            cand = held + [k for k in range(len(self.diff)) if k not in held]
            steady = self.problem.complementary_steady(tuple(active), tuple(cand), w0, par, len(held))
            held = by_start
        active_t, steady_t = tuple(active), tuple(steady)
        defaults, w0 = self.problem.default_starts(starts, active_t, steady_t, w0, par, tol)
        if defaults:
            par = np.concatenate([par, y_guess[list(defaults)]])
        g, jg = self.problem.functions(active_t, steady_t, defaults)
        self.problem.check_structure(jg, w0, par, active_t, steady_t, defaults)
        try:
            w, self._last_jac = solve(g, jg, w0, par, tol, self.problem.labels(active_t, steady_t, defaults),
                                      self.problem.unknown_names(), self.problem.nominal_w(), diagnose=diagnose)
        except InitializationError as err:
            best = getattr(err, "best", None)
            if best is not None:
                err.point = self._split(best)
            raise
        y, yp = self._split(w)
        if held:
            self.problem.check_equilibrium(y, yp, [k for k in held if k not in steady], active_t, steady_t,
                                    cond_vals[list(active_t)])
        return y, self.algebraic_rates(t0, y, yp, p)

    def _check_finite(self, p: np.ndarray, starts: dict[str, tuple[float, bool]]) -> None:
        """Parameters and start values must be finite (a NaN would only show as an unnamed failure later)."""
        m = self.model
        bad = [f"{name} = {v!r} [{unit}]" for name, v, unit in zip(m.param_names, p[:m.n_params], m.param_units,
                                                                     strict=True) if not np.isfinite(v)]
        if bad:
            raise ParameterError("parameter values must be finite; not finite: " + ", ".join(bad[:12])
                                 + (f" … and {len(bad) - 12} more" if len(bad) > 12 else ""))
        try:  # the usual case at once: scalar start values, all finite
            if np.isfinite(np.fromiter((v for v, _ in starts.values()), dtype=float, count=len(starts))).all():
                return
        except (TypeError, ValueError):  # an array or a non-number among them: checked one by one below
            pass
        bad = []
        for name, (val, fixed) in starts.items():
            try:
                finite = bool(np.all(np.isfinite(np.asarray(val, dtype=float))))
            except (TypeError, ValueError):
                finite = False
            if not finite:
                bad.append(f"{name} = {val!r}{' (fixed)' if fixed else ''}")
        if bad:
            raise InitializationError("start values must be finite; not finite: " + ", ".join(bad[:12])
                                      + (f" … and {len(bad) - 12} more" if len(bad) > 12 else ""))

    def guess(self, starts: dict[str, tuple[float, bool]]) -> np.ndarray:
        """Start guesses for ``y`` from the model's start values."""
        y = np.zeros(self.model.n)
        guesses = self.model.start_guesses  # build-time guesses (kept tree frames) where no start is given
        for i, sources in enumerate(self.model.start_sources):
            for name, sign in sources:
                val = starts.get(name, (0.0, False))[0]
                if val != 0.0:
                    y[i] = sign * val
                    break
            else:
                if guesses:
                    y[i] = guesses.get(self.model.y_names[i], 0.0)
        return y

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
               tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
        """Recompute algebraic variables and derivatives at an event [s], states held."""
        y_new, yp_new = self._reinit(t, y, yp, p, tol)
        return y_new, self.algebraic_rates(t, y_new, yp_new, p, self._last_jac)

    def algebraic_rates(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
                        jac: sps.spmatrix | None = None) -> np.ndarray:
        """``yp`` with the rates of the algebraic variables filled in
        (:func:`~flexlib.solve.init.reinit.algebraic_rates`)."""
        if self.model.differential.all():
            return yp
        return algebraic_rates(self.model, self._held_functions(), self.diff, t, y, yp, p, jac)

    def held_jacobian(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray) -> tuple[sps.csc_matrix,
                                                                                          np.ndarray]:
        """The Jacobian of the event problem with the states held (unknowns: the algebraic variables, then the
        states' derivatives) at ``(t, y, yp)``, and those unknowns' nominal values."""
        from flexlib.solve.init.newton import csc

        w, par, nominal = held_arguments(self.model, self.diff, t, y, yp, p)
        return csc(self._held_functions()[1](w, par)), nominal

    def _held_functions(self) -> tuple[Any, Any]:
        """Residual and Jacobian of the event problem with the states held (built once)."""
        if self._reinit_fns is None:
            self._reinit_fns = held_functions(self.model, self.diff)
        return self._reinit_fns

    def _reinit(self, t: float, y: np.ndarray, yp: np.ndarray, p: np.ndarray,
                tol: float, diagnose: bool = True) -> tuple[np.ndarray, np.ndarray]:
        y_new, yp_new, self._last_jac = reinit_point(self.model, self._held_functions(), self.diff, t, y, yp, p, tol,
                                                     diagnose)
        return y_new, yp_new

    def consistent_start(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]],
                         steady: bool) -> tuple[np.ndarray, np.ndarray]:
        """Consistent ``y(t0)``, ``y'(t0)`` together with the relation values in ``p`` (updated in place;
        :func:`flexlib.solve.init.relations.consistent_start`)."""
        return relations.consistent_start(self, t0, p, starts, steady)

    def start_by_flipping(self, t0: float, p: np.ndarray, starts: dict[str, tuple[float, bool]], steady: bool,
                          err: InitializationError, most: int = 16) -> tuple[np.ndarray, np.ndarray]:
        """The start with one state relation switched at a time
        (:func:`flexlib.solve.init.relations.start_by_flipping`)."""
        return relations.start_by_flipping(self, t0, p, starts, steady, err, most)

    def _split(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = self.model.n
        y = w[:n].copy()
        yp = np.zeros(n)
        yp[self.diff] = w[n:]
        return y, yp
