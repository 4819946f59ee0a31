"""What a result file stores of a run, and every other variable derived from it when read (format 2,
``docs/results.md``).

A run's named variables (thousands in a machine: aliases, connector variables, frame matrices, forces) are all
outputs of the model's ``out(t, y, y', p)`` function of its recorded rows. The file therefore stores, per model of
the run (a state switch changes it): the rows' unknowns ``y`` (each distinct column once), the entries of ``y'``
that ``out`` reads, the relation values (they are parameters of ``out``), and ``out`` itself as a serialised CasADi
SX function (about 1 MB for the pump truck, 0.1 MB compressed) — plus the variables the user asks to store
(``outputs=``). Of the unknowns only those that no row gives explicitly are stored: an algebraic unknown that a
residual row without derivatives defines (``c·v + f(t, y, p) = 0``, ``c`` a nonzero constant: cut forces, frame
velocities and accelerations of a tree; :func:`flexlib.compile.explicit.row_definitions`, found when the model is
compiled) is set by that definition in the run's recorded
rows after they are settled (:func:`flexlib.solve.assemble.assemble_result`: a change of the order of IDA's Newton
tolerance, its own row's residual then zero) and is derived when read by the definitions, stored as a function like
``out`` (479 of the rigid pump truck's 858 unknowns are stored). Reading a variable then costs: a stored column, a
column of ``y`` (an unknown or its alias), a constant, or an evaluation of the part of ``out``'s graph it needs over
the rows (a derived variable). Every value is the same as the run's in memory (the same rows, the same expression
graph, the same parameter folding): tested to 1e-12 relative.

A file opened where the CasADi that wrote ``out`` cannot read it still gives its stored variables (unknowns,
aliases, constants, ``outputs``); a derived one is then a :class:`~flexlib.errors.ResultFileError` saying which
CasADi wrote the file and how to get the variable (``outputs=`` or ``outputs="all"`` on the run).
"""

from __future__ import annotations

import hashlib
import zlib
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from flexlib.errors import ResultFileError

if TYPE_CHECKING:
    import casadi as ca

__all__ = ["CONSTANT", "DERIVED", "FileColumns", "FilePart", "OutputMap", "RowDefinitions", "StoredPart",
           "file_columns", "fold_parameters", "output_graph", "output_map", "pack_function", "signatures",
           "unique_columns", "unpack_function"]

#: ``OutputMap.source`` codes: a variable is an unknown's column (``>= 0``), derived from the rows, or a constant.
DERIVED, CONSTANT = -1, -2


@dataclass
class OutputMap:
    """How each output of ``out(t, y, y', p)`` is got from a row.

    Attributes
    ----------
    source : ndarray of int
        Per output: the index of the unknown ``y[j]`` it is (an alias of), :data:`DERIVED` or :data:`CONSTANT`.
    constant : ndarray
        Per output: its value if it is a constant, else NaN.
    yp_used : ndarray of int
        The entries of ``y'`` that ``out`` reads (the others are not stored).
    """

    source: np.ndarray
    constant: np.ndarray
    yp_used: np.ndarray


def output_graph(fn: ca.Function) -> tuple[list[ca.SX], ca.SX]:
    """``([t, y, yp, p], out)``: the SX function ``fn(t, y, yp, p)`` evaluated on its own symbols (its graph)."""
    args = fn.sx_in()
    return args, fn(*args)


def output_map(graph: tuple[list[ca.SX], ca.SX]) -> OutputMap:
    """Classify the outputs of the graph of ``out(t, y, yp, p)`` (:func:`output_graph`) (:class:`OutputMap`)."""
    import casadi as ca

    (_t, y, yp, _p), out = graph
    n = out.numel()
    source = np.full(n, DERIVED, dtype=np.int64)
    constant = np.full(n, np.nan)
    by_y = ca.jacobian_sparsity(out, y).get_triplet()  # (rows, cols) of the structural dependencies on y
    single: dict[int, int] = {}
    for i, j in zip(*by_y, strict=True):
        single[i] = -1 if i in single else j
    for i in range(n):
        e = out[i]
        if e.is_constant():
            source[i], constant[i] = CONSTANT, float(e)
        elif e.is_symbolic() and single.get(i, -1) >= 0:
            source[i] = single[i]
    yp_used = np.unique(np.asarray(ca.jacobian_sparsity(out, yp).get_triplet()[1], dtype=np.int64))
    return OutputMap(source, constant, yp_used)


@dataclass
class RowDefinitions:
    """The unknowns of a model that residual rows give explicitly, for storing rows (module docstring).

    Attributes
    ----------
    kept : ndarray of int
        The unknowns that are stored.
    given : ndarray of int
        The unknowns given by their rows' definitions.
    fn : casadi.Function or None
        ``(t, y, yp, p) -> y[given]`` (dense; ``yp`` unused), the definitions resolved in the kept unknowns; None if
        no unknown is given.
    """

    kept: np.ndarray
    given: np.ndarray
    fn: ca.Function | None

    def bound(self, pvec: np.ndarray) -> tuple[list[ca.SX], ca.SX]:
        """``([t, y, yp, rel], y[given])``: the definitions' graph with the parameter vector ``pvec`` put in, as a
        file's reader puts it into the output function (:meth:`FilePart.bound`): constant parts folded — the run's
        rows and its file are both evaluated on this graph, so that they agree to the last bit (folding lets CasADi
        simplify, e.g. ``a + (x − a)`` to ``x``)."""
        t, y, yp, _ = self.fn.sx_in()
        rel, values = fold_parameters(self.fn, pvec, t, y, yp)
        return [t, y, yp, rel], values


def fold_parameters(fn: ca.Function, pvec: np.ndarray, t: ca.SX, y: ca.SX, yp: ca.SX) -> tuple[ca.SX, ca.SX]:
    """``(rel, fn(t, y, yp, [pvec; rel]))``: a model function ``fn(t, y, yp, p)`` on the symbols ``t, y, yp`` with the
    parameter vector ``pvec`` put in (its constant parts folded) and the relation values ``rel`` left symbolic (one
    unused entry if the model has none). A run's rows and its file's reader are evaluated on such graphs."""
    import casadi as ca

    n_rel = fn.size1_in(3) - len(pvec)
    rel = ca.SX.sym("rel", max(n_rel, 1))
    return rel, fn(t, y, yp, ca.vertcat(ca.DM(pvec), rel[:n_rel] if n_rel else ca.SX(0, 1)))


def signatures(source: np.ndarray, constant: np.ndarray, out: Any, y_columns: np.ndarray | None = None) -> list[tuple]:
    """Per output (:class:`OutputMap` ``source`` and ``constant``): ``("y", j)`` (the unknown ``y[j]``, or its stored
    column ``y_columns[j]``), ``("c", value)`` or ``("x", node)`` (its node in the graph ``out``, evaluated only if
    some output is derived: a callable giving it): outputs with the same signature are the same function of the
    row."""
    graph = out() if (source == DERIVED).any() else None

    def unknown(j: int) -> tuple:
        if y_columns is None:
            return ("y", j)
        return ("y", int(y_columns[j])) if y_columns[j] >= 0 else ("g", j)  # ("g": given by its row, not stored)

    return [unknown(int(src)) if src >= 0
            else ("c", float(constant[i])) if src == CONSTANT else ("x", graph[i].element_hash())
            for i, src in enumerate(source)]


def pack_function(fn: ca.Function) -> np.ndarray:
    """A CasADi function as compressed bytes (``uint8``), for a dataset."""
    return np.frombuffer(zlib.compress(fn.serialize().encode("utf-8"), 6), dtype=np.uint8)


def unpack_function(data: np.ndarray, where: str, casadi_version: str) -> ca.Function:
    """The function :func:`pack_function` stored; :class:`ResultFileError` naming ``where`` if it cannot be read."""
    import casadi as ca

    try:
        return ca.Function.deserialize(zlib.decompress(np.asarray(data, dtype=np.uint8).tobytes()).decode("utf-8"))
    except Exception as err:  # zlib, UnicodeDecodeError, CasADi's RuntimeError: all say "cannot be read"
        raise ResultFileError(
            f"{where}: the model's output function stored in the file cannot be read by this CasADi "
            f"{ca.__version__} (written by CasADi {casadi_version or 'unknown'}: {type(err).__name__}: "
            f"{str(err).strip().splitlines()[-1] if str(err).strip() else ''}); the unknowns and the stored outputs "
            "are readable, a derived variable is not: install that CasADi, or repeat the run with outputs= naming "
            "the variable (or outputs='all')") from None


def unique_columns(Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct columns of ``Y`` (first occurrence) and, per column of ``Y``, its index among them."""
    first: dict[bytes, int] = {}
    keep, index = [], np.empty(Y.shape[1], dtype=np.int64)
    for j in range(Y.shape[1]):
        key = hashlib.blake2b(np.ascontiguousarray(Y[:, j]).tobytes(), digest_size=16).digest()
        if key not in first:
            first[key] = len(keep)
            keep.append(j)
        index[j] = first[key]
    return np.asarray(keep, dtype=np.int64), index


@dataclass
class StoredPart:
    """The rows of one model of a run, as a file holds them: ``out`` (serialised or as a function), the rows'
    indices into the result's time points, their unknowns ``Y`` and ``YP`` (row-major, ``(rows, n)``), relation
    values ``rel`` and the parameter vector ``pvec``."""

    out: ca.Function
    rows: np.ndarray
    T: np.ndarray
    Y: np.ndarray
    YP: np.ndarray
    rel: np.ndarray
    pvec: np.ndarray
    omap: OutputMap | None = None  # of ``out``, if the caller has it
    defs: RowDefinitions | None = None  # the unknowns the rows give (not stored), if any

    def output_map(self) -> OutputMap:
        """How each output of ``out`` is got from a row: :attr:`omap`, else classified now."""
        return self.omap if self.omap is not None else output_map(output_graph(self.out))


@dataclass
class FilePart:
    """One model's rows in an open file, read column by column when needed."""

    group: Any
    rows: np.ndarray
    T: np.ndarray
    n: int
    source: np.ndarray
    constant: np.ndarray
    y_columns: np.ndarray
    yp_used: np.ndarray
    pvec: np.ndarray
    where: str
    casadi_version: str
    given: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))  # unknowns the rows give
    _given: np.ndarray | None = None  # their values, once asked for
    _stored: np.ndarray | None = None  # every stored column of y, once more than a few were asked for
    _columns: dict[int, np.ndarray] = field(default_factory=dict)  # stored columns of y read one by one
    _yp_rel: tuple[np.ndarray, np.ndarray] | None = None
    _fn: ca.Function | None = None
    _bound: tuple[list[ca.SX], ca.SX] | None = None

    def function(self) -> ca.Function:
        """The part's output function ``out(t, y, yp, p)``, as stored."""
        if self._fn is None:
            self._fn = unpack_function(self.group["out"][()], self.where, self.casadi_version)
        return self._fn

    def bound(self) -> tuple[list[ca.SX], ca.SX]:
        """``([t, y, yp_used, rel], out)``: the output function's graph with the parameter vector put in (constant
        parts folded) and only the derivatives it reads as inputs."""
        if self._bound is None:
            import casadi as ca

            t, y = ca.SX.sym("t"), ca.SX.sym("y", self.n)
            ypu = ca.SX.sym("yp", max(len(self.yp_used), 1))  # inputs of at least one entry (an unused one if none)
            yp = ca.SX.zeros(self.n)
            for k, j in enumerate(self.yp_used):
                yp[int(j)] = ypu[k]
            rel, out = fold_parameters(self.function(), self.pvec, t, y, yp)
            self._bound = ([t, y, ypu, rel], out)
        return self._bound

    def stored_y(self, columns: np.ndarray) -> np.ndarray:
        """Stored columns ``columns`` of ``y`` at the part's rows, ``(rows, len(columns))`` row-major: read one by one
        when they are few, else the whole dataset once (kept)."""
        ds = self.group["y"]
        todo = [int(c) for c in dict.fromkeys(columns.tolist()) if int(c) not in self._columns]
        if self._stored is None and len(todo) > 32:
            self._stored = np.asarray(ds[()], dtype=float)
            self._columns.clear()
        if self._stored is not None:
            return np.ascontiguousarray(self._stored[:, columns])
        for c in todo:
            self._columns[c] = np.asarray(ds[:, c], dtype=float)
        out = np.empty((len(self.rows), len(columns)))
        for k, c in enumerate(columns):
            out[:, k] = self._columns[int(c)]
        return out

    def definitions(self) -> RowDefinitions:
        """The part's row definitions (:class:`RowDefinitions`) as stored."""
        fn = None
        if self.given.size:
            fn = unpack_function(self.group["defs"][()], self.where, self.casadi_version)
        return RowDefinitions(np.setdiff1d(np.arange(self.n), self.given), self.given, fn)

    def unknowns(self, columns: np.ndarray) -> np.ndarray:
        """Unknowns ``columns`` at the part's rows, ``(rows, len(columns))``: stored ones read (:meth:`stored_y`), the
        ones the rows give evaluated by the stored definitions with the parameters put in as the run put them in
        (:meth:`RowDefinitions.bound`), all of them at once and kept."""
        columns = np.asarray(columns, dtype=np.int64)
        mapped = self.y_columns[columns]
        if (mapped >= 0).all():
            return self.stored_y(mapped)
        if self._given is None:
            import casadi as ca

            (t, y, _, rel), expr = self.definitions().bound(self.pvec)
            deps = np.unique(np.asarray(ca.jacobian_sparsity(expr, y).get_triplet()[1], dtype=np.int64))
            if not deps.size:
                deps = np.zeros(1, dtype=np.int64)
            yp_all = ca.SX.sym("yp", max(len(self.yp_used), 1))
            fn = ca.Function("flexlib_read_given", [t, ca.vertcat(*[y[int(j)] for j in deps]), yp_all, rel],
                             [ca.densify(expr)])
            from flexlib.solve.rows import RowEvaluator

            _, REL = self.yp_rel()
            YPU = np.zeros((len(self.rows), max(len(self.yp_used), 1)))
            self._given = RowEvaluator().evaluate_function(fn, self, ("given",), self.T, self.stored_y(
                self.y_columns[deps]), YPU, REL)
        out = np.empty((len(self.rows), len(columns)))
        position = np.full(self.n, -1, dtype=np.int64)
        position[self.given] = np.arange(len(self.given))
        stored = mapped >= 0
        if stored.any():
            out[:, stored] = self.stored_y(mapped[stored])
        out[:, ~stored] = self._given[:, position[columns[~stored]]]
        return out

    def yp_rel(self) -> tuple[np.ndarray, np.ndarray]:
        """The stored derivatives and the relation values, row-major."""
        if self._yp_rel is None:
            m = len(self.rows)
            yp = np.asarray(self.group["yp"][()], dtype=float).reshape(m, -1)
            rel = np.asarray(self.group["rel"][()], dtype=float).reshape(m, -1)
            self._yp_rel = tuple(np.ascontiguousarray(x if x.shape[1] else np.zeros((m, 1))) for x in (yp, rel))
        return self._yp_rel


class FileColumns:
    """A loaded result's variables, read from its (open) file when asked for: stored columns, unknowns, constants,
    or derived over the rows by the stored ``out`` (module docstring). The source of a result from
    :func:`~flexlib.results.hdf5.load_result` (``Result.source``)."""

    def __init__(self, file: Any, path: str, n_rows: int, n_cols: int, stored: np.ndarray,
                 parts: list[FilePart]) -> None:
        self.file, self.path, self.n_rows, self.n_cols, self.parts = file, path, n_rows, n_cols, parts
        self.stored = {int(c): k for k, c in enumerate(stored)}
        self._rows: Any = None
        self._signatures: list[tuple] | None = None

    def all(self) -> np.ndarray:
        """Every variable at every row: ``(n_rows, n_cols)``."""
        return self.columns(list(range(self.n_cols)))

    def columns(self, cols: list[int]) -> np.ndarray:
        """The variables ``cols`` (indices into the result's names) at every row: ``(n_rows, len(cols))``."""
        cols = [int(c) for c in cols]
        values = np.empty((self.n_rows, len(cols)), order="F")
        on_file = [pos for pos, c in enumerate(cols) if c in self.stored]
        if len(on_file) > 64:  # many: one read of the dataset
            block = self.file["variables/values"][()]
            for pos in on_file:
                values[:, pos] = block[:, self.stored[cols[pos]]]
        else:
            for pos in on_file:
                values[:, pos] = self.file["variables/values"][:, self.stored[cols[pos]]]
        rest = np.asarray([pos for pos, c in enumerate(cols) if c not in self.stored], dtype=np.int64)
        if not rest.size:
            return values
        wanted = np.asarray(cols, dtype=np.int64)[rest]
        for part in self.parts:
            src = part.source[wanted]
            alias, const, derived = rest[src >= 0], rest[src == CONSTANT], rest[src == DERIVED]
            whole = len(part.rows) == self.n_rows  # one part: every row, in order (checked on reading)

            def at(positions: np.ndarray, part: FilePart = part, whole: bool = whole) -> Any:
                return (slice(None), positions) if whole else np.ix_(part.rows, positions)

            if const.size:
                values[at(const)] = part.constant[wanted[src == CONSTANT]]
            if alias.size:
                values[at(alias)] = part.unknowns(src[src >= 0])
            outputs = tuple(int(c) for c in wanted[src == DERIVED])
            if outputs:
                fn, deps = self._function(part, outputs)
                YP, REL = part.yp_rel()
                values[at(derived)] = self._rows.evaluate_function(fn, part, ("read", outputs), part.T,
                                                                   part.unknowns(deps), YP, REL)
        return values

    def _function(self, part: FilePart, outputs: tuple[int, ...]) -> tuple[Any, np.ndarray]:
        """``(t, y, yp, p) ->`` the outputs ``outputs`` of the part's ``out`` (dense), and the unknowns they read."""
        import casadi as ca

        if self._rows is None:
            from flexlib.solve.rows import RowEvaluator

            self._rows = RowEvaluator()
        (t, y, ypu, rel), out = part.bound()
        expr = out[list(outputs)]
        deps = np.unique(np.asarray(ca.jacobian_sparsity(expr, y).get_triplet()[1], dtype=np.int64))
        if not deps.size:  # an input of at least one entry
            deps = np.zeros(1, dtype=np.int64)
        ys = ca.vertcat(*[y[int(j)] for j in deps])
        return ca.Function("flexlib_read_columns", [t, ys, ypu, rel], [ca.densify(expr)]), deps

    def signatures(self) -> list[tuple]:
        """Per variable, what it is in each part: ``("y", column)``, ``("c", value)``, ``("x", node)`` (a derived
        variable: its expression node in ``out``) or ``("s", column)`` (stored): variables with the same signature
        have the same values (aliases), without reading them."""
        if self._signatures is None:
            per_part = [signatures(part.source, part.constant, lambda part=part: part.bound()[1], part.y_columns)
                        for part in self.parts]
            self._signatures = [("s", i) if i in self.stored else tuple(sig[i] for sig in per_part)
                                for i in range(self.n_cols)]
        return self._signatures

    def stored_parts(self) -> list[StoredPart]:
        """The rows as :class:`StoredPart` (to save the result again)."""
        parts = []
        for part in self.parts:
            YPU, REL = part.yp_rel()
            YP = np.zeros((len(part.rows), part.n))
            YP[:, part.yp_used] = YPU
            rel = REL[:, :part.group["rel"].shape[1]].copy()  # (without the padding of a run without relations)
            omap = OutputMap(part.source, part.constant, part.yp_used)
            parts.append(StoredPart(part.function(), part.rows, part.T, part.unknowns(np.arange(part.n)), YP, rel,
                                    part.pvec, omap, part.definitions() if part.given.size else None))
        return parts

    def nonfinite(self, names: list[str]) -> tuple[list[str], int | None]:
        """The variables whose stored values (unknowns, stored outputs) hold NaN or inf, and the first such row
        (reads the stored datasets, evaluates nothing)."""
        bad: dict[str, None] = {}
        first: int | None = None
        for part in self.parts:
            Y = np.asarray(part.group["y"][()], dtype=float)
            finite = np.isfinite(Y)
            if finite.all():
                continue
            cols = set(np.flatnonzero(~finite.all(axis=0)).tolist())
            row = int(part.rows[int(np.argmax(~finite.all(axis=1)))])
            first = row if first is None else min(first, row)
            for i, src in enumerate(part.source):
                if src >= 0 and int(part.y_columns[src]) in cols:
                    bad[names[i]] = None
        if "variables/values" in self.file and self.stored:
            V = np.asarray(self.file["variables/values"][()], dtype=float)
            finite = np.isfinite(V)
            if not finite.all():
                row = int(np.argmax(~finite.all(axis=1)))
                first = row if first is None else min(first, row)
                for c, k in self.stored.items():
                    if not finite[:, k].all():
                        bad[names[c]] = None
        return list(bad), first


def file_columns(f: Any, path: Any, n_rows: int, names: list[str], bad: Any) -> FileColumns | None:
    """The source of a format-2 file's variables (checked), or None when it stores every variable (``f`` an open
    ``h5py.File``, ``bad`` the reader's error maker)."""
    import h5py

    stored = np.asarray(f["variables/stored"][()])
    shape = f["variables/values"].shape
    if stored.ndim != 1 or (stored.size and stored.dtype.kind not in "iu"):
        raise bad(f"/variables/stored must be a list of column indices, got {stored.dtype} {stored.shape}")
    if stored.size and (stored.min() < 0 or stored.max() >= len(names) or np.any(np.diff(stored) <= 0)):
        raise bad(f"/variables/stored must hold increasing column indices 0 … {len(names) - 1}")
    if shape != (n_rows, len(stored)):
        raise bad(f"/variables/values has shape {shape}, expected {(n_rows, len(stored))} (time points × stored "
                  "variables)")
    if len(stored) == len(names):
        return None
    rows = f.get("rows")
    if rows is None or not isinstance(rows, h5py.Group) or not len(rows):
        raise bad(f"incomplete flexlib result: it stores {len(stored)} of {len(names)} variables and no /rows to "
                  "derive the others from")
    casadi_version = str(f.attrs.get("meta_casadi", ""))
    parts, covered, times = [], np.zeros(n_rows, dtype=int), np.asarray(f["time"][()], dtype=float)
    for key in sorted(rows, key=lambda k: int(k) if k.isdigit() else -1):
        g = rows[key]
        need = ("rows", "y", "y_columns", "yp", "yp_used", "rel", "p", "source", "constant", "out")
        missing = [f"/rows/{key}/{n}" for n in need if n not in g or not isinstance(g[n], h5py.Dataset)]
        if missing:
            raise bad(f"incomplete flexlib result, missing {', '.join(missing)}")
        idx = np.asarray(g["rows"][()], dtype=np.int64)
        if idx.ndim != 1 or (idx.size and (idx.min() < 0 or idx.max() >= n_rows or np.any(np.diff(idx) <= 0))):
            raise bad(f"/rows/{key}/rows must hold increasing row indices 0 … {n_rows - 1}")
        covered[idx] += 1
        source, constant = np.asarray(g["source"][()], dtype=np.int64), np.asarray(g["constant"][()], dtype=float)
        y_columns, yp_used = np.asarray(g["y_columns"][()], dtype=np.int64), np.asarray(g["yp_used"][()], np.int64)
        n = len(y_columns)
        if len(source) != len(names) or len(constant) != len(names):
            raise bad(f"/rows/{key}/source and constant must have one entry per variable ({len(names)})")
        if source.size and (source.min() < -2 or source.max() >= n):
            raise bad(f"/rows/{key}/source must hold unknown indices 0 … {n - 1}, -1 (derived) or -2 (constant)")
        given = np.asarray(g["given"][()], dtype=np.int64) if "given" in g else np.zeros(0, dtype=np.int64)
        if given.ndim != 1 or (given.size and (given.min() < 0 or given.max() >= n or "defs" not in g)):
            raise bad(f"/rows/{key}/given must list unknowns 0 … {n - 1}, with /rows/{key}/defs")
        unstored = np.flatnonzero(y_columns < 0)
        if g["y"].shape[0] != len(idx) or (n and (y_columns.min() < -1 or y_columns.max() >= g["y"].shape[1])) or \
                not np.array_equal(unstored, np.sort(given)):
            raise bad(f"/rows/{key}/y has shape {g['y'].shape}, inconsistent with its {len(idx)} rows and "
                      f"/rows/{key}/y_columns (-1 exactly for the unknowns in /rows/{key}/given)")
        if g["yp"].shape != (len(idx), len(yp_used)) or (yp_used.size and (yp_used.min() < 0 or yp_used.max() >= n)):
            raise bad(f"/rows/{key}/yp has shape {g['yp'].shape}, expected {(len(idx), len(yp_used))}")
        if g["rel"].shape[0] != len(idx):
            raise bad(f"/rows/{key}/rel has {g['rel'].shape[0]} rows, expected {len(idx)}")
        parts.append(FilePart(g, idx, np.ascontiguousarray(times[idx]), n, source, constant,
                               y_columns, yp_used, np.asarray(g["p"][()], dtype=float),
                               f"cannot read the result file {path}", casadi_version, given))
    if np.any(covered != 1):
        k = int(np.argmax(covered != 1))
        raise bad(f"/rows holds row {k} {covered[k]} times; each time point is in exactly one part")
    return FileColumns(f, str(path), n_rows, len(names), stored, parts)
