"""Stage 5 — compile: CasADi functions for the integrator, optionally generated as C.

From the index-1 DAE this builds

* ``res(t, y, yp, p) -> F`` — the residual;
* ``jac(t, y, yp, p, cj) -> dF/dy + cj·dF/dyp`` — IDA's iteration matrix, sparse (CSC);
* ``out(t, y, yp, p) -> every model variable`` — for results;
* ``ind(t, y, yp, p) -> relation indicators`` — for events;
* ``cond(t, y, yp, p) -> initial-condition expressions``.

``p`` holds the model parameters followed by the discrete values of the event relations, so
a parameter change never needs a recompile. With ``codegen=True`` the functions are written
as C, compiled with ``gcc`` and loaded with ``casadi.external`` (the route the notes measured
at 3.6× faster residuals for large models).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.flatten import FlatSystem
from flexlib.compile.index_reduction import DAE, IndexReport
from flexlib.compile.simplify import SimpleSystem
from flexlib.compile.structure import derivative_level
from flexlib.core.variables import time
from flexlib.errors import FlexlibError

__all__ = ["CompiledModel", "VariableInfo", "compile_dae"]

FUNCTIONS = ("res", "jac", "out", "ind", "cond", "tev", "cols", "jlev")

#: Number of times :func:`compile_dae` ran in this process (tests assert that runs reuse builds).
COMPILE_COUNT = [0]


@dataclass
class VariableInfo:
    """Metadata of one reported variable."""

    name: str
    unit: str
    doc: str
    kind: str
    owner: str


@dataclass
class RelationInfo:
    """Metadata of one event relation."""

    text: str
    strict: bool
    time_event: bool  # affine in time, independent of y: hit exactly with tstop
    owner: str = ""
    assertion: str = ""  # from assert_(): must stay true (message shown when it becomes false)

    def value(self, z: float) -> bool:
        """Relation value for indicator value ``z`` (``rhs - lhs``) away from an event."""
        return z > 0.0 if self.strict else z >= 0.0


@dataclass
class CompiledModel:
    """Everything the solver needs, picklable for the disk cache (functions are serialized)."""

    name: str
    n: int
    y_names: list[str]
    y_owners: list[str]
    differential: np.ndarray
    nominal: np.ndarray
    start_sources: list[list[tuple[str, float]]]
    param_names: list[str]
    param_units: list[str]
    param_defaults: np.ndarray
    variables: list[VariableInfo]
    relations: list[RelationInfo]
    conditions: list[tuple[str, float]]  # (variable name, default start value)
    report: IndexReport
    jac_colind: np.ndarray
    jac_row: np.ndarray
    row_labels: list[str] = field(default_factory=list)
    cond_depends: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    col_names: list[str] = field(default_factory=list)
    levels: list[tuple[int, int, list[int], list[int]]] = field(default_factory=list)
    """Per selection level: (rows, candidates, costs, selected positions) for the state-selection monitor."""
    _structure: Any = field(default=None, repr=False)

    @property
    def has_state_choice(self) -> bool:
        """True if some dummy-derivative level has more candidates than it needs (states may be re-selected)."""
        return any(nc > nr for nr, nc, _, _ in self.levels)
    stats: dict[str, Any] = field(default_factory=dict)
    serialized: dict[str, str] = field(default_factory=dict)
    library: str | None = None
    #: algebraic unknowns kept out of IDA's local error test (``structure.derivative_level``)
    derivative_level: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    #: parameter conditions the build relied on (``constants.eliminate_constants``), checked at every run
    assumed: dict[str, str] = field(default_factory=dict)
    _functions: dict[str, ca.Function] = field(default_factory=dict, repr=False)
    _sx: dict[str, ca.Function] = field(default_factory=dict, repr=False)  # serialized only when pickled

    @property
    def n_params(self) -> int:
        """Number of model parameters (without relation values)."""
        return len(self.param_names)

    @property
    def n_relations(self) -> int:
        """Number of event relations."""
        return len(self.relations)

    def function(self, name: str) -> ca.Function:
        """The CasADi function ``name`` (one of ``FUNCTIONS``)."""
        f = self._functions.get(name)
        if f is None:
            if self.library is not None and name in ("res", "jac") and Path(self.library).exists():
                f = ca.external(f"flexlib_{name}", self.library)
            else:
                f = self.sx_function(name)
            self._functions[name] = f
        return f

    def sx_function(self, name: str) -> ca.Function:
        """The SX (symbolic, differentiable) version of function ``name``, even with generated C."""
        f = self._sx.get(name)
        if f is None:
            f = ca.Function.deserialize(self.serialized[name])
            self._sx[name] = f
        return f

    def __getstate__(self) -> dict:
        if not self.serialized:
            self.serialized = {k: f.serialize() for k, f in self._sx.items()}
        state = dict(self.__dict__)
        state["_functions"] = {}
        state["_sx"] = {}
        state["_structure"] = None
        return state


#: ``codegen="auto"``: C code above this many unknowns ...
AUTO_C_MIN_UNKNOWNS = 300
#: ... unless the residual and Jacobian exceed this many operations. gcc's time grows faster than
#: linearly with the source (a 10-link pendulum chain: 267 000 operations, 268 000 lines, 10–16 s of
#: gcc for a 1.2–4× faster Jacobian), while a 1000-mass chain (59 000 operations) gains 2–3×.
AUTO_C_MAX_INSTRUCTIONS = 150_000


def compile_dae(flat: FlatSystem, simple: SimpleSystem, dae: DAE, *, codegen: bool | str = False,
                build_dir: str | os.PathLike | None = None) -> CompiledModel:
    """Build the CasADi functions of a DAE (and C code if ``codegen``; ``"auto"``: see the limits above)."""
    COMPILE_COUNT[0] += 1
    t, y, yp = time, dae.y, dae.yp
    pars = ca.vertcat(*[q.sym for q in flat.parameters]) if flat.parameters else ca.SX(0, 1)
    rels = ca.vertcat(*[rel.info.sym for rel, _ in dae.relations]) if dae.relations else ca.SX(0, 1)
    p = ca.vertcat(pars, rels)
    cj = ca.SX.sym("cj")
    F = dae.residual
    J = ca.jacobian(F, y) + cj * ca.jacobian(F, yp)
    out_names = list(dae.outputs)
    outs = ca.vertcat(*[dae.outputs[k] for k in out_names])
    inds = ca.vertcat(*[e for _, e in dae.relations]) if dae.relations else ca.SX(0, 1)
    conds = ca.vertcat(*[c.expr for c in dae.conditions]) if dae.conditions else ca.SX(0, 1)
    fns = {
        "res": ca.Function("flexlib_res", [t, y, yp, p], [F], ["t", "y", "yp", "p"], ["res"]),
        "jac": ca.Function("flexlib_jac", [t, y, yp, p, cj], [J], ["t", "y", "yp", "p", "cj"], ["jac"]),
        "out": ca.Function("flexlib_out", [t, y, yp, p], [outs]),
        "ind": ca.Function("flexlib_ind", [t, y, yp, p], [inds]),
        "cond": ca.Function("flexlib_cond", [t, y, yp, p], [conds]),
    }
    relations: list[RelationInfo] = []
    tev_rows = []
    for rel, ind in dae.relations:
        timed = not ca.depends_on(ind, ca.vertcat(y, yp)) and ca.depends_on(ind, t) and bool(ca.is_linear(ind, t))
        relations.append(RelationInfo(rel.text, rel.strict, timed, rel.owner, rel.assertion))
        slope = ca.jacobian(ind, t) if timed else ca.SX(0.0)
        offset = ca.substitute(ind, t, ca.SX(0.0)) if timed else ca.SX(0.0)
        tev_rows.append(ca.horzcat(slope, offset))
    tev = ca.vertcat(*tev_rows) if tev_rows else ca.SX(0, 2)
    fns["tev"] = ca.Function("flexlib_tev", [p], [tev])
    fns["cols"] = ca.Function("flexlib_cols", [t, y, yp, p], [dae.col_values])
    jl = [ca.vec(j) for j in dae.level_jacobians]
    fns["jlev"] = ca.Function("flexlib_jlev", [t, y, yp, p], [ca.vertcat(*jl) if jl else ca.SX(0, 1)])
    for f in fns.values():
        if f.has_free():
            raise FlexlibError(f"internal error: function {f.name()} has free symbols {f.get_free()}")
    sp = J.sparsity()
    colind, row = sp.get_ccs()
    variables = []
    var_by_name = {v.name: v for v in flat.variables}
    for name in out_names:
        v = var_by_name[name]
        variables.append(VariableInfo(name, v.unit, v.doc, v.kind.value, v.owner))
    start_sources = _start_sources(simple, dae)
    model = CompiledModel(
        name=flat.name, n=y.numel(), y_names=dae.names, y_owners=dae.owners, differential=dae.differential,
        nominal=dae.nominal, start_sources=start_sources,
        param_names=[q.name for q in flat.parameters], param_units=[q.unit for q in flat.parameters],
        param_defaults=np.array([q.value for q in flat.parameters]), variables=variables, relations=relations,
        conditions=[(c.name, c.value) for c in dae.conditions], report=dae.report,
        jac_colind=np.asarray(colind, dtype=np.int32), jac_row=np.asarray(row, dtype=np.int32),
        row_labels=dae.row_labels, col_names=dae.col_names,
        levels=[(len(lev.rows), len(lev.cands), lev.costs, [lev.cands.index(c) for c in lev.selected])
                for lev in dae.levels],
        cond_depends=np.array([bool(ca.depends_on(c.expr, ca.vertcat(y, yp))) for c in dae.conditions], dtype=bool),
        assumed=dict(simple.assumed),
    )
    model._structure = dae.structure
    model._sx = dict(fns)
    model._functions = dict(fns)
    model.derivative_level = derivative_level(F, y, yp, dae.differential)
    if codegen == "auto":
        codegen = (model.n > AUTO_C_MIN_UNKNOWNS
                   and fns["res"].n_instructions() + fns["jac"].n_instructions() <= AUTO_C_MAX_INSTRUCTIONS)
    if codegen:
        model.library = generate_c(fns["res"], fns["jac"], build_dir)
        model._functions.pop("res")
        model._functions.pop("jac")
    return model


def _start_sources(simple: SimpleSystem, dae: DAE) -> list[list[tuple[str, float]]]:
    """For each ``y`` entry, the variables (with sign) whose start value seeds it."""
    members: dict[int, list[tuple[str, float]]] = {}
    for name, expr in simple.outputs.items():
        if expr.is_symbolic():
            members.setdefault(expr.element_hash(), []).append((name, 1.0))
        elif expr.op() == ca.OP_NEG and expr.dep(0).is_symbolic():
            members.setdefault(expr.dep(0).element_hash(), []).append((name, -1.0))
        elif expr.op() == ca.OP_MUL and expr.dep(0).is_constant() and expr.dep(1).is_symbolic():
            members.setdefault(expr.dep(1).element_hash(), []).append((name, float(ca.evalf(expr.dep(0)))))
    out = []
    by_name = {v.name: v for v in simple.variables}
    for name in dae.names:
        v = by_name.get(name)
        if v is None:  # a derivative entry
            out.append([])
            continue
        srcs = members.get(v.sym.element_hash(), [(name, 1.0)])
        srcs = sorted(srcs, key=lambda s: s[0] != name)
        out.append(srcs)
    return out


def generate_c(res: ca.Function, jac: ca.Function, build_dir: str | os.PathLike | None) -> str:
    """Write ``res`` and ``jac`` as C, compile them with gcc and return the shared library path."""
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        raise FlexlibError("codegen=True needs a C compiler (gcc) on PATH")
    build = Path(build_dir) if build_dir else Path(tempfile.mkdtemp(prefix="flexlib_"))
    build.mkdir(parents=True, exist_ok=True)
    digest = hashlib.sha256((res.serialize() + jac.serialize()).encode()).hexdigest()[:16]
    lib = build / f"flexlib_{digest}.so"
    if lib.exists():
        return str(lib)
    cg = ca.CodeGenerator(f"flexlib_{digest}.c")
    cg.add(res)
    cg.add(jac)
    with tempfile.TemporaryDirectory(dir=build) as tmp:
        cg.generate(tmp + os.sep)
        src = Path(tmp) / f"flexlib_{digest}.c"
        with src.open() as fh:
            lines = sum(1 for _ in fh)
        # gcc time grows faster than linearly with the optimisation level; -O0 code still beats the SX VM ~2x
        opt = "-O2" if lines < 3000 else "-O1" if lines < 30000 else "-O0"
        tmp_lib = Path(tmp) / lib.name
        proc = subprocess.run([cc, opt, "-shared", "-fPIC", str(src), "-o", str(tmp_lib), "-lm"],
                              capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            raise FlexlibError(f"gcc failed on the generated model code:\n{proc.stderr[-2000:]}")
        os.replace(tmp_lib, lib)
    return str(lib)
