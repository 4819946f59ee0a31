"""Faults around the C driver of the default backend: without it (``FLEXLIB_NATIVE=0``, no gcc, a model it cannot
set up) the default ``solver="ida"`` steps IDA from Python with no error; ``solver="ida-native"`` asked for
explicitly raises :class:`~flexlib.errors.NativeSolverError` naming the backend and what failed."""

import numpy as np
import pytest

import flexlib as fl
from flexlib.errors import NativeSolverError
from flexlib.models.reference.mass_spring_damper import Oscillator
from flexlib.solve import native
from flexlib.solve.backends import ida_c

needs_driver = pytest.mark.skipif(not native.native_available(),
                                  reason="C driver unavailable (no gcc, or FLEXLIB_NATIVE=0)")



@pytest.fixture(scope="module")
def osc():
    return fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


def test_flexlib_native_0_falls_back_without_error(osc, monkeypatch):
    """``FLEXLIB_NATIVE=0``: the default steps IDA from Python (no wall-time split in the stats), x = cos t to 1e-5."""
    monkeypatch.setenv("FLEXLIB_NATIVE", "0")
    assert not native.native_available()
    res = osc.run(2.0, dt_out=0.1)
    assert res.success and "wall_model" not in res.stats
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-5)


@needs_driver
def test_driver_that_cannot_be_set_up_falls_back_for_the_default_only(osc, monkeypatch):
    """A model the driver cannot take (here: set-up refused) runs on the scikit-sundae route by default; asked for
    explicitly, ``ida-native`` raises NativeSolverError naming the backend."""

    def refuse(*args, **kwargs):
        raise NativeSolverError("the ida-native driver could not set up IDA: IDAInit failed")

    monkeypatch.setattr(ida_c, "make_driver", refuse)
    res = osc.run(2.0, dt_out=0.1)
    assert res.success and "wall_model" not in res.stats
    with pytest.raises(NativeSolverError, match="ida-native driver could not set up IDA"):
        osc.run(2.0, dt_out=0.1, solver="ida-native")


def test_no_compiler_falls_back_for_the_default_and_names_gcc_for_ida_native(osc, monkeypatch, tmp_path):
    """No gcc on PATH and no driver in the cache: the default runs (x = cos t to 1e-5); ``ida-native`` says it needs
    a C compiler."""
    monkeypatch.setattr(native, "_LIB", [])
    monkeypatch.setattr(native, "_AVAILABLE", [])
    monkeypatch.setattr(native.shutil, "which", lambda name: None)
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))  # no driver compiled there
    res = osc.run(2.0, dt_out=0.1)
    assert res.success and "wall_model" not in res.stats
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-5)
    with pytest.raises(NativeSolverError, match=r"solver='ida-native' needs a C compiler \(gcc\)"):
        osc.run(2.0, dt_out=0.1, solver="ida-native")


@needs_driver
def test_unknown_linear_solver_in_environment_names_the_variable(osc, monkeypatch):
    """``FLEXLIB_LINSOL`` with a name the driver does not know: RunArgumentError naming the variable, the value and
    the choices (no silent fallback to another solver)."""
    monkeypatch.setenv("FLEXLIB_LINSOL", "umfpack")
    with pytest.raises(fl.RunArgumentError, match=r"FLEXLIB_LINSOL='umfpack'.*dense, superlumt, klu"):
        osc.run(1.0, dt_out=0.1)


@needs_driver
def test_klu_requested_without_klu_names_the_package(osc, monkeypatch):
    """``FLEXLIB_LINSOL=klu`` where KLU cannot be loaded: NativeSolverError naming the linear solver and kvxopt; the
    default route (no override) still runs, on the other solvers."""
    monkeypatch.setattr(native, "klu_available", lambda: False)
    monkeypatch.setattr(ida_c, "klu_available", lambda: False)
    monkeypatch.setenv("FLEXLIB_LINSOL", "klu")
    with pytest.raises(NativeSolverError, match=r"linear solver 'klu'.*kvxopt"):
        osc.run(1.0, dt_out=0.1, solver="ida-native")
    monkeypatch.delenv("FLEXLIB_LINSOL")
    res = osc.run(1.0, dt_out=0.1)
    assert res.success and res.stats["linear_solver"] == "dense"


@needs_driver
@pytest.mark.parametrize("library", ["missing", "not_klu"])
def test_no_usable_klu_library_falls_back_to_superlumt(library, monkeypatch, tmp_path):
    """kvxopt not installed (no KLU library found) or a library without KLU's entry points in its place: KLU is
    reported unavailable (no error) and a model above ``KLU_MIN`` unknowns runs on SuperLU_MT."""
    path = None if library == "missing" else native.driver_library()  # a shared library without klu_* symbols
    monkeypatch.setattr(native, "_KLU", [])
    monkeypatch.setattr(native, "klu_library", lambda: path)
    assert not native.klu_available()

    class Big:
        n = ida_c.KLU_MIN + 1

    monkeypatch.delenv("FLEXLIB_LINSOL", raising=False)
    assert ida_c.linear_solver(Big()) == "superlumt"
