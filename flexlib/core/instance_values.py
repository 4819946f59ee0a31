"""Parameter values, start values and state preferences of a component instance, and the tree reader.

:class:`InstanceValues` is the part of :class:`~flexlib.core.component.Node` that holds what an instance is given
(``Mass(m=2, init={"s": 0.1}, state_select={"v": "prefer"})`` and later assignments), checks it on every path
(each value against its declaration, all values of the instance by :meth:`~InstanceValues.check`) and reads it back:
one instance at a time (:meth:`~InstanceValues.parameter_value`, :meth:`~InstanceValues.start_of`) or for a whole
tree by hierarchical name (:meth:`~InstanceValues.values`, the values the compiled model is run with).
"""

from __future__ import annotations

import difflib
from typing import Any

import numpy as np

from flexlib.core.values import numeric_array
from flexlib.core.variables import STATE_SELECT, Parameter, StateSelect, Variable
from flexlib.errors import ModelError, ParameterError

__all__ = ["DEFAULT_START", "InstanceValues"]

#: ``fixed`` value of a start that is an initial condition only where the initial system needs one.
DEFAULT_START = "default"


class InstanceValues:
    """Values given to one instance: parameter values, start values and state preferences.

    A mix-in of :class:`~flexlib.core.component.Node`, which provides the declarations (``_decls``), the stores
    (``_values``, ``_starts``, ``_state_select``), the naming (``path``, ``_label``) and the tree (``walk``).
    """

    def _assign(self, name: str, value: Any) -> None:
        decl = self._decls.get(name)
        if not isinstance(decl, Parameter):
            raise ParameterError(self._unknown(name, "parameter"))
        checked = decl.check(self.param_label(name), value)
        if self.__dict__.get("_constructed"):  # a later assignment: the cross-parameter rules must still hold
            values = self.parameter_values()
            values[name] = checked
            self.validate(values)
        self._values[name] = checked

    # -- parameter validation (one hook for construction, flatten and run(params=...)) -------------
    @property
    def where(self) -> str:
        """How messages name this instance: its path in the model, or its class name while unattached."""
        return self.path or type(self).__name__

    def param_label(self, name: str) -> str:
        """How messages name parameter ``name`` of this instance (``"boom.cyl2.Q_nom"``, or
        ``"DirectionalValve43: Q_nom"`` while unattached)."""
        return self._label(name) if self._parent is not None else f"{type(self).__name__}: {name}"

    def parameter_values(self) -> dict[str, np.ndarray]:
        """``{name: value}`` of the parameters of this instance that have a value (given or default)."""
        out = {}
        for name, decl in self._decls.items():
            if isinstance(decl, Parameter):
                value = self.parameter_value(name)
                if value is not None:
                    out[name] = value
        return out

    def check(self, values: dict[str, np.ndarray]) -> None:
        """Cross-parameter rules of this component (limits ordered, rod thinner than bore, ...).

        Override to raise :class:`~flexlib.ParameterError` when ``values`` (``{name: float array}`` of
        every parameter of this instance, each already within its declared bounds) break a rule. While
        the instance is being built a parameter without a value yet is absent (use ``values.get``); at
        flatten and at run time all are present.
        Read the values from ``values`` only, not from the instance: the same hook checks the
        constructor's values, the values at flatten and the values of a ``run(params=...)`` override.
        Name parameters with :meth:`param_label`; a message that does not name the instance gets its
        path in front. Call ``super().check(values)`` when a base class has rules too. Default: none.
        """

    def validate(self, values: dict[str, np.ndarray] | None = None) -> None:
        """Run :meth:`check` on ``values`` (default: the instance's current values), naming this
        instance in any error."""
        if values is None:
            values = self.parameter_values()
        try:
            self.check(values)
        except ParameterError as exc:
            msg = str(exc)
            if self.where not in msg:
                raise ParameterError(f"{self.where}: {msg}") from None
            raise

    def _unknown(self, name: str, what: str) -> str:
        is_param = what == "parameter"
        pool = [n for n, d in self._decls.items() if isinstance(d, Parameter) == is_param]
        where = self.path or ("(model)" if self._connections else "(unnamed)")
        head = f"{type(self).__name__} {where}: unknown {what} {name!r}"
        if not isinstance(name, str):
            return f"{head}: a {what} name is a string (known: {', '.join(sorted(pool)) or 'none'})"
        decl = self._decls.get(name)
        if decl is not None and not is_param:  # a parameter given as a start value / state choice
            path = self.path or "<component path>"
            return (f"{head}: {name} is a parameter [{decl.unit}], not a variable; set its value as "
                    f"{type(self).__name__}({name}=...), or per run with params={{'{path}.{name}': ...}} "
                    f"(variables: {', '.join(sorted(pool)) or 'none'})")
        if decl is not None:  # a variable given as a parameter
            return (f"{head}: {name} is a variable [{decl.unit}]; give its start value with init={{'{name}': ...}} "
                    f"(an initial condition) or guess={{'{name}': ...}} "
                    f"(parameters: {', '.join(sorted(pool)) or 'none'})")
        close = difflib.get_close_matches(name, pool, n=3)
        hint = f"; did you mean {', '.join(close)}?" if close else f"; known: {', '.join(sorted(pool)) or 'none'}"
        return f"{head}{hint}"

    def set_start(self, name: str, value: Any, fixed: bool | str = True) -> None:
        """Set the start value of variable ``name``.

        ``fixed=True``: an initial condition; ``False``: a guess; ``"default"``: an initial condition where the
        initial system needs one and a guess where the equations already determine the variable (a flexible
        body starts undeformed unless a joint locks a mode: no over-specified start then). The default
        conditions are taken in the model's order, each only if it determines an unknown nothing else does.
        """
        decl = self._declaration(name)
        if not isinstance(decl, Variable):
            raise ModelError(self._unknown(name, "variable"))
        if fixed != DEFAULT_START if isinstance(fixed, str) else not isinstance(fixed, (bool, np.bool_, int)):
            raise ModelError(f"{self._label(name)}: fixed must be True, False or {DEFAULT_START!r}, got {fixed!r}")
        label = self.param_label(name)
        wanted = (f"a real number [{decl.unit}]" if not decl.shape else
                  f"an array of real numbers of shape {decl.shape} [{decl.unit}]")
        arr = numeric_array(value, f"{label}: start value", wanted, ModelError)
        if arr.size != decl.size:
            raise ModelError(f"{label}: start value {value!r} has {arr.size} elements, the variable "
                             f"{'is a scalar' if decl.size == 1 else f'has {decl.size} (shape {decl.shape})'}")
        self._starts[name] = (arr.reshape(decl.shape) if decl.shape else arr.reshape(()),
                              DEFAULT_START if fixed == DEFAULT_START else bool(fixed))

    def set_state_select(self, name: str, value: Any) -> None:
        """Override the state preference of variable ``name`` on this instance (Modelica's ``stateSelect``
        modifier): ``"never"``, ``"avoid"``, ``"default"``, ``"prefer"``, ``"always"`` or a
        :class:`~flexlib.StateSelect` member."""
        decl = self._declaration(name)
        if not isinstance(decl, Variable):
            raise ModelError(self._unknown(name, "variable") + " (in state_select)")
        if isinstance(value, StateSelect):
            self._state_select[name] = value
            return
        choice = STATE_SELECT.get(value) if isinstance(value, str) else None
        if choice is None:
            raise ModelError(f"{self._label(name) if self._parent else type(self).__name__ + ': ' + name}: "
                             f"state_select {value!r} is not one of {', '.join(STATE_SELECT)} (or fl.StateSelect)")
        self._state_select[name] = choice

    def state_select_of(self, name: str) -> StateSelect:
        """State preference of variable ``name`` after the instance override (else the declaration's)."""
        sel = self._state_select.get(name)
        return sel if sel is not None else self._declaration(name).state_select

    def parameter_value(self, name: str) -> np.ndarray | None:
        """Current value of parameter ``name`` (None if it has neither a value nor a default)."""
        if name in self._values:
            return self._values[name]
        decl = self._decls[name]
        if decl.default is None:
            return None
        return decl.check(self.param_label(name), decl.default)

    def start_of(self, name: str) -> tuple[np.ndarray, bool | str]:
        """``(start, fixed)`` of variable ``name`` after instance overrides (``fixed`` may be ``"default"``, see
        :meth:`set_start`)."""
        if name in self._starts:
            return self._starts[name]
        decl = self._declaration(name)
        arr = np.asarray(decl.start, dtype=float)  # one value, or one per element (checked by Variable)
        if decl.shape:
            arr = np.broadcast_to(arr.reshape(()) if arr.size == 1 else arr.reshape(decl.shape), decl.shape).copy()
        else:
            arr = arr.reshape(())
        return arr, decl.fixed

    # -- the tree reader --------------------------------------------------------------------------------
    def values(self) -> tuple[dict[str, float], dict[str, tuple[float, bool | str]]]:
        """Parameter values and start values of every scalar of this node and the nodes below it.

        Returns
        -------
        params : dict
            ``{hierarchical name: value}`` of every parameter element that has a value (given or default), array
            elements named ``r[0]``, ``R[1,2]`` in CasADi column-major order.
        starts : dict
            ``{hierarchical name: (start, fixed)}`` of every variable element (``fixed`` may be
            :data:`DEFAULT_START`).
        """
        params: dict[str, float] = {}
        starts: dict[str, tuple[float, bool | str]] = {}
        for node in self.walk():
            for name, decl in node._decls.items():
                if not decl.shape:  # a scalar (the usual case): one label, one float
                    if isinstance(decl, Parameter):
                        value = node.parameter_value(name)
                        if value is not None:
                            params[node._label(name)] = float(value)
                    else:
                        value, fixed = node.start_of(name)
                        starts[node._label(name)] = (float(value), fixed)
                    continue
                labels = decl.element_names(node._label(name))
                if isinstance(decl, Parameter):
                    value = node.parameter_value(name)
                    if value is None:
                        continue
                    flat = np.asarray(value, dtype=float).flatten(order="F")
                    params.update({lab: float(flat[k]) for k, (lab, _) in enumerate(labels)})
                else:
                    value, fixed = node.start_of(name)
                    flat = np.asarray(value, dtype=float).flatten(order="F")
                    starts.update({lab: (float(flat[k]), fixed) for k, (lab, _) in enumerate(labels)})
        return params, starts
