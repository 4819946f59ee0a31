"""Print the architecture figures issue 27 asks for: files over 600 lines, functions over 80 lines and private names
imported across modules, in ``flexlib/``, ``components/`` and ``models/``.

Run: ``python .ci/architecture.py`` (repository root). Nothing is asserted; ``duplicates`` gives the duplicate pairs.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOTS = ("flexlib", "components", "models")
MAX_FILE, MAX_FUNCTION = 600, 80


def main() -> None:
    files, functions, private = [], [], []
    for root in ROOTS:
        for path in sorted(Path(root).rglob("*.py")):
            text = path.read_text(encoding="utf-8")
            if (n := len(text.splitlines())) > MAX_FILE:
                files.append((n, str(path)))
            for node in ast.walk(ast.parse(text)):
                if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    if (n := node.end_lineno - node.lineno + 1) > MAX_FUNCTION:
                        functions.append((n, f"{path}:{node.lineno} {node.name}"))
                elif isinstance(node, ast.ImportFrom):
                    for alias in node.names:
                        if alias.name.startswith("_") and not alias.name.startswith("__"):
                            private.append(f"{path}:{node.lineno} from {'.' * node.level}{node.module} "
                                           f"import {alias.name}")
    print(f"files over {MAX_FILE} lines: {len(files)}")
    for n, where in sorted(files, reverse=True):
        print(f"  {n:5d} {where}")
    print(f"functions over {MAX_FUNCTION} lines: {len(functions)}")
    for n, where in sorted(functions, reverse=True):
        print(f"  {n:5d} {where}")
    print(f"private names imported across modules: {len(private)}")
    for where in private:
        print(f"  {where}")


if __name__ == "__main__":
    main()
