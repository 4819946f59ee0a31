"""Shared test fixtures: every test session uses its own empty model cache."""

import pytest


@pytest.fixture(autouse=True, scope="session")
def _isolated_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    import os

    os.environ["FLEXLIB_CACHE_DIR"] = str(tmp_path_factory.mktemp("flexlib_cache"))
