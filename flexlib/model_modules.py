"""The modules that register models: the built-in ones, found by reading :data:`BUILTIN_PACKAGE`, and a user's
own, named in ``$FLEXLIB_MODELS`` or by ``flexlib --models``.

:mod:`flexlib.registry` imports them on its first lookup; an import failure is named by the module, the error and
the file and line it happened at.
"""

from __future__ import annotations

import importlib
import os
import sys
import traceback
from pathlib import Path

__all__ = ["BUILTIN_PACKAGE", "MODULES_ENV", "builtin_modules", "import_failure", "import_user_module",
           "module_hint"]

#: Package searched for built-in registrations: each of its modules (subpackages included) whose source calls
#: ``register_model(`` is imported on the first lookup, so a new model (``models/pump_truck/``) only registers
#: itself beside its definition.
BUILTIN_PACKAGE = "flexlib.models"

#: Environment variable: further modules (comma-separated) imported before a lookup, so that a user's own
#: models and scenarios appear in ``flexlib list`` and can be run.
MODULES_ENV = "FLEXLIB_MODELS"


def builtin_modules() -> list[str]:
    """Modules of :data:`BUILTIN_PACKAGE` whose source calls ``register_model(`` (sorted), found by reading the
    files, so that modules without registrations (examples, scripts) are not imported."""
    package = importlib.import_module(BUILTIN_PACKAGE)
    found = []
    for root in map(Path, package.__path__):
        for path in sorted(root.rglob("*.py")):
            rel = path.relative_to(root).with_suffix("")
            if any(part.startswith(".") for part in rel.parts):
                continue
            try:
                if "register_model(" not in path.read_text(encoding="utf-8"):
                    continue
            except (OSError, UnicodeDecodeError):
                continue
            parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
            found.append(".".join((BUILTIN_PACKAGE, *parts)))
    return sorted(set(found))


def import_failure(err: BaseException) -> str:
    """``Type: message (file:line)`` of an import failure: for a SyntaxError the offending line of the module,
    otherwise the innermost frame of the traceback outside the import machinery."""
    text = f"{type(err).__name__}: {err.msg if isinstance(err, SyntaxError) else err}"
    if isinstance(err, SyntaxError) and err.filename:
        return f"{text} ({err.filename}:{err.lineno})"
    here = os.path.abspath(__file__)  # this module and the registry's lookup that calls it, then importlib
    machinery = (here, os.path.join(os.path.dirname(here), "registry.py"), os.path.abspath(importlib.__file__))
    frames = [f for f in traceback.extract_tb(err.__traceback__)
              if not f.filename.startswith("<frozen") and os.path.abspath(f.filename) not in machinery]
    return f"{text} ({frames[-1].filename}:{frames[-1].lineno})" if frames else text


def module_hint(module: str) -> str:
    """A hint for a model module given as a file (``my_models.py``, ``./my_models``): what to give instead; ``""``
    for a module name."""
    if not (module.endswith(".py") or "/" in module or os.sep in module):
        return ""
    name = Path(module).name.removesuffix(".py")
    return (f" (give the module's name, {name!r}, not its file: run from its directory or put that directory on "
            "PYTHONPATH)")


def import_user_module(module: str) -> None:
    """Import a user's model module (``$FLEXLIB_MODELS``, ``flexlib --models``), also from the working directory;
    its errors propagate (the callers name the module and the source of the name)."""
    if "" not in sys.path:
        sys.path.append("")
    importlib.import_module(module)
