"""Stage 3 — index reduction: Pantelides' algorithm and dummy derivatives.

1. **Pantelides** (C. C. Pantelides, SIAM J. Sci. Stat. Comput. 9(2), 1988) finds, from the
   structural incidence alone, which equations must be differentiated how often so that
   the highest derivatives can be matched to equations. A structurally singular model is
   detected before that (no perfect matching of equations to variables).
2. The equations are differentiated symbolically with CasADi (forward AD, ``jtimes``).
3. **Dummy derivatives** (S. E. Mattsson, G. Söderlind, SIAM J. Sci. Comput. 14(3), 1993):
   for every differentiated equation one derivative becomes an algebraic "dummy", chosen
   level by level so that the selected sub-Jacobian is non-singular at the start point,
   honouring ``state_select`` (generated derivatives first, then never < avoid < default <
   prefer < always) and, within a class, by pivoted QR on the numeric Jacobian.
   All original and differentiated equations stay in the system: constraints do not drift.
4. **Known derivatives are substituted**: where a state's derivative has an explicit
   definition (``der(x) = u``), it replaces ``der(x)`` in the other equations, and trivial
   dummy aliases (``der(y) = v``) are eliminated.

The result is an index-1 DAE ``F(t, y, y', p) = 0`` whose states are the differential part
of ``y``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from flexlib.compile.dummy_derivatives import Col, Level, Row, col_name, select_dummies
from flexlib.compile.explicit import explicit_mode
from flexlib.compile.flatten import FlatEquation, FlatVariable, describe_all
from flexlib.compile.post_simplify import post_simplify as _post_simplify
from flexlib.compile.simplify import Condition, SimpleSystem
from flexlib.core.functions import Relation
from flexlib.core.variables import full_name, lookup, time
from flexlib.errors import ModelError, StructuralSingularityError

__all__ = ["DAE", "IndexReport", "reduce_index"]


@dataclass
class IndexReport:
    """What index reduction did, by component name.

    Attributes
    ----------
    index : int
        Differential index of the original DAE (0 for an ODE, 1 if algebraic equations need no
        differentiation, …).
    differentiated : list of (owner, equation, times)
        Equations that were differentiated and how often.
    states : list of str
        Variables chosen as states (``der(x)`` for a derivative chosen as state).
    dummy_derivatives : list of str
        Derivatives made algebraic (their variables are not states).
    redundant : list of str
        Redundant loop-closure constraints that were dropped, with the reaction set to zero.
    indeterminate : int
        Number of variables those rows leave statically indeterminate (results list them:
        ``Result.indeterminate``).
    explicit : list of str
        Algebraic unknowns eliminated after index reduction because one row gives them explicitly
        (:mod:`flexlib.compile.explicit`); results report them through their expressions.
    """

    index: int
    differentiated: list[tuple[str, str, int]] = field(default_factory=list)
    states: list[str] = field(default_factory=list)
    dummy_derivatives: list[str] = field(default_factory=list)
    redundant: list[str] = field(default_factory=list)
    explicit: list[str] = field(default_factory=list)
    tree_frames: str = ""
    """Frame kinematics of the kinematic tree torn or kept as unknowns, and why
    (``compile/passes/multibody/tearing.py``)."""
    indeterminate: int = 0

    def __str__(self) -> str:
        lines = [f"DAE index {self.index}; {len(self.states)} states"]
        if self.differentiated:
            lines.append("Differentiated equations:")
            lines += [f"  {owner or '(model)'}: {text}  (×{n})" for owner, text, n in self.differentiated]
        lines.append("States: " + (", ".join(self.states) or "none"))
        if self.dummy_derivatives:
            lines.append("Dummy derivatives: " + ", ".join(self.dummy_derivatives))
        if self.redundant:
            lines.append("Redundant constraints removed:")
            lines += [f"  {text}" for text in self.redundant]
            if self.indeterminate:
                lines.append(f"  they leave {self.indeterminate} variables statically indeterminate (marked in "
                             "results: result.indeterminate; a Bushing or a flexible link determines them)")
        if self.explicit:
            lines.append(f"Explicit algebraics eliminated ({len(self.explicit)}): " + ", ".join(self.explicit))
        if self.tree_frames:
            lines.append(f"Tree frame kinematics: {self.tree_frames}")
        return "\n".join(lines)


@dataclass(eq=False)
class DAE:
    """Output of stage 3: an index-1 DAE ready to compile.

    Attributes
    ----------
    y, yp : casadi.SX
        Unknowns and their derivatives (column vectors of symbols).
    residual : casadi.SX
        ``F(t, y, yp, p)`` (same length as ``y``).
    differential : ndarray of bool
        True for states (their derivative appears), False for algebraic entries.
    names : list of str
        Name of each entry of ``y``.
    nominal, start : ndarray
        Per-entry nominal magnitude and start guess.
    outputs : dict of str to casadi.SX
        Every variable of the model as an expression of ``t, y, yp, p``.
    conditions : list of Condition
        Initial conditions in ``y`` (and ``p``).
    relations : list of (Relation, casadi.SX)
        Event relations with indicators in ``t, y, yp, p``.
    report : IndexReport
    """

    y: ca.SX
    yp: ca.SX
    residual: ca.SX
    differential: np.ndarray
    names: list[str]
    nominal: np.ndarray
    start: np.ndarray
    outputs: dict[str, ca.SX]
    conditions: list[Condition]
    relations: list[tuple[Relation, ca.SX]]
    report: IndexReport
    owners: list[str]
    row_labels: list[str] = field(default_factory=list)
    col_names: list[str] = field(default_factory=list)
    col_values: ca.SX | None = None
    levels: list[Level] = field(default_factory=list)
    level_jacobians: list[ca.SX] = field(default_factory=list)
    untested: np.ndarray | None = None
    """Algebraic entries declared ``error_test=False`` (kept out of IDA's error test with the derivative level)."""
    structure: Structure | None = None


@dataclass(eq=False)
class Structure:
    """Index-reduced equations before state selection (kept to re-select states at run time)."""

    simple: SimpleSystem
    rows: list
    cols: list
    param_values: dict[int, float]
    #: The explicit-algebraics stage's mode of the build (:func:`flexlib.compile.explicit.explicit_mode`), kept for
    #: every re-assembly after a new state selection
    explicit: str = "error-test"

    def select(self, point: tuple[ca.SX, np.ndarray] | None = None) -> tuple[set[int], list[Level]]:
        """Dummy derivatives chosen at ``point`` (symbols, values); the start values if None."""
        return select_dummies(self.rows, self.cols, self.simple.variables, self.simple, self.param_values, point)

    def assemble(self, dummies: set[int], levels: list[Level], explicit: bool = True) -> DAE:
        """The index-1 DAE for a dummy-derivative selection (``explicit=False``: no explicit algebraics
        eliminated, the form in which initialisation failures are diagnosed; True: as the build chose)."""
        return _assemble(self.simple, self.rows, self.cols, dummies, levels, self, self.explicit if explicit else "off")

    def point(self, col_values: np.ndarray, t: float, p: np.ndarray) -> tuple[ca.SX, np.ndarray]:
        """A numeric point for :meth:`select` from all column values, time and the parameter vector."""
        syms = [time, *[c.info.sym for c in self.cols]]
        syms += [q for q in self._param_syms()]
        syms += [rel.info.sym for rel, _ in self.simple.relations]
        vals = np.concatenate([[t], col_values, p])
        return ca.vertcat(*syms), vals

    def _param_syms(self) -> list[ca.SX]:
        return [q.sym for q in self.simple.flat.parameters]


class _Unterminated(Exception):
    """Pantelides' algorithm kept differentiating: the source equations and variables of the last failed search."""

    def __init__(self, sources: list[int], variables: list[int]) -> None:
        super().__init__(sources, variables)
        self.sources, self.variables = sources, variables


class _Pantelides:
    """Pantelides' algorithm on the structural incidence (iterative augmenting paths)."""

    def __init__(self, cols: list[Col], rows: list[Row], col_of: dict[int, int], rules: dict[int, ca.SX]) -> None:
        self.cols, self.rows = cols, rows
        self.assign = [-1] * len(cols)
        self.col_of = col_of   # symbol hash -> column
        self.rules = rules     # column -> expression of its derivative (derivative rules)
        self.defined_by = _defining_rows(rows, cols, rules)
        for c in list(rules):  # a rule column without a defining row is treated as an ordinary unknown
            if c not in self.defined_by:
                del rules[c]

    def _augment(self, start: int, vcol: set[int], vrow: set[int]) -> bool:
        cols, rows, assign = self.cols, self.rows, self.assign
        vrow.add(start)
        # iterative DFS over (row, iterator of candidate columns); parent links for the path
        stack = [(start, iter(sorted(rows[start].inc)))]
        via: list[int] = []
        # first a free column directly adjacent (Pantelides: look for an unassigned variable first)
        while stack:
            r, it = stack[-1]
            free = next((c for c in rows[r].inc if cols[c].der < 0 and assign[c] < 0 and c not in self.rules), None)
            if free is not None:
                assign[free] = r
                # flip the path
                for depth in range(len(via) - 1, -1, -1):
                    c = via[depth]
                    assign[c] = stack[depth][0]
                return True
            advanced = False
            for c in it:
                if cols[c].der >= 0 or c in vcol:
                    continue
                if c in self.rules:
                    continue  # determined by its defining row (pre-matched); known everywhere else
                vcol.add(c)
                r2 = assign[c]
                if r2 < 0 or r2 in vrow:
                    continue
                vrow.add(r2)
                via.append(c)
                stack.append((r2, iter(sorted(rows[r2].inc))))
                advanced = True
                break
            if not advanced:
                stack.pop()
                if via:
                    via.pop()
        return False

    def run(self, n_orig: int, max_rounds: int = 200) -> None:
        """Pantelides: differentiate until every original row is matched; a row still unmatched after ``max_rounds``
        rounds (a differentiation index far beyond any physical model's, which stays below ten) is a structurally
        singular subsystem (:class:`_Unterminated`)."""
        cols, rows = self.cols, self.rows
        defining = set()
        for c, r in self.defined_by.items():
            self.assign[c] = r
            defining.add(r)
        for k in range(n_orig):
            if k in defining:
                continue
            i = k
            rounds = 0
            while True:
                vcol: set[int] = set()
                vrow: set[int] = set()
                if self._augment(i, vcol, vrow):
                    break
                rounds += 1
                if rounds > max_rounds:
                    raise _Unterminated(sorted({rows[r].source for r in vrow | {i}}),
                                        sorted({cols[c].var for c in vcol}))
                for c in sorted(vcol):
                    self._derive_col(c)
                for r in sorted(vrow):
                    self._derive_row(r)
                for c in sorted(vcol):
                    if self.assign[c] >= 0 and cols[c].der >= 0:
                        self.assign[cols[c].der] = rows[self.assign[c]].der
                i = rows[i].der

    def _derive_col(self, c: int) -> int:
        col = self.cols[c]
        if c in self.rules:
            return -1  # its derivative is an expression (derivative rule), never an unknown
        if col.der < 0:
            col.der = len(self.cols)
            info = col.info.der_info
            self.cols.append(Col(col.var, col.order + 1, info))
            self.col_of[info.sym.element_hash()] = col.der
            self.assign.append(-1)
        return col.der

    def _derive_row(self, r: int) -> int:
        """Differentiate row ``r`` symbolically (forward AD, derivative rules substituted); the new row's
        incidence is read off the derivative, so rules change the structure as they should."""
        row = self.rows[r]
        if row.der < 0:
            plain = [c for c in sorted(row.inc) if c not in self.rules]
            ruled = [c for c in sorted(row.inc) if c in self.rules]
            for c in plain:
                self._derive_col(c)
            v = ca.vertcat(time, *[self.cols[c].info.sym for c in plain + ruled])
            vd = ca.vertcat(ca.SX(1.0), *[self.cols[self.cols[c].der].info.sym for c in plain],
                            *[self.rules[c] for c in ruled])
            expr = ca.jtimes(row.expr, v, vd)
            inc = {self.col_of[s.element_hash()] for s in ca.symvar(expr) if s.element_hash() in self.col_of}
            row.der = len(self.rows)
            self.rows.append(Row(row.source, row.order + 1, inc, expr, pred=r))
        return row.der


def _defining_rows(rows: list[Row], cols: list[Col], rules: dict[int, ca.SX]) -> dict[int, int]:
    """For each column with a derivative rule, the row that defines it explicitly (``T_b = T_rel·T_a``,
    ``T = T(Q)``: linear in it with a unit coefficient), found by a matching over such pairs."""
    import scipy.sparse as sp

    from flexlib.compile.structure import matching, unit_coefficients

    rule_cols = sorted(rules)
    if not rule_cols:
        return {}
    index = {c: k for k, c in enumerate(rule_cols)}
    cand = [(r, sorted(c for c in row.inc if c in index)) for r, row in enumerate(rows) if not row.order]
    cand = [(r, cs) for r, cs in cand if cs]
    found = unit_coefficients([rows[r].expr for r, _ in cand], [[cols[c].info.sym for c in cs] for _, cs in cand])
    entries = [(r, index[cs[k]]) for (r, cs), units in zip(cand, found, strict=True) for k, _ in units]
    if not entries:
        return {}
    rr, cc = zip(*entries, strict=True)
    inc = sp.csr_matrix((np.ones(len(rr)), (rr, cc)), shape=(len(rows), len(rule_cols)))
    _, col_match = matching(inc)
    return {rule_cols[k]: int(r) for k, r in enumerate(col_match) if r >= 0}


def reduce_index(simple: SimpleSystem, param_values: dict[int, float], explicit: str | None = None) -> DAE:
    """Reduce a simplified system to an index-1 DAE.

    Parameters
    ----------
    simple : SimpleSystem
        Output of stage 2.
    param_values : dict
        Parameter values by symbol hash, used for the numeric pivoting of the dummy
        derivative selection.
    explicit : {"off", "error-test", "all"} or None
        The explicit-algebraics stage (:func:`flexlib.compile.explicit.explicit_mode`; None: its environment
        default).
    """
    variables, equations = simple.variables, simple.equations
    cols: list[Col] = []
    col_of: dict[int, int] = {}
    for i, v in enumerate(variables):
        col_of[v.sym.element_hash()] = len(cols)
        cols.append(Col(i, 0, v.info))
    used_ders = {s.element_hash() for s in ca.symvar(ca.vertcat(*[e.expr for e in equations]))} if equations else set()
    for i, v in enumerate(variables):
        if v.info._der is not None and v.info._der.sym.element_hash() in used_ders:
            c0 = col_of[v.sym.element_hash()]
            cols[c0].der = len(cols)
            col_of[v.info._der.sym.element_hash()] = len(cols)
            cols.append(Col(i, 1, v.info._der))
    exprs = ca.vertcat(*[e.expr for e in equations])
    syms = ca.vertcat(*[c.info.sym for c in cols])
    spj = ca.jacobian_sparsity(exprs, syms) if len(equations) else None
    rows: list[Row] = [Row(k, 0, set(), equations[k].expr) for k in range(len(equations))]
    if spj is not None:
        colind, rowidx = spj.get_ccs()
        for c in range(len(cols)):
            for r in rowidx[colind[c]:colind[c + 1]]:
                rows[r].inc.add(c)
    rules = {col_of[h]: e for h, e in simple.der_rules.items() if h in col_of}
    pant = _Pantelides(cols, rows, col_of, rules)
    try:
        pant.run(len(equations))
    except _Unterminated as err:
        eqs = [equations[k] for k in err.sources]
        lines = [f"  {e.owner or '(model)'}: {text}" for e, text in zip(eqs[:8], describe_all(eqs[:8]), strict=True)]
        names = sorted({simple.variables[v].name for v in err.variables})
        more = f" (and {len(eqs) - 8} more)" if len(eqs) > 8 else ""
        raise StructuralSingularityError(
            "index reduction did not terminate: these equations" + more + "\n" + "\n".join(lines)
            + "\ndo not determine " + ", ".join(names[:8]) + (", ..." if len(names) > 8 else "")
            + " at any derivative order (a structurally singular subsystem: a component connected to itself, or "
            "constraints that leave an unknown without an equation)") from None
    structure = Structure(simple, rows, cols, param_values, explicit_mode() if explicit is None else explicit)
    dummies, levels = structure.select()
    return structure.assemble(dummies, levels)


def _entries(cols: list[Col], dummies: set[int]) -> tuple[dict[int, int], list[bool], list[int]]:
    """Antiderivative of each derivative column, which columns are states, and the columns that are entries of y."""
    anti = {c.der: k for k, c in enumerate(cols) if c.der >= 0}
    is_state = [c.der >= 0 and c.der not in dummies for c in cols]
    # y entries: every column that is not the derivative of a state, plus derivative columns that are states too
    entries: list[int] = []
    for k in range(len(cols)):
        a = anti.get(k)
        if a is not None and is_state[a] and not is_state[k]:
            continue  # represented by yp of its antiderivative
        entries.append(k)
    return anti, is_state, entries


def _row_labels(simple: SimpleSystem, rows: list[Row]) -> tuple[list[str], dict[int, str]]:
    """A label per row (owner, equation, times differentiated) and the text of each source equation."""
    labels = []
    sources = sorted({r.source for r in rows})
    described = dict(zip(sources, describe_all([simple.equations[k] for k in sources]), strict=True))
    for r in rows:
        e = simple.equations[r.source]
        text = f"{e.owner or '(model)'}: {described[r.source]}"
        labels.append(text if r.order == 0 else f"{text}  [differentiated ×{r.order}]")
    return labels, described


def _level_jacobians(levels: list[Level], rows: list[Row], cols: list[Col]) -> list[ca.SX]:
    """Each selection level's d(rows)/d(cands), the one the selection built where it kept it."""
    jacs = []
    for lev in levels:
        jac = lev.jacobian
        if jac is None:
            jac = ca.jacobian(ca.vertcat(*[rows[r].expr for r in lev.rows]),
                              ca.vertcat(*[cols[c].info.sym for c in lev.cands]))
        jacs.append(jac)
    return jacs


def _assemble(simple: SimpleSystem, rows: list[Row], cols: list[Col], dummies: set[int],
              levels: list[Level], structure: Structure, explicit: str) -> DAE:
    variables = simple.variables
    anti, is_state, entries = _entries(cols, dummies)
    pos = {c: i for i, c in enumerate(entries)}
    n = len(entries)
    y = ca.SX.sym("y", n)
    yp = ca.SX.sym("yp", n)
    col_value = [y[pos[k]] if k in pos else yp[pos[anti[k]]] for k in range(len(cols))]
    res_list = [r.expr for r in rows]
    # link equations: a state whose derivative is itself a state
    for k in entries:
        if is_state[k] and cols[k].der in pos:
            res_list.append(yp[pos[k]] - y[pos[cols[k].der]])
    # (SX(0, 1) first: a model whose unknowns were all eliminated has none, and an empty vertcat is a DM)
    col_syms = ca.vertcat(ca.SX(0, 1), *[c.info.sym for c in cols])
    col_vals = ca.vertcat(ca.SX(0, 1), *[col_value[k] for k in range(len(cols))])
    F = ca.substitute([ca.vertcat(ca.SX(0, 1), *res_list)], [col_syms], [col_vals])[0]
    differential = np.array([is_state[k] for k in entries], dtype=bool)
    if F.numel() != n:
        raise StructuralSingularityError(f"index reduction produced {F.numel()} equations for {n} unknowns")
    labels, described = _row_labels(simple, rows)
    labels += [f"der({col_name(cols[k], variables)}) link" for k in entries if is_state[k] and cols[k].der in pos]
    cand_cols = {c for lev in levels for c in lev.cands}
    protected = np.array([k in cand_cols for k in entries], dtype=bool)
    # declarations of the algebraic entries that are variables (not derivative columns), alias classes merged
    untested = np.array([cols[k].order == 0 and not variables[cols[k].var].error_test for k in entries],
                        dtype=bool) & ~differential
    intermediate = np.array([cols[k].order == 0 and variables[cols[k].var].intermediate for k in entries],
                            dtype=bool) & ~differential
    F, keep, subs_syms, subs_vals, kept_rows, explicit = _post_simplify(F, y, yp, differential, protected, explicit,
                                                                        untested=untested, intermediate=intermediate)
    labels = [labels[k] for k in kept_rows]
    # rebuild y without eliminated entries
    y_keep = ca.vertcat(*[y[i] for i in keep])
    yp_keep = ca.vertcat(*[yp[i] for i in keep])
    y_new = ca.SX.sym("y", len(keep))
    yp_new = ca.SX.sym("yp", len(keep))
    allsyms = ca.vertcat(y_keep, yp_keep)
    allnew = ca.vertcat(y_new, yp_new)

    def final_matrix(e: ca.SX) -> ca.SX:
        e = ca.substitute([e], [col_syms], [col_vals])[0]
        if subs_syms.numel():
            e = ca.substitute([e], [subs_syms], [subs_vals])[0]
        return ca.substitute([e], [allsyms], [allnew])[0]

    def final(exprs: list[ca.SX]) -> list[ca.SX]:
        if not exprs:
            return []
        e = final_matrix(ca.vertcat(*exprs))
        return [e[k] for k in range(e.numel())]

    F = ca.substitute([F], [allsyms], [allnew])[0]
    out_names = list(simple.outputs)
    out_exprs = final([simple.outputs[nm] for nm in out_names])
    col_exprs = final([c.info.sym for c in cols])
    level_jacs = [final_matrix(jac) for jac in _level_jacobians(levels, rows, cols)]
    names = [col_name(cols[entries[i]], variables) for i in keep]
    cond_exprs = _initial_derivatives(simple.conditions, final([c.expr for c in simple.conditions]),
                                      dict(zip(out_names, out_exprs, strict=True)), F, y_new, yp_new,
                                      differential[keep], names)
    rel_exprs = final([i for _, i in simple.relations])
    owners = [variables[cols[entries[i]].var].owner for i in keep]
    nominal = np.array([variables[cols[entries[i]].var].nominal for i in keep])
    start = np.array([variables[cols[entries[i]].var].start if cols[entries[i]].order == 0 else 0.0 for i in keep])
    diff_keep = differential[keep]
    report = _report(simple, rows, cols, dummies, is_state, variables, described)
    report.explicit = [col_name(cols[entries[i]], variables) for i in explicit]
    return DAE(
        y=y_new, yp=yp_new, residual=F, differential=diff_keep, names=names, nominal=nominal, start=start,
        outputs=dict(zip(out_names, out_exprs, strict=True)),
        conditions=[Condition(c.name, e, c.value) for c, e in zip(simple.conditions, cond_exprs, strict=True)],
        relations=[(rel, e) for (rel, _), e in zip(simple.relations, rel_exprs, strict=True)],
        report=report, owners=owners, row_labels=labels,
        col_names=[col_name(c, variables) for c in cols], col_values=ca.vertcat(*col_exprs),
        levels=levels, level_jacobians=level_jacs, structure=structure, untested=untested[keep],
    )


def _initial_derivatives(conditions: list[Condition], exprs: list[ca.SX], outputs: dict[str, ca.SX], F: ca.SX,
                         y: ca.SX, yp: ca.SX, differential: np.ndarray, names: list[str]) -> list[ca.SX]:
    """``der(v)`` in an initial equation, for a variable ``v`` whose derivative the equations do not contain.

    MSL's ``PID_Controller`` writes ``der(spring.w_rel) = 0`` where MSL makes ``w_rel`` a state; here ``w_rel`` may
    be a dummy derivative, defined by the differentiated constraint as ``der(i2.phi) - der(i1.phi)`` and so, through
    ``w = der(phi)``, as ``i2.w - i1.w``. As Modelica tools do, the derivative is taken from the index-reduced
    system: ``v`` is expressed in the states ``x`` by the rows of the residual that define an unknown explicitly
    (linear in it with a constant coefficient), and then ``der(v) = dv/dx · x' + dv/dt``, with the states'
    derivatives ``x'`` unknowns of the initialisation. A ``v`` that the rows do not express in the states is
    refused, naming the initial equation, the variable, the unknowns it depends on and what to write instead.
    """
    out = []
    for cond, expr in zip(conditions, exprs, strict=True):
        pending = [s for s in ca.symvar(expr) if (info := lookup(s)) is not None and info.kind == "der"]
        for s in pending:
            info = lookup(s)
            name = full_name(info.base)
            where = f"initial equation of {cond.name.rsplit(' #', 1)[0]}"
            e = outputs.get(name) if info.base.kind != "der" else None
            if e is None:
                raise ModelError(f"{where}: der({name}) cannot be evaluated at the start ({name} is not a variable "
                                 "of the model's equations, or der() is applied twice); write the condition on a "
                                 "variable, e.g. der(v) = 0 for the variable v, or use steady_state=True")
            e, left = _in_states(e, F, y, yp, differential, names)
            if left:
                raise ModelError(
                    f"{where}: der({name}) is not known at the start: {name} is not a state of this model and the "
                    "equations do not express it in the states (it depends on "
                    + ", ".join(left[:5]) + (", ..." if len(left) > 5 else "")
                    + f"). Write the condition on states (der() of the state variables {name} is computed from; "
                    "the build's report lists the states), declare " + name + " with state_select='prefer' so that it "
                    "becomes a state, or use steady_state=True")
            d = ca.mtimes(ca.jacobian(e, y), yp) + ca.jacobian(e, time)
            expr = ca.substitute([expr], [s], [d])[0]
        out.append(expr)
    return out


def _in_states(e: ca.SX, F: ca.SX, y: ca.SX, yp: ca.SX, differential: np.ndarray, names: list[str],
               rounds: int = 50) -> tuple[ca.SX, list[str]]:
    """``e`` with its algebraic unknowns and derivatives replaced by the rows of ``F`` that define them explicitly
    (``c·u + rest = 0`` with ``c`` constant), until it depends on the states ``x`` only; also the names of what is
    left (empty on success)."""
    left: list[tuple[ca.SX, str]] = []
    for _ in range(rounds):
        left = [(y[k], names[k]) for k in sorted(set(ca.jacobian(e, y).sparsity().get_col())) if not differential[k]]
        left += [(yp[k], f"der({names[k]})") for k in sorted(set(ca.jacobian(e, yp).sparsity().get_col()))]
        if not left:
            return e, []
        for u, _label in left:
            col = ca.jacobian(F, u)
            rows = sorted(set(col.sparsity().row()))
            defining = [r for r in rows if col[r].is_constant() and float(ca.evalf(col[r])) != 0.0]
            if defining:
                r = defining[0]
                rest = ca.substitute([F[r]], [u], [ca.SX(0.0)])[0]  # F[r] = c·u + rest, rest free of u
                e = ca.substitute([e], [u], [-rest / col[r]])[0]
                break
        else:
            break
    return e, [label for _, label in left]


def _report(simple: SimpleSystem, rows: list[Row], cols: list[Col], dummies: set[int],
            is_state: list[bool], variables: list[FlatVariable], described: dict[int, str]) -> IndexReport:
    times: dict[int, int] = {}
    for r in rows:
        times[r.source] = max(times.get(r.source, 0), r.order)
    eqs: list[FlatEquation] = simple.equations
    differentiated = [(eqs[k].owner, described[k], n) for k, n in times.items() if n > 0]
    has_alg = any(c.der < 0 and c.order == 0 for c in cols)
    max_diff = max(times.values(), default=0)
    index = max_diff + 1 if (max_diff > 0 or has_alg) else 0
    states = [col_name(c, variables) for k, c in enumerate(cols) if is_state[k]]
    dummy_names = [col_name(cols[k], variables) for k in sorted(dummies)]
    return IndexReport(index, differentiated, states, dummy_names, list(simple.redundant),
                       tree_frames=simple.tree_frames, indeterminate=len(simple.indeterminate))
