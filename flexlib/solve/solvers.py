"""Solver objects: the integrator of a run with its own options, ``sim.run(solver=fl.IDA(max_order=2))``.

Each solver object is a frozen record that makes the :class:`~flexlib.solve.backends.base.Integrator` adapter of a
run (:meth:`Solver.integrator`). The strings accepted by ``run(solver=...)`` are aliases (:data:`ALIASES`):
``"ida"`` is ``IDA()``, ``"ida-native"`` ``IDA(native=True)``, ``"ida-sksundae"`` ``IDA(native=False)``,
``"casadi-idas"`` ``CasadiIDAS()``, ``"fixed-step"`` ``FixedStep()``. A solver is also given as a record, a mapping
with its kind and options (:data:`KINDS`), ``{"kind": "fixed-step", "h": 0.002}``: the form a scenario file, a result's
run record and ``flexlib run --solver fixed-step --step 0.002`` use (:meth:`Solver.record`, :func:`as_solver`).
"""

from __future__ import annotations

import dataclasses
import numbers
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from flexlib.compile.environment import env_default
from flexlib.errors import RunArgumentError

if TYPE_CHECKING:  # the solver records and their names stay light (flexlib's command line imports them)
    from flexlib.solve.backends.base import Integrator
    from flexlib.solve.trajectory import Trajectory

__all__ = ["ALIASES", "IDA", "KINDS", "METHODS", "SOLVERS", "CasadiIDAS", "FixedStep", "Solver", "as_solver",
           "integrate"]

#: The formulas of :class:`FixedStep`: name → order
METHODS = {"euler": 1, "bdf2": 2}

#: Linear solvers of the C driver (``IDA(linear_solver=...)``)
LINEAR_SOLVERS = ("dense", "klu", "superlumt")


def _check_order(owner: str, max_order: Any) -> None:
    if max_order is not None and (isinstance(max_order, (bool, np.bool_)) or not isinstance(max_order, numbers.Real)
                                  or not float(max_order).is_integer() or not 1 <= max_order <= 5):
        raise RunArgumentError(f"{owner}(max_order={max_order!r}): must be an integer 1 ... 5 (the highest BDF order) "
                               "or None (the run's max_order)")


def _check_switch(owner: str, name: str, value: Any) -> None:
    if value not in (None, True, False):
        raise RunArgumentError(f"{owner}({name}={value!r}): must be True, False or None")


class Solver:
    """Base of the solver objects."""

    #: The alias in statistics and messages
    label = ""
    max_order: int | None = None
    #: Every unknown in IDA's local error test, also the derivative-level ones it leaves out by default
    #: (:func:`flexlib.solve.backends.base.absolute_tolerances`; None: ``FLEXLIB_ERROR_TEST_ALL``, off unless ``1``)
    error_test_all: bool | None = None
    #: A solver to fall back on when this one cannot be set up for a model (None: the error is raised)
    fallback: Solver | None = None

    def integrator(self, *, rtol: float, atol: float, max_step: float, max_order: int,
                   max_steps: int) -> Integrator:
        """The adapter of one run (``max_order``: the run's, used where the solver object has none) [SI units], with
        ``error_test_all`` resolved (its environment default read now where the object leaves it None)."""
        integ = self.adapter(rtol, atol, max_step, self.max_order or max_order, max_steps)
        integ.error_test_all = env_default("error_test_all") if self.error_test_all is None else self.error_test_all
        return integ

    def adapter(self, rtol: float, atol: float, max_step: float, max_order: int, max_steps: int) -> Integrator:
        """The :class:`~flexlib.solve.backends.base.Integrator` with these options (a subclass's own)."""
        raise NotImplementedError

    def record(self) -> dict[str, Any]:
        """The solver as a JSON-ready mapping: its kind (:data:`KINDS`) and the options that differ from their
        defaults; :func:`as_solver` turns it back into an equal object."""
        kind = next(k for k, cls in KINDS.items() if type(self) is cls)
        return {"kind": kind, **{f.name: getattr(self, f.name) for f in dataclasses.fields(self)  # type: ignore[arg-type]
                                 if getattr(self, f.name) != f.default}}


@dataclass(frozen=True)
class IDA(Solver):
    """SUNDIALS IDA (variable-order BDF).

    Parameters
    ----------
    max_order : int, optional
        Highest BDF order, 1–5 (default: the run's ``max_order``).
    linear_solver : {"dense", "klu", "superlumt"}, optional
        The C driver's linear solver (default: the rule of :func:`flexlib.solve.backends.ida_c.linear_solver`,
        which the environment variable ``FLEXLIB_LINSOL`` overrides).
    native : bool, optional
        True: IDA stepped in C (:class:`~flexlib.errors.NativeSolverError` where the driver cannot be built); False:
        stepped from Python through scikit-sundae; None (default): C where the driver is available
        (``FLEXLIB_NATIVE=0`` in the environment turns it off), scikit-sundae otherwise.
    error_test_all : bool, optional
        Keep every unknown in the local error test, also the derivative-level ones left out by default (for
        measurements; default: the environment variable ``FLEXLIB_ERROR_TEST_ALL``, off unless ``1``).
    """

    max_order: int | None = None
    linear_solver: str | None = None
    native: bool | None = None
    error_test_all: bool | None = None

    def __post_init__(self) -> None:
        _check_order("IDA", self.max_order)
        if self.linear_solver is not None and self.linear_solver not in LINEAR_SOLVERS:
            raise RunArgumentError(f"IDA(linear_solver={self.linear_solver!r}): must be one of "
                                   f"{', '.join(LINEAR_SOLVERS)} or None")
        _check_switch("IDA", "native", self.native)
        _check_switch("IDA", "error_test_all", self.error_test_all)

    @property
    def label(self) -> str:  # type: ignore[override]
        return {None: "ida", True: "ida-native", False: "ida-sksundae"}[self.native]

    @property
    def fallback(self) -> Solver | None:  # type: ignore[override]
        return dataclasses.replace(self, native=False) if self.native is None else None

    def adapter(self, rtol: float, atol: float, max_step: float, max_order: int, max_steps: int) -> Integrator:
        from flexlib.solve.native import native_available

        if self.native or (self.native is None and native_available()):
            from flexlib.solve.backends.ida_c import IdaC

            return IdaC(rtol, atol, max_step, max_order, self.linear_solver)
        from flexlib.solve.backends.sksundae import SkSundae

        return SkSundae(rtol, atol, max_step, max_order)


@dataclass(frozen=True)
class CasadiIDAS(Solver):
    """CasADi's built-in IDAS, every step in C; state events located on its output grid.

    ``max_order`` (optional) is the highest BDF order and ``error_test_all`` (optional) the error-test option, as
    for :class:`IDA`.
    """

    max_order: int | None = None
    error_test_all: bool | None = None
    label = "casadi-idas"

    def __post_init__(self) -> None:
        _check_order("CasadiIDAS", self.max_order)
        _check_switch("CasadiIDAS", "error_test_all", self.error_test_all)

    def adapter(self, rtol: float, atol: float, max_step: float, max_order: int, max_steps: int) -> Integrator:
        from flexlib.solve.backends.casadi import CasadiIdas

        return CasadiIdas(rtol, atol, max_step, max_order, max_steps)


@dataclass(frozen=True)
class FixedStep(Solver):
    """A fixed-step implicit integrator for real-time use: every step ``h``, a bounded cost per step, events at step
    boundaries (:mod:`flexlib.solve.backends.fixed_step`).

    Parameters
    ----------
    h : float
        Step size [s], > 0.
    method : {"bdf2", "euler"}
        BDF2 (second order, default) or implicit Euler (first order).
    newton_iters : int
        Most Newton corrections per step, 1 … 20 (default 4): the bound of a step's cost; a step whose corrections
        still contract then is taken (``stats["unconverged_steps"]``), one whose corrections grow fails the run,
        naming the time and the step.
    max_halvings : int
        Times a step whose corrections do not converge may be halved, 0 … 8 (default 2): the step is then taken as two
        implicit-Euler halves (each halved again if needed), so a step costs at most ``2**(max_halvings + 1) − 1``
        step solutions (``stats["halved_steps"]``); a step that still does not converge at the smallest size is
        taken if its corrections contract, else the run fails.
    realtime : bool
        Keep the run in step with the wall clock: each step waits until the wall time since the first step reaches
        its simulated time; a step that ends later is an overrun (``stats["overruns"]``, ``stats["worst_late"]`` [s]).
    native : bool, optional
        True: stepped in C (the ``ida-native`` driver; :class:`~flexlib.errors.NativeSolverError` where it cannot be
        built); False: stepped from Python; None (default): C where the driver is available, as for :class:`IDA`.
        Both take the same steps.
    error_test_all : bool, optional
        Weigh every unknown in the Newton test, also the derivative-level ones (as for :class:`IDA`).
    """

    h: float = 1e-3
    method: str = "bdf2"
    newton_iters: int = 4
    max_halvings: int = 2
    realtime: bool = False
    native: bool | None = None
    error_test_all: bool | None = None
    label = "fixed-step"

    def __post_init__(self) -> None:
        if (isinstance(self.h, (bool, np.bool_)) or not isinstance(self.h, numbers.Real) or not np.isfinite(self.h)
                or not self.h > 0):
            raise RunArgumentError(f"FixedStep(h={self.h!r}): the step must be a positive number of seconds")
        if self.method not in METHODS:
            raise RunArgumentError(f"FixedStep(method={self.method!r}): must be one of {', '.join(METHODS)}")
        if (isinstance(self.newton_iters, (bool, np.bool_)) or not isinstance(self.newton_iters, numbers.Integral)
                or not 1 <= self.newton_iters <= 20):
            raise RunArgumentError(f"FixedStep(newton_iters={self.newton_iters!r}): must be an integer 1 … 20")
        _check_switch("FixedStep", "error_test_all", self.error_test_all)
        if (isinstance(self.max_halvings, (bool, np.bool_)) or not isinstance(self.max_halvings, numbers.Integral)
                or not 0 <= self.max_halvings <= 8):
            raise RunArgumentError(f"FixedStep(max_halvings={self.max_halvings!r}): must be an integer 0 … 8")
        _check_switch("FixedStep", "native", self.native)
        if self.realtime not in (True, False):
            raise RunArgumentError(f"FixedStep(realtime={self.realtime!r}): must be True or False")

    @property
    def fallback(self) -> Solver | None:  # type: ignore[override]
        return dataclasses.replace(self, native=False) if self.native is None else None

    def adapter(self, rtol: float, atol: float, max_step: float, max_order: int, max_steps: int) -> Integrator:
        from flexlib.solve.backends import fixed_step
        from flexlib.solve.native import native_available

        native = self.native or (self.native is None and native_available())
        cls = fixed_step.FixedStepNative if native else fixed_step.FixedStepIntegrator
        return cls(float(self.h), self.method, int(self.newton_iters), rtol, atol, bool(self.realtime),
                   int(self.max_halvings))


#: The solver strings of ``run(solver=...)`` and the objects they stand for
ALIASES: dict[str, Solver] = {"ida": IDA(), "casadi-idas": CasadiIDAS(), "ida-native": IDA(native=True),
                              "ida-sksundae": IDA(native=False), "fixed-step": FixedStep()}
#: The solver names accepted by ``run(solver=...)``, scenarios and ``flexlib run --solver``
SOLVERS = tuple(ALIASES)
#: The kinds of solver records (``{"kind": ..., option: value, ...}``) and their classes
KINDS: dict[str, type[Solver]] = {"ida": IDA, "casadi-idas": CasadiIDAS, "fixed-step": FixedStep}


def as_solver(solver: str | Solver | Mapping[str, Any]) -> Solver:
    """The solver object of ``solver``: an alias of :data:`ALIASES`, a solver object, or a record
    (``{"kind": "fixed-step", "h": 0.002}``, :meth:`Solver.record`).

    Raises
    ------
    RunArgumentError
        A record without a known kind, with an option its solver does not have, or with a bad value (named).
    """
    if isinstance(solver, str):
        return ALIASES[solver]
    if not isinstance(solver, Mapping):
        return solver
    options = dict(solver)
    kind = options.pop("kind", None)
    if kind not in KINDS:
        raise RunArgumentError(f"solver record {dict(solver)!r}: 'kind' must be one of {', '.join(map(repr, KINDS))}")
    cls = KINDS[kind]
    names = [f.name for f in dataclasses.fields(cls)]  # type: ignore[arg-type]
    unknown = [k for k in options if k not in names]
    if unknown:
        raise RunArgumentError(f"solver record {dict(solver)!r}: {kind} has no option {unknown[0]!r} "
                               f"(its options: {', '.join(names)})")
    return cls(**options)


def integrate(solver: str | Solver, model: Any, init: Any, p: np.ndarray, y0: np.ndarray, yp0: np.ndarray,
              t0: float, t_end: float, t_out: np.ndarray | None, *, rtol: float = 1e-6, atol: float = 1e-8,
              max_step: float = 0.0, max_steps: int = 5_000_000, progress: bool | None = None,
              monitor: Any = None, max_order: int = 5) -> Trajectory:
    """Integrate a compiled model from the consistent ``y0, yp0`` at ``t0`` to ``t_end`` [s] with ``solver``
    (:func:`flexlib.solve.loop.run_loop` on the solver's adapter; arguments as there and as :meth:`Solver.integrator`).
    """
    integ = as_solver(solver).integrator(rtol=rtol, atol=atol, max_step=max_step, max_order=max_order,
                                         max_steps=max_steps)
    from flexlib.solve.loop import run_loop

    return run_loop(integ, model, init, p, y0, yp0, t0, t_end, t_out, max_steps=max_steps, progress=progress,
                    monitor=monitor)
