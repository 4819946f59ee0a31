"""flexlib — acausal component models → one CasADi DAE → index reduction → SUNDIALS IDA."""

import importlib as _importlib
import os as _os
from typing import Any as _Any

_os.environ.setdefault("OMP_NUM_THREADS", "1")  # before sksundae is imported (see docs/engine.md)

from flexlib.errors import (
    AccuracyWarning,
    BalanceError,
    CacheWarning,
    ConnectError,
    EmptyResultError,
    FlexlibError,
    IndeterminateReactionWarning,
    InitializationError,
    LinearizationError,
    ModalDataWarning,
    ModalFileError,
    ModalValidityWarning,
    ModelError,
    ModelTypeError,
    ModelWarning,
    NativeSolverError,
    ParameterError,
    RegistryError,
    ResultCheckWarning,
    ResultFileError,
    ResultKeyError,
    ResultSaveWarning,
    RunArgumentError,
    SimulationInterrupted,
    SolverError,
    StructuralSingularityError,
    StructureChangedError,
)

#: The engine's public names and their modules, imported when first used (PEP 562): ``import flexlib`` and
#: ``flexlib --version`` do not load CasADi, SUNDIALS and SciPy.
_LAZY = {
    "linearize": "flexlib.analysis",
    "modal_analysis": "flexlib.analysis",
    "modal_sweep": "flexlib.analysis",
    "BuildOptions": "flexlib.compile.build_options",
    "Build": "flexlib.compile.pipeline",
    "build": "flexlib.compile.pipeline",
    "Component": "flexlib.core.component",
    "Connector": "flexlib.core.component",
    "Model": "flexlib.core.component",
    "der": "flexlib.core.equations",
    "eq": "flexlib.core.equations",
    "abs_": "flexlib.core.functions",
    "assert_": "flexlib.core.functions",
    "if_else": "flexlib.core.functions",
    "latch": "flexlib.core.functions",
    "define_latch": "flexlib.core.functions",
    "initial": "flexlib.core.functions",
    "reinit": "flexlib.core.functions",
    "max_": "flexlib.core.functions",
    "min_": "flexlib.core.functions",
    "no_event": "flexlib.core.functions",
    "segment_row": "flexlib.core.tables",
    "sign": "flexlib.core.functions",
    "Flow": "flexlib.core.variables",
    "Input": "flexlib.core.variables",
    "Output": "flexlib.core.variables",
    "Parameter": "flexlib.core.variables",
    "Potential": "flexlib.core.variables",
    "StateSelect": "flexlib.core.variables",
    "Variable": "flexlib.core.variables",
    "time": "flexlib.core.variables",
    "load_result": "flexlib.results.hdf5",
    "Result": "flexlib.results.result",
    "Experiment": "flexlib.solve.options",
    "RunOptions": "flexlib.solve.options",
    "Simulation": "flexlib.solve.simulation",
    "IDA": "flexlib.solve.solvers",
    "CasadiIDAS": "flexlib.solve.solvers",
    "FixedStep": "flexlib.solve.solvers",
}

__version__ = "0.1.0"

__all__ = [
    "IDA",
    "AccuracyWarning",
    "BalanceError",
    "Build",
    "BuildOptions",
    "CacheWarning",
    "CasadiIDAS",
    "Component",
    "ConnectError",
    "Connector",
    "EmptyResultError",
    "Experiment",
    "FixedStep",
    "FlexlibError",
    "Flow",
    "IndeterminateReactionWarning",
    "InitializationError",
    "Input",
    "LinearizationError",
    "ModalDataWarning",
    "ModalFileError",
    "ModalValidityWarning",
    "Model",
    "ModelError",
    "ModelTypeError",
    "ModelWarning",
    "NativeSolverError",
    "Output",
    "Parameter",
    "ParameterError",
    "Potential",
    "RegistryError",
    "Result",
    "ResultCheckWarning",
    "ResultFileError",
    "ResultKeyError",
    "ResultSaveWarning",
    "RunArgumentError",
    "RunOptions",
    "Simulation",
    "SimulationInterrupted",
    "SolverError",
    "StateSelect",
    "StructuralSingularityError",
    "StructureChangedError",
    "Variable",
    "__version__",
    "abs_",
    "assert_",
    "build",
    "define_latch",
    "der",
    "eq",
    "if_else",
    "initial",
    "latch",
    "linearize",
    "load_result",
    "max_",
    "min_",
    "modal_analysis",
    "modal_sweep",
    "no_event",
    "reinit",
    "segment_row",
    "sign",
    "time",
]


#: Subpackages reachable as attributes without an import of their own (``fl.analysis.mobility(sim)``, as documented)
_SUBPACKAGES = ("analysis", "fe")


def __getattr__(name: str) -> _Any:
    if name in _SUBPACKAGES:
        return _importlib.import_module(f"{__name__}.{name}")  # the import system also sets the attribute
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'flexlib' has no attribute {name!r}")
    value = getattr(_importlib.import_module(module), name)
    globals()[name] = value  # once imported, a plain attribute
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY) | set(_SUBPACKAGES))
