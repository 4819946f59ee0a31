"""The C driver of the ``ida-native`` backend: SUNDIALS IDA stepped in C (``ida_driver.c``).

The driver is compiled once per machine (and per scikit-sundae install) with ``gcc -O2`` into
:func:`flexlib.compile.cache.cache_dir` ``/native/``, keyed by the sha256 of its source, the
SUNDIALS library paths and the flags, and written atomically (temporary file, then
``os.replace``). It links against the SUNDIALS 7.9 shared libraries that scikit-sundae bundles
(full paths plus an rpath, so it needs no headers and no SUNDIALS install of its own: the
prototypes are declared in the C source from ``sksundae/c_*.pxd``).

Model functions are evaluated from C as well: the generated library's ``flexlib_res`` /
``flexlib_jac`` symbols when the model has one (``model.library``), otherwise CasADi's SX
virtual machine through the C API of ``libcasadi.so`` (``casadi_c_push_file`` /
``casadi_c_eval_id``), which works for every model without gcc per model.

Linear solvers (``LINEAR_SOLVERS``; chosen by :func:`flexlib.solve.backends.ida_c.linear_solver`): SUNDIALS' dense LU,
SUNDIALS' SuperLU_MT, and KLU (SuiteSparse), which the bundled SUNDIALS lacks: the driver wraps them in a
``SUNLinearSolver`` of its own (setup and solve timed in C) and calls KLU through entry points handed over from
Python (:func:`klu_available`: the shared library of the ``kvxopt`` wheel, its ``klu_common`` layout checked against
``klu_defaults``), so the driver builds and runs without KLU too.
"""

from __future__ import annotations

import ctypes
import hashlib
import importlib.util
import os
import shutil
import subprocess
import tempfile
import threading
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.environment import env_default
from flexlib.errors import FlexlibError, NativeSolverError

__all__ = ["FD_CHUNK", "FD_DIVERGED", "FD_FULL", "FD_ROOT", "FD_TINY", "FD_TSTOP", "LINEAR_SOLVERS", "Driver",
           "NativeUnavailable", "cpu_clock", "driver_library", "klu_available", "klu_library", "native_available",
           "use_cpu_clock"]

FD_TSTOP, FD_FULL, FD_ROOT, FD_CHUNK, FD_TINY, FD_DIVERGED = 0, 1, 2, 3, 4, 5
#: Linear solvers of the driver and their codes in ``ida_driver.c`` (``LS_DENSE``, ``LS_SUPERLUMT``, ``LS_KLU``)
LINEAR_SOLVERS = {"dense": 0, "superlumt": 1, "klu": 2}
_KLU_FUNCTIONS = ("defaults", "analyze", "factor", "solve", "free_symbolic", "free_numeric", "refactor", "rcond")
#: From this many unknowns KLU refactorises with the pivots of its last full factorisation (``klu_refactor``, as
#: SUNDIALS' own KLU module does) while ``klu_rcond`` stays above :data:`KLU_REUSE_RCOND` times that factorisation's;
#: below it, where the factorisation is cheap, every setup pivots afresh (``docs/decisions/014-*``).
KLU_REUSE_MIN_UNKNOWNS = 300
#: Share of the last full factorisation's reciprocal condition estimate below which a setup pivots afresh.
KLU_REUSE_RCOND = 1e-3

_SOURCE = Path(__file__).with_name("ida_driver.c")
_SUNDIALS = ("core", "nvecserial", "sunmatrixdense", "sunmatrixsparse", "sunlinsoldense", "sunlinsolsuperlumt", "ida")
_LOCK = threading.Lock()
_LIB: list[ctypes.CDLL] = []
_CASADI: list[ctypes.CDLL] = []
_KLU: list[ctypes.CDLL | None] = []

_dp = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
_ip = np.ctypeslib.ndpointer(dtype=np.int32, flags="C_CONTIGUOUS")
_lp = np.ctypeslib.ndpointer(dtype=np.int64, flags="C_CONTIGUOUS")


#: The driver cannot be built or set up here (kept as a short alias).
NativeUnavailable = NativeSolverError


def _sundials_libs() -> list[Path]:
    spec = importlib.util.find_spec("sksundae")  # its location only: importing it costs 0.2 s (scipy.optimize)
    if spec is None or spec.origin is None:
        raise NativeUnavailable("scikit-sundae is not installed (the ida-native backend links against its bundled "
                                "SUNDIALS)")
    libdir = Path(spec.origin).resolve().parent.parent / "scikit_sundae.libs"
    paths = []
    for name in _SUNDIALS:
        found = sorted(libdir.glob(f"libsundials_{name}-*.so*"))
        if not found:
            raise NativeUnavailable(f"SUNDIALS library 'libsundials_{name}' not found in {libdir} "
                                    "(the ida-native backend links against scikit-sundae's bundled SUNDIALS)")
        paths.append(found[0])
    return paths


def driver_library() -> Path:
    """Path of the compiled driver (compiled now if not cached)."""
    from flexlib.compile.cache import cache_dir

    libs = _sundials_libs()
    flags = ["-O2", "-shared", "-fPIC"]
    key = hashlib.sha256(_SOURCE.read_bytes() + "\n".join(map(str, [*libs, *flags])).encode()).hexdigest()[:20]
    out_dir = cache_dir() / "native"
    target = out_dir / f"ida_driver_{key}.so"
    if target.exists():
        return target
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        raise NativeUnavailable("solver='ida-native' needs a C compiler (gcc) on PATH to build its driver once")
    out_dir.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=target.name + ".", suffix=".tmp", dir=out_dir)
    os.close(fd)
    try:
        cmd = [cc, *flags, str(_SOURCE), "-o", tmp, *map(str, libs), f"-Wl,-rpath,{libs[0].parent}", "-lm"]
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            raise NativeUnavailable(f"compiling the ida-native driver failed:\n{proc.stderr[-2000:]}")
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return target


#: Cells of the fixed-step driver's work histogram (``FX_WORK_C``, ``FX_WORK_M`` in ``ida_driver.c``): corrections, then
#: matrix evaluations and full factorisations (a step beyond a bound counts in the last cell)
WORK_CORRECTIONS, WORK_MATRICES = 64, 8

_AVAILABLE: list[bool] = []


def native_available() -> bool:
    """Whether the default ``solver="ida"`` runs on the C driver: True once the driver is compiled (or cached)
    and loads; False without a C compiler, when the build or the load fails, or with ``FLEXLIB_NATIVE=0`` in
    the environment, the default of ``IDA(native=None)`` (then the default backend steps scikit-sundae's IDA from
    Python, with no error). The answer is kept for the process (the environment variable is read on every call,
    :func:`flexlib.compile.environment.env_default`)."""
    if not env_default("native"):  # 0, false, no, off (another word is a RunArgumentError)
        return False
    if not _AVAILABLE:
        try:
            _lib()
            ok = True
        except (FlexlibError, OSError, subprocess.SubprocessError):
            ok = False
        _AVAILABLE.append(ok)
    return _AVAILABLE[0]


def _lib() -> ctypes.CDLL:
    with _LOCK:
        if _LIB:
            return _LIB[0]
        lib = ctypes.CDLL(str(driver_library()))
        vp, i, d, L = ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.c_long
        lib.fd_create.restype = vp
        lib.fd_create.argtypes = [i, i, _ip, _ip, i, i, vp, ctypes.POINTER(vp), vp, _ip, _ip, _lp, d, _dp, _dp, d,
                                  d, _dp, _dp, ctypes.c_char_p]
        lib.fd_free.argtypes = [vp]
        lib.fd_free.restype = None
        lib.fd_reinit.argtypes = [vp, d, _dp, _dp]
        lib.fd_reinit.restype = i
        lib.fd_set_grid.argtypes = [vp, vp, i]
        lib.fd_set_grid.restype = None
        lib.fd_grid_pos.argtypes = [vp]
        lib.fd_grid_pos.restype = i
        lib.fd_set_funs.argtypes = [vp, ctypes.POINTER(vp), vp, _ip, _ip, _lp]
        lib.fd_set_funs.restype = i
        lib.fd_set_wall_chunk.argtypes = [vp, d]
        lib.fd_set_wall_chunk.restype = None
        lib.fd_set_limits.argtypes = [vp, d, d]
        lib.fd_set_limits.restype = None
        lib.fd_last_step.argtypes = [vp]
        lib.fd_last_step.restype = d
        # the output buffers go in as raw addresses (Driver.advance): see there why not as ndpointers
        lib.fd_advance.argtypes = [vp, d, L, vp, vp, vp, i, ctypes.POINTER(i), ctypes.POINTER(d),
                                   ctypes.POINTER(L)]
        lib.fd_advance.restype = i
        lib.fd_state.argtypes = [vp, _dp, _dp]
        lib.fd_state.restype = None
        lib.fd_roots.argtypes = [vp, _ip]
        lib.fd_roots.restype = None
        lib.fd_diagnostics.argtypes = [vp, _dp, _dp]
        lib.fd_diagnostics.restype = i
        lib.fd_stats.argtypes = [vp, _lp, _dp]
        lib.fd_stats.restype = None
        lib.fd_flag_name.argtypes = [L, ctypes.c_char_p, i]
        lib.fd_flag_name.restype = None
        lib.fd_set_klu.argtypes = [ctypes.POINTER(vp)]
        lib.fd_set_klu.restype = i
        lib.fd_set_klu_reuse.argtypes = [i, ctypes.c_double]
        lib.fd_set_klu_reuse.restype = None
        lib.fd_use_cpu_clock.argtypes = [i]
        lib.fd_use_cpu_clock.restype = None
        lib.fd_set_newton.argtypes = [vp, d, i, d]
        lib.fd_set_newton.restype = i
        lib.fd_set_max_order.argtypes = [vp, i]
        lib.fd_set_max_order.restype = i
        lib.fd_set_fixed_step.argtypes = [vp, d, i, i, i, d, _ip, i, d]
        lib.fd_set_fixed_step.restype = i
        lib.fd_fixed_stats.argtypes = [vp, _lp, _dp, _lp]
        lib.fd_fixed_stats.restype = None
        _LIB.append(lib)
        return lib


def klu_library() -> Path | None:
    """KLU (SuiteSparse) as shipped in the kvxopt wheel (``kvxopt.libs/libklu-*.so*``), or None.

    The SUNDIALS that scikit-sundae bundles has no KLU; kvxopt's wheel carries SuiteSparse's shared libraries
    (KLU with BTF, AMD, COLAMD). Only the library file is used: kvxopt's Python modules are not imported.
    """
    import importlib.util

    try:
        spec = importlib.util.find_spec("kvxopt")
    except (ImportError, ValueError):  # e.g. a module entry set to None
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    for loc in spec.submodule_search_locations:
        found = sorted((Path(loc).parent / "kvxopt.libs").glob("libklu-*.so*"))
        if found:
            return found[0]
    return None


def klu_available() -> bool:
    """Whether the driver can factorise with KLU: kvxopt's KLU library is installed, loads, and its
    ``klu_common`` layout is the one the driver expects (checked against ``klu_defaults``). Kept per process."""
    lib = _lib()
    with _LOCK:
        if not _KLU:
            klu = None
            path = klu_library()
            if path is not None:
                try:
                    cand = ctypes.CDLL(str(path))
                    fns = (ctypes.c_void_p * len(_KLU_FUNCTIONS))(
                        *[ctypes.cast(getattr(cand, f"klu_{f}"), ctypes.c_void_p).value for f in _KLU_FUNCTIONS])
                    if lib.fd_set_klu(fns) == 0:
                        klu = cand
                        lib.fd_set_klu_reuse(KLU_REUSE_MIN_UNKNOWNS, KLU_REUSE_RCOND)
                except (OSError, AttributeError):
                    klu = None
            _KLU.append(klu)
        return _KLU[0] is not None


_CPU_CLOCK = [False]


def use_cpu_clock(on: bool) -> None:
    """Report the integration's time split (``wall_model``, ``wall_ida``, ``wall_python``, ``wall_lsetup``, …
    in a run's stats) in the thread's CPU time instead of wall time, for benchmarks on a loaded machine (each reading
    in C is then a system call, ~0.3 µs). Process-wide; off by default."""
    _lib().fd_use_cpu_clock(int(on))
    _CPU_CLOCK[0] = bool(on)


def cpu_clock() -> bool:
    """Whether :func:`use_cpu_clock` is on."""
    return _CPU_CLOCK[0]


def _casadi() -> ctypes.CDLL:
    with _LOCK:
        if not _CASADI:
            lib = ctypes.CDLL(str(Path(ca.__file__).parent / "libcasadi.so"), mode=ctypes.RTLD_GLOBAL)
            lib.casadi_c_push_file.argtypes = [ctypes.c_char_p]
            lib.casadi_c_n_loaded.restype = ctypes.c_int
            lib.casadi_c_checkout_id.argtypes = [ctypes.c_int]
            lib.casadi_c_checkout_id.restype = ctypes.c_int
            _CASADI.append(lib)
        return _CASADI[0]


class Evaluator:
    """One CasADi function callable from C: a generated symbol or an id of CasADi's C API."""

    def __init__(self, fn: ca.Function, symbol: int | None = None, keep: Any = None) -> None:
        self.fn = fn
        self.symbol = symbol  # address of the generated C function, or None for the SX virtual machine
        self.keep = keep  # the CDLL holding ``symbol``
        self.sizes = [fn.sz_arg(), fn.sz_res(), fn.sz_iw(), fn.sz_w()]
        self.id = -1
        if symbol is None:
            lib = _casadi()
            with tempfile.TemporaryDirectory(prefix="flexlib_native_") as tmp:
                path = os.path.join(tmp, "f.casadi")
                fn.save(path)
                with _LOCK:
                    self.id = lib.casadi_c_n_loaded()
                    if lib.casadi_c_push_file(path.encode()) != 0:
                        raise NativeUnavailable(f"casadi_c_push_file failed for function {fn.name()}")

    def checkout(self) -> int:
        """A memory slot for one driver (0 for generated code)."""
        return 0 if self.symbol is not None else int(_casadi().casadi_c_checkout_id(self.id))


def evaluators(model: Any, zc: ca.Function | None) -> dict[str, Evaluator]:
    """Evaluators of ``res``, ``jac`` (generated C when the model has a library) and ``zc``; cached on the model."""
    model.function("res")  # adopts a finished background compile; drops a library that fails its manifest
    cached = model._functions.get("ida_native")
    if cached is not None and cached.get("zc_fn") is zc and cached.get("library") == model.library:
        return cached["ev"]
    ev: dict[str, Evaluator] = {}
    lib_path = model.library
    if lib_path is not None and model.library_problem() is None:
        clib = ctypes.CDLL(lib_path)
        for name in ("res", "jac"):
            sym = getattr(clib, f"flexlib_{name}")
            ev[name] = Evaluator(model.function(name), ctypes.cast(sym, ctypes.c_void_p).value, clib)
    else:
        for name in ("res", "jac"):
            ev[name] = Evaluator(model.sx_function(name))
    if zc is not None:
        ev["zc"] = Evaluator(zc)
    model._functions["ida_native"] = {"ev": ev, "zc_fn": zc, "library": lib_path}  # type: ignore[assignment]
    return ev


class Driver:
    """An IDA instance held in C for one model (see ``ida_driver.c``)."""

    def __init__(self, model: Any, p: np.ndarray, ev: dict[str, Evaluator], n_roots: int, linsol: str, rtol: float,
                 atol: np.ndarray, max_step: float, t0: float, y0: np.ndarray, yp0: np.ndarray) -> None:
        lib = _lib()
        if linsol == "klu" and not klu_available():
            raise NativeUnavailable("linear solver 'klu' requested, but KLU is not available (pip install kvxopt)")
        self.linsol = linsol
        self._lib = lib
        self.n = model.n
        self.p = p  # the C side reads p's memory: parameters and relation values updated in place at events
        self._keep = [ev]
        self.colind = np.ascontiguousarray(model.jac_colind, dtype=np.int32)
        self.row = np.ascontiguousarray(model.jac_row, dtype=np.int32)
        names = ["res", "jac", "zc"] if n_roots else ["res", "jac"]
        fptr, fid, ids, mems, sizes = self._functions(ev, names)
        self._mems = [(ev[k].id, int(m)) for k, m in zip(("res", "jac", "zc"), mems, strict=True)
                      if k in names and ev[k].symbol is None]
        err = ctypes.create_string_buffer(128)
        diff = np.asarray(model.differential, dtype=float)
        self._ptr = lib.fd_create(model.n, len(self.row), self.colind, self.row, LINEAR_SOLVERS[linsol], n_roots,
                                  p.ctypes.data, fptr, fid, ids, mems, sizes, rtol,
                                  np.ascontiguousarray(atol, dtype=float), np.ascontiguousarray(diff), max_step, t0,
                                  np.ascontiguousarray(y0, dtype=float), np.ascontiguousarray(yp0, dtype=float), err)
        if not self._ptr:
            raise NativeUnavailable(f"the ida-native driver could not set up IDA: {err.value.decode()} failed")
        self.n_roots = n_roots
        self._grid: np.ndarray | None = None
        self._nrows, self._tnow, self._steps = ctypes.c_int(), ctypes.c_double(), ctypes.c_long()

    @staticmethod
    def _functions(ev: dict[str, Evaluator], names: list[str]) -> tuple[Any, Any, np.ndarray, np.ndarray, np.ndarray]:
        """Function pointers, CasADi's eval-by-id entry, ids, checked-out memory slots and work sizes (res, jac, zc)."""
        keys = ("res", "jac", "zc")
        fptr = (ctypes.c_void_p * 3)(*[ev[k].symbol if k in names else None for k in keys])
        ids = np.array([ev[k].id if k in names else -1 for k in keys], dtype=np.int32)
        mems = np.array([ev[k].checkout() if k in names else 0 for k in keys], dtype=np.int32)
        sizes = np.array([s for k in keys for s in (ev[k].sizes if k in names else [0] * 4)], dtype=np.int64)
        fid = ctypes.cast(_casadi().casadi_c_eval_id, ctypes.c_void_p).value if any(
            ev[k].symbol is None for k in names) else None
        return fptr, fid, ids, mems, sizes

    def rebind(self, ev: dict[str, Evaluator]) -> None:
        """Evaluate the residual and Jacobian with ``ev`` from the next step on (generated C that has become
        ready during the run; no restart)."""
        fptr, fid, ids, mems, sizes = self._functions(ev, ["res", "jac"])
        if self._lib.fd_set_funs(self._ptr, fptr, fid, ids, mems, sizes) != 0:
            raise NativeUnavailable("the ida-native driver could not switch to the compiled library (no memory)")
        self._keep.append(ev)

    def __del__(self) -> None:
        ptr = getattr(self, "_ptr", None)
        if ptr:
            self._lib.fd_free(ptr)
            self._ptr = None
            release = _CASADI[0].casadi_c_release_id if _CASADI else None
            for fid, mem in getattr(self, "_mems", []):  # CasADi memory slots checked out for this driver
                if release is not None:
                    release(fid, mem)

    def reinit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        """Restart IDA at ``t`` (after an event)."""
        flag = self._lib.fd_reinit(self._ptr, t, np.ascontiguousarray(y, dtype=float),
                                   np.ascontiguousarray(yp, dtype=float))
        if flag != 0:
            raise FlexlibError(f"IDAReInit failed ({self.flag_name(flag)})")

    def set_grid(self, grid: np.ndarray | None) -> None:
        """Output times for the following :meth:`advance` calls (None: every step)."""
        self._grid = None if grid is None else np.ascontiguousarray(grid, dtype=float)
        g = self._grid
        self._lib.fd_set_grid(self._ptr, None if g is None else g.ctypes.data, 0 if g is None else len(g))

    def grid_pos(self) -> int:
        """Number of grid times already written."""
        return int(self._lib.fd_grid_pos(self._ptr))

    def set_limits(self, t_limit: float, h_min: float) -> None:
        """:meth:`advance` also stops (``FD_CHUNK``) after a step ending at or after ``t_limit`` [s] or shorter
        than ``h_min`` [s] (``inf`` and 0 switch this off)."""
        self._lib.fd_set_limits(self._ptr, t_limit, h_min)

    def set_wall_chunk(self, seconds: float) -> None:
        """:meth:`advance` also stops (``FD_CHUNK``) after ``seconds`` of wall time (0: no limit)."""
        self._lib.fd_set_wall_chunk(self._ptr, seconds)

    def last_step(self) -> float:
        """Size of the last step taken [s]."""
        return float(self._lib.fd_last_step(self._ptr))

    def advance(self, t_stop: float, max_chunk: int, T: np.ndarray, Y: np.ndarray,
                YP: np.ndarray) -> tuple[int, int, float, int]:
        """Step towards ``t_stop``; returns (code, rows written, solver time, steps taken).

        ``T``, ``Y``, ``YP`` (C-contiguous float64, checked here) are passed as raw addresses. As numpy
        ``ndpointer`` arguments they were converted by Python code inside the foreign call, and a SIGTERM or
        Ctrl-C arriving there surfaced as ``ctypes.ArgumentError`` (a failed run) instead of the run's interrupt.
        """
        for a in (T, Y, YP):
            if a.dtype != np.float64 or not a.flags.c_contiguous:
                raise TypeError(f"ida-native output buffers must be C-contiguous float64, got {a.dtype}")
        code = self._lib.fd_advance(self._ptr, t_stop, max_chunk, T.ctypes.data, Y.ctypes.data, YP.ctypes.data,
                                    len(T), ctypes.byref(self._nrows), ctypes.byref(self._tnow),
                                    ctypes.byref(self._steps))
        return code, self._nrows.value, self._tnow.value, self._steps.value

    def last_advance(self) -> tuple[int, float]:
        """Rows written and the solver time of the last :meth:`advance` call, also when the call's return values were
        lost to an interrupt that arrived as it returned."""
        return int(self._nrows.value), float(self._tnow.value)

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        """The solver's solution at its current time."""
        y, yp = np.empty(self.n), np.empty(self.n)
        self._lib.fd_state(self._ptr, y, yp)
        return y, yp

    def roots(self) -> np.ndarray:
        """IDA's root info of the last root return (+1 rising, -1 falling, 0 none)."""
        out = np.zeros(max(self.n_roots, 1), dtype=np.int32)
        self._lib.fd_roots(self._ptr, out)
        return out[: self.n_roots]

    def diagnostics(self) -> tuple[np.ndarray, np.ndarray]:
        """IDA's error weights and estimated local errors of the last step."""
        ewt, ele = np.zeros(self.n), np.zeros(self.n)
        self._lib.fd_diagnostics(self._ptr, ewt, ele)
        return ewt, ele

    def set_newton(self, dcj: float = 0.0, max_iters: int = 0, conv_coef: float = 0.0) -> None:
        """IDA's Newton knobs (measurements; 0 keeps IDA's default): relative change of ``cj`` that triggers a new
        iteration matrix (``IDASetDeltaCjLSetup``, default 0.25), Newton iterations per step
        (``IDASetMaxNonlinIters``, 4), convergence coefficient (``IDASetNonlinConvCoef``, 0.33)."""
        if self._lib.fd_set_newton(self._ptr, dcj, max_iters, conv_coef) != 0:
            raise FlexlibError(f"invalid IDA Newton options dcj={dcj}, max_iters={max_iters}, conv_coef={conv_coef}")

    def set_max_order(self, order: int) -> None:
        """Highest BDF order IDA may use (``IDASetMaxOrd``, 1–5; default 5)."""
        if not 1 <= int(order) <= 5 or self._lib.fd_set_max_order(self._ptr, int(order)) != 0:
            raise FlexlibError(f"invalid IDA maximum order {order!r} (1 ... 5)")

    def set_fixed_step(self, h: float, bdf2: bool, newton_iters: int, max_halvings: int, rtol: float,
                       relation_index: np.ndarray, realtime: bool = False, speed: float = 1.0) -> None:
        """Step with fixed steps of ``h`` [s] from now on instead of IDA (``ida_driver.c``, "fixed-step mode"): BDF2
        or implicit Euler, at most ``newton_iters`` Newton corrections, a step that does not converge halved up to
        ``max_halvings`` times, the Newton test weighted with ``rtol`` and
        the driver's absolute tolerances; ``relation_index``: the index into ``p`` of each root function's relation
        value; ``realtime``: each step waits for the wall clock (``speed`` times real time)."""
        rel = np.ascontiguousarray(relation_index, dtype=np.int32)
        if len(rel) != self.n_roots:
            raise ValueError(f"set_fixed_step: {len(rel)} relation indices for {self.n_roots} root functions")
        self._rel = rel
        if self._lib.fd_set_fixed_step(self._ptr, h, int(bdf2), int(newton_iters), int(max_halvings), rtol,
                                       rel if len(rel) else np.zeros(1, dtype=np.int32), int(realtime), speed):
            raise NativeUnavailable("the ida-native driver could not switch to fixed steps (no memory)")

    def fixed_stats(self) -> dict[str, Any]:
        """Fixed-step counters (:meth:`set_fixed_step`): steps, Newton corrections, unconverged steps, matrix
        evaluations, real-time overruns, halved steps; summed and worst step cost, worst lateness behind the wall
        clock, the end of the first step taken unconverged (NaN: none) and the start of the costliest step [s]; the
        costliest step's work and the steps by their work (rows ``[corrections, matrices, full factorisations,
        steps]``); the time of the full KLU factorisations [s]."""
        c, s = np.zeros(9, dtype=np.int64), np.zeros(6)
        work = np.zeros((WORK_CORRECTIONS, WORK_MATRICES, WORK_MATRICES), dtype=np.int64)
        self._lib.fd_fixed_stats(self._ptr, c, s, work)
        return {"steps": int(c[0]), "newton_iters": int(c[1]), "unconverged_steps": int(c[2]), "njev": int(c[3]),
                "worst_step_work": [int(c[6]), int(c[7]), int(c[8])], "t_full": float(s[5]),
                "step_work": [[int(i), int(j), int(k), int(work[i, j, k])] for i, j, k in zip(*np.nonzero(work),
                                                                                            strict=True)],
                "overruns": int(c[4]), "halved_steps": int(c[5]), "step_wall": float(s[0]),
                "worst_step_wall": float(s[1]), "worst_late": float(s[2]), "first_unconverged_t": float(s[3]),
                "worst_step_t": float(s[4])}

    def stats(self) -> dict[str, float]:
        """Evaluation counts, linear-solver counts and seconds spent in C."""
        c, s = np.zeros(11, dtype=np.int64), np.zeros(6)
        self._lib.fd_stats(self._ptr, c, s)
        return {"nfev": int(c[0]), "njev": int(c[1]), "nroot": int(c[2]), "steps": int(c[3]), "nonfinite": int(c[4]),
                "n_lsetup": int(c[5]), "n_lsolve": int(c[6]), "n_factor_full": int(c[7]), "n_newton": int(c[8]),
                "n_newton_fail": int(c[9]), "n_err_fail": int(c[10]),
                "t_res": float(s[0]), "t_jac": float(s[1]), "t_root": float(s[2]), "t_advance": float(s[3]),
                "t_lsetup": float(s[4]), "t_lsolve": float(s[5])}

    def flag_name(self, flag: int) -> str:
        """IDA's name of a return flag."""
        buf = ctypes.create_string_buffer(64)
        self._lib.fd_flag_name(flag, buf, 64)
        return buf.value.decode() or f"flag {flag}"
