"""The ``python`` code blocks of a Markdown document, for the tests that run a document's examples as written."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def python_blocks(document: str) -> list[str]:
    """The ```` ```python ```` blocks of ``document`` (a path relative to the repository root), in order, dedented
    (a block indented under a list item runs as written)."""
    text = (ROOT / document).read_text()
    return [textwrap.dedent(b) for b in re.findall(r"```python\n(.*?)```", text, flags=re.S)]


def run_blocks(document: str, namespace: dict | None = None) -> dict:
    """Execute the python blocks of ``document`` in order in one namespace (as a reader pasting them into one
    session would); return the namespace. A failing block's traceback names the document."""
    namespace = {} if namespace is None else namespace
    for block in python_blocks(document):
        exec(compile(block, document, "exec"), namespace)
    return namespace
