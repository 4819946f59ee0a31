"""Components, connectors and models: the instance tree that the compiler flattens.

A :class:`Component` declares parameters and variables as class attributes, holds
sub-components and connectors as attributes (assigning one registers and names it),
and writes its physics in :meth:`Component.equations`. A model is a component with
sub-components and :meth:`Component.connect` statements.

Classes, sub-components and connectors declared at class level are templates: each
instance gets its own copy, built again from the template's constructor arguments.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

import casadi as ca

from flexlib.core.docs import document
from flexlib.core.equations import Equation
from flexlib.core.instance_values import InstanceValues
from flexlib.core.variables import (
    Declaration,
    Kind,
    Parameter,
    StateSelect,
    SymInfo,
    lookup,
)
from flexlib.errors import ConnectError, ModelError, ParameterError

__all__ = ["Component", "Connector", "Model", "Node"]


#: Per class: its declarations and its sub-component templates in MRO order (one walk of the MRO per class,
#: not per instance; a model of N components builds N instances of a handful of classes), with the sizes of
#: the class dictionaries it was read from (an attribute added to a class later invalidates the entry).
#: Hooks ``(node, name) -> (declaration, name it follows) | None`` of the registered compile passes
#: (:meth:`flexlib.compile.passes.base.Pass.declaration`): a variable a pass declares on the nodes of its family
#: (the multibody pass: a frame's ``v``, ``a``, ``z``), on demand before the model is flattened.
PASS_DECLARATIONS: list[Callable[[Node, str], tuple[Declaration, str | None] | None]] = []

_CLASS_MEMBERS: dict[type, tuple[tuple[int, ...], dict[str, Declaration], list[tuple[str, Node]]]] = {}

#: Bumped whenever a node is attached to a parent: a path cached under an older generation is recomputed.
_TREE_GENERATION = [0]


def _class_members(cls: type) -> tuple[dict[str, Declaration], list[tuple[str, Node]]]:
    """``({name: declaration}, [(name, template)])`` of class ``cls`` and its bases, bases first."""
    sizes = tuple(len(vars(klass)) for klass in cls.__mro__)
    found = _CLASS_MEMBERS.get(cls)
    if found is None or found[0] != sizes:
        decls: dict[str, Declaration] = {}
        templates: list[tuple[str, Node]] = []
        for klass in reversed(cls.__mro__):
            for name, value in vars(klass).items():
                if isinstance(value, Declaration):
                    decls[name] = value
        for klass in reversed(cls.__mro__):
            for name, value in vars(klass).items():
                if isinstance(value, Node):
                    templates.append((name, value))
        found = (sizes, decls, templates)
        _CLASS_MEMBERS[cls] = found
    return found[1], found[2]


class _NodeMeta(type):
    """Runs a node's parameter checks once its constructor (the outermost ``__init__``) has finished,
    so cross-parameter rules see every value and every structural option."""

    def __call__(cls, *args: Any, **kwargs: Any) -> Any:
        obj = super().__call__(*args, **kwargs)
        obj.__dict__["_constructed"] = True
        obj.validate()
        return obj


class Node(InstanceValues, metaclass=_NodeMeta):
    """Common base of components and connectors (named, hierarchical, with declarations)."""

    #: The variables a single ``state_select`` value applies to, as MSL's ``stateSelect`` parameter of a joint does
    #: (``Revolute(state_select="always")``: ``phi`` and ``w``); empty: only the dict form.
    state_select_variables: ClassVar[tuple[str, ...]] = ()

    def __new__(cls, *args: Any, **kwargs: Any) -> Node:
        obj = super().__new__(cls)
        object.__setattr__(obj, "_ctor", (args, dict(kwargs)))
        return obj

    def __init__(
        self, *args: Any, doc: str = "", init: dict[str, Any] | None = None,
        guess: dict[str, Any] | None = None, state_select: dict[str, Any] | None = None, **params: Any,
    ) -> None:
        if args:  # Mass(1.0): Python's message names Node.__init__ and no parameter
            names = [n for n, decl in _class_members(type(self))[0].items() if isinstance(decl, Parameter)]
            example = f"{type(self).__name__}({names[0]}=...)" if names else f"{type(self).__name__}()"
            raise ParameterError(f"{type(self).__name__}: got positional argument{'s' if len(args) > 1 else ''} "
                                 f"{', '.join(repr(a) for a in args)}; give parameters by name, e.g. {example} "
                                 f"(parameters: {', '.join(sorted(names)) or 'none'})")
        d = self.__dict__
        d["_parent"] = None
        d["_name"] = ""
        d["doc"] = doc
        d["_children"] = {}
        d["_decls"] = {}
        d["_syms"] = {}
        d["_infos"] = []
        d["_values"] = {}
        d["_starts"] = {}
        d["_state_select"] = {}
        d["_connections"] = []
        decls, templates = _class_members(type(self))
        d["_decls"] = dict(decls)
        for name, value in templates:
            if name not in self._children:
                self._add_child(name, value._clone())
        for name, value in params.items():
            self._assign(name, value)
        for what, given in (("init", init), ("guess", guess)):
            if given is not None and not isinstance(given, Mapping):
                raise ModelError(f"{type(self).__name__}: {what} must be a dict {{variable name: start value}}, "
                                 f"got {type(given).__name__} {given!r}")
        both = sorted(str(k) for k in (init or {}) if k in (guess or {}))
        if both:  # the guess replaced the initial condition without a word
            raise ModelError(f"{type(self).__name__}: {', '.join(repr(k) for k in both)} given in both init (an "
                             "initial condition) and guess (a start guess only); give each variable in one of them")
        for what, given in (("init", init), ("guess", guess)):
            for name, value in (given or {}).items():
                self._start_target(name, what).set_start(name.rpartition(".")[2], value, fixed=what == "init")
        own = type(self).state_select_variables
        if state_select is not None and not isinstance(state_select, Mapping):
            if not own or not isinstance(state_select, str | StateSelect):
                one = (f" or one value for {', '.join(own)} (MSL's stateSelect)" if own else "")
                raise ModelError(f"{type(self).__name__}: state_select must be a dict {{variable: 'always' | "
                                 f"'prefer' | 'default' | 'avoid' | 'never'}}{one}, got {state_select!r}")
            state_select = dict.fromkeys(own, state_select)  # MSL's single modifier of a joint's coordinates
        for name, value in (state_select or {}).items():
            self._start_target(name, "state_select").set_state_select(name.rpartition(".")[2], value)

    def _start_target(self, name: Any, what: str) -> Node:
        """The node that owns the variable ``name`` of an ``init``/``guess``/``state_select`` dict: this one, or for
        a dotted name (``"flange.phi"``) the sub-component or connector it names."""
        if not isinstance(name, str):
            raise ModelError(f"{type(self).__name__}: {what} key {name!r} ({type(name).__name__}) is not a variable "
                             "name; keys are strings such as 's' or 'flange.phi'")
        node: Node = self
        parts = name.split(".")
        for k, part in enumerate(parts[:-1]):
            child = node._children.get(part)
            if child is None:
                known = ", ".join(sorted(node._children)) or "none yet"
                hint = sorted(difflib.get_close_matches(part, list(node._children), n=3))
                raise ModelError(
                    f"{type(self).__name__}: {what} key {name!r}: {type(node).__name__} has no sub-component or "
                    f"connector {'.'.join(parts[:k + 1])!r}" + (f"; did you mean {', '.join(hint)}?" if hint else "")
                    + f" (known: {known}; a sub-component assigned in the constructor after super().__init__() "
                    "takes its own init=... instead)")
            node = child
        return node

    # -- construction -------------------------------------------------------------------------
    def _clone(self) -> Node:
        args, kwargs = self._ctor
        return type(self)(*args, **kwargs)

    def _add_child(self, name: str, node: Node) -> None:
        if not name.isidentifier():  # setattr(self, "a.b", ...): the path "a.b.x" would name another component
            raise ModelError(f"{self._label(name)!r}: a sub-component name must be a Python identifier (letters, "
                             f"digits and _, not starting with a digit), got {name!r}; it becomes part of the "
                             "variable names ('mass1.s')")
        if hasattr(type(self), name) and not isinstance(getattr(type(self), name), Node):
            raise ModelError(f"{self._label(name)}: '{name}' is a method or attribute of {type(self).__name__}; "
                             "choose another name for the sub-component")
        if node._parent is not None or node._name:
            raise ModelError(f"{self._label(name)}: component is already part of {node.path or node._name!r}")
        node.__dict__["_parent"] = self
        node.__dict__["_name"] = name
        _TREE_GENERATION[0] += 1  # paths cached before this attachment may have changed
        self._children[name] = node
        object.__setattr__(self, name, node)

    def __setattr__(self, name: str, value: Any) -> None:
        if name.startswith("_") or "_children" not in self.__dict__:
            object.__setattr__(self, name, value)
        elif name in self.__dict__.get("_options", ()) and self.__dict__.get("_constructed"):
            self._set_option(name, value)
        elif isinstance(value, Node):
            old = self._children.get(name)
            if old is not None:
                if old is value:
                    return
                raise ModelError(
                    f"{self._label(name)}: already holds {type(old).__name__} {old.path}; assigning "
                    f"{type(value).__name__} {value.path or '(unnamed)'} to the same name would drop it. "
                    "Choose another attribute name")
            self._add_child(name, value)
        elif isinstance(value, Declaration):
            if name in self._decls and name in self._syms:
                raise ModelError(f"{self._label(name)}: already declared and in use")
            value.name = name
            self._decls[name] = value
        elif name in self._decls:
            self._assign(name, value)
        elif name in self._children:
            old = self._children[name]
            raise ModelError(f"{self._label(name)}: holds {type(old).__name__} {old.path}; assigning {value!r} to the "
                             "same name would hide it (the component stays in the model). Choose another name")
        else:
            object.__setattr__(self, name, value)

    def _set_option(self, name: str, value: Any) -> None:
        """Assign constructor option ``name`` after construction, checked as the constructor checked it
        (:func:`remember_option`)."""
        check, structural = self.__dict__["_options"][name]
        new = check(value)
        old = self.__dict__.get(name)
        if structural and not (new is old or (type(new) is type(old) and new == old)):
            cls = type(self).__name__
            raise ModelError(
                f"{self.where}: {name} = {old!r} decided the structure of this {cls} when it was built (its "
                f"connectors, variables or start values); assigning {value!r} afterwards would be ignored in part. "
                f"Build it as {cls}({name}={value!r}, ...) instead")
        object.__setattr__(self, name, new)

    def __getattr__(self, name: str) -> Any:
        decls = self.__dict__.get("_decls")
        if decls is not None and not name.startswith("_") and self._declaration(name) is not None:
            return self._symbol(name)
        raise AttributeError(f"{type(self).__name__} {self.path or '(unnamed)'!s} has no attribute {name!r}")

    # -- naming -------------------------------------------------------------------------------
    @property
    def path(self) -> str:
        """Hierarchical name relative to the root model (``"boom.cyl1.port_a"``)."""
        d = self.__dict__
        cached = d.get("_path_cache")
        if cached is not None and cached[0] == _TREE_GENERATION[0]:
            return cached[1]
        parts = []
        node: Node | None = self
        while node is not None and node._parent is not None:
            parts.append(node._name)
            node = node._parent
        path = ".".join(reversed(parts))
        d["_path_cache"] = (_TREE_GENERATION[0], path)
        return path

    def _label(self, name: str) -> str:
        p = self.path
        return f"{p}.{name}" if p else name

    @property
    def root(self) -> Node:
        """The top of the instance tree."""
        node = self
        while node._parent is not None:
            node = node._parent
        return node

    # -- declarations -------------------------------------------------------------------------
    def _symbol(self, name: str) -> ca.SX:
        sym = self._syms.get(name)
        if sym is None:
            decl = self._decls[name]
            sym = decl.new_symbol(name)
            kind = "parameter" if isinstance(decl, Parameter) else "variable"
            if not decl.shape:  # a scalar: the symbol is its own only element
                self._infos.append(SymInfo(sym, kind, node=self, name=name, index=()))
            else:
                for k, (_, index) in enumerate(decl.element_names(name)):
                    self._infos.append(SymInfo(sym.nz[k], kind, node=self, name=name, index=index))
            self._syms[name] = sym
        return sym

    def add_pass_declaration(self, name: str, decl: Declaration, after: str | None = None) -> None:
        """Declare ``name`` on this instance for a compile pass: an unknown the pass also defines (the multibody
        pass's frame velocities and accelerations), placed after the declaration ``after`` (default: last). It is
        not one of the class's declarations, so the cache key and the connectability of connectors do not see it;
        declaring it again (a second flatten) keeps the first."""
        decls = self._decls
        if name in decls:
            if name in self.__dict__.get("_pass_decls", ()):
                return
            raise ModelError(f"{self._label(name)}: already declared by {type(self).__name__}; a compile pass cannot "
                             "declare it again")
        decl.name = name
        items = list(decls.items())
        at = next((k + 1 for k, (n, _) in enumerate(items) if n == after), len(items))
        items.insert(at, (name, decl))
        decls.clear()
        decls.update(items)
        self.__dict__.setdefault("_pass_decls", set()).add(name)

    def _declaration(self, name: str) -> Declaration | None:
        """The declaration of ``name``: this node's, or one a registered compile pass declares on it on demand
        (:data:`PASS_DECLARATIONS`: a frame's ``v`` given a start value before the model is flattened)."""
        decl = self._decls.get(name)
        if decl is None and isinstance(name, str):
            if not PASS_DECLARATIONS:  # the passes register their hooks when imported: not only once a build ran
                import flexlib.compile.passes  # noqa: F401
            for hook in PASS_DECLARATIONS:
                found = hook(self, name)
                if found is not None:
                    self.add_pass_declaration(name, *found)
                    return found[0]
        return decl

    def class_declarations(self) -> dict[str, Declaration]:
        """This node's declarations without those a compile pass added (:meth:`add_pass_declaration`)."""
        extra = self.__dict__.get("_pass_decls", ())
        return {n: d for n, d in self._decls.items() if n not in extra}

    # -- tree walk ----------------------------------------------------------------------------
    def walk(self) -> list[Node]:
        """This node and all nodes below it, parents before children."""
        out, stack = [], [self]
        while stack:
            node = stack.pop()
            out.append(node)
            stack.extend(reversed(list(node._children.values())))
        return out

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.path or '(root)'}>"


class Connector(Node):
    """A connector: potential and flow variables (or causal signals) shared across connections.

    Two connectors can be connected when they declare the same variables (name, kind,
    shape, unit). A flow variable is positive into the component that owns the connector.
    A connector with over-determined potentials (``Potential(overdetermined=True)``) must
    implement :meth:`equality_constraint`.
    """

    @property
    def overdetermined(self) -> bool:
        """True if the connector has over-determined potentials."""
        return any(getattr(d, "overdetermined", False) for d in self._decls.values())

    def equality_constraint(self, other: Connector) -> Any:
        """Residue (a short vector) that is zero when the over-determined records of ``self`` and
        ``other`` describe the same thing; used where a connection closes a loop."""
        raise NotImplementedError(f"{type(self).__name__} has over-determined variables but no equality_constraint")

    def check_connection(self, members: list[Connector]) -> None:
        """Hook called when the model is flattened, once per connection set of two or more connectors, on its
        first member with all ``members``: raise :class:`~flexlib.ConnectError` if they cannot share the set
        beyond their declarations (the hydraulic ``Port``: one fluid per circuit). Default: nothing."""

    def connection_set(self) -> list[Connector]:
        """The other connectors connected to this one, directly or through other connections, in the whole
        model (Modelica's connection set; the basis of MSL's ``cardinality``-style structural choices)."""
        links: dict[int, list[Connector]] = {}
        for node in self.root.walk():
            for a, b in getattr(node, "_connections", ()):
                if a[0] == "connector" and b[0] == "connector":
                    links.setdefault(id(a[1]), []).append(b[1])
                    links.setdefault(id(b[1]), []).append(a[1])
        seen, stack, out = {id(self)}, [self], []
        while stack:
            for other in links.get(id(stack.pop()), ()):
                if id(other) not in seen:
                    seen.add(id(other))
                    out.append(other)
                    stack.append(other)
        return out

    def signature(self) -> tuple:
        """What must match for two connectors to be connectable."""
        return tuple(sorted((n, d.kind.value, d.shape, d.unit) for n, d in self.class_declarations().items()))

    def describe(self) -> str:
        """``"Flange(phi [rad], flow tau [N.m])"``."""
        parts = []
        for n, d in self._decls.items():
            prefix = "flow " if d.kind is Kind.flow else ""
            parts.append(f"{prefix}{n} [{d.unit}]")
        return f"{type(self).__name__}({', '.join(parts)})"


class Component(Node):
    """A physical component or a model (a component made of connected components).

    Subclasses declare :class:`~flexlib.Parameter` and :class:`~flexlib.Variable` class
    attributes, assign sub-components and connectors as attributes, and return their
    equations from :meth:`equations`.

    Parameters
    ----------
    init : dict, optional
        ``{variable: value}`` initial conditions (start value with ``fixed=True``). A dotted name
        (``"flange_a.s"``) reaches a variable of a connector or sub-component that exists when the constructor
        runs (declared at class level). Values are real numbers (arrays for array variables): a string, a bool,
        None or a complex number is refused naming the component, the variable and the value; a parameter named
        here is refused with how to set it (``Mass(m=2)``, ``run(params={"mass.m": 2})``).
    guess : dict, optional
        ``{variable: value}`` start values used only as initialisation guesses (checked as ``init``).
    state_select : dict, optional
        ``{variable: "never" | "avoid" | "default" | "prefer" | "always"}`` (or :class:`~flexlib.StateSelect`
        members): this instance's preference for choosing the variable as a state, overriding the declaration
        (Modelica's ``stateSelect`` modifier, e.g. ``Revolute(state_select={"phi": "always", "w": "always"})``);
        a component with :attr:`state_select_variables` also takes one value for all of them, as MSL's joints
        (``Revolute(state_select="always")``).
    doc : str, optional
        Description of this instance.
    **params
        Parameter values (SI), overriding declared defaults: real numbers or arrays of them of the declared shape
        (strings, bools, None and complex numbers are refused, see :meth:`Parameter.check`).

    Notes
    -----
    Parameter values are validated by one hook on every path: each value against its declaration's bounds
    (``min``/``max``/``gt``/``lt``), and all values of the instance together by :meth:`check` (rules between
    parameters), when the component is built or a value is assigned, at flatten and for
    ``Simulation.run(params=...)`` overrides. Override :meth:`check` rather than the constructor for such rules.
    """

    experiment: ClassVar[Any] = None

    def __init_subclass__(cls, **kwargs: Any) -> None:
        """Append the *Parameters*, *Connectors* and *Variables* tables built from the class's declarations to its
        docstring (:func:`flexlib.core.docs.document`)."""
        super().__init_subclass__(**kwargs)
        document(cls, *_class_members(cls))

    # -- over-determined connectors (Modelica Connections.branch/root/potentialRoot/rooted/isRoot) ------
    def branch(self, a: Connector, b: Connector) -> None:
        """Declare that this component's equations relate the over-determined records of ``a`` and ``b``
        (e.g. a joint computes the orientation of frame_b from frame_a, or the reverse: see :meth:`rooted`)."""
        self.__dict__.setdefault("_od_branches", []).append((a, b))

    def definite_root(self, conn: Connector) -> None:
        """Declare ``conn``'s over-determined record a definite root (this component computes it, e.g. World)."""
        self.__dict__.setdefault("_od_roots", []).append(conn)

    def potential_root(self, conn: Connector, priority: int = 0) -> None:
        """Declare that this component can compute ``conn``'s record from states if no definite root
        reaches it (a free body); lower ``priority`` is chosen first."""
        self.__dict__.setdefault("_od_potential_roots", []).append((conn, priority))

    def rooted(self, conn: Connector) -> bool:
        """For a :meth:`branch` ``(a, b)`` of this component: True if ``conn`` is on the side nearer the root,
        so the equations compute the other side from it. Valid inside :meth:`equations`."""
        depth = self.__dict__.get("_od_depth")
        if depth is None:
            raise ModelError(f"{self.path}: rooted() is only available while the model is flattened")
        for a, b in self.__dict__.get("_od_branches", []):
            if conn is a or conn is b:
                other = b if conn is a else a
                return depth[id(conn)] < depth[id(other)]
        raise ModelError(f"{self.path}: rooted({conn.path}): {conn.path} is not in a branch() of this component")

    def is_root(self, conn: Connector) -> bool:
        """True if ``conn`` was chosen as the root of its orientation tree. Valid inside :meth:`equations`."""
        roots = self.__dict__.get("_od_selected_roots")
        if roots is None:
            raise ModelError(f"{self.path}: is_root() is only available while the model is flattened")
        return id(conn) in roots

    def structure_key(self) -> Any:
        """Extra plain data that decides this component's equations, for the disk cache key.

        The key already covers the class's code, declarations, connections and plain-data attributes.
        Override this when the equations depend on something the key cannot see, typically the *contents*
        of a file named by an attribute (``modal_file="boom.h5"``: return a hash of the file's bytes, or of
        the data read from it), so that changing the file does not reuse a stale compiled model. flexlib
        never guesses files from strings. Return numbers, strings, bytes, arrays, tuples, lists or dicts of
        these. Default: nothing.

        Examples
        --------
        >>> def structure_key(self):                                  # doctest: +SKIP
        ...     return hashlib.sha256(Path(self.modal_file).read_bytes()).hexdigest()
        """
        return ()

    def advise(self) -> None:
        """Hook called once per build of a model containing this component (also when the compiled model comes from
        the disk cache), after its connections are final: warn (never raise) about a structure that is valid but
        likely not what is meant — a flexible body whose modal basis is clamped at a node that sits on a free
        hinge. Name the component, what was found and the better choice. Default: nothing.
        """

    def check_run(self, result: Any) -> dict[str, Any] | None:
        """Hook called after each run of a model containing this component, with its result: warn (never raise)
        when the run left the range the component's equations hold for (a modal body's small deformation), and
        return a summary of plain numbers for ``result.stats["validity"][path]``, or None. Default: nothing."""
        return None

    def on_structure(self) -> None:
        """Called when the model structure is known, before equations are collected.

        A component may add declarations here that depend on :meth:`is_root` / :meth:`rooted`
        (a free body adds its orientation states). Default: nothing.
        """

    def initial_equations(self) -> list[Equation]:
        """Equations that hold at the start time only (Modelica ``initial equation``).

        They replace fixed start values where those cannot express the condition, e.g. the initial
        orientation of a free body (3 equations on a 4-entry quaternion). Each counts as one initial
        condition. Default: none.
        """
        return []

    def equations(self) -> list[Equation]:
        """The component's own equations (connections are added by the compiler)."""
        return []

    def connect(self, *items: Any) -> None:
        """Connect two or more connectors (or a signal output to inputs).

        Connectors must be of the same type. Potentials become equal and flows sum
        to zero over the connection set (Modelica semantics); signals become equal.
        """
        if len(items) < 2:
            raise ConnectError(f"{self.path or 'model'}: connect() needs at least two connectors")
        resolved = [self._resolve(item) for item in items]
        seen: dict[int, Any] = {}
        for item in resolved:
            key = id(item[1])
            if key in seen:
                raise ConnectError(f"{self.path or 'model'}: connect() got {self._show(item)} twice; "
                                   "a connector cannot be connected to itself")
            seen[key] = item
        first = resolved[0]
        for other in resolved[1:]:
            if first[0] == "connector" and other[0] == "connector":
                a, b = first[1], other[1]
                if a.signature() != b.signature():
                    raise ConnectError(
                        f"{self.path or 'model'}: cannot connect {a.path} {a.describe()} "
                        f"with {b.path} {b.describe()}: incompatible connector types")
            elif first[0] == "signal" and other[0] == "signal":
                self._check_signal(first[1], other[1])
            else:
                raise ConnectError(
                    f"{self.path or 'model'}: cannot connect {self._show(first)} with {self._show(other)}: "
                    "a signal can only be connected to a signal")
        for other in resolved[1:]:
            self._connections.append((first, other))

    def _show(self, item: tuple) -> str:
        if item[0] == "connector":
            return f"{item[1].path} {item[1].describe()}"
        info: SymInfo = item[1]
        return f"signal {info.node._label(info.name)}"

    def _resolve(self, item: Any) -> tuple:
        if isinstance(item, Connector):
            self._check_scope(item, item.path)
            return ("connector", item)
        if isinstance(item, Component):
            raise ConnectError(
                f"{self.path or 'model'}: connect() got component {item.path}; pass one of its connectors")
        if isinstance(item, ca.SX) and item.is_valid_input() and item.nnz() >= 1:
            info = lookup(item.nz[0])
            if info is not None and info.kind == "variable":
                decl = info.node._decls[info.name]
                if decl.kind in (Kind.input, Kind.output) and item.nnz() == decl.size:
                    self._check_scope(info.node, info.node._label(info.name))
                    return ("signal", info)
        raise ConnectError(f"{self.path or 'model'}: connect() got {item!r}: not a connector or a signal input/output")

    def _check_scope(self, node: Node, label: str) -> None:
        n: Node | None = node
        while n is not None and n is not self:
            n = n._parent
        if n is None:
            top = node.root
            if top is self.root:
                why = f"it is outside {self.path}; connect it in the model that contains both"
            else:
                why = (f"it belongs to a {type(top).__name__} that is not part of this model; assign the component "
                       "to an attribute of this model first (self.name = ...; an attribute whose name starts with "
                       "'_' is a plain attribute, not a sub-component)")
            raise ConnectError(f"{self.path or 'model'}: cannot connect {label}: it is not inside this model: {why}")

    def _check_signal(self, a: SymInfo, b: SymInfo) -> None:
        da, db = a.node._decls[a.name], b.node._decls[b.name]
        la, lb = a.node._label(a.name), b.node._label(b.name)
        if da.shape != db.shape:
            raise ConnectError(f"cannot connect signal {la} {da.shape} with {lb} {db.shape}: shapes differ")

        def outward(info: SymInfo) -> bool:  # an outside connector of this model seen from inside
            return info.node is self

        def source(info: SymInfo, decl: Declaration) -> bool:
            return (decl.kind is Kind.output) != outward(info)

        if source(a, da) and source(b, db):
            raise ConnectError(f"cannot connect signal {la} with {lb}: both are sources (outputs)")


Model = Component
"""A model is a component; the alias reads better for complete systems."""
