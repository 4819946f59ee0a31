"""Exceptions raised by flexlib.

Every message names the component path and the variable involved, so that an
engineer can find the culprit in a model of a few thousand equations.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "AccuracyWarning",
    "BalanceError",
    "CacheWarning",
    "ConnectError",
    "EmptyResultError",
    "FlexlibError",
    "IndeterminateReactionWarning",
    "InitializationError",
    "LinearizationError",
    "ModalDataWarning",
    "ModalFileError",
    "ModalValidityWarning",
    "ModelError",
    "ModelTypeError",
    "ModelWarning",
    "ParameterError",
    "ResultFileError",
    "ResultKeyError",
    "ResultSaveWarning",
    "RunArgumentError",
    "SimulationInterrupted",
    "SolverError",
    "StructuralSingularityError",
    "StructureChangedError",
]


class FlexlibError(Exception):
    """Base class of all flexlib errors."""


class ModelError(FlexlibError):
    """A model is ill-formed: bad declaration, bad equation, bad parameter value."""


class ModelTypeError(ModelError, TypeError):
    """Something other than a model instance where flexlib expects one: a model class instead of an instance, a
    name, None (``Simulation(Osc)``, ``sim.with_model("Osc")``, ``flexlib.build(...)``); a ``TypeError`` too."""


class ParameterError(ModelError):
    """An unknown parameter name or an invalid parameter value."""


class ConnectError(ModelError):
    """Two connectors that cannot be connected."""


class BalanceError(ModelError):
    """The flattened model has more or fewer equations than unknowns.

    Attributes
    ----------
    excess_equations : list of str
        Descriptions of the equations in the over-determined part.
    free_variables : list of str
        Names of the variables in the under-determined part.
    """

    def __init__(
        self, message: str, excess_equations: list[str] | None = None,
        free_variables: list[str] | None = None,
    ) -> None:
        super().__init__(message)
        self.excess_equations = excess_equations or []
        self.free_variables = free_variables or []


class StructuralSingularityError(BalanceError):
    """Equations and unknowns balance in number, but not in structure."""


class InitializationError(FlexlibError):
    """Consistent initial values could not be found, or initial conditions are over/under-specified."""


class LinearizationError(FlexlibError):
    """A model cannot be linearised as asked: an unknown input or output, a DAE that is not index 1 at the
    operating point, joints that cannot be locked together (``flexlib.analysis``)."""


class SolverError(FlexlibError):
    """The integrator failed.

    Attributes
    ----------
    result : flexlib.Result or None
        The result up to the failure (all variables, solver statistics).
    """

    def __init__(self, message: str, result: Any = None) -> None:
        super().__init__(message)
        self.result = result


class SimulationInterrupted(SolverError):
    """The run was interrupted (Ctrl-C); ``result`` holds everything up to the interrupt."""


class RunArgumentError(FlexlibError, ValueError):
    """An argument of :meth:`Simulation.run` (or of a result-file operation) is invalid; checked before any work."""


class ResultFileError(FlexlibError, OSError):
    """A result file cannot be read (missing, truncated, not a flexlib result, from a newer format) or written."""


class StructureChangedError(ModelError):
    """A numeric choice made when the model was built (dropped redundant loop rows, dummy-derivative
    pivots) does not hold at the parameter and start values of this run, and could not be rebuilt."""


class CacheWarning(UserWarning):
    """The disk cache could not be used (unwritable, unsafe, damaged entry); flexlib went on without it."""


class ResultSaveWarning(UserWarning):
    """A result could not be written to its file; the result is kept in memory and returned (or attached
    to the solver error)."""


class ResultKeyError(FlexlibError, KeyError):
    """No variable of that name in a result; the message suggests close matches ("did you mean")."""

    def __str__(self) -> str:  # KeyError would show the repr of the message
        return str(self.args[0]) if self.args else ""


class EmptyResultError(FlexlibError, ValueError):
    """A value was asked of a result without rows (a run that failed or was interrupted at its start)."""


class NativeSolverError(FlexlibError, RuntimeError):
    """``solver="ida-native"`` cannot be used here: no C compiler for its driver, the SUNDIALS libraries bundled
    with scikit-sundae are missing, or the driver failed to compile or to set up IDA. The other solvers still work."""


class ModalFileError(FlexlibError, ValueError):
    """A modal data file (or FE matrix file) is missing, truncated, malformed or from a newer format; the message
    names the file and the dataset."""


class RegistryError(FlexlibError, LookupError):
    """An unknown registered model or scenario (the message names it, the known ones and the closest match), or
    a bad registration (``flexlib.registry``)."""


class ResultCheckWarning(UserWarning):
    """A check of a result's recorded rows (the settling of derivative-level unknowns) could not run; the rows are
    returned as the solver left them, and ``result.stats["settle_error"]`` says why."""


class AnalysisWarning(UserWarning):
    """A linear-analysis result that rests on a numerical choice flexlib cannot confirm at this operating point
    (``lock="rigid"`` / ``mobility`` on loops closed through flexible bodies); the message says what to check."""


class ModalDataWarning(UserWarning):
    """A flexible body's output that its modal data cannot give as asked: recovered by default, it falls back to
    plain modal superposition where the data hold no static responses for it; the message names the body and why."""


class ModalValidityWarning(UserWarning):
    """A run in which a modal body left the range its model holds for: an elastic deflection or rotation past the
    small-deformation limit, or left-out modes carrying a large share of the recovered deformation; the message names
    the body, the node, the time and the limit (``FlexibleBody(validity=...)``)."""


class ModelWarning(UserWarning):
    """A model that runs but is probably not what was meant: a component connected to nothing that has no effect
    on the rest of the model (Modelica tools' check of unconnected components); the message names it."""


class AccuracyWarning(UserWarning):
    """A run whose result may be inaccurate without the integrator having failed: fixed steps
    (``solver=fl.FixedStep(...)``) whose Newton corrections had not converged when the step was taken; the message
    says how many, the first time and what to change."""


class IndeterminateReactionWarning(UserWarning):
    """A read of a force or torque that the rigid model does not determine: the mechanism is over-constrained, the
    build dropped redundant loop rows, and the value depends on which ones (``result.indeterminate``); the message
    names the variables, the dropped rows and the compliant alternatives (a ``Bushing``, a flexible body)."""
