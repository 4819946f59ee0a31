"""Run-time parameter vectors of a compiled model: instance values with overrides, each checked by its declaration.

:class:`ParameterTable` maps the dotted names of a model instance's parameters to the compiled model's parameter
vector (``CompiledModel.param_names``) and checks overrides as the component's constructor would (declared bounds,
the component's cross-parameter rules), naming what a wrong name is instead (a variable, a component, an element of a
scalar).
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from typing import Any

import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.compile.constants import check_assumed
from flexlib.core.component import Component
from flexlib.core.values import numeric_array
from flexlib.core.variables import Input, Parameter
from flexlib.errors import ParameterError

__all__ = ["ParameterTable"]


class ParameterTable:
    """The parameters of ``model`` (an instance) as compiled in ``compiled``."""

    def __init__(self, model: Component, compiled: CompiledModel) -> None:
        self.model, self.compiled = model, compiled
        self.index = {n: k for k, n in enumerate(compiled.param_names)}

    def vector(self, params: Mapping[str, Any], values: Mapping[str, float]) -> np.ndarray:
        """One value per name of ``compiled.param_names``: ``values`` (defaults where missing) with the checked
        overrides ``params`` [SI units]; :class:`~flexlib.errors.ParameterError` for an unknown name or a value its
        declaration refuses."""
        m = self.compiled
        vec = np.array([values.get(n, d) for n, d in zip(m.param_names, m.param_defaults, strict=True)])
        touched: dict[int, tuple[Any, set[str]]] = {}
        for name, value in params.items():
            found = self.find_decl(name)
            if found is None:
                close = difflib.get_close_matches(name, m.param_names, n=3)
                hint = self.not_a_parameter(name) or (f"; did you mean {', '.join(close)}?" if close else "")
                raise ParameterError(f"unknown parameter {name!r} in model {m.name}{hint}")
            node, decl, elem = found
            decl_name = name.rpartition(".")[2].split("[")[0]
            if elem is None:  # the whole declaration (scalar or array)
                flat = np.asarray(decl.check(name, value), dtype=float).flatten(order="F")
                for (label, _), v in zip(decl.element_names(name), flat, strict=True):
                    vec[self.index[label]] = v
            else:  # one element of an array parameter: checked below with the rest of the array
                arr = numeric_array(value, f"{name}: parameter value", f"a real number [{decl.unit}]", ParameterError)
                if arr.ndim:
                    raise ParameterError(f"{name}: parameter value {value!r} is an array; give one element as a real "
                                         f"number [{decl.unit}]")
                vec[self.index[name]] = float(arr)
            touched.setdefault(id(node), (node, set()))[1].add(decl_name)
        self.validate(vec, touched)
        check_assumed(m.assumed, m.param_names, vec, m.name)
        return vec

    def validate(self, vec: np.ndarray, touched: dict[int, tuple[Any, set[str]]]) -> None:
        """Each overridden component's rules (:meth:`~flexlib.Component.validate`) with its values from ``vec``."""
        for node, names in touched.values():
            current: dict[str, np.ndarray] = {}
            for pname, pdecl in node._decls.items():
                if not isinstance(pdecl, Parameter):
                    continue
                labels = [label for label, _ in pdecl.element_names(node._label(pname))]
                if all(label in self.index for label in labels):
                    arr = np.array([vec[self.index[label]] for label in labels])
                    arr = arr.reshape(pdecl.shape, order="F") if pdecl.shape else arr.reshape(())
                else:  # not a run-time parameter of the compiled model: the instance value holds
                    arr = node.parameter_value(pname)
                if pname in names:
                    arr = pdecl.check(node._label(pname), arr)
                current[pname] = arr
            node.validate(current)

    def node(self, path: str) -> Any:
        """The component at the dotted ``path`` below the model (``""``: the model), or None."""
        node = self.model
        for part in path.split(".") if path else []:
            node = node._children.get(part) if part else None  # "", ".k", "a..k": an empty part names nothing
            if node is None:
                return None
        return node

    def not_a_parameter(self, name: str) -> str:
        """What ``name`` (not a run-time parameter) is instead, as a hint for the error: a variable, a component,
        an element of a scalar, a name with a stray ``.``; ``""`` otherwise."""
        parts = name.split(".")
        if not all(parts):  # a stray "." (".k", "a..k", "a.k."): the name without the empty parts, if it is one
            joined = ".".join(part for part in parts if part)
            return (f"; the name has an empty part (a stray '.'): did you mean {joined!r}?"
                    if joined in self.index else "")
        path, _, leaf = name.rpartition(".")
        base = leaf.split("[")[0]
        node = self.node(path)
        if node is None or not base:
            return ""
        if base in node._children:
            inner = [n for n in self.compiled.param_names if n.startswith(f"{name}.")]
            listed = f" such as {', '.join(inner[:3])}" if inner else ""
            return f"; {name!r} is a component, not a parameter: name one of its parameters{listed}"
        decl = node._decls.get(base)
        if decl is None:
            return ""
        full = f"{path}.{base}" if path else base
        if not isinstance(decl, Parameter):
            return (f"; {full!r} is a {type(decl).__name__.lower()}, not a parameter: its start value is set with "
                    f"init={{{base!r}: ...}} on the component (or set_start), not with params")
        if "[" in leaf and [label for label, _ in decl.element_names(full)] == [full]:
            return f"; {full!r} is a scalar parameter: give {full!r} without an index"
        return ""  # an element outside an array: the close matches name its elements

    def find_decl(self, name: str) -> tuple[Any, Parameter, Any] | None:
        if not all(name.split(".")):  # ".k", "a..k", "k.": an empty part names nothing
            return None
        path, _, leaf = name.rpartition(".")
        base = leaf.split("[")[0]
        node = self.node(path)
        if node is None:
            return None
        decl = node._decls.get(base)
        if isinstance(decl, Input) and node is self.model:
            decl = decl.as_parameter()  # a top-level input is a run-time parameter
        if not isinstance(decl, Parameter):
            return None
        elem = None if "[" not in leaf else leaf
        if elem is not None and name not in self.index:
            return None
        return node, decl, elem
