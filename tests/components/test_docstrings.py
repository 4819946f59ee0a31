"""Docs lint: every public component documents its parameters with their units.

House style (``docs/house_style.md``, "Docstrings"): numpydoc sections; each
``Parameter`` is listed under *Parameters* with its SI unit in brackets, and the unit equals
the declaration's ``unit=`` (the descriptor is the source of truth). The *Parameters*,
*Connectors* and *Variables* entries of a declaration with ``doc=`` are generated from it
(``flexlib.core.docs``); the author writes an entry only where it says more, and such hand text
must not merely restate the declaration. Every public component
names its reference under *References* (the MSL class for the MSL-shaped libraries;
Simscape / Hopsan / textbook sections for hydraulics).
"""

from __future__ import annotations

import importlib
import inspect
import re

import pytest

import flexlib as fl
from flexlib.core.docs import hand_doc
from flexlib.core.variables import Declaration, Kind, Parameter

PACKAGES = [
    "flexlib.components.control",
    "flexlib.components.mechanics.rotational",
    "flexlib.components.mechanics.translational",
    "flexlib.components.mechanics.multibody",
    "flexlib.components.hydraulics",
]
#: Libraries whose hand-written entries say more than the declarations (the generated tables give the rest).
GENERATED_TABLES = (
    "flexlib.components.control",
    "flexlib.components.mechanics.rotational",
    "flexlib.components.mechanics.translational",
)
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


def _plain(text: str) -> str:
    """Words of a description without units in brackets, markup and punctuation."""
    text = re.sub(r"\[[^\]]*\]", " ", text).replace("`", "")
    return " ".join(re.sub(r"[^a-z0-9_*/+\-=<>() ]", " ", text.lower()).split())


def restated(cls: type) -> list[str]:
    """Hand-written entries whose description is the declaration's ``doc=`` (plus its unit and bounds) again."""
    doc = hand_doc(cls) or ""
    decls = {}
    for klass in reversed(cls.__mro__):
        decls.update({n: v for n, v in vars(klass).items() if isinstance(v, Declaration)})
    out = []
    for title in ("Parameters", "Variables", "Connectors"):
        for name, text in section(doc, title).items():
            decl = decls.get(name)
            if decl is None or not decl.doc or (title == "Variables") != (decl.kind is Kind.variable):
                continue
            rules = decl.rules() if isinstance(decl, Parameter) else ""
            if _plain(text) in {_plain(decl.doc), _plain(f"{decl.doc} {rules}"), _plain(f"{decl.doc}, {rules}")}:
                out.append(f"{cls.__name__}: {title} entry {name!r} restates its declaration's doc=")
    return out


def test_lint_detects_restated_entries():
    """The lint itself: an entry that repeats ``doc=`` and the unit is reported; a richer one is not."""
    hand = ("Spring.\n\nParameters\n----------\nc : float\n    Spring constant [N/m], >= 0.\n"
            "s0 : float\n    Unstretched length [m]; the spring pushes below it.\n")
    spring = type("Spring", (fl.Component,), {
        "__doc__": hand,
        "c": Parameter(1.0, unit="N/m", min=0.0, doc="Spring constant"),
        "s0": Parameter(0.0, unit="m", doc="Unstretched length"),
    })
    assert restated(spring) == ["Spring: Parameters entry 'c' restates its declaration's doc="]
    assert "s0 : float, default 0" not in (spring.__doc__ or "")  # the hand entry stands for the generated one


@pytest.mark.parametrize("cls", [c for c in CLASSES if c.__module__.startswith(GENERATED_TABLES)],
                         ids=lambda c: f"{c.__module__.rsplit('.', 2)[-2]}.{c.__name__}")
def test_hand_entries_say_more_than_declarations(cls):
    """Hand-written *Parameters/Variables/Connectors* entries add to the declaration (the table gives the rest)."""
    assert restated(cls) == []
