"""Generated docstring tables: a component's *Parameters*, *Connectors* and *Variables* from its declarations.

A component's author writes the summary, the equations, notes and references; the declarations already say what
each parameter, variable and connector is (``doc=``, ``unit=``, bounds, shape, default). :func:`document` (called by
``Component.__init_subclass__``) appends one numpydoc entry per declaration to the class docstring::

    Parameters
    ----------
    Ti : float, default 0.5
        Time constant of the integrator [s], > 0.

An entry the author wrote by hand (a richer description, a constructor option such as ``use_support``, a connector
made in the constructor) is kept as written and not generated again; a constructor option, a connector or a
variable documented by hand in a base class (``PartialOneFlangeAndSupport``) is carried into the subclass's
table. A declaration without ``doc=`` gets no entry: it is documented by hand or not at all (the docs lint then
names it).
"""

from __future__ import annotations

import inspect
import re
import weakref
from typing import Any

import numpy as np

from flexlib.core.variables import Declaration, Kind, Parameter

__all__ = ["SECTIONS", "document", "hand_doc", "parse_sections"]

#: The generated sections, in the order the house style puts them.
SECTIONS = ("Parameters", "Connectors", "Variables")
#: Rank of a section title in a docstring: generated sections go before the first section of a higher rank.
_RANK = {"Parameters": 0, "Other Parameters": 0, "Connectors": 1, "Variables": 2, "Attributes": 3}
_LATE = 10  # Notes, References, Examples, See Also, ...

#: Each documented class's docstring as its author wrote it (the generated tables are not in it).
_HAND: weakref.WeakKeyDictionary[type, str] = weakref.WeakKeyDictionary()


def hand_doc(cls: type) -> str | None:
    """The docstring of ``cls`` as written in its source, without the generated entries (None if it has none)."""
    return _HAND.get(cls, cls.__dict__.get("__doc__"))


def parse_sections(doc: str) -> tuple[list[str], list[tuple[str, list[str]]]]:
    """``(preamble lines, [(title, body lines)])`` of a cleaned (``inspect.cleandoc``) numpydoc docstring."""
    lines = doc.splitlines()
    heads = [i for i in range(len(lines) - 1)
             if lines[i].strip() and not lines[i].startswith(" ") and re.fullmatch(r"-{3,}", lines[i + 1].strip())
             and len(lines[i + 1].strip()) >= len(lines[i].strip()) - 1]
    if not heads:
        return lines, []
    sections = []
    for k, i in enumerate(heads):
        end = heads[k + 1] if k + 1 < len(heads) else len(lines)
        sections.append((lines[i].strip(), lines[i + 2:end]))
    return lines[:heads[0]], sections


def _entries(body: list[str]) -> dict[str, list[str]]:
    """``{name: entry lines}`` of a section body (``a, b : type`` entries are listed under each name)."""
    out: dict[str, list[str]] = {}
    current: list[str] = []
    for line in body:
        if line and not line.startswith(" "):
            current = [line]
            for name in line.split(":")[0].split(","):
                out[name.strip()] = current
        elif current and line.strip():
            current.append(line)
    return out


def _number(x: Any) -> str:
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0:
        return f"{float(arr):g}"
    return np.array2string(arr, separator=", ", formatter={"float_kind": lambda v: f"{v:g}"}, threshold=12)


def _sentence(text: str) -> str:
    text = text.strip()
    return text if not text or text.endswith((".", "!", "?")) else text + "."


def _parameter(name: str, decl: Parameter) -> list[str]:
    kind = "float" if not decl.shape else f"array of shape {decl.shape}"
    head = f"{name} : {kind}" + ("" if decl.default is None else f", default {_number(decl.default)}")
    rules = decl.rules()
    text = f"{decl.doc.strip().rstrip('.')} [{decl.unit}]" + (f", {rules}" if rules else "")
    return [head, "    " + _sentence(text)]


def _variable(name: str, decl: Declaration) -> list[str]:
    shape = f", shape {decl.shape}" if decl.shape else ""
    return [f"{name} : {decl.unit}{shape}", "    " + _sentence(decl.doc)]


def _signal(name: str, decl: Declaration) -> list[str]:
    shape = f", shape {decl.shape}" if decl.shape else ""
    return [f"{name} : {decl.kind.value.capitalize()} [{decl.unit}]{shape}", "    " + _sentence(decl.doc)]


def _connector(name: str, template: Any) -> list[str]:
    return [f"{name} : {type(template).__name__}", "    " + _sentence(template.doc)]


def _inherited(cls: type, title: str, names: Any = None) -> dict[str, list[str]]:
    """Hand entries of section ``title`` in the documented base classes of ``cls`` (nearest first), restricted to
    ``names`` if given."""
    out: dict[str, list[str]] = {}
    for base in cls.__mro__[1:]:
        doc = _HAND.get(base)
        if not doc:
            continue
        for t, body in parse_sections(inspect.cleandoc(doc))[1]:
            if t == title:
                for n, lines in _entries(body).items():
                    if (names is None or n in names) and n not in out:
                        out[n] = lines
    return out


def _generated(cls: type, decls: dict[str, Declaration], templates: list[tuple[str, Any]]) -> dict[str, dict]:
    """``{section: {name: entry lines}}`` that the declarations of ``cls`` and its documented bases give."""
    try:
        options = [n for n, p in inspect.signature(cls.__init__).parameters.items()
                   if n != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    except (TypeError, ValueError):  # pragma: no cover - a C-level __init__
        options = []
    from flexlib.core.component import Connector

    hand = {"Parameters": _inherited(cls, "Parameters", set(options)), "Connectors": _inherited(cls, "Connectors"),
            "Variables": _inherited(cls, "Variables")}
    params: dict[str, list[str]] = {}
    connectors: dict[str, list[str]] = {}
    variables: dict[str, list[str]] = {}
    for n, t in templates:  # declaration order; an entry written by hand in a base says more than the declaration
        if isinstance(t, Connector) and t.doc:
            connectors[n] = hand["Connectors"].get(n) or _connector(n, t)
    for n, d in decls.items():
        if d.doc and isinstance(d, Parameter):
            params[n] = hand["Parameters"].get(n) or _parameter(n, d)
        elif d.doc and d.kind in (Kind.input, Kind.output):
            connectors[n] = hand["Connectors"].get(n) or _signal(n, d)
        elif d.doc and d.kind is Kind.variable:
            variables[n] = hand["Variables"].get(n) or _variable(n, d)
    for title, found in (("Parameters", params), ("Connectors", connectors), ("Variables", variables)):
        for n, lines in hand[title].items():  # constructor options, connectors made in the constructor
            found.setdefault(n, lines)
    return {"Parameters": params, "Connectors": connectors, "Variables": variables}


def document(cls: type, decls: dict[str, Declaration], templates: list[tuple[str, Any]]) -> None:
    """Append the generated *Parameters*, *Connectors* and *Variables* entries to ``cls.__doc__``.

    Parameters
    ----------
    cls : type
        A component class, just defined.
    decls : dict
        ``{name: declaration}`` of ``cls`` and its bases.
    templates : list
        ``[(name, template)]`` of the sub-components and connectors declared at class level.

    Notes
    -----
    A class without a docstring of its own is left alone. Entries already in the docstring (by name) are kept as
    written; the others go at the end of their section, which is created before *Notes*/*References* if absent.
    """
    own = cls.__dict__.get("__doc__")
    if not isinstance(own, str) or not own.strip():
        return
    _HAND[cls] = own
    preamble, sections = parse_sections(inspect.cleandoc(own))
    present = {t: set(_entries(body)) for t, body in sections}
    added = False
    for title, entries in _generated(cls, decls, templates).items():
        new: list[str] = []
        seen: set[int] = set()
        for name, lines in entries.items():
            if name not in present.get(title, ()) and id(lines) not in seen:  # "a, b : float" once
                seen.add(id(lines))
                new += lines
        if not new:
            continue
        added = True
        for k, (t, body) in enumerate(sections):
            if t == title:
                while body and not body[-1].strip():
                    body.pop()
                sections[k] = (t, [*body, *new, ""])
                break
        else:
            rank = _RANK[title]
            at = next((k for k, (t, _) in enumerate(sections) if _RANK.get(t, _LATE) > rank), len(sections))
            sections.insert(at, (title, [*new, ""]))
    if not added:
        return
    while preamble and not preamble[-1].strip():
        preamble.pop()
    out = [*preamble, ""]
    for title, body in sections:
        out += [title, "-" * len(title), *body]
    while out and not out[-1].strip():
        out.pop()
    cls.__doc__ = "\n".join(out) + "\n"
