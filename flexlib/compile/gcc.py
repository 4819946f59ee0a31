"""Generated C compiled with gcc into a shared library, in the foreground or in the background.

When C pays, and the gcc level
------------------------------
Generated C is faster than CasADi's SX virtual machine at every size measured, but gcc's time grows quickly with
the source and the optimisation level (the measured table:
``docs/decisions/012-generated-c-gcc-level-and-background-compile.md``; the cost per call and per run:
``docs/casadi_ida.md``).

So -O1 is the level that pays at every size (close to -O2's code at a fraction of its compile time), -O2 only for
small files where gcc takes well under a second. ``codegen="auto"`` therefore never waits for gcc: above
:data:`AUTO_C_MIN_UNKNOWNS` unknowns the C source is written and gcc runs as a separate process (:func:`generate_c`
with ``background=True``) while the run starts on the VM; the integrator adapter (``flexlib.solve.backends``) checks
every 32 steps whether the library exists and then rebinds its callbacks to it, without restarting IDA
(``stats["compiled_at"]``): VM and C perform the same operations in the same order, so the trajectory is the same;
later runs and cached builds of later sessions use it from the start (``CompiledModel.function``). The same holds
below :data:`AUTO_C_MIN_UNKNOWNS` unknowns for models with at least :data:`AUTO_C_MIN_OPERATIONS` operations
(closed-loop mechanisms). ``codegen=True`` compiles in the foreground and drops to -O0 above
:data:`GCC_O1_MAX_LINES` lines so that an explicit request never blocks for minutes.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

import casadi as ca

from flexlib.compile.integrity import sha256_file
from flexlib.errors import FlexlibError

__all__ = ["GCC_O1_MAX_LINES", "GCC_O2_MAX_LINES", "JOIN_AGE", "compile_functions", "earlier_compile", "gcc_level",
           "generate_c"]

#: A background compile of the same source younger than this [s] that has not finished is joined, not repeated.
JOIN_AGE = 900.0


def _source_digest(texts: tuple[str, str]) -> str:
    """The digest that names the C source of ``res`` and ``jac`` (serialized) (``flexlib_<digest>.c``)."""
    return hashlib.sha256((texts[0] + texts[1]).encode()).hexdigest()[:16]


def earlier_compile(build_dir: str | os.PathLike, texts: tuple[str, str]) -> str | None:
    """The library path of a background compile of the same ``res`` and ``jac`` that an earlier process started in
    ``build_dir`` and that finished, or is still running and younger than :data:`JOIN_AGE` — None if there is none.

    A background gcc outlives the process that started it; a process that ends first (a short CLI run) leaves the
    finished library in its private directory without adopting it. The next process of the same build adopts that
    one (``CompiledModel._adopt_pending`` hashes it and records the manifest) instead of compiling the same source
    again. Only directories of this user, mode 0700, as :func:`generate_c` makes them, are considered.
    """
    name = f"flexlib_{_source_digest(texts)}.c"
    build = Path(build_dir)
    running = None
    try:
        candidates = sorted(build.glob(".flexlib-gcc-*.tmp"))
    except OSError:
        return None
    for work in candidates:
        try:
            st = work.stat()
            if st.st_uid != os.getuid() or (st.st_mode & 0o777) != 0o700 or not (work / name).is_file():
                continue
            if (work / "flexlib.so").is_file():
                return str(work / "flexlib.so")
            log = work / "gcc.log"
            failed = log.is_file() and log.stat().st_size > 0 and not (work / "flexlib.so.part").exists()
            if not failed and time.time() - st.st_mtime < JOIN_AGE:
                running = str(work / "flexlib.so")
        except OSError:
            continue
    return running


def gcc_level(lines: int, background: bool = False) -> str:
    """gcc optimisation flag for generated C of ``lines`` lines (the measurements: ``docs/decisions/012-*``):
    -O2 for small files, -O1 above; in the foreground -O0 above :data:`GCC_O1_MAX_LINES` lines."""
    if lines < GCC_O2_MAX_LINES:
        return "-O2"
    return "-O1" if background or lines < GCC_O1_MAX_LINES else "-O0"


#: ``-O2`` below this many lines of generated C (gcc well under a second), ``-O1`` above.
GCC_O2_MAX_LINES = 3000
#: In the foreground (``codegen=True``), ``-O0`` above this many lines.
GCC_O1_MAX_LINES = 30000


def generate_c(res: ca.Function, jac: ca.Function, build_dir: str | os.PathLike | None, *,
               background: bool = False, serialized: tuple[str, str] | None = None) -> Any:
    """Write ``res`` and ``jac`` as C, compile them with gcc and return the shared library's manifest.

    The library is named by the SHA-256 of its own bytes (``flexlib_<sha256[:32]>.so``, so processes
    compiling the same model concurrently never overwrite each other's file with different bytes) and is
    moved into ``build_dir`` atomically. The hash and size are computed here, from the file this process
    just compiled, before it is visible to anyone else.

    With ``background=True`` the C source is written into a private directory (mode 0700) under
    ``build_dir``, gcc is started as a separate process and the path its library will have there is returned
    at once (:meth:`CompiledModel._adopt_pending` hashes and moves it when it exists). gcc's messages go to
    ``gcc.log`` in that directory.

    ``serialized``: ``res`` and ``jac`` already serialized (the source file's name is their hash), so a build
    that stores them in the cache serializes them once.

    Returns
    -------
    path, sha256, size
        The library path, its SHA-256 (hex) and its size [bytes]; with ``background=True`` only the path
        gcc's output will have.
    """
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        raise FlexlibError("codegen=True needs a C compiler (gcc) on PATH")
    build = Path(build_dir) if build_dir else Path(tempfile.mkdtemp(prefix="flexlib_"))
    build.mkdir(parents=True, exist_ok=True)
    texts = serialized if serialized is not None else (res.serialize(), jac.serialize())
    digest = _source_digest(texts)
    cg = ca.CodeGenerator(f"flexlib_{digest}.c")
    cg.add(res)
    cg.add(jac)
    if background:
        work = Path(tempfile.mkdtemp(dir=build, prefix=".flexlib-gcc-", suffix=".tmp"))
        cg.generate(str(work) + os.sep)
        src = work / f"flexlib_{digest}.c"
        with src.open() as fh:
            lines = sum(1 for _ in fh)
        out, part = work / "flexlib.so", work / "flexlib.so.part"
        # the shell starts gcc in a subshell of its own and exits at once: nothing is left for this
        # process to wait for (the compile outlives it if need be)
        script = (f'("$1" {gcc_level(lines, background=True)} -shared -fPIC "$2" -o "$3" -lm > "$5" 2>&1 '
                  '&& chmod 700 "$3" && mv -f "$3" "$4") < /dev/null > /dev/null 2>&1 &')
        subprocess.run(["sh", "-c", script, "sh", cc, str(src), str(part), str(out), str(work / "gcc.log")],
                       stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                       start_new_session=True, check=False)
        return str(out)
    return _compile_foreground(cc, cg, build, f"flexlib_{digest}", "flexlib")


def compile_functions(functions: list[ca.Function], build_dir: str | os.PathLike, stem: str,
                      background_level: bool = False) -> tuple[str, str, int]:
    """CasADi functions as generated C in one shared library, compiled by gcc in the foreground at
    :func:`gcc_level` (``background_level``: the level of a background compile, -O1 for large sources) and moved
    into ``build_dir`` as ``<stem>_<sha256[:32]>.so``, named by its own bytes; ``(path, sha256, size)``. Raises
    :class:`FlexlibError` without a C compiler or when gcc fails."""
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        raise FlexlibError("generated C needs a C compiler (gcc) on PATH")
    build = Path(build_dir)
    build.mkdir(parents=True, exist_ok=True)
    cg = ca.CodeGenerator(f"{stem}.c")
    for fn in functions:
        cg.add(fn)
    return _compile_foreground(cc, cg, build, stem, stem, background_level)


def _compile_foreground(cc: str, cg: ca.CodeGenerator, build: Path, source: str, stem: str,
                        background_level: bool = False) -> tuple[str, str, int]:
    """``cg`` (whose file is ``<source>.c``) compiled into ``build/<stem>_<sha256[:32]>.so``, atomically."""
    with tempfile.TemporaryDirectory(dir=build, prefix=".flexlib-gcc-", suffix=".tmp") as tmp:
        cg.generate(tmp + os.sep)
        src = Path(tmp) / f"{source}.c"
        with src.open() as fh:
            lines = sum(1 for _ in fh)
        tmp_lib = Path(tmp) / f"{source}.so"
        proc = subprocess.run([cc, gcc_level(lines, background_level), "-shared", "-fPIC", str(src), "-o",
                               str(tmp_lib), "-lm"], capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            raise FlexlibError(f"gcc failed on the generated model code:\n{proc.stderr[-2000:]}")
        os.chmod(tmp_lib, 0o700)
        sha, size = sha256_file(tmp_lib), tmp_lib.stat().st_size
        lib = build / f"{stem}_{sha[:32]}.so"
        os.replace(tmp_lib, lib)
    return str(lib), sha, size
