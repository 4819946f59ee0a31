"""flexlib — acausal component models → one CasADi DAE → index reduction → SUNDIALS IDA."""

import os as _os

_os.environ.setdefault("OMP_NUM_THREADS", "1")  # before sksundae is imported (see docs/engine.md)

from flexlib.analysis import linearize, modal_analysis, modal_sweep
from flexlib.compile.build_options import BuildOptions
from flexlib.compile.pipeline import Build, build
from flexlib.core.component import Component, Connector, Model
from flexlib.core.equations import der, eq
from flexlib.core.functions import abs_, assert_, if_else, max_, min_, no_event, sign
from flexlib.core.variables import (
    Flow,
    Input,
    Output,
    Parameter,
    Potential,
    StateSelect,
    Variable,
    time,
)
from flexlib.errors import (
    BalanceError,
    CacheWarning,
    ConnectError,
    EmptyResultError,
    FlexlibError,
    InitializationError,
    LinearizationError,
    ModalFileError,
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
from flexlib.results.hdf5 import load_result
from flexlib.results.result import Result
from flexlib.solve.options import Experiment, RunOptions
from flexlib.solve.simulation import Simulation
from flexlib.solve.solvers import IDA, CasadiIDAS

__version__ = "0.1.0"

__all__ = [
    "IDA",
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
    "FlexlibError",
    "Flow",
    "InitializationError",
    "Input",
    "LinearizationError",
    "ModalFileError",
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
    "der",
    "eq",
    "if_else",
    "linearize",
    "load_result",
    "max_",
    "min_",
    "modal_analysis",
    "modal_sweep",
    "no_event",
    "sign",
    "time",
]
