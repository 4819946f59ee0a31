"""Docs lint: every public component documents its parameters with their units.

House style (``docs/house_style.md``, "Docstrings"): numpydoc sections; each
``Parameter`` is listed under *Parameters* with its SI unit in brackets, and the unit equals
the declaration's ``unit=`` (the descriptor is the source of truth). Every public component
names its reference under *References* (the MSL class for the MSL-shaped libraries;
Simscape / Hopsan / textbook sections for hydraulics).
"""

from __future__ import annotations

import importlib
import inspect
import re

import pytest

import flexlib as fl
from flexlib.core.variables import Parameter

PACKAGES = [
    "flexlib.components.control",
    "flexlib.components.mechanics.rotational",
    "flexlib.components.mechanics.translational",
    "flexlib.components.mechanics.multibody",
    "flexlib.components.hydraulics",
]
#: Libraries in Modelica Standard Library shape: their components cite the MSL class.
MSL_SHAPED = ("flexlib.components.control", "flexlib.components.mechanics")


def public_classes() -> list[type]:
    out = []
    for name in PACKAGES:
        module = importlib.import_module(name)
        for attr in module.__all__:
            obj = getattr(module, attr)
            if inspect.isclass(obj) and issubclass(obj, fl.Component):
                out.append(obj)
    return out


def parameters(cls: type) -> dict[str, Parameter]:
    found: dict[str, Parameter] = {}
    for klass in reversed(cls.__mro__):
        for name, value in vars(klass).items():
            if isinstance(value, Parameter):
                found[name] = value
    return found


def section(doc: str, title: str) -> dict[str, str]:
    """``{name: description}`` of a numpydoc section (``a, b : type`` entries are split)."""
    lines = inspect.cleandoc(doc).splitlines()
    try:
        start = next(i for i, line in enumerate(lines[:-1])
                     if line.strip() == title and set(lines[i + 1].strip()) == {"-"})
    except StopIteration:
        return {}
    entries: dict[str, str] = {}
    current: list[str] = []
    for line in lines[start + 2:]:
        if line and not line.startswith(" "):
            if re.fullmatch(r"-+", line.strip()):  # next section title was the previous line
                break
            names = line.split(":")[0]
            current = [n.strip() for n in names.split(",")]
            for n in current:
                entries[n] = ""
        elif line.strip():
            for n in current:
                entries[n] += " " + line.strip()
        elif not current:
            break
    return entries


CLASSES = public_classes()


def test_all_packages_export_components():
    """The lint sees every component module (guards against an empty ``__all__``)."""
    assert len(CLASSES) >= 30


def unit_problems(cls: type) -> list[str]:
    """Parameters missing from the docstring or documented with another unit."""
    documented = section(cls.__doc__ or "", "Parameters")
    problems = []
    for name, decl in parameters(cls).items():
        if name not in documented:
            problems.append(f"{cls.__name__}: parameter {name!r} missing from the docstring")
        elif f"[{decl.unit}]" not in documented[name]:
            problems.append(f"{cls.__name__}.{name}: docstring must give [{decl.unit}], got {documented[name]!r}")
    return problems


def test_lint_detects_wrong_and_missing_units():
    """The lint itself: a wrong unit and an undocumented parameter are both reported."""

    class Bad(fl.Component):
        """Bad docstring.

        Parameters
        ----------
        k, c : float
            Stiffness [m].
        """

        k = Parameter(1.0, unit="N/m")
        c = Parameter(1.0, unit="m")
        d = Parameter(1.0, unit="N.s/m")

    assert len(unit_problems(Bad)) == 2
    assert "Bad.k" in unit_problems(Bad)[0]
    assert "'d'" in unit_problems(Bad)[1]


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: f"{c.__module__.rsplit('.', 2)[-2]}.{c.__name__}")
def test_parameters_documented_with_units(cls):
    """Each Parameter appears under *Parameters* with ``[unit]`` equal to its ``unit=``."""
    assert unit_problems(cls) == []


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: f"{c.__module__.rsplit('.', 2)[-2]}.{c.__name__}")
def test_structure_documented(cls):
    """Structural options (``use_support``) are documented; the MSL reference is named."""
    doc = cls.__doc__ or ""
    documented = section(doc, "Parameters")
    for name in inspect.signature(cls.__init__).parameters:
        if name.startswith("use_"):
            assert name in documented, f"{cls.__name__}: structural option {name!r} is not documented"
    references = inspect.cleandoc(doc).split("References\n----------")
    assert len(references) == 2 and references[1].strip(), f"{cls.__name__}: no reference"
    if cls.__module__.startswith(MSL_SHAPED):
        assert "Modelica" in references[1], f"{cls.__name__}: no MSL reference"
