"""Export a model as an FMI 2.0 co-simulation unit (``fl.export_fmu``, ``flexlib export-fmu``).

The unit is self-contained for Linux x86-64: a shared library built with gcc at export time from

* the model's residual, iteration matrix, event indicators and outputs as generated C (CasADi's code generator, the
  functions the ``ida-native`` driver evaluates),
* the fixed-step stepper of that driver (``flexlib/solve/native/ida_driver.c``, its "fixed-step mode": the steps of
  ``solver=fl.FixedStep(h)`` in a flexlib run, bit for bit on the same machine) with SUNDIALS' dense LU or KLU,
* the FMI 2.0 co-simulation interface (``flexlib/fmi/fmu_cs.c``),

and the SUNDIALS and (above :data:`~flexlib.solve.backends.ida_c.KLU_MIN` unknowns) KLU shared libraries that
scikit-sundae and kvxopt ship, copied beside it (found through ``$ORIGIN``). No Python runs inside the unit.

What the unit holds: the consistent start found by flexlib at export (``t_start``, ``params``) and the parameter
vector there. Every model parameter is an FMI parameter (``causality="parameter"``, ``variability="fixed"``): one set
before ``fmi2ExitInitializationMode`` keeps the states' start values and recomputes the algebraic unknowns and the
derivatives there (IDA's ``IDACalcIC``), which is flexlib's own start wherever the states' start values do not depend
on that parameter (a start found by initial equations or a steady state is not found again). The outputs are the
variables named at export (default: the model's top-level ``Output`` declarations, else its states), each computed
from the unknowns by the model's own output function. Events: a relation that switches is found at the end of the
fixed step (as ``FixedStep`` does) and the stepper restarts there with the new value; a time event (a relation of
time and parameters) is stepped onto exactly, as in a flexlib run.

Not exported (refused at export, naming the reason): ``reinit()``; ``initial()`` relations are held at their
post-start value. Platforms: Linux x86-64 only (the unit is built on the exporting machine).

References
----------
Modelica Association, *Functional Mock-up Interface for Model Exchange and Co-Simulation*, version 2.0.4 (2022),
sections 2 (common concepts, ``modelDescription.xml``) and 4 (co-simulation).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import uuid
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import casadi as ca
import numpy as np

from flexlib.compile.gcc import gcc_level
from flexlib.errors import FlexlibError, ModelError, RunArgumentError

__all__ = ["export_fmu"]

_HERE = Path(__file__).resolve().parent
_DRIVER = _HERE.parent / "solve" / "native" / "ida_driver.c"
_WRAPPER = _HERE / "fmu_cs.c"
#: SUNDIALS libraries the unit links (no SuperLU_MT: it would bring OpenBLAS along)
_SUNDIALS = ("core", "nvecserial", "sunmatrixdense", "sunmatrixsparse", "sunlinsoldense", "ida")


def export_fmu(model: Any, path: str | os.PathLike, *, h: float = 1e-3, method: str = "bdf2",
               newton_iters: int = 4, max_halvings: int = 2, t_start: float | None = None,
               params: dict[str, float] | None = None, outputs: Sequence[str] | None = None, rtol: float = 1e-6,
               atol: float = 1e-8, name: str | None = None) -> Path:
    """Write ``model`` as an FMI 2.0 co-simulation unit ``path`` (``.fmu``; see the module docstring).

    Parameters
    ----------
    model : Model or Simulation
        The model (built now, or taken from the simulation's build).
    path : str or path-like
        The unit to write (written atomically: a temporary file renamed over it).
    h : float
        The unit's fixed step [s]; a communication step is a whole number of these (the last one shortened).
    method, newton_iters, max_halvings : optional
        The stepper's formula and Newton budget, as :class:`~flexlib.solve.solvers.FixedStep`'s.
    t_start : float, optional
        Start time [s] of the consistent start the unit holds (default: the model's experiment).
    params : dict, optional
        Parameter values of that start [SI units]; the unit's parameters start there.
    outputs : sequence of str, optional
        Variables (result names) the unit outputs; default the top-level ``Output`` declarations, else the states.
    rtol, atol : float
        Weights of the Newton test (as for a run) [1], [SI units].
    name : str, optional
        The unit's model name and identifier (default: the model class's name).

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    RunArgumentError
        A bad argument (named), an output that is not a variable of the model.
    ModelError
        The model uses what the unit cannot do (``reinit``).
    FlexlibError
        gcc is missing or fails, or a library to bundle is not installed.
    """
    from flexlib.solve.backends.base import absolute_tolerances
    from flexlib.solve.backends.ida_c import KLU_MIN
    from flexlib.solve.native import KLU_REUSE_MIN_UNKNOWNS, KLU_REUSE_RCOND, klu_available
    from flexlib.solve.simulation import Simulation
    from flexlib.solve.solvers import FixedStep

    solver = FixedStep(h=h, method=method, newton_iters=newton_iters, max_halvings=max_halvings)  # checks them
    sim = model if isinstance(model, Simulation) else Simulation(model)
    m = sim.compiled
    ident = _identifier(name or type(sim.model).__name__)
    chosen = _checked(m, ident, outputs)
    start = sim.start_point(t_start=t_start, params=params)
    units = {v.name: v.unit for v in m.variables}
    docs = {v.name: v.doc for v in m.variables}
    inputs = set(_top_level_inputs(sim.model))
    rel = [k for k, r in enumerate(m.relations) if not r.initial and not r.time_event]
    timed = [k for k, r in enumerate(m.relations) if r.time_event]
    klu = m.n > KLU_MIN
    if klu and not klu_available():
        raise FlexlibError(f"export_fmu: {ident} has {m.n} unknowns and needs KLU, which is not installed "
                           "(pip install kvxopt)")
    functions = _unit_functions(m, len(start.p), chosen, rel, timed)
    data = {
        "N": m.n, "NNZ": len(m.jac_row), "NP_ALL": len(start.p), "NROOT": len(rel), "NOUT": len(chosen),
        "NTIME": len(timed),
        "T0": start.t, "STEP": float(h), "BDF2": int(method == "bdf2"), "NEWTON_ITERS": int(newton_iters),
        "MAX_HALVINGS": int(max_halvings), "RTOL": float(rtol), "FMU_KLU": int(klu),
        "KLU_REUSE_MIN_N": KLU_REUSE_MIN_UNKNOWNS, "KLU_REUSE_RCOND": KLU_REUSE_RCOND,
    }
    params_vr = list(range(m.n_params))
    table = [(0, k, m.param_names[k], m.param_units[k], float(start.p[k]), m.param_names[k] in inputs)
             for k in params_vr] + [(1, j, o, units[o], None, False) for j, o in enumerate(chosen)]
    header = _data_header(data, m, start, rel, timed, table, absolute_tolerances(m, atol, solver.error_test_all))
    guid = str(uuid.UUID(hashlib.sha256(header.encode() + b"".join(f.serialize().encode()
                                                                  for f in functions)).hexdigest()[:32]))
    header = f'#define FMU_GUID "{{{guid}}}"\n' + header
    xml = _model_description(ident, guid, m, table, docs, chosen, start.t, h)
    return _build(Path(path), ident, functions, header, xml, klu)


def _checked(m: Any, ident: str, outputs: Sequence[str] | None) -> list[str]:
    """The outputs of the unit (checked names), after checking that the model can be exported."""
    reinit = [r.owner or r.text for r in m.relations if r.reinit]
    if reinit:
        raise ModelError(f"export_fmu: {ident}: reinit() ({', '.join(reinit[:3])}) is not supported in an FMU; "
                         "export a model without it")
    names = [v.name for v in m.variables]
    chosen = list(outputs) if outputs is not None else _default_outputs(m)
    missing = [o for o in chosen if o not in names]
    if missing:
        raise RunArgumentError(f"export_fmu: output {missing[0]!r} is not a variable of {ident} "
                               f"({len(names)} variables, e.g. {', '.join(names[:5])})")
    return chosen


def _unit_functions(m: Any, n_p: int, chosen: list[str], rel: list[int], timed: list[int]) -> list[ca.Function]:
    """The unit's model functions (CasADi, generated as C): the residual and iteration matrix, the indicators of the
    state relations ``rel``, the ``chosen`` outputs, and ``a·t + b`` of the time relations ``timed``."""
    from flexlib.solve.backends.ida_c import indicator_function

    names = [v.name for v in m.variables]
    t, y, yp = ca.SX.sym("t"), ca.SX.sym("y", m.n), ca.SX.sym("yp", m.n)
    pp = ca.SX.sym("p", n_p)
    every = m.sx_function("out")(t, y, yp, pp)
    out_fn = ca.Function("flexlib_out", [t, y, yp, pp], [ca.vertcat(*[every[names.index(o)] for o in chosen])])
    zc = indicator_function(m, n_p, rel) if rel else _empty_zc(m.n, n_p)
    ab = m.sx_function("tev")(pp)  # a·t + b of every relation (rows), for the time events
    tev = ca.Function("flexlib_tev", [pp], [ca.vertcat(*[ab[k, 0] for k in timed], 0),
                                            ca.vertcat(*[ab[k, 1] for k in timed], 0)])
    return [m.sx_function("res"), m.sx_function("jac"), zc, out_fn, tev]


def _identifier(text: str) -> str:
    """A C identifier from ``text`` (the unit's model identifier names its library)."""
    out = "".join(ch if ch.isalnum() or ch == "_" else "_" for ch in text) or "model"
    return out if not out[0].isdigit() else f"m_{out}"


def _default_outputs(m: Any) -> list[str]:
    """The top-level ``Output`` declarations of the model, else its states (differential unknowns)."""
    top = [v.name for v in m.variables if v.kind == "output" and "." not in v.name]
    if top:
        return top
    return [name for name, d in zip(m.y_names, m.differential, strict=True) if d]


def _top_level_inputs(model: Any) -> list[str]:
    """Names of the model's top-level ``Input`` declarations (parameters of the run a master sets between steps)."""
    from flexlib.core.variables import Kind

    return [label for name, decl in getattr(model, "_decls", {}).items() if getattr(decl, "kind", None) is Kind.input
            for label, _ in decl.element_names(name)]


def _empty_zc(n: int, n_p: int) -> ca.Function:
    t, y, yp, p = ca.SX.sym("t"), ca.SX.sym("y", n), ca.SX.sym("yp", n), ca.SX.sym("p", n_p)
    return ca.Function("flexlib_zc", [t, y, yp, p], [ca.SX(1, 1)])


def _c_array(ctype: str, name: str, values: Any) -> str:
    vals = list(values) or [0]
    fmt = (lambda v: repr(float(v))) if ctype == "double" else (lambda v: str(int(v)))
    body = ", ".join(fmt(v) if np.isfinite(v) or ctype != "double" else "1e300" for v in vals)
    return f"static const {ctype} {name}[] = {{{body}}};\n"


def _data_header(data: dict[str, Any], m: Any, start: Any, rel: list[int], timed: list[int], table: list,
                 atol: np.ndarray) -> str:
    """``fmu_data.h``: sizes, settings, the start and the variable table as C constants."""
    lines = [f"#define {k} {v!r}\n" for k, v in data.items()]
    lines.append(f"#define NVAR {len(table)}\n")
    lines.append(_c_array("int", "JAC_COLIND", m.jac_colind))
    lines.append(_c_array("int", "JAC_ROW", m.jac_row))
    lines.append(_c_array("double", "P0", start.p))
    lines.append(_c_array("double", "Y0", start.y))
    lines.append(_c_array("double", "YP0", start.yp))
    lines.append(_c_array("double", "ATOL", np.minimum(atol, 1e300)))
    lines.append(_c_array("double", "DIFFERENTIAL", np.asarray(m.differential, dtype=float)))
    lines.append(_c_array("int", "REL_INDEX", [m.n_params + k for k in rel]))
    lines.append(_c_array("int", "TIME_INDEX", [m.n_params + k for k in timed]))
    lines.append(_c_array("int", "VAR_KIND", [row[0] for row in table]))
    lines.append(_c_array("int", "VAR_INDEX", [row[1] for row in table]))
    lines.append(_c_array("int", "VAR_INPUT", [int(row[5]) for row in table]))
    names = ", ".join(_c_string(row[2]) for row in table) or '""'
    lines.append(f"static const char *VAR_NAME[] = {{{names}}};\n")
    return "".join(lines)


def _c_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _model_description(ident: str, guid: str, m: Any, table: list, docs: dict[str, str], chosen: list[str],
                       t0: float, h: float) -> str:
    """``modelDescription.xml`` (FMI 2.0, co-simulation)."""
    from flexlib import __version__

    units = sorted({row[3] for row in table if row[3]})
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<fmiModelDescription fmiVersion="2.0" modelName={quoteattr(ident)} guid="{{{guid}}}" '
           f'generationTool="flexlib {__version__}" variableNamingConvention="structured" '
           f'numberOfEventIndicators="0">',
           f'  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true" '
           'canInterpolateInputs="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions'
           '="true" canGetAndSetFMUstate="false" canSerializeFMUstate="false" '
           'providesDirectionalDerivative="false"/>']
    if units:
        out.append("  <UnitDefinitions>")
        out += [f"    <Unit name={quoteattr(u)}/>" for u in units]
        out.append("  </UnitDefinitions>")
    out.append(f'  <DefaultExperiment startTime="{t0!r}" stepSize="{h!r}"/>')
    out.append("  <ModelVariables>")
    for vr, (kind, _, name, unit, value, is_input) in enumerate(table):
        unit_attr = f" unit={quoteattr(unit)}" if unit else ""
        if kind == 0:
            causality = 'causality="input" variability="continuous"' if is_input else \
                'causality="parameter" variability="fixed" initial="exact"'
            out.append(f'    <ScalarVariable name={quoteattr(name)} valueReference="{vr}" {causality}>')
            out.append(f'      <Real{unit_attr} start="{value!r}"/>')
        else:
            described = f" description={quoteattr(docs[name])}" if docs.get(name) else ""
            out.append(f'    <ScalarVariable name={quoteattr(name)} valueReference="{vr}" causality="output" '
                       f'variability="continuous" initial="calculated"{described}>')
            out.append(f"      <Real{unit_attr}/>")
        out.append("    </ScalarVariable>")
    out.append("  </ModelVariables>")
    out.append("  <ModelStructure>")
    outputs = [vr + 1 for vr, row in enumerate(table) if row[0] == 1]
    if outputs:
        out.append("    <Outputs>")
        out += [f'      <Unknown index="{i}"/>' for i in outputs]
        out.append("    </Outputs>")
        out.append("    <InitialUnknowns>")
        out += [f'      <Unknown index="{i}"/>' for i in outputs]
        out.append("    </InitialUnknowns>")
    out.append("  </ModelStructure>")
    out.append("</fmiModelDescription>")
    return "\n".join(out) + "\n"


def _libraries(klu: bool) -> list[Path]:
    """The shared libraries the unit links and carries: SUNDIALS (scikit-sundae's) and, with KLU, SuiteSparse's."""
    import sksundae

    libdir = Path(sksundae.__file__).resolve().parent.parent / "scikit_sundae.libs"
    found = []
    for name in _SUNDIALS:
        hits = sorted(libdir.glob(f"libsundials_{name}-*.so*"))
        if not hits:
            raise FlexlibError(f"export_fmu: SUNDIALS library 'libsundials_{name}' not found in {libdir}")
        found.append(hits[0])
    if klu:
        from flexlib.solve.native import klu_library

        path = klu_library()
        if path is None:
            raise FlexlibError("export_fmu: KLU (kvxopt) is not installed")
        found.append(path)
        for dep in ("amd", "colamd", "btf", "suitesparseconfig"):
            hits = sorted(path.parent.glob(f"lib{dep}-*.so*"))
            if not hits:
                raise FlexlibError(f"export_fmu: lib{dep} (KLU's dependency) not found in {path.parent}")
            found.append(hits[0])
    return found


def _build(path: Path, ident: str, functions: list[ca.Function], header: str, xml: str, klu: bool) -> Path:
    """Generate, compile and zip the unit into ``path`` (atomically)."""
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        raise FlexlibError("export_fmu needs a C compiler (gcc) on PATH")
    libs = _libraries(klu)
    with tempfile.TemporaryDirectory(prefix="flexlib_fmu_") as tmp:
        work = Path(tmp)
        cg = ca.CodeGenerator("model.c", {"with_header": False})
        for f in functions:
            cg.add(f)
        cg.generate(str(work) + os.sep)
        (work / "fmu_data.h").write_text(header)
        shutil.copy(_DRIVER, work / "ida_driver.c")
        shutil.copy(_WRAPPER, work / "fmu_cs.c")
        unit = work / "unit"
        binaries = unit / "binaries" / "linux64"
        binaries.mkdir(parents=True)
        sources = unit / "sources"
        sources.mkdir()
        for src in ("model.c", "fmu_data.h", "ida_driver.c", "fmu_cs.c"):
            shutil.copy(work / src, sources / src)
        target = binaries / f"{ident}.so"
        with (work / "model.c").open() as fh:
            lines = sum(1 for _ in fh)
        steps = [[cc, gcc_level(lines, background=True), "-c", "-fPIC", "-fvisibility=hidden", str(work / "model.c"),
                  "-o", str(work / "model.o")],
                 [cc, "-O2", "-c", "-fPIC", "-fvisibility=hidden", "-I", str(work), str(work / "fmu_cs.c"), "-o",
                  str(work / "fmu_cs.o")],
                 [cc, "-shared", str(work / "fmu_cs.o"), str(work / "model.o"), "-o", str(target), *map(str, libs),
                  "-Wl,-rpath,$ORIGIN", "-lm"]]
        for cmd in steps:
            proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
            if proc.returncode != 0:
                raise FlexlibError(f"export_fmu: gcc failed on the unit's code:\n{proc.stderr[-3000:]}")
        for lib in libs:
            shutil.copy(lib, binaries / lib.name)
        (unit / "modelDescription.xml").write_text(xml)
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, part = tempfile.mkstemp(prefix=path.name + ".", suffix=".part", dir=path.parent)
        os.close(fd)
        try:
            with zipfile.ZipFile(part, "w", zipfile.ZIP_DEFLATED) as z:
                for f in sorted(unit.rglob("*")):
                    if f.is_file():
                        z.write(f, f.relative_to(unit).as_posix())
            os.replace(part, path)
        finally:
            if os.path.exists(part):
                os.unlink(part)
    return path
