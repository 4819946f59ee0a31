"""A co-simulation FMU as a causal block of a flexlib model (``flexlib.fmi.FMU``): a controller delivered as an FMU
drives a flexlib machine.

The block samples: every ``step`` seconds (the unit's communication step, default its ``DefaultExperiment``
``stepSize``) the run stops exactly there (a time event of the run loop, :mod:`flexlib.solve.loop`) and

1. the unit's outputs of the step just finished become the block's outputs, held until the next sample (each output
   is a state of the flexlib model with ``der(y) = 0``, set at the sample as ``reinit`` sets a state, so the result
   file records it as every other state);
2. the block's inputs are read at that instant and set as the unit's inputs;
3. the unit is stepped from there by one communication step (``fmi2DoStep``).

This is the usual co-simulation master's order (Jacobi): an output reacts to an input one sample later, so a loop
closed through the block has no algebraic loop. At the start the outputs are the unit's after its initialisation.
The unit is run through fmpy (the ``fmi`` extra) and re-instantiated at the start of every run.

References
----------
Modelica Association, *Functional Mock-up Interface 2.0.4*, section 4 (co-simulation); R. Kübler, W. Schiehlen,
"Two methods of simulator coupling", *Mathematical and Computer Modelling of Dynamical Systems* 6 (2000) 93–113
(the Jacobi scheme).
"""

from __future__ import annotations

import hashlib
import os
import re
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from flexlib.core.component import Component
from flexlib.core.equations import der, eq
from flexlib.core.variables import Input, Output
from flexlib.errors import ModelError

__all__ = ["FMU", "FMUBlock"]


def _name(text: str, taken: set[str]) -> str:
    """A Python identifier for an FMI variable name (``J1.w`` → ``J1_w``), unique among ``taken``."""
    base = re.sub(r"\W", "_", text).strip("_") or "v"
    base = base if not base[0].isdigit() else f"v_{base}"
    name, k = base, 1
    while name in taken:
        k += 1
        name = f"{base}_{k}"
    taken.add(name)
    return name


class FMUBlock(Component):
    """Base of the classes :func:`FMU` makes: one per unit, with an ``Input`` per FMI input and an ``Output`` per FMI
    output (FMI names with ``.`` and ``[`` made identifiers: ``J1.w`` → ``J1_w``; ``fmi_names`` maps them back)."""

    #: FMI name of each declaration: {declaration name: (FMI name, value reference, causality)}
    fmi_names: ClassVar[dict[str, tuple[str, int, str]]] = {}

    def __init__(self, path: str | os.PathLike, step: float | None = None,
                 start_values: dict[str, float] | None = None, **kw: Any) -> None:
        super().__init__(**kw)
        self.path_fmu = str(Path(path).resolve())
        self.digest = hashlib.sha256(Path(self.path_fmu).read_bytes()).hexdigest()
        self.step = float(step) if step is not None else float(type(self).default_step)
        if not np.isfinite(self.step) or self.step <= 0:
            raise ModelError(f"FMU {Path(path).name}: step = {step!r} must be a positive number of seconds")
        self.start_values = dict(start_values or {})
        self._slave: Any = None

    def structure_key(self) -> Any:
        return self.digest  # another unit under the same path is another model

    def equations(self) -> list:
        return [eq(der(getattr(self, name)), 0.0) for name, (_, _, c) in self.fmi_names.items() if c == "output"]

    # ---- sampling (called by the run loop) ----
    def sampled_inputs(self) -> list[str]:
        """Full names of the block's inputs, in the order :meth:`sample` takes them."""
        return [self._label(n) for n, (_, _, c) in self.fmi_names.items() if c == "input"]

    def sampled_states(self) -> list[str]:
        """Full names of the held outputs (states of the model), in the order :meth:`sample` returns them."""
        return [self._label(n) for n, (_, _, c) in self.fmi_names.items() if c == "output"]

    def sample_start(self, t0: float) -> np.ndarray:
        """Instantiate and initialise the unit at ``t0`` [s]; its outputs there."""
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.sample_stop()
        md = read_model_description(self.path_fmu)
        unzipped = extract(self.path_fmu)
        slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                          instanceName=self.path or type(self).__name__)
        slave.instantiate()
        slave.setupExperiment(startTime=t0)
        by_name = {v.name: v.valueReference for v in md.modelVariables}
        for name, value in self.start_values.items():
            if name not in by_name:
                raise ModelError(f"{self.path}: start value for {name!r}, which is not a variable of the unit")
            slave.setReal([by_name[name]], [float(value)])
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        self._slave, self._unzipped = slave, unzipped
        return self._outputs()

    def sample(self, t: float, inputs: np.ndarray) -> np.ndarray:
        """At a sample instant ``t`` [s]: the unit's outputs now (of the step just finished), then the ``inputs``
        (values of :meth:`sampled_inputs`) set and one communication step taken."""
        out = self._outputs()
        vrs = [vr for _, (_, vr, c) in self.fmi_names.items() if c == "input"]
        if vrs:
            self._slave.setReal(vrs, [float(v) for v in inputs])
        self._slave.doStep(currentCommunicationPoint=t, communicationStepSize=self.step)
        return out

    def sample_stop(self) -> None:
        """Free the unit (after a run, or before a new one)."""
        import shutil

        if self._slave is not None:
            try:
                self._slave.terminate()
                self._slave.freeInstance()
            finally:
                self._slave = None
                shutil.rmtree(self._unzipped, ignore_errors=True)

    def _outputs(self) -> np.ndarray:
        vrs = [vr for _, (_, vr, c) in self.fmi_names.items() if c == "output"]
        return np.asarray(self._slave.getReal(vrs), dtype=float) if vrs else np.zeros(0)


def FMU(path: str | os.PathLike, step: float | None = None, start_values: dict[str, float] | None = None,
        **kw: Any) -> FMUBlock:
    """A co-simulation FMU (FMI 2.0) as a block: an ``Input`` per FMI input, an ``Output`` per FMI output.

    Parameters
    ----------
    path : str or path-like
        The ``.fmu`` file (co-simulation; for this platform).
    step : float, optional
        Sample period [s] (default: the unit's ``DefaultExperiment`` ``stepSize``).
    start_values : dict, optional
        Values of the unit's parameters (FMI names) set before its initialisation [SI units].
    **kw
        As for any component (``init``, ``name``).

    Returns
    -------
    FMUBlock
        An instance of a class made for this unit (its declarations are the unit's inputs and outputs).

    Raises
    ------
    ModelError
        The file is not a co-simulation FMU, or ``step`` is not positive.
    """
    from fmpy import read_model_description

    try:
        md = read_model_description(str(path))
    except Exception as err:  # fmpy raises several kinds for a file that is not an FMU
        raise ModelError(f"FMU {path}: not a readable FMI unit ({err})") from None
    if md.coSimulation is None:
        raise ModelError(f"FMU {path}: not a co-simulation unit (model exchange only)")
    taken: set[str] = set(dir(FMUBlock))
    attrs: dict[str, Any] = {"fmi_names": {}, "__module__": __name__}
    for v in md.modelVariables:
        if v.causality not in ("input", "output") or v.type != "Real":
            continue
        name = _name(v.name, taken)
        unit = v.unit or "1"
        start = float(v.start) if v.start is not None else 0.0
        attrs[name] = (Input(unit=unit, doc=v.description or v.name) if v.causality == "input" else
                       Output(unit=unit, start=start, fixed=True, doc=v.description or v.name))
        attrs["fmi_names"][name] = (v.name, v.valueReference, v.causality)
    default = md.defaultExperiment.stepSize if md.defaultExperiment is not None else None
    attrs["default_step"] = float(default) if default else 1e-3
    cls = type(_name(md.modelName, set()) + "FMU", (FMUBlock,), attrs)
    return cls(path, step, start_values, **kw)
