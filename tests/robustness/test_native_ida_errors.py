"""Bad environments and arguments for ``solver="ida-native"``: each raises a clear error naming the culprit."""


import numpy as np
import pytest

import flexlib as fl
from flexlib.models.reference.blow_up import Decay
from flexlib.solve import native


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty cache directory, so the driver would have to be compiled."""
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_no_c_compiler_names_gcc_and_the_solver(fresh_cache, monkeypatch):
    monkeypatch.setattr(native.shutil, "which", lambda name: None)
    with pytest.raises(fl.NativeSolverError, match=r"solver='ida-native' needs a C compiler \(gcc\)"):
        native.driver_library()
    assert not (fresh_cache / "native").exists() or not list((fresh_cache / "native").iterdir())


def test_missing_sundials_library_is_named(fresh_cache, monkeypatch):
    monkeypatch.setattr(native, "_SUNDIALS", (*native._SUNDIALS, "nosuchsolver"))
    with pytest.raises(fl.NativeSolverError, match=r"'libsundials_nosuchsolver' not found in .*scikit_sundae\.libs"):
        native.driver_library()


def test_driver_compile_failure_shows_gcc_output_and_leaves_no_temporary(fresh_cache, monkeypatch, tmp_path):
    broken = tmp_path / "ida_driver.c"
    broken.write_text("int fd_create(void) { return syntax error here }\n")
    monkeypatch.setattr(native, "_SOURCE", broken)
    pattern = r"(?s)compiling the ida-native driver failed:\n.*ida_driver\.c.*error"
    with pytest.raises(fl.NativeSolverError, match=pattern):
        native.driver_library()
    assert not list((fresh_cache / "native").glob("*"))  # neither a library nor a temporary left behind


def test_solver_name_typo_suggests_ida_native():
    sim = fl.Simulation(Decay(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.RunArgumentError, match=r"solver.*'ida_native'.*did you mean 'ida-native'"):
        sim.run(1.0, solver="ida_native")


def test_parameter_vector_must_be_float64_in_place():
    """The C driver reads the parameter array in place: a copy (or another dtype) would silently freeze
    relation values, so the C driver refuses it, naming ``p``."""
    from flexlib.solve.solvers import integrate

    sim = fl.Simulation(Decay(init={"x": 1.0}), use_cache=False)
    p = np.zeros(sim.compiled.n_params + sim.compiled.n_relations, dtype=np.float32)
    with pytest.raises(TypeError, match=r"ida-native: p must be a C-contiguous float64 array"):
        integrate("ida-native", sim.compiled, sim.initializer, p, np.array([1.0]), np.array([-1.0]), 0.0, 1.0, None)
