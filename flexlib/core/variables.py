"""Declarations (parameters, variables, connector variables), the symbol registry and ``time``.

A component class declares its quantities as class attributes::

    class Inertia(Component):
        J = Parameter(unit="kg.m2", min=0.0, doc="Moment of inertia")
        w = Variable(unit="rad/s", state_select="prefer", doc="Angular velocity")

On an instance, ``self.J`` and ``self.w`` are CasADi SX symbols, so equations are
ordinary CasADi expressions. Every scalar symbol is registered with the node that
owns it, which is how ``der`` finds derivatives, how ``connect`` finds signal
variables, and how the compiler names every equation and variable.
"""

from __future__ import annotations

import enum
import math
import weakref
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np

from flexlib.core.values import as_bool, not_a_number, numeric_array
from flexlib.errors import ModelError

if TYPE_CHECKING:  # pragma: no cover
    from flexlib.core.component import Node

__all__ = [
    "STATE_SELECT",
    "Declaration",
    "Flow",
    "Input",
    "Output",
    "Parameter",
    "Potential",
    "StateSelect",
    "Variable",
    "full_name",
    "lookup",
    "lookup_hash",
    "render",
    "render_many",
    "time",
]


class StateSelect(enum.IntEnum):
    """Preference for choosing a variable as a state (Modelica ``StateSelect``)."""

    never = 0
    avoid = 1
    default = 2
    prefer = 3
    always = 4


class Kind(str, enum.Enum):
    """Role of a declared quantity."""

    parameter = "parameter"
    variable = "variable"
    potential = "potential"
    flow = "flow"
    input = "input"
    output = "output"


# ---------------------------------------------------------------------------------------------
# Symbol registry: scalar SX symbol (by element hash) -> SymInfo. Weak values: a SymInfo lives
# as long as the node that owns it, and it holds the SX symbol, so a hash is never reused while
# its entry exists.
# ---------------------------------------------------------------------------------------------
_REGISTRY: weakref.WeakValueDictionary[int, SymInfo] = weakref.WeakValueDictionary()


@dataclass(eq=False)
class SymInfo:
    """What a scalar SX symbol stands for.

    Attributes
    ----------
    sym : casadi.SX
        The scalar symbol.
    kind : str
        ``"variable"`` (any declared variable), ``"parameter"``, ``"der"``, ``"time"``,
        ``"relation"`` (a discrete relation created by :func:`flexlib.if_else`) or ``"table"`` (an entry of a
        table's row, :func:`flexlib.segment_row`).
    node : Node or None
        Owning component (None for time and for derivative/relation symbols).
    name : str
        Declaration name in the owner (``"w"``) or a description.
    index : tuple
        Index of the element inside an array declaration (``()`` for scalars).
    base : SymInfo or None
        For ``kind == "der"``: the symbol this is the time derivative of.
    """

    sym: ca.SX
    kind: str
    node: Any = None
    name: str = ""
    index: tuple = ()
    base: SymInfo | None = None
    _der: SymInfo | None = field(default=None, repr=False)
    extra: dict = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        _REGISTRY[self.sym.element_hash()] = self

    @property
    def der_info(self) -> SymInfo:
        """The SymInfo of ``der(sym)``, created on first use."""
        if self._der is None:
            self._der = SymInfo(ca.SX.sym(f"der({self.sym.name()})"), "der", base=self)
        return self._der

    @property
    def order(self) -> int:
        """Differentiation order (0 for a plain variable)."""
        return 0 if self.base is None else self.base.order + 1

    @property
    def root(self) -> SymInfo:
        """The undifferentiated symbol."""
        return self if self.base is None else self.base.root


def lookup(sym: ca.SX) -> SymInfo | None:
    """Return the registry entry of a scalar symbol, or None."""
    return _REGISTRY.get(sym.element_hash())


def lookup_hash(h: int) -> SymInfo | None:
    """Return the registry entry of the scalar symbol with element hash ``h``, or None."""
    return _REGISTRY.get(h)


def full_name(info: SymInfo) -> str:
    """Hierarchical name of a symbol (``inertia1.flange_a.phi``, ``der(mass.v)``, ``frame.r[0]``)."""
    if info.kind == "der" and info.base is not None:
        return f"der({full_name(info.base)})"
    if info.node is None:
        return info.name or str(info.sym)
    label = info.node._label(info.name)
    if info.index:
        label += "[" + ",".join(str(i) for i in info.index) + "]"
    return label


def render(expr: ca.SX, limit: int = 160) -> str:
    """Printable form of an expression with every symbol written by its hierarchical name."""
    if ca.n_nodes(expr) > 8 * limit:  # printing would cost more than it tells: name the symbols instead
        names = [full_name(i) if (i := lookup(s)) is not None else str(s) for s in ca.symvar(expr)]
        text = f"<expression of {len(names)} symbols: " + ", ".join(names) + ">"
        return text if len(text) <= limit else text[: limit - 4] + "...>"
    syms = ca.symvar(expr)
    named = []
    for s in syms:
        info = lookup(s)
        named.append(ca.SX.sym(full_name(info)) if info is not None else s)
    text = str(ca.substitute(expr, ca.vertcat(*syms), ca.vertcat(*named))) if syms else str(expr)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def render_many(exprs: list[ca.SX], limit: int = 160) -> list[str]:
    """:func:`render` of each expression, with one substitution of names over all of them.

    The same strings as ``[render(e, limit) for e in exprs]``; each symbol is named once rather than once per
    expression it occurs in (``docs/decisions/030-row-labels-named-once.md``).
    """
    out = [""] * len(exprs)
    small = []
    for i, e in enumerate(exprs):
        if ca.n_nodes(e) > 8 * limit:
            out[i] = render(e, limit)
        else:
            small.append(i)
    if not small:
        return out
    v = ca.vertcat(*[exprs[i] for i in small])
    syms = ca.symvar(v)
    if syms:
        named = [ca.SX.sym(full_name(info)) if (info := lookup(s)) is not None else s for s in syms]
        v = ca.substitute(v, ca.vertcat(*syms), ca.vertcat(*named))
    for k, i in enumerate(small):
        text = str(v[k])
        out[i] = text if len(text) <= limit else text[: limit - 3] + "..."
    return out


time = ca.SX.sym("time")
"""Simulation time [s] (Modelica ``time``)."""
_TIME_INFO = SymInfo(time, "time", name="time")


# ---------------------------------------------------------------------------------------------
# Declarations
# ---------------------------------------------------------------------------------------------
def _shape(shape: Any) -> tuple[int, ...]:
    """A declaration's ``shape`` as a tuple of at most two positive ints (``()``, ``(n,)``, ``(n, m)``).

    Only ints (Python or numpy, not bools) are sizes: ``shape="12"`` was read as ``(1, 2)``, ``shape=True`` as
    ``(1,)`` and ``shape=2.5`` failed with a TypeError.
    """
    items = (shape,) if isinstance(shape, (int, np.integer)) and not isinstance(shape, (bool, np.bool_)) else shape
    if not isinstance(items, (tuple, list)) or not all(
            isinstance(s, (int, np.integer)) and not isinstance(s, (bool, np.bool_)) for s in items):
        raise ModelError(f"shape {shape!r}: give () for a scalar, an int n or (n,) for a vector, (n, m) for a "
                         "matrix (sizes are ints >= 1)")
    out = tuple(int(s) for s in items)
    if len(out) > 2 or any(s < 1 for s in out):
        raise ModelError(f"shape {out}: only scalars, vectors and matrices are supported (sizes >= 1)")
    return out


def _text(value: Any, what: str) -> str:
    """A declaration's ``unit`` or ``doc``: a string (a number there is a misplaced argument)."""
    if not isinstance(value, str):
        raise ModelError(f"{what} must be a string, got {type(value).__name__} {value!r:.60}")
    return value


def _switch(value: Any, what: str) -> bool:
    """A declaration's on/off option (``fixed``, ``error_test``, ...)."""
    return as_bool(value, what, ModelError)


class Declaration:
    """Base class of the class-attribute declarations (parameters and variables).

    On an instance the attribute is the CasADi SX symbol; on the class it is the
    declaration itself (so ``Inertia.J.unit == "kg.m2"``).
    """

    kind: Kind = Kind.variable

    def __init__(self, *, unit: str = "1", doc: str = "", shape: int | tuple[int, ...] = ()) -> None:
        self.unit = _text(unit, "unit")
        self.doc = _text(doc, "doc")
        self.shape = _shape(shape)
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, instance: Node | None, owner: type) -> Any:
        if instance is None:
            return self
        return instance._symbol(self.name)

    def __set__(self, instance: Node, value: Any) -> None:
        instance._assign(self.name, value)

    @property
    def size(self) -> int:
        """Number of scalar elements."""
        return int(np.prod(self.shape)) if self.shape else 1

    def element_names(self, base: str) -> list[tuple[str, tuple]]:
        """Scalar element names (``r[0]``, ``R[1,2]``) in CasADi column-major nonzero order."""
        if not self.shape:
            return [(base, ())]
        if len(self.shape) == 1:
            return [(f"{base}[{i}]", (i,)) for i in range(self.shape[0])]
        n, m = self.shape
        return [(f"{base}[{i},{j}]", (i, j)) for j in range(m) for i in range(n)]

    def new_symbol(self, label: str) -> ca.SX:
        """A fresh SX symbol with this declaration's shape."""
        if not self.shape:
            return ca.SX.sym(label)
        if len(self.shape) == 1:
            return ca.SX.sym(label, self.shape[0])
        return ca.SX.sym(label, *self.shape)


class Parameter(Declaration):
    """A numeric parameter, tunable at run time without recompiling.

    Parameters
    ----------
    default : float or array_like, optional
        Default value in SI units; None means the user must give a value.
    unit : str
        Unit in Modelica syntax (``"kg.m2"``, ``"N/m"``).
    min, max : float, optional
        Inclusive bounds (``min <= value <= max``), checked for every element whenever a value is set:
        at construction, at flatten and for ``run(params=...)`` overrides.
    gt, lt : float, optional
        Exclusive bounds (``gt < value < lt``), checked like ``min``/``max`` (Modelica's
        ``min=Modelica.Constants.small`` for a quantity that must be strictly positive: ``gt=0``).
    doc : str
        One-line description.
    shape : int or tuple
        ``()`` for a scalar, ``(3,)`` for a vector, ``(3, 3)`` for a matrix.
    """

    kind = Kind.parameter

    def __init__(
        self, default: Any = None, *, unit: str = "1", doc: str = "", min: float | None = None,
        max: float | None = None, gt: float | None = None, lt: float | None = None,
        shape: int | tuple[int, ...] = (),
    ) -> None:
        super().__init__(unit=unit, doc=doc, shape=shape)
        self.default = default
        bounds = {}
        for key, bound in (("min", min), ("max", max), ("gt", gt), ("lt", lt)):
            if bound is not None:  # a string bound failed in the first comparison; NaN made the bound a no-op
                why = not_a_number(bound)
                if why is None and (np.ndim(bound) != 0 or math.isnan(float(bound))):
                    why = "not a single number" if np.ndim(bound) else "NaN"
                if why is not None:
                    raise ModelError(f"Parameter {key}={bound!r:.60} is {why}; bounds are real numbers (or None)")
                bounds[key] = float(bound)
        lower = [(k, bounds[k]) for k in ("min", "gt") if k in bounds]
        upper = [(k, bounds[k]) for k in ("max", "lt") if k in bounds]
        for lk, lo in lower:
            for uk, hi in upper:
                if lo > hi or (lo == hi and (lk, uk) != ("min", "max")):
                    raise ModelError(f"Parameter bounds {lk}={lo:g} and {uk}={hi:g} admit no value")
        self.min = bounds.get("min")
        self.max = bounds.get("max")
        self.gt = bounds.get("gt")
        self.lt = bounds.get("lt")

    def rules(self) -> str:
        """The bounds as text (``"> 0, <= 1"``; empty without bounds)."""
        parts = [f"{op} {b:g}" for op, b in ((">=", self.min), (">", self.gt), ("<=", self.max), ("<", self.lt))
                 if b is not None]
        return ", ".join(parts)

    def check(self, path: str, value: Any) -> np.ndarray:
        """Return ``value`` as a float array of the declared shape, or raise naming ``path``.

        Raises :class:`~flexlib.ParameterError` for a value that is not a real number or an array of them (a
        string such as ``'1.6e9'``, a bool, None, a complex number), of another shape (a vector of the declared
        size is reshaped), not finite, or outside the declared bounds; the message names ``path`` and the value.
        """
        from flexlib.errors import ParameterError

        if not self.shape and (type(value) is float or (type(value) is int and abs(value) < 2**1000)):
            v = float(value)  # the usual scalar: plain float comparisons (a huge int is named below)
            if (math.isfinite(v) and (self.min is None or v >= self.min) and (self.max is None or v <= self.max)
                    and (self.gt is None or v > self.gt) and (self.lt is None or v < self.lt)):
                return np.array(v)
        wanted = (f"a real number [{self.unit}]" if not self.shape else
                  f"an array of real numbers of shape {self.shape} [{self.unit}]")
        arr = numeric_array(value, f"{path}: parameter value", wanted, ParameterError)
        if arr.shape != self.shape:
            if arr.size == self.size and self.shape:
                arr = arr.reshape(self.shape)
            else:
                what = " (a scalar)" if not self.shape else ""
                shown = arr.tolist() if arr.size <= 12 else f"<{arr.size} values>"
                raise ParameterError(f"{path}: parameter has shape {self.shape}{what}, got value of shape {arr.shape}: "
                                     f"{shown!r} [{self.unit}]")
        shown = value if np.ndim(value) == 0 else arr.tolist()
        if not np.all(np.isfinite(arr)):
            raise ParameterError(f"{path}: parameter value {shown!r} is not finite")
        if self.min is not None and np.any(arr < self.min):
            raise ParameterError(f"{path} = {shown!r} [{self.unit}] is below its minimum {self.min}")
        if self.max is not None and np.any(arr > self.max):
            raise ParameterError(f"{path} = {shown!r} [{self.unit}] is above its maximum {self.max}")
        if self.gt is not None and np.any(arr <= self.gt):
            raise ParameterError(f"{path} must be > {self.gt:g}, got {shown!r} [{self.unit}]")
        if self.lt is not None and np.any(arr >= self.lt):
            raise ParameterError(f"{path} must be < {self.lt:g}, got {shown!r} [{self.unit}]")
        return arr


#: ``StateSelect`` members by name (``"prefer"``).
STATE_SELECT = {s.name: s for s in StateSelect}


class Variable(Declaration):
    """A time-varying unknown.

    Parameters
    ----------
    unit : str
        Unit in Modelica syntax.
    start : float or array_like
        Start value: the initial value if ``fixed``, otherwise a guess for initialisation.
    fixed : bool
        True if the start value is an initial condition (Modelica ``fixed=true``).
    nominal : float
        Typical magnitude; scales the absolute tolerance of the integrator.
    state_select : str
        ``"never"``, ``"avoid"``, ``"default"``, ``"prefer"`` or ``"always"``.
    doc : str
        One-line description.
    shape : int or tuple
        ``()``, ``(n,)`` or ``(n, m)``.
    derivative : callable, optional
        ``derivative(node) -> expression``: the time derivative of this variable in terms of other
        variables of the same node (Modelica's derivative annotation; for a frame's orientation
        matrix ``der(T) = −[w×] T``). Index reduction uses it instead of introducing ``der(x)`` as an
        unknown, so such a variable is never a state and its derivative costs no equations.
    error_test : bool
        False for an acceleration-level quantity that the equations of motion determine without derivatives of
        the states (a joint's relative acceleration, a frame's acceleration carried along a multibody tree): as an
        algebraic unknown it stays out of IDA's local error test, with the reactions it determines, like the
        unknowns the engine finds determined only through derivatives — unless positions and velocities alone
        determine it (``flexlib.compile.structure.derivative_level``). A state is always tested.
    intermediate : bool
        True for a quantity that only carries kinematics from one component to the next (a multibody frame's
        velocity and accelerations along the tree): where a row gives it explicitly, the engine eliminates it even
        while IDA's error test checks it (stage 3c, ``flexlib/compile/explicit.py``), as it does the unknowns
        outside the test; it stays in results by name.
    """

    kind = Kind.variable

    def __init__(
        self, *, unit: str = "1", doc: str = "", start: Any = 0.0, fixed: bool = False,
        nominal: float = 1.0, state_select: str = "default", shape: int | tuple[int, ...] = (),
        derivative: Any = None, error_test: bool = True, intermediate: bool = False,
    ) -> None:
        super().__init__(unit=unit, doc=doc, shape=shape)
        if derivative is not None and not callable(derivative):
            raise ModelError(f"derivative must be a function derivative(node) -> expression, got "
                             f"{type(derivative).__name__} {derivative!r:.60}")
        self.derivative = derivative
        self.error_test = _switch(error_test, "error_test")
        self.intermediate = _switch(intermediate, "intermediate")
        if isinstance(state_select, StateSelect):
            state_select = state_select.name
        if not isinstance(state_select, str) or state_select not in STATE_SELECT:
            raise ModelError(f"state_select must be one of {sorted(STATE_SELECT)} (or a fl.StateSelect member), "
                             f"got {state_select!r}")
        if not_a_number(nominal) is not None or np.ndim(nominal) != 0 or not float(nominal) > 0:
            raise ModelError(f"nominal must be a number > 0, got {nominal!r}")
        size = self.size
        arr = numeric_array(start, "Variable start value", "a real number (an array of them for an array variable)",
                            ModelError)  # NaN is allowed here: it is named at initialisation with the variable's path
        if arr.size != 1 and (arr.size != size or not self.shape):  # one value for every element, or one each
            raise ModelError(f"Variable start value {start!r:.80} has {arr.size} elements; give one number"
                             + (f" or {size} (shape {self.shape})" if self.shape else " (the variable is a scalar)"))
        self.start = start
        self.fixed = _switch(fixed, "fixed")
        self.nominal = float(nominal)
        self.state_select = STATE_SELECT[state_select]


class Potential(Variable):
    """A connector variable that is equal across a connection (angle, position, pressure).

    Parameters
    ----------
    overdetermined : bool
        True for the entries of an over-determined record (the orientation of a 3D frame: 9 matrix
        entries for 3 degrees of freedom). They are equated only along a spanning tree of the
        connection graph; a connection that closes a loop uses the connector's
        ``equality_constraint`` instead (Modelica spec §9.4). See :meth:`Component.branch`.
    **kwargs
        As :class:`Variable`.
    """

    kind = Kind.potential

    def __init__(self, *, overdetermined: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.overdetermined = _switch(overdetermined, "overdetermined")


class Flow(Variable):
    """A connector variable that sums to zero over a connection, positive into the component."""

    kind = Kind.flow


class Input(Variable):
    """A causal signal input: its value comes from the output it is connected to.

    An input of the top-level model (Modelica's top-level ``input``) is connected to nothing inside the model: it is
    a run-time parameter whose value is its start value (default 0) unless ``run(params={name: value})`` sets it, and
    the input an FMI master sets between steps in an exported unit (:func:`flexlib.fmi.export_fmu`).
    """

    kind = Kind.input

    def as_parameter(self) -> Parameter:
        """The parameter a top-level input is in the flat model (its start value as default, its unit and doc)."""
        found = self.__dict__.get("_parameter")
        if found is None:
            start = 0.0 if self.start is None else self.start
            found = Parameter(start, unit=self.unit, doc=self.doc, shape=self.shape)
            self.__dict__["_parameter"] = found
        return found


class Output(Variable):
    """A causal signal output: the block computes it."""

    kind = Kind.output
