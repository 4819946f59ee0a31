"""A cached load of a model whose background gcc (started by this process) has not finished shares that compile
instead of writing the C again and starting a second gcc (issue 9: the boom proxy's cached build took 1.8 s and
two compilers competed for the cores).

Reference: the library both models adopt is the one file the single compile produced, its manifest (SHA-256,
size) identical; the two models' results agree exactly (same C, same operations).
"""

import time
from pathlib import Path

import numpy as np

import flexlib as fl
from flexlib.compile import pipeline
from flexlib.models.n_mass_chain import NMassChain


def test_cached_load_shares_the_running_background_compile(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    started = []
    real = pipeline.generate_c

    def counting(*args, **kwargs):
        started.append(kwargs.get("background", False))
        return real(*args, **kwargs)

    monkeypatch.setattr(pipeline, "generate_c", counting)
    first = fl.Simulation(NMassChain(100)).compiled
    assert first.n > 300 and first.wants_c
    if first.library is not None:  # gcc finished before the second load: nothing to share (rare, fast machine)
        return
    second = fl.Simulation(NMassChain(100)).compiled
    assert second is not first
    assert started == []  # the cached load started no gcc of its own (the first build's went through compile_dae)
    assert second.library_pending == first.library_pending is not None
    deadline = time.monotonic() + 600.0
    while (first.library is None or second.library is None) and time.monotonic() < deadline:
        time.sleep(0.2)
        for m in (second, first):  # the second model adopts first: the first must find the moved library
            if m.c_ready():
                m.function("res")
    assert first.library is not None, "background gcc did not finish"
    assert second.library == first.library and Path(first.library).exists()
    assert (second.library_sha256, second.library_size) == (first.library_sha256, first.library_size)
    assert first.library_pending is None and second.library_pending is None
    p = np.concatenate([np.asarray(first.param_defaults, dtype=float), np.zeros(first.n_relations)])
    y, yp = np.linspace(0.0, 1.0, first.n), np.zeros(first.n)
    np.testing.assert_array_equal(np.asarray(first.function("res")(0.0, y, yp, p)),
                                  np.asarray(second.function("res")(0.0, y, yp, p)))
    assert first.function("res").class_name() == second.function("res").class_name() == "External"
