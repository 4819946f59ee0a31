"""``docs/msl_compatibility.md`` keeps up with the library: every public component has a row, and every row is one.

A public component is a class in the ``__all__`` of a domain subpackage that subclasses :class:`flexlib.Component`.
Each domain has its own section of the page, the ``## `` heading that names the subpackage in backticks
(``## Rotational: `flexlib.components.mechanics.rotational` ``); a component's row is a table row of that section
whose first cell is the class name in backticks (``| `Inertia` | ...``), so a rotational ``Fixed`` is not
covered by the multibody ``Fixed``. No tolerance: the names must match exactly.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

import flexlib as fl

PAGE = Path(__file__).resolve().parents[1] / "docs" / "msl_compatibility.md"

DOMAINS = [
    "flexlib.components.mechanics.multibody",
    "flexlib.components.mechanics.flexible",
    "flexlib.components.mechanics.rotational",
    "flexlib.components.mechanics.translational",
    "flexlib.components.hydraulics",
    "flexlib.components.control",
]

ROW = re.compile(r"^\|\s*`(\w+)`\s*\|")


def public_components(module_name: str) -> list[str]:
    """The names in ``module_name.__all__`` that are :class:`flexlib.Component` subclasses.

    Parameters
    ----------
    module_name : str
        Dotted name of a domain subpackage.

    Returns
    -------
    list of str
        The class names, in the order of ``__all__``.
    """
    module = importlib.import_module(module_name)
    members = ((name, getattr(module, name)) for name in module.__all__)
    return [name for name, obj in members if isinstance(obj, type) and issubclass(obj, fl.Component)]


def section(module_name: str) -> str:
    """The text of the page's section on ``module_name``: from its ``## `` heading to the next one.

    Parameters
    ----------
    module_name : str
        Dotted name of a domain subpackage, named in backticks in the section's heading.

    Returns
    -------
    str
        The section's lines after the heading.
    """
    lines = PAGE.read_text(encoding="utf-8").splitlines()
    starts = [i for i, line in enumerate(lines) if line.startswith("## ") and f"`{module_name}`" in line]
    assert len(starts) == 1, f"docs/msl_compatibility.md needs one '## ' heading naming `{module_name}`"
    body = []
    for line in lines[starts[0] + 1 :]:
        if line.startswith("## "):
            break
        body.append(line)
    return "\n".join(body)


def rows(module_name: str) -> list[str]:
    """The class names in the first cells of the table rows of ``module_name``'s section.

    Parameters
    ----------
    module_name : str
        Dotted name of a domain subpackage.

    Returns
    -------
    list of str
        The names, in the order of the rows.
    """
    return [m.group(1) for line in section(module_name).splitlines() if (m := ROW.match(line))]


@pytest.mark.parametrize("module_name", DOMAINS)
def test_every_public_component_has_a_row(module_name: str) -> None:
    names = public_components(module_name)
    assert names, f"{module_name} exports no component: the domain list of this test is stale"
    listed = set(rows(module_name))
    missing = [name for name in names if name not in listed]
    assert not missing, f"docs/msl_compatibility.md, section `{module_name}`: no row for {missing}"


@pytest.mark.parametrize("module_name", DOMAINS)
def test_every_row_is_a_public_component(module_name: str) -> None:
    names = set(public_components(module_name))
    listed = rows(module_name)
    stale = [name for name in listed if name not in names]
    assert not stale, f"docs/msl_compatibility.md, section `{module_name}`: rows for {stale}, not public components"
    twice = sorted({name for name in listed if listed.count(name) > 1})
    assert not twice, f"docs/msl_compatibility.md, section `{module_name}`: more than one row for {twice}"
