"""Dask worker preload: a study's worker process made ready for flexlib runs when it starts, not in its first task.

A worker process starts empty. Without this its first task imports flexlib's engine and numeric stack (CasADi,
SciPy's sparse matrices), imports every registered model module to find the model it is given, and loads the C
driver of the default solver — about half a second of every worker's first run of a study, which on a short study
is the difference between two workers and one. Dask runs a *preload* module's ``dask_setup(worker)`` as each worker
starts (distributed.dask.org, "Customize initialization"); :func:`flexlib.study.run.local_cluster` passes this one to
the workers of the embedded cluster, and a cluster of your own takes it on the command line::

    dask worker tcp://HOST:8786 --nthreads 1 --preload flexlib.study.worker

The model itself is still built (or loaded from the cache) by the worker's first task of a study: which model and
which options are the study's to say.
"""

from __future__ import annotations

from typing import Any

__all__ = ["dask_setup", "warm"]


def warm() -> None:
    """Import what a worker's runs need and load the registered models and the default solver's C driver (compiled
    once per machine if it is not yet; a machine without a C compiler runs without it, as any run does)."""
    import casadi  # noqa: F401
    import scipy.sparse  # noqa: F401

    from flexlib import registry
    from flexlib.solve.native import native_available
    from flexlib.solve.simulation import Simulation  # noqa: F401

    registry.models()
    native_available()


def dask_setup(worker: Any) -> None:
    """Dask's preload hook, called once as ``worker`` starts: :func:`warm`."""
    warm()
