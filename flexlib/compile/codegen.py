"""Stage 5 — compile: CasADi functions for the integrator, optionally generated as C.

From the index-1 DAE this builds

* ``res(t, y, yp, p) -> F`` — the residual;
* ``jac(t, y, yp, p, cj) -> dF/dy + cj·dF/dyp`` — IDA's iteration matrix, sparse (CSC);
* ``out(t, y, yp, p) -> every model variable`` — for results;
* ``ind(t, y, yp, p) -> relation indicators`` — for events;
* ``cond(t, y, yp, p) -> initial-condition expressions``;
* ``chk(t, y, yp, p) -> loop-closure rows dropped as redundant`` — zero while the build's choice holds.

``p`` holds the model parameters followed by the discrete values of the event relations, so
a parameter change never needs a recompile. With ``codegen=True`` the functions are written
as C, compiled with ``gcc`` and loaded with ``casadi.external``.

When C pays, which gcc level, and how ``codegen="auto"`` avoids waiting for gcc: ``flexlib/compile/gcc.py`` and
``docs/decisions/012-generated-c-gcc-level-and-background-compile.md``.
"""

from __future__ import annotations

import dataclasses
import os
import shutil
import time as _time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.explicit import row_definitions
from flexlib.compile.flatten import FlatSystem
from flexlib.compile.gcc import generate_c
from flexlib.compile.index_reduction import DAE, IndexReport
from flexlib.compile.integrity import check_serialized, deserialize_function, file_problem, sha256_file
from flexlib.compile.json_fields import expect, index_report, levels, name_number, plain_dict, record, str_list
from flexlib.compile.redundancy import CHECK_PREFIX
from flexlib.compile.simplify import SimpleSystem
from flexlib.compile.structure import derivative_level, row_jacobian
from flexlib.core.tables import bind_tables
from flexlib.core.variables import time
from flexlib.errors import CacheWarning, FlexlibError, ModelError

__all__ = ["CompiledModel", "VariableInfo", "compile_dae", "iteration_matrix"]

FUNCTIONS = ("res", "jac", "out", "ind", "cond", "tev", "cols", "jlev", "chk", "defs")

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
    initial: bool = False  # initial(): 1 while the start is found, 0 afterwards
    #: reinit(): ``[state name, value]`` pairs (value a number or a variable's name), applied where it becomes true
    reinit: list = field(default_factory=list)

    def value(self, z: float) -> bool:
        """Relation value for indicator value ``z`` (``rhs - lhs``) away from an event."""
        return z > 0.0 if self.strict else z >= 0.0


@dataclass
class CompiledModel:
    """Everything the solver needs; :meth:`to_data` / :meth:`from_data` give the disk cache's plain-data form."""

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
    check_labels: list[str] = field(default_factory=list)
    """Loop-closure rows dropped as redundant at build time (``chk`` evaluates them; they must stay 0)."""
    start_guesses: dict[str, float] = field(default_factory=dict)
    """Start guesses of unknowns without a start value of their own, computed at build time (frames kept as
    unknowns: their tree definitions at the start values, ``tearing.tear_or_keep_frames``); used where the
    instance gives the entry no non-zero start."""
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
    #: manifest of ``library``: SHA-256 and size [bytes], recorded by the process that compiled it
    library_sha256: str | None = None
    library_size: int = 0
    #: ``codegen="auto"`` chose C for this model: a build (or a cache load) without a library compiles it in the
    #: background (``library_pending``) and switches to it when gcc has finished
    wants_c: bool = False
    #: gcc's output in a private directory of this process while it compiles in the background; adopted (hashed,
    #: moved into the library directory, recorded in the manifest) once it exists. Never stored.
    library_pending: str | None = None
    #: algebraic unknowns kept out of IDA's local error test (``structure.derivative_level``)
    derivative_level: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    #: parameter conditions the build relied on (``constants.eliminate_constants``), checked at every run
    assumed: dict[str, str] = field(default_factory=dict)
    #: variables the redundant loop rows leave statically indeterminate, each with the indices in
    #: ``report.redundant`` of the rows that do (``passes.multibody.indeterminate``)
    indeterminate: dict[str, list[int]] = field(default_factory=dict)
    #: the algebraic unknowns a row of the residual gives explicitly (``explicit.row_definitions``), in the order of
    #: the outputs of ``defs``: a result file derives them instead of storing them (``results.stored``)
    given: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    #: called with the model when a library compiled in the background has been adopted (the cache updates
    #: its entry); set by the pipeline, never stored
    on_library: Any = field(default=None, repr=False, compare=False)
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
        """The CasADi function ``name`` (one of ``FUNCTIONS``).

        ``res`` and ``jac`` come from the compiled library when there is one; the library is loaded only
        after its size and SHA-256 match the manifest written by the process that compiled it (a damaged or
        replaced library gives a :class:`~flexlib.errors.CacheWarning` and the SX function instead). While gcc
        still compiles in the background (``library_pending``) they are the SX functions, not kept, so the first
        call after gcc has finished switches to C (callers fetch them at every (re)start, and ``ida.py`` checks
        :meth:`c_ready` during a run).
        """
        f = self._functions.get(name)
        if f is None:
            if name in ("res", "jac"):
                self._adopt_pending()
            if self.library is not None and name in ("res", "jac"):
                problem = self.library_problem()
                if problem is None:
                    f = ca.external(f"flexlib_{name}", self.library)
                else:
                    warnings.warn(f"compiled model library {self.library} not used ({problem}); "
                                  "using the symbolic functions", CacheWarning, stacklevel=2)
                    self.library = None
                    self._functions.pop("res", None)
                    self._functions.pop("jac", None)
            if f is None:
                f = self.sx_function(name)
                if name in ("res", "jac") and self.library_pending is not None:
                    return f  # not kept: C replaces it when gcc has finished
                f = self.sx_function(name)
            self._functions[name] = f
        return f

    def library_problem(self) -> str | None:
        """Why the compiled library must not be loaded (None: it matches its manifest)."""
        if self.library is None:
            return None
        if self.library_sha256 is None:
            return "no manifest entry (size and SHA-256) for it"
        return file_problem(Path(self.library), self.library_sha256, self.library_size)

    def c_ready(self) -> bool:
        """True if generated C compiled in the background has just become available (not yet in use)."""
        return self.library is None and self.library_pending is not None and (
            self.library_pending in _ADOPTED or Path(self.library_pending).exists())

    def wait_for_library(self, timeout: float = 600.0) -> bool:
        """Wait until the library compiled in the background is in use (at most ``timeout`` [s]).

        For benchmarks and parameter sweeps that should time the compiled model from their first run.
        Returns True if the model now evaluates ``res`` and ``jac`` in C, False if it has no C coming
        (``codegen=False``, a model below the size where C pays) or gcc did not finish in time (its
        messages are in ``gcc.log`` beside ``library_pending``).
        """
        deadline = _time.monotonic() + timeout
        while self.library is None and self.library_pending is not None:
            if self.c_ready():
                self.function("res")  # adopt it
                break
            if _time.monotonic() >= deadline:
                return False
            _time.sleep(0.05)
        return self.library is not None

    def _adopt_pending(self) -> None:
        """Take over the library gcc has finished in the background: hash it (this process started that gcc,
        in a directory only this user can write), move it to its content-derived name beside the others, record
        the manifest, and tell the cache (``on_library``)."""
        if self.library_pending is None or self.library is not None:
            return
        pending = self.library_pending
        if pending in _ADOPTED:  # another model of this process shared this compile and adopted it first
            lib_path, sha, size = _ADOPTED[pending]
        else:
            out = Path(pending)
            if not out.exists():
                return
            sha, size = sha256_file(out), out.stat().st_size
            lib = out.parent.parent / f"flexlib_{sha[:32]}.so"
            os.replace(out, lib)
            shutil.rmtree(out.parent, ignore_errors=True)
            lib_path = str(lib)
            _ADOPTED[pending] = (lib_path, sha, size)
        self.library, self.library_sha256, self.library_size, self.library_pending = lib_path, sha, size, None
        self._functions.pop("res", None)
        self._functions.pop("jac", None)
        if self.on_library is not None:
            self.on_library(self)

    def sx_function(self, name: str) -> ca.Function:
        """The SX (symbolic, differentiable) version of function ``name``, even with generated C.

        A function read from the cache is checked before use: the serialized stream must describe an
        ``SXFunction`` (no external code), and the deserialized function must have the expected name and
        signature (:meth:`check_function`).
        """
        f = self._sx.get(name)
        if f is None:
            try:
                f = deserialize_function(self.serialized[name], f"flexlib_{name}")
                self.check_function(name, f)
            except (ValueError, RuntimeError) as exc:
                raise FlexlibError(f"the stored function {name!r} of model {self.name} is damaged ({exc}); "
                                   f"remove its entry from the cache ({self.stats.get('cache_entry', '?')})") from None
            self._sx[name] = f
        return f

    def functions_needed(self) -> list[str]:
        """The functions every run of this model evaluates (the others are deserialized when first used)."""
        names = ["out", "ind", "cond", "tev"]
        if self.library is None:
            names += ["res", "jac"]
        if self.has_state_choice:
            names += ["cols", "jlev"]
        return names

    def signature(self, name: str) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
        """Expected (input shapes, output shapes) of function ``name``."""
        n, n_p = self.n, self.n_params + self.n_relations
        tyyp = [(1, 1), (n, 1), (n, 1), (n_p, 1)]
        n_lev = sum(nr * nc for nr, nc, _, _ in self.levels)
        return {
            "res": (tyyp, [(n, 1)]),
            "jac": ([*tyyp, (1, 1)], [(n, n)]),
            "out": (tyyp, [(len(self.variables), 1)]),
            "ind": (tyyp, [(self.n_relations, 1)]),
            "cond": (tyyp, [(len(self.conditions), 1)]),
            "tev": ([(n_p, 1)], [(self.n_relations, 2)]),
            "cols": (tyyp, [(len(self.col_names), 1)]),
            "jlev": (tyyp, [(n_lev, 1)]),
            "chk": (tyyp, [(len(self.check_labels), 1)]),
            "defs": (tyyp, [(len(self.given), 1)]),
        }[name]

    def check_function(self, name: str, f: ca.Function) -> None:
        """Raise ``ValueError`` unless ``f`` is the SX function ``flexlib_<name>`` with this model's signature."""
        if not isinstance(f, ca.Function) or not f.is_a("SXFunction"):
            raise ValueError(f"function {name!r} is not an SX function")
        if f.name() != f"flexlib_{name}":
            raise ValueError(f"function {name!r} is named {f.name()!r}")
        ins, outs = self.signature(name)
        got_in = [(f.size1_in(k), f.size2_in(k)) for k in range(f.n_in())]
        got_out = [(f.size1_out(k), f.size2_out(k)) for k in range(f.n_out())]
        if got_in != ins or got_out != outs:
            raise ValueError(f"function {name!r} has inputs {got_in} and outputs {got_out}, expected {ins} and {outs}")
        if name == "jac" and f.nnz_out(0) != len(self.jac_row):
            raise ValueError(f"function 'jac' has {f.nnz_out(0)} nonzeros, expected {len(self.jac_row)}")

    def __getstate__(self) -> dict:
        if not self.serialized:
            self.serialized = {k: f.serialize() for k, f in self._sx.items()}
        state = dict(self.__dict__)
        state["_functions"] = {}
        state["_sx"] = {}
        state["_structure"] = None
        return state

    # -- plain-data form (the disk cache: JSON + arrays, no pickle) -------------------------------------------
    def to_data(self) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
        """The model as JSON-able metadata and numeric arrays (functions as CasADi serialized strings)."""
        if not self.serialized:
            self.serialized = {k: f.serialize() for k, f in self._sx.items()}
        meta: dict[str, Any] = {}
        arrays: dict[str, np.ndarray] = {}
        for f in dataclasses.fields(self):
            if f.name in _TRANSIENT:
                continue
            value = getattr(self, f.name)
            if f.name in _ARRAYS:
                arrays[f.name] = np.asarray(value)
            elif f.name in ("variables", "relations"):  # flat records of str/bool: vars() is asdict without the
                meta[f.name] = [dict(vars(v)) for v in value]  # deep copy (0.15 s of a 100-mass chain's cold build)
            elif f.name == "report":
                meta[f.name] = dataclasses.asdict(value)
            else:
                meta[f.name] = value
        return meta, arrays

    @classmethod
    def from_data(cls, meta: dict[str, Any], arrays: dict[str, np.ndarray]) -> CompiledModel:
        """Inverse of :meth:`to_data`; every field is type-checked (``ValueError`` on anything unexpected)."""
        expect(meta, dict, "metadata")
        kw: dict[str, Any] = {}
        for f in dataclasses.fields(cls):
            if f.name in _TRANSIENT:
                continue
            if f.name in _ARRAYS:
                if f.name not in arrays:
                    raise ValueError(f"array {f.name!r} missing")
                a = np.asarray(arrays[f.name])
                if a.dtype.kind not in _ARRAYS[f.name] or a.ndim != 1:
                    raise ValueError(f"array {f.name!r} has dtype {a.dtype} and shape {a.shape}")
                kw[f.name] = a
                continue
            if f.name not in meta:
                raise ValueError(f"field {f.name!r} missing")
            kw[f.name] = _FIELD_CHECKS[f.name](meta[f.name], f.name)
        model = cls(**kw)
        if len(model.differential) != model.n or len(model.nominal) != model.n or len(model.y_names) != model.n:
            raise ValueError("inconsistent sizes")
        if set(model.serialized) != set(FUNCTIONS):
            raise ValueError(f"functions {sorted(model.serialized)} stored, expected {sorted(FUNCTIONS)}")
        for name, text in model.serialized.items():
            check_serialized(text, f"flexlib_{name}", full=False)
        return model


_TRANSIENT = {"_structure", "_functions", "_sx", "library_pending", "on_library"}
_ARRAYS = {"differential": "b", "nominal": "f", "param_defaults": "f", "jac_colind": "i", "jac_row": "i",
           "cond_depends": "b", "derivative_level": "b", "given": "i"}
_FIELD_CHECKS: dict[str, Any] = {
    "name": lambda v, w: expect(v, str, w),
    "n": lambda v, w: expect(v, int, w),
    "y_names": str_list,
    "y_owners": str_list,
    "start_sources": lambda v, w: [[name_number(s, w) for s in expect(row, list, w)] for row in expect(v, list, w)],
    "param_names": str_list,
    "param_units": str_list,
    "variables": lambda v, w: [record(VariableInfo, x, w) for x in expect(v, list, w)],
    "relations": lambda v, w: [record(RelationInfo, x, w) for x in expect(v, list, w)],
    "conditions": lambda v, w: [name_number(s, w) for s in expect(v, list, w)],
    "report": index_report,
    "row_labels": str_list,
    "col_names": str_list,
    "check_labels": str_list,
    "assumed": lambda v, w: {expect(k, str, w): expect(s, str, w) for k, s in expect(v, dict, w).items()},
    "indeterminate": lambda v, w: {expect(k, str, w): [expect(i, int, w) for i in expect(rows, list, w)]
                                   for k, rows in expect(v, dict, w).items()},
    "levels": levels,
    "start_guesses": lambda v, w: {expect(k, str, w): float(expect(x, (int, float), w))
                                   for k, x in expect(v, dict, w).items()},
    "stats": plain_dict,
    "serialized": lambda v, w: {expect(k, str, w): expect(s, str, w) for k, s in expect(v, dict, w).items()},
    "library": lambda v, w: v if v is None else expect(v, str, w),
    "library_sha256": lambda v, w: v if v is None else expect(v, str, w),
    "library_size": lambda v, w: expect(v, int, w),
    "wants_c": lambda v, w: expect(v, bool, w),
}


#: Background compiles adopted by this process: pending path -> (library, SHA-256, size). Models sharing one
#: compile (``pipeline.build`` of a cached entry while this process's gcc for it still runs) find the library
#: here after the first of them has moved it to its content-derived name.
_ADOPTED: dict[str, tuple[str, str, int]] = {}

#: ``codegen="auto"``: C code above this many unknowns, compiled in the background (see the module
#: docstring): the run starts at once on CasADi's SX virtual machine and switches to C at the first
#: solver (re)start after gcc has finished (later runs and cached builds use C from the start).
AUTO_C_MIN_UNKNOWNS = 300
#: ... or at least this many operations in the residual and Jacobian together, at any size: the SX
#: VM costs ~10–30 ns per operation against well under 1 ns in C (``docs/decisions/012-*``).
AUTO_C_MIN_OPERATIONS = 5000


#: IDA's iteration matrix ``dF/dy + cj·dF/dyp``: its dense rows are differentiated one by one, in reverse mode
#: (:func:`~flexlib.compile.structure.row_jacobian`). If the result has at most ``CSE_MAX_OPS`` operations, the
#: matrix is built as before instead, all rows at once (CasADi picks forward mode with column colouring), and
#: merged by CasADi's common-subexpression pass (``cse``); on the torn rigid chains and linkages below the limit
#: that gives the fewest operations. Above the limit the pass would cost more build time than it saves over a run
#: of typical length (``docs/decisions/006-*``, ``007-*``).
CSE_MAX_OPS = 100_000


def iteration_matrix(F: ca.SX, t: ca.SX, y: ca.SX, yp: ca.SX, p: ca.SX, cj: ca.SX) -> ca.SX:
    """IDA's iteration matrix ``dF/dy + cj·dF/dyp`` (dense rows in reverse mode, or merged: :data:`CSE_MAX_OPS`)."""
    n = y.numel()
    G = row_jacobian(F, ca.vertcat(y, yp))
    J = G[:, :n] + cj * G[:, n:]
    if ca.Function("flexlib_ops", [t, y, yp, p, cj], [J]).n_instructions() > CSE_MAX_OPS:
        return J
    return ca.cse(ca.jacobian(F, y) + cj * ca.jacobian(F, yp))


def compile_dae(flat: FlatSystem, simple: SimpleSystem, dae: DAE, *, codegen: bool | str = False,
                build_dir: str | os.PathLike | None = None) -> CompiledModel:
    """Build the CasADi functions of a DAE (and C code if ``codegen``; ``"auto"``: see the limits above)."""
    COMPILE_COUNT[0] += 1
    fns, F, J, out_names, check_names, relations, given = _functions(flat, dae)
    y, yp = dae.y, dae.yp
    colind, row = J.sparsity().get_ccs()
    var_by_name = {v.name: v for v in flat.variables}
    variables = [VariableInfo(name, v.unit, v.doc, v.kind.value, v.owner)
                 for name in out_names for v in (var_by_name[name],)]
    named = set(out_names)
    model = CompiledModel(
        name=flat.name, n=y.numel(), y_names=dae.names, y_owners=dae.owners, differential=dae.differential,
        nominal=dae.nominal, start_sources=_start_sources(simple, dae),
        start_guesses={k: x for k, x in simple.start_guesses.items() if k in set(dae.names)},
        param_names=[q.name for q in flat.parameters], param_units=[q.unit for q in flat.parameters],
        param_defaults=np.array([q.value for q in flat.parameters]), variables=variables, relations=relations,
        conditions=[(c.name, c.value) for c in dae.conditions], report=dae.report,
        jac_colind=np.asarray(colind, dtype=np.int32), jac_row=np.asarray(row, dtype=np.int32),
        row_labels=dae.row_labels, col_names=dae.col_names,
        check_labels=[k[len(CHECK_PREFIX):] for k in check_names],
        levels=[(len(lev.rows), len(lev.cands), lev.costs, [lev.cands.index(c) for c in lev.selected])
                for lev in dae.levels],
        cond_depends=_depends_on_y(dae.conditions, y, yp),
        assumed=dict(simple.assumed),
        indeterminate={k: v for k, v in simple.indeterminate.items() if k in named},
        given=given,
    )
    model._structure = dae.structure
    model._sx = dict(fns)
    model._functions = dict(fns)
    model.derivative_level = derivative_level(F, y, yp, dae.differential, dae.untested)
    _attach_c(model, fns, codegen, build_dir)
    return model


def _functions(flat: FlatSystem, dae: DAE) -> tuple[dict[str, ca.Function], ca.SX, ca.SX, list[str], list[str],
                                                    list[RelationInfo], np.ndarray]:
    """The SX functions of :data:`FUNCTIONS` for a DAE, with the residual ``F`` and the iteration matrix ``J`` (for
    their structure: with the tables' symbols), the names of the outputs and of the loop-closure checks, the
    relations' descriptions and the unknowns the rows give explicitly (``defs``).

    Every derivative (``J``, the row definitions, the time-event slopes) is taken while the tables of time
    (:func:`flexlib.segment_row`) are still symbols, constant to the differentiation; the functions then get their
    lookups (:func:`~flexlib.core.tables.bind_tables`)."""
    t, y, yp = time, dae.y, dae.yp
    pars = ca.vertcat(*[q.sym for q in flat.parameters]) if flat.parameters else ca.SX(0, 1)
    rels = ca.vertcat(*[rel.info.sym for rel, _ in dae.relations]) if dae.relations else ca.SX(0, 1)
    p = ca.vertcat(pars, rels)
    U = ca.vertcat(*[s for tbl in flat.tables for s in tbl.symbols]) if flat.tables else ca.SX(0, 1)
    cj = ca.SX.sym("cj")
    # common subexpressions merged (casadi.cse: same operations, same values, each computed once): component
    # equations repeat rotations and kinematics, and substituted definitions (compile/explicit.py) recur in rows
    F = ca.cse(dae.residual)
    J = iteration_matrix(F, t, y, yp, ca.vertcat(p, U), cj)
    out_names = [k for k in dae.outputs if not k.startswith(CHECK_PREFIX)]
    check_names = [k for k in dae.outputs if k.startswith(CHECK_PREFIX)]
    outs = ca.vertcat(*[dae.outputs[k] for k in out_names])
    checks = ca.vertcat(*[dae.outputs[k] for k in check_names]) if check_names else ca.SX(0, 1)
    inds = ca.vertcat(*[e for _, e in dae.relations]) if dae.relations else ca.SX(0, 1)
    conds = ca.vertcat(*[c.expr for c in dae.conditions]) if dae.conditions else ca.SX(0, 1)
    given, defs = row_definitions(F, outs, y, yp, dae.differential)
    relations: list[RelationInfo] = []
    tev_rows = []
    states = {name for name, d in zip(dae.names, dae.differential, strict=True) if d}
    for rel, ind in dae.relations:
        timed = (not ca.depends_on(ind, ca.vertcat(y, yp, U)) and ca.depends_on(ind, t)
                 and bool(ca.is_linear(ind, t)))
        for target, value in rel.reinit:
            if target not in states:
                raise ModelError(f"{rel.owner}: reinit(): {target} is not a state of the compiled model (the index "
                                 f"reduction chose other states): give it state_select='always'")
            if isinstance(value, str) and value not in dae.outputs:
                raise ModelError(f"{rel.owner}: reinit(): the value {value} is not a variable of the model")
        relations.append(RelationInfo(rel.text, rel.strict, timed, rel.owner, rel.assertion, rel.initial,
                                      [list(a) for a in rel.reinit]))
        slope = ca.jacobian(ind, t) if timed else ca.SX(0.0)
        offset = ca.substitute(ind, t, ca.SX(0.0)) if timed else ca.SX(0.0)
        tev_rows.append(ca.horzcat(slope, offset))
    tev = ca.vertcat(*tev_rows) if tev_rows else ca.SX(0, 2)
    jl = [ca.vec(j) for j in dae.level_jacobians]
    jlev = ca.vertcat(*jl) if jl else ca.SX(0, 1)
    Fb, Jb, outs, checks, inds, conds, cols, jlev, defs = bind_tables(
        [F, J, outs, checks, inds, conds, dae.col_values, jlev, defs], flat.tables)
    tyyp, names = [t, y, yp, p], ["t", "y", "yp", "p"]
    fns = {
        "res": ca.Function("flexlib_res", tyyp, [Fb], names, ["res"]),
        "jac": ca.Function("flexlib_jac", [*tyyp, cj], [Jb], [*names, "cj"], ["jac"]),
        "out": ca.Function("flexlib_out", tyyp, [outs]),
        "ind": ca.Function("flexlib_ind", tyyp, [inds]),
        "cond": ca.Function("flexlib_cond", tyyp, [conds]),
        "chk": ca.Function("flexlib_chk", tyyp, [checks]),
        "tev": ca.Function("flexlib_tev", [p], [tev]),
        "cols": ca.Function("flexlib_cols", tyyp, [cols]),
        "jlev": ca.Function("flexlib_jlev", tyyp, [jlev]),
        "defs": ca.Function("flexlib_defs", tyyp, [defs]),
    }
    for f in fns.values():
        if f.has_free():
            raise FlexlibError(f"internal error: function {f.name()} has free symbols {f.get_free()}")
    return fns, F, J, out_names, check_names, relations, given


def _attach_c(model: CompiledModel, fns: dict[str, ca.Function], codegen: bool | str,
              build_dir: str | os.PathLike | None) -> None:
    """Generate C for the residual and the iteration matrix where ``codegen`` asks for it: compiled now
    (``True``), or for a large model in the background while the run starts on the SX functions (``"auto"``)."""

    def texts() -> tuple[str, str]:  # serialized once, for the C file's name and the cache entry
        model.serialized = {k: f.serialize() for k, f in fns.items()}
        return model.serialized["res"], model.serialized["jac"]

    if codegen == "auto":
        ops = fns["res"].n_instructions() + fns["jac"].n_instructions()
        big = model.n > AUTO_C_MIN_UNKNOWNS or ops >= AUTO_C_MIN_OPERATIONS
        if big and (shutil.which("gcc") or shutil.which("cc")):
            model.wants_c = True
            model.library_pending = generate_c(fns["res"], fns["jac"], build_dir, background=True,
                                               serialized=texts())
            model._functions.pop("res")
            model._functions.pop("jac")
    elif codegen:
        model.library, model.library_sha256, model.library_size = generate_c(fns["res"], fns["jac"], build_dir,
                                                                             serialized=texts())
        model._functions.pop("res")
        model._functions.pop("jac")


def _depends_on_y(conditions: list, y: ca.SX, yp: ca.SX) -> np.ndarray:
    """Which conditions depend on ``y`` or ``yp`` (one symvar each, not ``depends_on`` against all 2n symbols)."""
    hashes = {y[i].element_hash() for i in range(y.numel())} | {yp[i].element_hash() for i in range(yp.numel())}
    return np.array([any(s.element_hash() in hashes for s in ca.symvar(c.expr)) for c in conditions], dtype=bool)


def _start_sources(simple: SimpleSystem, dae: DAE) -> list[list[tuple[str, float]]]:
    """For each ``y`` entry, the variables (with sign) whose start value seeds it."""
    members: dict[int, list[tuple[str, float]]] = {}
    for name, expr in simple.outputs.items():
        if name.startswith(CHECK_PREFIX):
            continue
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
