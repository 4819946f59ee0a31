"""Shared test fixtures: every test session uses its own empty model cache (shared by the session's workers when
it runs on several, ``pytest -n 2``: a build made by one is found by the other, as two processes share a cache)."""

import pytest


@pytest.fixture(autouse=True, scope="session")
def _isolated_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    import os

    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if worker is None:
        os.environ["FLEXLIB_CACHE_DIR"] = str(tmp_path_factory.mktemp("flexlib_cache"))
    else:  # the workers' base temporary directories are siblings under the session's
        shared = tmp_path_factory.getbasetemp().parent / "flexlib_cache"
        shared.mkdir(exist_ok=True)
        os.environ["FLEXLIB_CACHE_DIR"] = str(shared)
